/* What `brdfit info` reports about a data set once loaded (brdfit/load.h): the JSON and
 * the text, made here once so that the command and every front end print the same. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/sized.h"
#include "brdfit/load.h"
#include "brdfit/prep.h"

/* What the options said, as the report names it. */
typedef struct asked {
    char negative[16], scene[4096], subsample[32];
} asked;

static bf_status read_asked(const bf_options *o, asked *a, bf_error *err)
{
    bf_options *own = NULL;
    bf_status rc = BF_OK;
    if (!o) { /* no options: the defaults */
        if ((rc = bf_options_new(BF_TASK_READ, &own, err)) != BF_OK)
            return rc;
        o = own;
    }
    if ((rc = bf_options_get(o, "negative", a->negative, sizeof a->negative, err)) == BF_OK &&
        (rc = bf_options_get(o, "scene", a->scene, sizeof a->scene, err)) == BF_OK)
        rc = bf_options_get(o, "subsample", a->subsample, sizeof a->subsample, err);
    bf_options_free(own);
    return rc;
}

/* The description, the options' values, and the arguments checked: what both forms need. */
static bf_status gather(bf_samples *s, const bf_load_report *r, const bf_options *o, const char *path, asked *a,
                        bf_samples_info *info, bf_error *err)
{
    if (!s || !r || !path)
        return bf_fail(err, BF_ERR_ARG, "data report: no samples, load report or file name");
    if (bf_sized_check(r, sizeof *r, "bf_load_report", err) != BF_OK)
        return BF_ERR_ARG;
    bf_status rc = read_asked(o, a, err);
    if (rc != BF_OK)
        return rc;
    bf_samples_info_init(info);
    bf_error e;
    if ((rc = bf_samples_describe(s, info, &e)) != BF_OK) {
        bf_samples_info_clear(info);
        return bf_fail(err, rc, "%s: %s", path, e.msg);
    }
    return BF_OK;
}

static cJSON *range_json(bf_range r)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "min", r.lo); /* cJSON writes NaN (nothing covered) as null */
    cJSON_AddNumberToObject(o, "max", r.hi);
    return o;
}

static cJSON *report_json(const char *path, const bf_samples *s, const asked *o, const bf_load_report *r,
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
    return root;
}

bf_status bf_samples_info_json(bf_samples *s, const bf_load_report *report, const bf_options *o, const char *path,
                               char **out, bf_error *err)
{
    *out = NULL;
    asked a;
    bf_samples_info info;
    bf_status rc = gather(s, report, o, path, &a, &info, err);
    if (rc != BF_OK)
        return rc;
    cJSON *root = report_json(path, s, &a, report, &info);
    char *text = root ? cJSON_Print(root) : NULL;
    cJSON_Delete(root);
    bf_samples_info_clear(&info);
    size_t n = text ? strlen(text) : 0;
    char *line = text ? malloc(n + 2) : NULL; /* with the final newline the command prints */
    if (!line) {
        free(text);
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory for the report", path);
    }
    memcpy(line, text, n);
    line[n] = '\n';
    line[n + 1] = '\0';
    free(text);
    *out = line;
    return BF_OK;
}

/* Channel names, shortened to the first three and the last when there are many; each
 * as a terminal can show it (the header of a CSV may hold anything). */
static void put_channel_names(FILE *fp, const bf_samples *s)
{
    const int C = s->channels;
    for (int c = 0; c < C; c++) {
        if (C > 8 && c == 3) {
            fprintf(fp, ", ...");
            c = C - 2;
            continue;
        }
        char shown[4 * BF_ERROR_TOKEN_CHARS];
        fprintf(fp, "%s%s", c ? ", " : "",
                bf_printable(s->channel_names[c], BF_ERROR_TOKEN_CHARS, 0, shown, sizeof shown));
    }
}

/* What the option negative did to the samples with a negative value, in words. */
static const char *negative_done(const char *action)
{
    return !strcmp(action, "drop") ? "dropped" : !strcmp(action, "clamp") ? "clamped to 0" : "kept";
}

static void put_text(FILE *fp, const char *path, const bf_samples *s, const asked *o, const bf_load_report *r,
                     const bf_samples_info *info)
{
    fprintf(fp, "%s: %zu samples read, %zu used\n", path, r->read, info->n);
    fprintf(fp, "channels: %d (", s->channels);
    put_channel_names(fp, s);
    fprintf(fp, ")");
    if (s->wavelength) {
        double lo = s->wavelength[0], hi = lo;
        for (int c = 1; c < s->channels; c++) {
            lo = s->wavelength[c] < lo ? s->wavelength[c] : lo;
            hi = s->wavelength[c] > hi ? s->wavelength[c] : hi;
        }
        fprintf(fp, ", %g-%g nm", lo, hi);
    }
    fprintf(fp, "; %s\n", info->weighted ? "weighted per sample" : "unweighted");

    fprintf(fp,
            "preprocessing: dropped %zu below the horizon, %zu with NaN or Inf, %zu above max theta, %zu by "
            "subsampling; %zu with negative values %s\n",
            r->below_horizon, r->nonfinite, r->above_max_theta, r->subsampled_out, r->negative,
            negative_done(o->negative));
    if (r->scene)
        fprintf(fp, "scene %s: kept %zu of %zu samples (those its lights and views use)\n", o->scene, r->scene_kept,
                r->scene_in);
    if (strcmp(o->subsample, "all") && r->subsampled_out == 0)
        fprintf(fp, "subsample %s: all %zu samples kept (no more available)\n", o->subsample, info->n);

    fprintf(fp, "coverage (degrees, samples used):\n");
    const struct {
        const char *name;
        bf_range r;
    } cov[] = {
        {"theta_i", info->theta_i}, {"theta_o", info->theta_o}, {"theta_h", info->theta_h}, {"theta_d", info->theta_d}};
    for (int k = 0; k < 4; k++)
        fprintf(fp, "  %-8s %11.6g .. %.6g\n", cov[k].name, cov[k].r.lo, cov[k].r.hi);

    fprintf(fp, "values (samples used): %zu with a zero, %zu with a negative value\n", info->zero, info->negative);
    fprintf(fp, "  %-12s %13s %13s %13s\n", "channel", "min", "max", "mean");
    for (int c = 0; c < s->channels; c++) {
        char shown[4 * BF_ERROR_TOKEN_CHARS];
        fprintf(fp, "  %-12s %13.6g %13.6g %13.6g\n",
                bf_printable(s->channel_names[c], BF_ERROR_TOKEN_CHARS, 0, shown, sizeof shown), info->value[c].lo,
                info->value[c].hi, info->mean[c]);
    }
}

bf_status bf_samples_info_text(bf_samples *s, const bf_load_report *report, const bf_options *o, const char *path,
                               char **out, bf_error *err)
{
    *out = NULL;
    asked a;
    bf_samples_info info;
    bf_status rc = gather(s, report, o, path, &a, &info, err);
    if (rc != BF_OK)
        return rc;
    char *text = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&text, &len);
    if (fp) {
        put_text(fp, path, s, &a, report, &info);
        if (fclose(fp) != 0) {
            free(text);
            text = NULL;
        }
    }
    bf_samples_info_clear(&info);
    if (!text)
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory for the report", path);
    *out = text;
    return BF_OK;
}
