/* Parsing of the shared data options, and reading + preprocessing in one call. */
#include "data_options.h"

#include "args.h"

#include "brdfit/formats.h"
#include "brdfit/scene.h"

#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* What spectral data becomes: --rgb, --color, --rgb-bands and --luminance each choose
 * it, so two of them exclude each other (--rgb with --color srgb repeats one choice). */
static int set_spectral(data_options *o, const char *opt, bf_color color, int *reduction, const char *cmd)
{
    const char *prev = o->spectral_opt;
    int same = prev && color != BF_COLOR_NONE && o->prep.color == color;
    if (prev && strcmp(prev, opt) && !same) {
        fprintf(stderr, "%s: %s and %s exclude each other\n", cmd, prev, opt);
        return -1;
    }
    o->spectral_opt = opt;
    if (color != BF_COLOR_NONE)
        o->prep.color = color;
    else
        *reduction = 1;
    return 0;
}

static int take_rgb(void *o, const cli_option *opt, const char *v, const char *cmd)
{
    (void)v;
    return set_spectral(o, opt->name, BF_COLOR_SRGB, NULL, cmd);
}

static int take_bands(void *target, const cli_option *opt, const char *v, const char *cmd)
{
    data_options *o = target;
    (void)v;
    return set_spectral(o, opt->name, BF_COLOR_NONE, &o->prep.to_bands, cmd);
}

static int take_luminance(void *target, const cli_option *opt, const char *v, const char *cmd)
{
    data_options *o = target;
    (void)v;
    return set_spectral(o, opt->name, BF_COLOR_NONE, &o->prep.to_luminance, cmd);
}

static int take_color(void *o, const cli_option *opt, const char *v, const char *cmd)
{
    int k = bf_color_from_name(v);
    if (k < 0) {
        fprintf(stderr, "%s: %s takes srgb, acescg or xyz, got '%s'\n", cmd, opt->name, v);
        return -1;
    }
    return set_spectral(o, opt->name, (bf_color)k, NULL, cmd);
}

static int take_illuminant(void *target, const cli_option *opt, const char *v, const char *cmd)
{
    int k = bf_illuminant_from_name(v);
    if (k < 0) {
        fprintf(stderr, "%s: %s takes d65, e, a or d50, got '%s'\n", cmd, opt->name, v);
        return -1;
    }
    ((data_options *)target)->prep.illuminant = (bf_illuminant)k;
    return 0;
}

static int take_format(void *target, const cli_option *opt, const char *v, const char *cmd)
{
    (void)opt;
    int f = bf_format_from_name(v);
    if (f < 0) {
        fprintf(stderr, "%s: unknown format '%s' (csv, merl, cornell, alta, rgl, mbsdf)\n", cmd, v);
        return -1;
    }
    ((data_options *)target)->read.format = (bf_format)f;
    return 0;
}

static int take_negative(void *target, const cli_option *opt, const char *v, const char *cmd)
{
    static const char *const names[] = {"keep", "drop", "clamp"};
    static const bf_negative modes[] = {BF_NEGATIVE_KEEP, BF_NEGATIVE_DROP, BF_NEGATIVE_CLAMP};
    (void)opt;
    for (int k = 0; k < 3; k++)
        if (!strcmp(v, names[k])) {
            ((data_options *)target)->prep.negative = modes[k];
            return 0;
        }
    fprintf(stderr, "%s: --negative takes keep, drop or clamp, got '%s'\n", cmd, v);
    return -1;
}

/* --angles TI,PI,TO,PO: four names, kept in o->angles_buf. */
static int take_angles(void *target, const cli_option *opt, const char *v, const char *cmd)
{
    data_options *o = target;
    (void)opt;
    snprintf(o->angles_buf, sizeof o->angles_buf, "%s", v);
    char *p = o->angles_buf;
    for (int k = 0; k < 4; k++) {
        char *comma = strchr(p, ',');
        if ((k < 3) != (comma != NULL) || p == comma || !*p) {
            fprintf(stderr, "%s: --angles needs four comma-separated column names, got '%s'\n", cmd, v);
            return -1;
        }
        o->read.csv.angle_cols[k] = p;
        if (comma) {
            *comma = '\0';
            p = comma + 1;
        }
    }
    return 0;
}

/* --seed: any unsigned 64-bit integer, digits only. */
static int take_seed(void *target, const cli_option *opt, const char *v, const char *cmd)
{
    char *end;
    (void)opt;
    errno = 0;
    unsigned long long n = isdigit((unsigned char)*v) ? strtoull(v, &end, 10) : 0;
    if (!isdigit((unsigned char)*v) || *end || errno) {
        fprintf(stderr, "%s: --seed needs an integer from 0 to 18446744073709551615, got '%s'\n", cmd, v);
        return -1;
    }
    ((data_options *)target)->prep.seed = (uint64_t)n;
    return 0;
}

/* --subsample: a count, or "all" (over a preset's); 0 is not a count. */
static int take_subsample(void *target, const cli_option *opt, const char *v, const char *cmd)
{
    data_options *o = target;
    long n = 0;
    (void)opt;
    if (strcmp(v, "all") && !args_int(v, 1, 1000000000000L, &n)) {
        fprintf(stderr, "%s: --subsample needs a sample count of at least 1 or 'all', got '%s'\n", cmd, v);
        return -1;
    }
    o->prep.subsample = (size_t)n; /* 0: every sample */
    o->subsample_given = 1;
    return 0;
}

/* The names (--values, --weight, --grid, --channels, --scene) are kept as given and
 * checked when the data is read. */
static const cli_option reading[] = {
    {"--format", 0, "csv|merl|cornell|alta|rgl|mbsdf", "file format (default: by extension, then content)", NULL,
     CLI_CALLS(take_format)},
    {"--grid", 0, "merl|uniform:N|FILE", "evaluate an RGL .bsdf or .mbsdf file at these directions\n"
                                         "instead of its measured points (docs/formats.md)", NULL,
     CLI_STRING_AT(data_options, read.grid)},
    {"--angles", 0, "TI,PI,TO,PO", "CSV angle column names (default theta_i,phi_i,theta_o,phi_o)", NULL,
     CLI_CALLS(take_angles)},
    {"--radians", 0, NULL, "CSV angles are in radians (default degrees)", NULL,
     CLI_SETS(data_options, read.csv.radians, 1)},
    {"--values", 0, "COL,...", "CSV value columns (default: all but angles and weight)", NULL,
     CLI_STRING_AT(data_options, read.csv.channels)},
    {"--weight", 0, "COL", "CSV weight column (default: 'weight' if present)", NULL,
     CLI_STRING_AT(data_options, read.csv.weight_col)},
};
static const cli_option preprocessing[] = {
    {"--channels", 0, "NAME|INDEX,...", "keep these channels, in this order", NULL,
     CLI_STRING_AT(data_options, prep.channels)},
    {"--rgb", 0, NULL, "spectral data to linear sRGB (CIE 1931 2 deg, D65; --color srgb)", NULL, CLI_CALLS(take_rgb)},
    {"--color", 0, "srgb|acescg|xyz", "spectral data to this colour space (docs/colour.md)", NULL,
     CLI_CALLS(take_color)},
    {"--illuminant", 0, "d65|e|a|d50", "illuminant of --color/--rgb, or of --luminance on spectra (default d65)", NULL,
     CLI_CALLS(take_illuminant)},
    {"--rgb-bands", 0, NULL, "spectral data to three band means (600-700, 500-600,\n"
                             "400-500 nm; not colorimetric: the old --rgb)", NULL, CLI_CALLS(take_bands)},
    {"--luminance", 0, NULL, "spectral (CIE Y) or RGB (Rec. 709) data to one channel", NULL,
     CLI_CALLS(take_luminance)},
    {"--max-theta", 0, "DEG", "drop samples with theta_i or theta_o above DEG", NULL,
     CLI_NUMBER_AT(data_options, prep.max_theta, DBL_TRUE_MIN, 90.0, "degrees in (0, 90]")},
    {"--negative", 0, "keep|drop|clamp", "negative values (default keep: they are data)", NULL,
     CLI_CALLS(take_negative)},
    {"--subsample", 0, "N|all", "seeded stratified subsample to N samples (all: every one)", NULL,
     CLI_CALLS(take_subsample)},
    {"--seed", 0, "K", "seeds the subsample, the multistart and anything else random (default 0)", NULL,
     CLI_CALLS(take_seed)},
    {"--scene", 0, "FILE", "keep and weight the samples a scene's lights and views use\n"
                           "(JSON; README \"Scenes\"); error is reported over them", "file",
     CLI_STRING_AT(data_options, scene)},
};
const cli_group data_options_reading = CLI_GROUP("reading", reading);
const cli_group data_options_preprocessing = CLI_GROUP("preprocessing", preprocessing);

int data_options_take_file(const char **data, const char *v, const char *cmd)
{
    if (*data) {
        fprintf(stderr, "%s: one data file only, got '%s' and '%s'\n", cmd, *data, v);
        return -1;
    }
    *data = v;
    return 0;
}

int data_options_has_scene(const data_options *o)
{
    return o->scene != NULL;
}

/* The scene goes between preprocessing's drops and its subsampling: prep without the
 * subsample, the scene, then prep again with only the subsample (nothing else is left to
 * drop), so that --subsample N means N samples inside the scene. */
static int apply_scene(const data_options *o, bf_samples *s, bf_prep_report *report, data_scene_report *sr,
                       const char *path, const char *cmd)
{
    bf_error err;
    bf_scene *sc = NULL;
    if (bf_scene_read(o->scene, &sc, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return -1;
    }
    sr->in = s->n;
    int rc = bf_scene_apply(sc, s, &sr->kept, &err);
    bf_scene_free(sc);
    if (rc != BF_OK) {
        fprintf(stderr, "%s: %s: scene %s: %s\n", cmd, path, o->scene, err.msg);
        return -1;
    }
    bf_prep sub = {.subsample = o->prep.subsample, .seed = o->prep.seed};
    bf_prep_report r2;
    if (bf_samples_prep(s, &sub, &r2, &err) != BF_OK) {
        fprintf(stderr, "%s: %s: %s\n", cmd, path, err.msg);
        return -1;
    }
    report->subsampled_out = r2.subsampled_out;
    report->kept = s->n;
    return 0;
}

bf_samples *data_options_load(const data_options *o, const char *path, bf_prep_report *report,
                              const char *cmd)
{
    return data_options_load_scene(o, path, report, NULL, cmd);
}

bf_samples *data_options_load_scene(const data_options *o, const char *path, bf_prep_report *report,
                                    data_scene_report *scene, const char *cmd)
{
    bf_error err;
    bf_samples *s = NULL;
    bf_prep_report rep;
    data_scene_report sr = {0, 0};
    if (!report)
        report = &rep;
    if (scene)
        *scene = sr;
    if (bf_samples_read(path, &o->read, &s, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return NULL;
    }
    cli_note(cmd, "read %s: %zu samples x %d channels", path, s->n, s->channels);
    bf_prep p = o->prep;
    if (o->scene)
        p.subsample = 0;
    if (bf_samples_prep(s, &p, report, &err) != BF_OK) {
        fprintf(stderr, "%s: %s: %s\n", cmd, path, err.msg);
        bf_samples_free(s);
        return NULL;
    }
    if (o->scene && apply_scene(o, s, report, &sr, path, cmd) != 0) {
        bf_samples_free(s);
        return NULL;
    }
    if (scene)
        *scene = sr;
    if (report->kept != report->read)
        cli_note(cmd, "%s: %zu samples after preprocessing%s", path, report->kept, o->scene ? " and the scene" : "");
    return s;
}

void data_options_load_reason(const data_options *o, const char *path, char *msg, size_t size)
{
    bf_samples *s = NULL;
    bf_error e;
    if (bf_samples_read(path, &o->read, &s, &e) != BF_OK)
        snprintf(msg, size, "%s", e.msg);
    else if (bf_samples_prep(s, &o->prep, NULL, &e) != BF_OK)
        snprintf(msg, size, "%s: %s", path, e.msg);
    else {
        bf_scene *sc = NULL;
        if (o->scene && (bf_scene_read(o->scene, &sc, &e) != BF_OK || bf_scene_apply(sc, s, NULL, &e) != BF_OK))
            snprintf(msg, size, "%s: --scene %s: %s", path, o->scene, e.msg);
        else
            snprintf(msg, size, "%s: could not be loaded", path);
        bf_scene_free(sc);
    }
    bf_samples_free(s);
}
