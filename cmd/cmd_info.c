/* brdfit info DATA [data options] [--json]: what a data file holds once read and
 * preprocessed as a fit would see it: samples, channels, angle coverage, what the
 * preprocessing dropped or clamped, and value ranges per channel. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/load.h"
#include "brdfit/prep.h"
#include "commands.h"
#include "data_options.h"

static const char cmd[] = "brdfit info";

static cJSON *range_json(bf_range r)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "min", r.lo); /* cJSON writes NaN (nothing covered) as null */
    cJSON_AddNumberToObject(o, "max", r.hi);
    return o;
}

/* What the options said, for the outputs. */
typedef struct asked {
    char negative[16], scene[4096], subsample[32];
} asked;

static void print_json(const char *path, const bf_samples *s, const asked *o, const bf_load_report *r,
                       const bf_samples_info *info)
{
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "file", path);
    cJSON_AddNumberToObject(root, "samples_read", (double)r->read);
    cJSON_AddNumberToObject(root, "samples", (double)info->n);
    cJSON *names = cJSON_AddArrayToObject(root, "channels");
    for (int c = 0; c < s->channels; c++)
        cJSON_AddItemToArray(names, cJSON_CreateString(s->channel_names[c]));
    if (s->wavelength)
        cJSON_AddItemToObject(root, "wavelengths", cJSON_CreateDoubleArray(s->wavelength, s->channels));
    else
        cJSON_AddNullToObject(root, "wavelengths");
    cJSON_AddBoolToObject(root, "weighted", info->weighted);

    cJSON *prep = cJSON_AddObjectToObject(root, "prep");
    cJSON_AddNumberToObject(prep, "below_horizon", (double)r->below_horizon);
    cJSON_AddNumberToObject(prep, "nonfinite", (double)r->nonfinite);
    cJSON_AddNumberToObject(prep, "above_max_theta", (double)r->above_max_theta);
    cJSON_AddNumberToObject(prep, "negative", (double)r->negative);
    cJSON_AddStringToObject(prep, "negative_action", o->negative);
    cJSON_AddNumberToObject(prep, "subsampled_out", (double)r->subsampled_out);
    cJSON_AddNumberToObject(prep, "kept", (double)r->kept);
    if (r->scene) {
        /* The scene runs after the drops and before subsampling. */
        cJSON *sc = cJSON_AddObjectToObject(root, "scene");
        cJSON_AddStringToObject(sc, "file", o->scene);
        cJSON_AddNumberToObject(sc, "samples_in", (double)r->scene_in);
        cJSON_AddNumberToObject(sc, "kept", (double)r->scene_kept);
    } else {
        cJSON_AddNullToObject(root, "scene");
    }

    cJSON *cov = cJSON_AddObjectToObject(root, "coverage_deg");
    cJSON_AddItemToObject(cov, "theta_i", range_json(info->theta_i));
    cJSON_AddItemToObject(cov, "theta_o", range_json(info->theta_o));
    cJSON_AddItemToObject(cov, "theta_h", range_json(info->theta_h));
    cJSON_AddItemToObject(cov, "theta_d", range_json(info->theta_d));

    cJSON *counts = cJSON_AddObjectToObject(root, "counts");
    cJSON_AddNumberToObject(counts, "below_horizon", (double)info->below_horizon);
    cJSON_AddNumberToObject(counts, "nonfinite", (double)info->nonfinite);
    cJSON_AddNumberToObject(counts, "negative", (double)info->negative);
    cJSON_AddNumberToObject(counts, "zero", (double)info->zero);

    cJSON *vals = cJSON_AddArrayToObject(root, "values");
    for (int c = 0; c < s->channels; c++) {
        cJSON *v = cJSON_CreateObject();
        cJSON_AddStringToObject(v, "channel", s->channel_names[c]);
        cJSON_AddNumberToObject(v, "min", info->value[c].lo);
        cJSON_AddNumberToObject(v, "max", info->value[c].hi);
        cJSON_AddNumberToObject(v, "mean", info->mean[c]);
        cJSON_AddItemToArray(vals, v);
    }
    char *text = cJSON_Print(root);
    puts(text);
    free(text);
    cJSON_Delete(root);
}

/* Channel names, shortened to the first three and the last when there are many; each
 * as a terminal can show it (the header of a CSV may hold anything). */
static void print_channel_names(const bf_samples *s)
{
    const int C = s->channels;
    for (int c = 0; c < C; c++) {
        if (C > 8 && c == 3) {
            printf(", ...");
            c = C - 2;
            continue;
        }
        char shown[4 * BF_ERROR_TOKEN_CHARS];
        printf("%s%s", c ? ", " : "", bf_printable(s->channel_names[c], BF_ERROR_TOKEN_CHARS, 0, shown, sizeof shown));
    }
}

static void print_text(const char *path, const bf_samples *s, const asked *o, const bf_load_report *r,
                       const bf_samples_info *info)
{
    printf("%s: %zu samples read, %zu used\n", path, r->read, info->n);
    printf("channels: %d (", s->channels);
    print_channel_names(s);
    printf(")");
    if (s->wavelength) {
        double lo = s->wavelength[0], hi = lo;
        for (int c = 1; c < s->channels; c++) {
            lo = s->wavelength[c] < lo ? s->wavelength[c] : lo;
            hi = s->wavelength[c] > hi ? s->wavelength[c] : hi;
        }
        printf(", %g-%g nm", lo, hi);
    }
    printf("; %s\n", info->weighted ? "weighted per sample" : "unweighted");

    const char *done = !strcmp(o->negative, "drop")    ? "dropped"
                       : !strcmp(o->negative, "clamp") ? "clamped to 0"
                                                       : "kept";
    printf("preprocessing: dropped %zu below the horizon, %zu with NaN or Inf, %zu above max theta, %zu by "
           "subsampling; %zu with negative values %s\n",
           r->below_horizon, r->nonfinite, r->above_max_theta, r->subsampled_out, r->negative, done);
    if (r->scene)
        printf("scene %s: kept %zu of %zu samples (those its lights and views use)\n", o->scene, r->scene_kept,
               r->scene_in);
    if (strcmp(o->subsample, "all") && r->subsampled_out == 0)
        printf("subsample %s: all %zu samples kept (no more available)\n", o->subsample, info->n);

    printf("coverage (degrees, samples used):\n");
    const struct { const char *name; bf_range r; } cov[] = {
        {"theta_i", info->theta_i}, {"theta_o", info->theta_o},
        {"theta_h", info->theta_h}, {"theta_d", info->theta_d}};
    for (int k = 0; k < 4; k++)
        printf("  %-8s %11.6g .. %.6g\n", cov[k].name, cov[k].r.lo, cov[k].r.hi);

    printf("values (samples used): %zu with a zero, %zu with a negative value\n", info->zero, info->negative);
    printf("  %-12s %13s %13s %13s\n", "channel", "min", "max", "mean");
    for (int c = 0; c < s->channels; c++) {
        char shown[4 * BF_ERROR_TOKEN_CHARS];
        printf("  %-12s %13.6g %13.6g %13.6g\n",
               bf_printable(s->channel_names[c], BF_ERROR_TOKEN_CHARS, 0, shown, sizeof shown), info->value[c].lo,
               info->value[c].hi, info->mean[c]);
    }
}

/* What the command line asked for. */
typedef struct info_args {
    bf_options *o;
    const char *path;
    int json;
} info_args;

static const cli_option own[] = {
    {"--json", 0, NULL, "the same as JSON", NULL, CLI_SETS(info_args, json, 1)},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group, &data_options_reading, &data_options_preprocessing};
const cli_command cli_info = {
    "brdfit", "info", "DATA [data options] [--json]", "describe what a data file holds",
    "Format, samples, channels, angle ranges, values and weights of DATA (- for standard input) after the data "
    "options: what a fit of it would see.",
    "file", groups, sizeof groups / sizeof groups[0],
};

/* Loads the data and prints what it holds: the exit status. */
static int describe(const info_args *a)
{
    const char *path = a->path;
    if (!path) {
        fprintf(stderr, "%s: no data file (usage: brdfit info DATA [data options] [--json])\n", cmd);
        return 2;
    }
    bf_load_report report;
    bf_samples *s = data_options_load(a->o, path, &report, NULL, cmd);
    if (!s)
        return 1;
    asked o;
    bf_options_get(a->o, "negative", o.negative, sizeof o.negative, NULL);
    bf_options_get(a->o, "scene", o.scene, sizeof o.scene, NULL);
    bf_options_get(a->o, "subsample", o.subsample, sizeof o.subsample, NULL);
    bf_samples_info info;
    bf_samples_info_init(&info);
    bf_error err;
    if (bf_samples_describe(s, &info, &err) != BF_OK) {
        fprintf(stderr, "%s: %s: %s\n", cmd, path, err.msg);
        bf_samples_free(s);
        return 1;
    }
    if (a->json)
        print_json(path, s, &o, &report, &info);
    else
        print_text(path, s, &o, &report, &info);
    bf_samples_info_clear(&info);
    bf_samples_free(s);
    return 0;
}

/* The operand: the one data file. */
static int take_path(void *ctx, const char *v, const char *c)
{
    info_args *a = ctx;
    if (a->path) {
        fprintf(stderr, "%s: one data file at a time ('%s' and '%s')\n", c, a->path, v);
        return -1;
    }
    a->path = v;
    return 0;
}

int cmd_info(int argc, char **argv)
{
    info_args a;
    memset(&a, 0, sizeof a);
    if (!(a.o = cmd_options_new(BF_TASK_READ, cmd)))
        return 1;
    cli_args args;
    int p = cli_parse(&cli_info, argc, argv, &args);
    if (p != CLI_OK) {
        bf_options_free(a.o);
        return p == CLI_EXIT ? 0 : 2;
    }
    void *const targets[] = {&a, &a.o, &a.o};
    int bad = cli_take(&cli_info, targets, CLI_COUNT(targets), &args, take_path, &a, cmd);
    cli_args_free(&args);
    int status = bad ? 2 : describe(&a);
    bf_options_free(a.o);
    return status;
}
