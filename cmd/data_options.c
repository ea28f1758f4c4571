/* Parsing of the shared data options, and reading + preprocessing in one call. */
#include "data_options.h"

#include "args.h"

#include "brdfit/scene.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char data_options_usage[] =
    "reading:\n"
    "  --format csv|merl|cornell|alta   file format (default: by extension, then content)\n"
    "  --angles TI,PI,TO,PO             CSV angle column names (default theta_i,phi_i,theta_o,phi_o)\n"
    "  --radians                        CSV angles are in radians (default degrees)\n"
    "  --values COL,...                 CSV value columns (default: all but angles and weight)\n"
    "  --weight COL                     CSV weight column (default: 'weight' if present)\n"
    "preprocessing:\n"
    "  --channels NAME|INDEX,...        keep these channels, in this order\n"
    "  --rgb | --luminance              spectral to three bands / to one channel\n"
    "  --max-theta DEG                  drop samples with theta_i or theta_o above DEG\n"
    "  --negative keep|drop|clamp       negative values (default keep: they are data)\n"
    "  --subsample N|all [--seed K]     seeded stratified subsample to N samples (all: every one)\n"
    "  --scene FILE                     keep and weight the samples a scene's lights and views\n"
    "                                   use (JSON; README \"Scenes\"); error is reported over them\n";

int data_options_parse(data_options *o, int argc, char **argv, int *i, const char *cmd)
{
    const char *a = argv[*i];
    static const char *const with_value[] = {"--format", "--angles", "--values", "--weight", "--channels",
                                             "--max-theta", "--negative", "--subsample", "--seed",
                                             "--scene"};
    int needs = 0;
    for (size_t k = 0; k < sizeof with_value / sizeof with_value[0]; k++)
        needs |= strcmp(a, with_value[k]) == 0;
    if (!strcmp(a, "--radians")) {
        o->read.csv.radians = 1;
        return 1;
    }
    if (!strcmp(a, "--rgb") || !strcmp(a, "--luminance")) {
        *(a[2] == 'r' ? &o->prep.to_rgb : &o->prep.to_luminance) = 1;
        if (o->prep.to_rgb && o->prep.to_luminance) {
            fprintf(stderr, "%s: --rgb and --luminance exclude each other\n", cmd);
            return -1;
        }
        return 1;
    }
    if (!needs)
        return 0;
    if (*i + 1 >= argc) {
        fprintf(stderr, "%s: %s needs a value\n", cmd, a);
        return -1;
    }
    const char *v = argv[++*i];
    double d;
    if (!strcmp(a, "--format")) {
        int f = bf_format_from_name(v);
        if (f < 0) {
            fprintf(stderr, "%s: unknown format '%s' (csv, merl, cornell, alta)\n", cmd, v);
            return -1;
        }
        o->read.format = (bf_format)f;
    } else if (!strcmp(a, "--angles")) {
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
    } else if (!strcmp(a, "--values")) {
        o->read.csv.channels = v;
    } else if (!strcmp(a, "--weight")) {
        o->read.csv.weight_col = v;
    } else if (!strcmp(a, "--scene")) {
        o->scene = v;
    } else if (!strcmp(a, "--channels")) {
        o->prep.channels = v;
    } else if (!strcmp(a, "--max-theta")) {
        if (!args_number(v, 0.0, 90.0, &d) || !(d > 0.0)) {
            fprintf(stderr, "%s: --max-theta needs degrees in (0, 90], got '%s'\n", cmd, v);
            return -1;
        }
        o->prep.max_theta = d;
    } else if (!strcmp(a, "--negative")) {
        if (!strcmp(v, "keep"))
            o->prep.negative = BF_NEGATIVE_KEEP;
        else if (!strcmp(v, "drop"))
            o->prep.negative = BF_NEGATIVE_DROP;
        else if (!strcmp(v, "clamp"))
            o->prep.negative = BF_NEGATIVE_CLAMP;
        else {
            fprintf(stderr, "%s: --negative takes keep, drop or clamp, got '%s'\n", cmd, v);
            return -1;
        }
    } else if (!strcmp(a, "--seed")) { /* any unsigned 64-bit integer, digits only */
        char *end;
        errno = 0;
        unsigned long long n = isdigit((unsigned char)*v) ? strtoull(v, &end, 10) : 0;
        if (!isdigit((unsigned char)*v) || *end || errno) {
            fprintf(stderr, "%s: --seed needs an integer from 0 to 18446744073709551615, got '%s'\n", cmd, v);
            return -1;
        }
        o->prep.seed = (uint64_t)n;
    } else { /* --subsample: a count, or "all" (over a preset's); 0 is not a count */
        long n = 0;
        if (strcmp(v, "all") && !args_int(v, 1, 1000000000000L, &n)) {
            fprintf(stderr, "%s: --subsample needs a sample count of at least 1 or 'all', got '%s'\n", cmd, v);
            return -1;
        }
        o->prep.subsample = (size_t)n; /* 0: every sample */
        o->subsample_given = 1;
    }
    return 1;
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
    return s;
}
