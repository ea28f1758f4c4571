/* brdfit export RESULT.json --to gltf|blender|mitsuba [-o OUT] [--convert]: a fitted material as
 * a renderer's file. A result in the target's native model (gltf, blender_principled)
 * maps exactly; any other is converted by fitting the native model to the source
 * model's values over a dense grid of directions, and the conversion's error is reported
 * and written into the file. The writers are export_gltf.c, export_blender.c and
 * export_mitsuba.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/fit.h"
#include "brdfit/io.h"
#include "brdfit/model.h"
#include "brdfit/samples.h"
#include "args.h"
#include "cli.h"
#include "commands.h"
#include "export.h"

static const cli_option own[] = {
    {"--to", 0, "gltf|blender|mitsuba",
     "the renderer: glTF 2.0 (.gltf with a sphere), Blender 3.4 (a Python script) or\nMitsuba 3 (scene XML)",
     NULL},
    {"--output", 'o', "FILE", "the file (default and -: standard output)", "file"},
    {"--convert", 0, NULL, "convert an anisotropic or multi-lobe source too (the target holds one isotropic\n"
                           "lobe: the conversion error says what is lost)", NULL},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group};
const cli_command cli_export = {
    "brdfit", "export", "RESULT.json --to gltf|blender|mitsuba [-o OUT] [--convert]", "write a fitted material for a renderer",
    "A result whose model is the target's own (gltf for glTF, blender_principled for Blender, mitsuba_principled for Mitsuba) is written exactly. "
    "Any other model is converted: the target's model is fitted to the source's values at 11664 direction pairs "
    "(theta 2.5..87.5 by 5 degrees, phi_o 0..350 by 10; phi_i 0..150 by 30 for an anisotropic source), and the "
    "conversion's metrics go to standard error and into the file (glTF asset.extras.brdfit, a comment in the "
    "script or the XML). Colours need 1 or 3 channels. Parameter conventions: docs/export.md.",
    "file", groups, sizeof groups / sizeof groups[0],
};

typedef struct target {
    const char *name;  /* --to */
    const char *model; /* the native model family */
} target;

static const target targets[] = {{"gltf", "gltf"}, {"blender", "blender_principled"}, {"mitsuba", "mitsuba_principled"}};

double export_param(const export_material *e, const char *name, int c)
{
    int i = bf_model_find_param(e->m, name);
    const bf_param_info *p = bf_model_param(e->m, i);
    int off = bf_model_param_offset(e->m, i);
    return p->colour && bf_model_channels(e->m) > 1 ? e->x[off + c] : e->x[off];
}

void export_conversion_note(const export_material *e, FILE *fp)
{
    fprintf(fp, "conversion over %zu direction pairs: rmse %.6g, rmse_cos %.6g, rmse_log %.6g, rmse_rel %.6g, "
                "max_err %.6g (1/sr)",
            e->directions, e->metrics.rmse, e->metrics.rmse_cos, e->metrics.rmse_log, e->metrics.rmse_rel,
            e->metrics.max_err);
}

/* Takes the parsed command line: 0, or 2 after a one-line error. */
static int take_args(const cli_args *args, const char **in, const target **to, const char **out, int *convert)
{
    const char *to_name = NULL;
    for (int i = 0; i < args->n; i++) {
        const char *a = args->v[i].name, *v = args->v[i].value;
        if (!a) {
            if (*in) {
                fprintf(stderr, "brdfit export: one result file, not '%s' too (see brdfit export --help)\n", v);
                return 2;
            }
            *in = v;
        } else if (!strcmp(a, "--to")) {
            to_name = v;
        } else if (!strcmp(a, "--output")) {
            *out = v;
        } else if (!strcmp(a, "--convert")) {
            *convert = 1;
        }
    }
    if (!*in || !to_name) {
        fprintf(stderr, "brdfit export: a result file and --to are required (see brdfit export --help)\n");
        return 2;
    }
    for (size_t k = 0; k < sizeof targets / sizeof targets[0]; k++)
        if (!strcmp(to_name, targets[k].name))
            *to = &targets[k];
    if (!*to) {
        fprintf(stderr, "brdfit export: --to '%s': not a target (gltf, blender, mitsuba)\n", to_name);
        return 2;
    }
    return 0;
}

static const bf_family_info *family_of(const bf_model *m)
{
    for (int i = 0; i < bf_family_count(); i++)
        if (!strcmp(bf_family_get(i)->name, bf_model_name(m)))
            return bf_family_get(i);
    return NULL;
}

/* The grid the conversion fits on, with the source's values: NULL after a one-line
 * error. Isotropic sources need only phi_i = 0. */
static bf_samples *source_samples(const bf_model *src, const double *xs, int aniso)
{
    enum { NT = 18, NPO = 36 };
    const int npi = aniso ? 6 : 1;
    size_t n = (size_t)NT * NT * NPO * (size_t)npi, i = 0;
    bf_samples *s = NULL;
    bf_error err;
    const bf_geometry *g = NULL;
    if (bf_samples_new(n, bf_model_channels(src), &s, &err) != BF_OK) {
        fprintf(stderr, "brdfit export: %s\n", err.msg);
        return NULL;
    }
    for (int a = 0; a < npi; a++)
        for (int ti = 0; ti < NT; ti++)
            for (int to = 0; to < NT; to++)
                for (int po = 0; po < NPO; po++, i++) {
                    s->theta_i[i] = 2.5 + 5.0 * ti;
                    s->phi_i[i] = 30.0 * a;
                    s->theta_o[i] = 2.5 + 5.0 * to;
                    s->phi_o[i] = 10.0 * po;
                }
    if (bf_samples_geometry(s, &g, &err) != BF_OK) {
        fprintf(stderr, "brdfit export: %s\n", err.msg);
        bf_samples_free(s);
        return NULL;
    }
    bf_model_eval(src, xs, g, s->value, NULL);
    return s;
}

/* Fits the target's model to the source's values: 0 with r filled (r->ok), or -1 after a
 * one-line error. */
static int convert(const bf_model *src, const double *xs, const char *model, int aniso, export_material *e,
                   bf_fit_result *r)
{
    bf_samples *s = source_samples(src, xs, aniso);
    if (!s)
        return -1;
    bf_fit_options o;
    bf_fit_options_init(&o);
    o.starts = 4; /* the native models have several basins (metallic against specular) */
    bf_error err;
    int rc = bf_fit(s, model, &o, r, &err);
    e->directions = s->n;
    bf_samples_free(s);
    if (rc != BF_OK || !r->ok) {
        fprintf(stderr, "brdfit export: converting %s to %s: %s\n", bf_model_spec(src), model,
                rc != BF_OK ? err.msg : "the fit found no usable solution");
        return -1;
    }
    e->m = r->model;
    e->x = r->x;
    e->converted = 1;
    e->metrics = r->metrics;
    fprintf(stderr, "brdfit export: converted %s to %s, ", bf_model_spec(src), model);
    export_conversion_note(e, stderr);
    fputc('\n', stderr);
    return 0;
}

/* The file to out_path: 0, or -1 after a one-line error (nothing left behind). */
static int write_file(const target *to, const export_material *e, const char *out_path)
{
    bf_error err;
    bf_outfile out;
    if (bf_outfile_open(&out, out_path, &err) != BF_OK) {
        fprintf(stderr, "brdfit export: %s\n", err.msg);
        return -1;
    }
    if (!strcmp(to->name, "gltf")) {
        if (export_write_gltf(e, out.fp) < 0) {
            bf_outfile_abort(&out);
            fprintf(stderr, "brdfit export: out of memory for the glTF document\n");
            return -1;
        }
    } else if (!strcmp(to->name, "blender")) {
        export_write_blender(e, out.fp);
    } else {
        export_write_mitsuba(e, out.fp);
    }
    if (bf_outfile_commit(&out, &err) != BF_OK) {
        fprintf(stderr, "brdfit export: %s\n", err.msg);
        return -1;
    }
    return 0;
}

int cmd_export(int argc, char **argv)
{
    const char *in = NULL, *out_path = NULL;
    const target *to = NULL;
    int want_convert = 0;
    cli_args args;
    int p = cli_parse(&cli_export, argc, argv, &args);
    if (p != CLI_OK)
        return p == CLI_EXIT ? 0 : 2;
    int bad = take_args(&args, &in, &to, &out_path, &want_convert);
    cli_args_free(&args);
    if (bad)
        return bad;
    const bf_path_use ins[] = {{"result file", in}}, outs[] = {{"-o", out_path}};
    if ((bad = args_check_outputs("brdfit export", ins, 1, outs, 1)) != 0)
        return bad;

    bf_error err;
    bf_model *src = NULL;
    double *xs = NULL;
    bf_fit_result r;
    memset(&r, 0, sizeof r);
    int status = 1;
    if (bf_params_read(in, &src, &xs, &err) != BF_OK) {
        fprintf(stderr, "brdfit export: %s\n", err.msg);
        goto done;
    }
    int C = bf_model_channels(src);
    if (C != 1 && C != 3) {
        fprintf(stderr, "brdfit export: %s: %d channels; a renderer's colour needs 1 (grey) or 3 (RGB)\n", in, C);
        goto done;
    }
    export_material e = {.m = src, .x = xs, .source = bf_model_spec(src)};
    if (strcmp(bf_model_name(src), to->model) != 0) {
        const bf_family_info *fi = family_of(src);
        int aniso = fi && fi->anisotropic, multi = bf_model_lobes(src) > 1;
        if ((aniso || multi) && !want_convert) {
            fprintf(stderr, "brdfit export: %s: %s is %s; %s holds one isotropic lobe (--convert fits it anyway)\n",
                    in, bf_model_spec(src), aniso ? "anisotropic" : "multi-lobe", to->model);
            goto done;
        }
        if (convert(src, xs, to->model, aniso, &e, &r) < 0)
            goto done;
    }
    if (write_file(to, &e, out_path) == 0)
        status = 0;
done:
    bf_fit_result_clear(&r);
    bf_model_free(src);
    free(xs);
    return status;
}
