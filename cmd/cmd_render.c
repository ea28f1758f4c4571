/* brdfit render: pictures of a model (or a MERL table) as PNG or EXR; slice plots as
 * PNG, SVG or PDF.
 *   sphere (default)  --params P.json [--light T,P ...] [--view T,P]
 *   --slice           --params P.json [--incidence A,B,...] [--data FILE [data options]] [--plane-tol D]
 *                     (without --incidence, with --data: the measured incidences nearest 0, 30, 60)
 *   --half-diff       --params P.json | --data T.binary  [--phi-d D]
 *
 * Decisions:
 *  - EXR holds linear values (f, or radiance for the sphere); PNG holds display values:
 *    --tonemap clamp (exposure * v, clipped; the sphere's default), reinhard
 *    (e/(1+e)), or log (--decades decades below the maximum; the half/difference
 *    image's default, as BRDF papers show it), then sRGB-encoded to 8 bits. Slice plots
 *    are figures (render.h: axes, ticks, legend) drawn with Cairo as PNG, SVG or PDF;
 *    EXR is for linear images only, and SVG/PDF for plots only: a --half-diff to .svg or
 *    .pdf is the figure (sqrt theta_h axis in degrees, log colour scale, colour bar).
 *  - The default light is at theta 45, phi 0 (the highlight off-centre, shading visible);
 *    the default view is straight down +z. Angles in degrees; render.h defines frames.
 *  - --size N or WxH (default 256; slice plots 640x480).
 *  - Every default, limit and check is the library's (render.h: the options' inits,
 *    BF_RENDER_MAX_*, the checks); the command adds the syntax and the messages naming
 *    its options.
 *  - Exit 2 for bad usage, 1 for bad data or an unwritable image; no partial file. */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "brdfit/formats.h"
#include "brdfit/image.h"
#include "brdfit/io.h"
#include "brdfit/render.h"
#include "args.h"
#include "cli.h"
#include "commands.h"
#include "data_options.h"

static const char cmd[] = "brdfit render";

static int parse_double(const char *s, double *out)
{
    return args_number(s, -HUGE_VAL, HUGE_VAL, out);
}

/* "T,P" in degrees. */
static int parse_dir(const char *s, bf_dir *d)
{
    char *end;
    errno = 0;
    d->theta = strtod(s, &end);
    if (end == s || *end != ',' || errno)
        return 0;
    const char *p = end + 1;
    d->phi = strtod(p, &end);
    return end != p && !*end && !errno && isfinite(d->theta) && isfinite(d->phi);
}

static int parse_size(const char *s, int *w, int *h)
{
    return args_size(s, 1, BF_RENDER_MAX_SIDE, w, h);
}

/* --to and the extensions: images are PNG or EXR, plots PNG, SVG or PDF. */
enum to_format { TO_PNG = 1, TO_EXR, TO_SVG, TO_PDF };

static int to_of(const char *path)
{
    int p = bf_plot_format_of(path);
    return bf_image_format_of(path) == BF_IMAGE_EXR ? TO_EXR
           : p == BF_PLOT_PNG                       ? TO_PNG
           : p == BF_PLOT_SVG                       ? TO_SVG
           : p == BF_PLOT_PDF                       ? TO_PDF
                                                    : 0;
}

/* What the command line asked for, over the library's defaults (the options' inits). */
typedef struct render_args {
    bf_options *o;
    const char *params, *data, *out_path;
    bf_sphere_options sphere;
    bf_slice_options slices;
    bf_halfdiff_options hd;
    bf_tonemap_options tm;
    bf_dir lights[BF_RENDER_MAX_LIGHTS + 1];     /* one more: the one the check refuses */
    int nlights, slice, halfdiff, width, height; /* width 0: the mode's default size */
    int tonemap_given;
    int to; /* --to: a to_format, or 0 */
    double incidence[BF_SLICE_MAX_INCIDENCE];
    int incidence_given;
} render_args;

/* --incidence A,B,...: at most BF_SLICE_MAX_INCIDENCE angles in [0, 90). */
static int parse_incidence(const char *v, render_args *r)
{
    char buf[512], *save = NULL;
    int ok = 1, n = 0;
    snprintf(buf, sizeof buf, "%s", v);
    for (char *t = strtok_r(buf, ",", &save); t && ok; t = strtok_r(NULL, ",", &save)) {
        double x;
        ok = n < BF_SLICE_MAX_INCIDENCE && parse_double(t, &x) && x >= 0.0 && x < 90.0;
        if (ok)
            r->incidence[n++] = x;
    }
    r->slices.incidence = r->incidence;
    r->slices.nincidence = n;
    return ok && n > 0;
}

/* A value render cannot take: the same line for every option. */
static int bad_value(const cli_option *o, const char *v, const char *c)
{
    fprintf(stderr, "%s: bad value '%s' for %s\n", c, v, o->name);
    return -1;
}

static int take_to(void *target, const cli_option *o, const char *v, const char *c)
{
    render_args *r = target;
    r->to = !strcmp(v, "png")   ? TO_PNG
            : !strcmp(v, "exr") ? TO_EXR
            : !strcmp(v, "svg") ? TO_SVG
            : !strcmp(v, "pdf") ? TO_PDF
                                : 0;
    return r->to ? 0 : bad_value(o, v, c);
}

static int take_light(void *target, const cli_option *o, const char *v, const char *c)
{
    render_args *r = target;
    if (r->nlights >= BF_RENDER_MAX_LIGHTS) { /* one too many: the library's limit, in its words */
        bf_sphere_options so = r->sphere;
        so.lights = r->lights;
        so.nlights = r->nlights + 1;
        bf_error err;
        if (bf_sphere_options_check(&so, &err) != BF_OK) {
            fprintf(stderr, "%s: %s\n", c, err.msg);
            return -1;
        }
    }
    if (!parse_dir(v, &r->lights[r->nlights]))
        return bad_value(o, v, c);
    r->sphere.lights = r->lights;
    r->sphere.nlights = ++r->nlights;
    return 0;
}

static int take_view(void *target, const cli_option *o, const char *v, const char *c)
{
    return parse_dir(v, &((render_args *)target)->sphere.view) ? 0 : bad_value(o, v, c);
}

static int take_size(void *target, const cli_option *o, const char *v, const char *c)
{
    render_args *r = target;
    return parse_size(v, &r->width, &r->height) ? 0 : bad_value(o, v, c);
}

/* --exposure and --decades: a number the display mapping takes (bf_tonemap_options_check). */
static int take_mapping(render_args *r, double *d, const cli_option *o, const char *v, const char *c)
{
    return parse_double(v, d) && bf_tonemap_options_check(&r->tm, NULL) == BF_OK ? 0 : bad_value(o, v, c);
}

static int take_exposure(void *target, const cli_option *o, const char *v, const char *c)
{
    render_args *r = target;
    return take_mapping(r, &r->tm.exposure, o, v, c);
}

static int take_decades(void *target, const cli_option *o, const char *v, const char *c)
{
    render_args *r = target;
    return take_mapping(r, &r->tm.decades, o, v, c);
}

static int take_plane_tol(void *target, const cli_option *o, const char *v, const char *c)
{
    render_args *r = target;
    return parse_double(v, &r->slices.plane_tol) && r->slices.plane_tol >= 0.0 ? 0 : bad_value(o, v, c);
}

static int take_phi_d(void *target, const cli_option *o, const char *v, const char *c)
{
    render_args *r = target;
    return parse_double(v, &r->hd.phi_d) && bf_halfdiff_options_check(&r->hd, NULL) == BF_OK ? 0 : bad_value(o, v, c);
}

static int take_tonemap(void *target, const cli_option *o, const char *v, const char *c)
{
    render_args *r = target;
    r->tonemap_given = 1;
    return bf_tonemap_parse(v, &r->tm.mode, NULL) == BF_OK ? 0 : bad_value(o, v, c);
}

static int take_incidence(void *target, const cli_option *o, const char *v, const char *c)
{
    render_args *r = target;
    r->incidence_given = 1;
    return parse_incidence(v, r) ? 0 : bad_value(o, v, c);
}

static const cli_option modes[] = {
    {"--slice", 0, NULL, "in-plane slices: f (log axis) against theta_o (-90..90, + on the mirror side)", NULL,
     CLI_SETS(render_args, slice, 1)},
    {"--half-diff", 0, NULL,
     "theta_h (x, 0..90 even in sqrt(theta_h)) by theta_d (y, 0..90 downwards)\n"
     "at a fixed phi_d; as .svg or .pdf a figure with axes and a colour bar",
     NULL, CLI_SETS(render_args, halfdiff, 1)},
};
static const cli_option own[] = {
    {"--params", 0, "FILE", "the model and its parameters (a brdfit fit result; - for standard input)", "file",
     CLI_STRING_AT(render_args, params)},
    {"--output", 'o', "FILE",
     "the image: .png or .exr; slices .png, .svg or .pdf (- for standard\n"
     "output, with --to)",
     "file", CLI_STRING_AT(render_args, out_path)},
    {"--to", 0, "png|exr|svg|pdf",
     "format (default: by the output's extension; svg and pdf for\n"
     "--slice, exr for images)",
     NULL, CLI_CALLS(take_to)},
    {"--light", 0, "THETA,PHI", "a directional light, degrees (repeatable; default 45,0)", NULL, CLI_CALLS(take_light)},
    {"--view", 0, "THETA,PHI", "towards the camera, degrees (default 0,0: looking down +z)", NULL,
     CLI_CALLS(take_view)},
    {"--size", 0, "N|WxH",
     "image size (default 256; slices 640x480, half-diff plots 480x400;\n"
     "points for SVG and PDF)",
     NULL, CLI_CALLS(take_size)},
    {"--exposure", 0, "E", "multiplies values before the PNG mapping (default 1)", NULL, CLI_CALLS(take_exposure)},
    {"--tonemap", 0, "clamp|reinhard|log", "PNG mapping (default: clamp; log for --half-diff)", NULL,
     CLI_CALLS(take_tonemap)},
    {"--decades", 0, "D", "range of the log mapping (default 4)", NULL, CLI_CALLS(take_decades)},
    {"--incidence", 0, "A,B,...",
     "slice incidence angles (default 0,30,60; with --data, the\n"
     "measured incidences nearest those)",
     NULL, CLI_CALLS(take_incidence)},
    {"--data", 0, "FILE", "slices: measured samples to overlay; half-diff: a MERL table", "file",
     CLI_STRING_AT(render_args, data)},
    {"--plane-tol", 0, "D", "slices: overlay samples within D degrees of the plane (default 2)", NULL,
     CLI_CALLS(take_plane_tol)},
    {"--phi-d", 0, "D", "half-diff: phi_d in degrees (default 90)", NULL, CLI_CALLS(take_phi_d)},
};
static const cli_group mode_group = CLI_GROUP("modes (default: a lit sphere of the model)", modes);
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&mode_group, &own_group, &data_options_reading, &data_options_preprocessing};
const cli_command cli_render = {
    "brdfit",
    "render",
    "--params P.json [--slice|--half-diff] [options] -o OUT.png|.exr|.svg|.pdf",
    "render pictures of a model or a MERL table",
    "A lit sphere or a half-diff image as PNG (tone mapped) or EXR (linear values), or in-plane slices with "
    "measured samples overlaid as a plot (PNG, SVG or PDF).",
    NULL,
    groups,
    sizeof groups / sizeof groups[0],
};

/* Takes the parsed command line into r: 0, or -1 after a one-line error. */
static int take_args(render_args *r, const cli_args *args)
{
    void *const targets[] = {r, r, &r->o, &r->o};
    return cli_take(&cli_render, targets, CLI_COUNT(targets), args, NULL, NULL, cmd);
}

/* Which inputs the mode needs, and the image's format: 0, or 2 after a one-line error
 * (sets *fmt). */
static int check_mode(const render_args *r, int *fmt)
{
    if (r->slice && r->halfdiff) {
        fprintf(stderr, "%s: --slice and --half-diff exclude each other\n", cmd);
        return 2;
    }
    if (!r->out_path) {
        fprintf(stderr, "%s: -o OUT.png|OUT.exr (slices: .png|.svg|.pdf) is required\n", cmd);
        return 2;
    }
    if (!(*fmt = r->to ? r->to : to_of(r->out_path))) {
        fprintf(stderr, "%s: %s: unknown format (use .png or .exr%s, or --to)\n", cmd, r->out_path,
                r->slice ? "; .svg or .pdf for --slice" : "");
        return 2;
    }
    if (r->slice && *fmt == TO_EXR) {
        fprintf(stderr, "%s: %s: slices are a plot: PNG, SVG or PDF, not EXR\n", cmd, r->out_path);
        return 2;
    }
    if (!r->slice && !r->halfdiff && (*fmt == TO_SVG || *fmt == TO_PDF)) {
        fprintf(stderr, "%s: %s: SVG and PDF are for --slice and --half-diff plots; the sphere is PNG or EXR\n", cmd,
                r->out_path);
        return 2;
    }
    if (r->halfdiff ? (!r->params == !r->data) : !r->params) {
        fprintf(stderr, "%s: %s\n", cmd,
                r->halfdiff ? "--half-diff takes --params P.json or --data T.binary (one of them)"
                            : "--params P.json is required");
        return 2;
    }
    if (r->data && !r->slice && !r->halfdiff) {
        fprintf(stderr, "%s: --data is for --slice or --half-diff\n", cmd);
        return 2;
    }
    return 0;
}

/* The mode's defaults for what was not given (the size: the library's for the mode),
 * then the checks that need them: 0, or the exit status after a one-line error. */
static int settle(render_args *r, int fmt)
{
    const int hd_plot = r->halfdiff && (fmt == TO_SVG || fmt == TO_PDF);
    if (r->width == 0) {
        r->width = r->slice      ? r->slices.width
                   : hd_plot     ? r->hd.plot_width
                   : r->halfdiff ? r->hd.width
                                 : r->sphere.resolution;
        r->height = r->slice      ? r->slices.height
                    : hd_plot     ? r->hd.plot_height
                    : r->halfdiff ? r->hd.height
                                  : r->sphere.resolution;
    }
    bf_error err;
    if (r->halfdiff) {
        if (hd_plot) {
            r->hd.plot_width = r->width;
            r->hd.plot_height = r->height;
        } else {
            r->hd.width = r->width;
            r->hd.height = r->height;
        }
        if (!r->tonemap_given)
            r->tm.mode = r->hd.tonemap;
        if (bf_halfdiff_options_check(&r->hd, &err) != BF_OK) {
            fprintf(stderr, "%s: %s\n", cmd, err.msg);
            return 2;
        }
    } else if (!r->slice) {
        if (r->width != r->height) {
            fprintf(stderr, "%s: the sphere image is square: --size N\n", cmd);
            return 2;
        }
        r->sphere.resolution = r->width;
    } else {
        r->slices.width = r->width;
        r->slices.height = r->height;
    }
    if (bf_render_memory_check(r->width, r->height, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return 1; /* the request is well formed; this machine cannot hold it */
    }
    char scene[4096];
    const bf_path_use in[] = {{"--params file", r->params},
                              {"--data file", r->data},
                              {"--scene file", data_options_scene(r->o, scene, sizeof scene)}},
                      out[] = {{"-o", r->out_path}};
    return args_check_outputs(cmd, in, 3, out, 1);
}

/* The parameter file and the data, as the mode takes them: 0, or -1 after the error. */
static int load_inputs(const render_args *r, bf_model **m, double **x, bf_samples **s)
{
    bf_error err;
    if (r->params && bf_params_read(r->params, m, x, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return -1;
    }
    if (!r->data)
        return 0;
    if (!r->halfdiff)
        return (*s = data_options_load(r->o, r->data, NULL, NULL, cmd)) ? 0 : -1;
    /* Cells as read: preprocessing would reshape the table. */
    if (bf_samples_read_merl(r->data, 0, s, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return -1;
    }
    return 0;
}

/* Draws the mode's picture into rgb (width x height x 3, linear), and tone maps it for
 * a PNG. Returns a BF_ status. */
static bf_status draw(const render_args *r, int fmt, const bf_model *m, const double *x, bf_samples *s, float *rgb,
                      bf_error *err)
{
    bf_status rc = r->halfdiff ? (m ? bf_render_halfdiff_model(m, x, r->width, r->height, r->hd.phi_d, rgb, err)
                                    : bf_render_halfdiff_merl(s, r->width, r->height, r->hd.phi_d, rgb, err))
                               : bf_render_sphere(m, x, &r->sphere, rgb, err);
    if (rc == BF_OK && fmt == TO_PNG)
        rc = bf_tonemap_apply(rgb, (size_t)r->width * (size_t)r->height * 3, &r->tm, err);
    return rc;
}

/* The slice plot, written: a BF_ status. Without --incidence, measured data is sliced
 * where it was measured (the Cornell files have no 0 degree incidence). */
static bf_status slice_plot(const render_args *r, int fmt, const bf_model *m, const double *x, bf_samples *s,
                            bf_error *err)
{
    double measured[BF_SLICE_MAX_INCIDENCE];
    bf_slice_options so = r->slices;
    int nm = s && !r->incidence_given ? bf_slice_incidences(s, so.incidence, so.nincidence, measured) : 0;
    if (nm) {
        so.incidence = measured;
        so.nincidence = nm;
    }
    so.samples = s;
    int pf = fmt == TO_SVG ? BF_PLOT_SVG : fmt == TO_PDF ? BF_PLOT_PDF : BF_PLOT_PNG;
    return bf_render_slice(m, x, &so, r->out_path, pf, NULL, err);
}

/* Loads, draws and writes the image: the exit status. */
static int render(render_args *r, int fmt)
{
    bf_error err;
    bf_model *m = NULL;
    double *x = NULL;
    bf_samples *s = NULL;
    float *rgb = NULL;
    int status = 1, rc;
    if (load_inputs(r, &m, &x, &s) < 0)
        goto done;
    if (r->slice || (r->halfdiff && (fmt == TO_SVG || fmt == TO_PDF))) {
        rc = r->slice ? slice_plot(r, fmt, m, x, s, &err)
                      : bf_render_halfdiff_plot(m, x, s, r->hd.phi_d, r->tm.decades, r->width, r->height, r->out_path,
                                                fmt == TO_SVG ? BF_PLOT_SVG : BF_PLOT_PDF, &err);
        if (rc != BF_OK) {
            fprintf(stderr, "%s: %s\n", cmd, err.msg);
            status = rc == BF_ERR_ARG ? 2 : 1;
        } else
            status = 0;
        goto done;
    }
    if (!(rgb = malloc((size_t)r->width * (size_t)r->height * 3 * sizeof *rgb))) {
        fprintf(stderr, "%s: out of memory for a %dx%d image\n", cmd, r->width, r->height);
        goto done;
    }
    if ((rc = draw(r, fmt, m, x, s, rgb, &err)) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        status = rc == BF_ERR_ARG ? 2 : 1;
        goto done;
    }
    if (bf_image_write_rgb_as(r->out_path, fmt == TO_EXR ? BF_IMAGE_EXR : BF_IMAGE_PNG, r->width, r->height, rgb,
                              &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        goto done;
    }
    status = 0;
done:
    free(rgb);
    bf_samples_free(s);
    bf_model_free(m);
    free(x);
    return status;
}

/* The library's defaults of every mode (settle picks the mode's size). */
static void render_args_init(render_args *r)
{
    memset(r, 0, sizeof *r);
    bf_sphere_options_init(&r->sphere);
    bf_slice_options_init(&r->slices);
    bf_halfdiff_options_init(&r->hd);
    bf_tonemap_options_init(&r->tm);
}

int cmd_render(int argc, char **argv)
{
    render_args r;
    render_args_init(&r);
    if (!(r.o = cmd_options_new(BF_TASK_READ, cmd)))
        return 1;
    cli_args args;
    int p = cli_parse(&cli_render, argc, argv, &args);
    if (p != CLI_OK) {
        bf_options_free(r.o);
        return p == CLI_EXIT ? 0 : 2;
    }
    int bad = take_args(&r, &args) < 0 ? 2 : 0;
    cli_args_free(&args);
    int fmt = 0;
    if (!bad && (bad = check_mode(&r, &fmt)) == 0 && (bad = settle(&r, fmt)) == 0)
        bad = render(&r, fmt);
    bf_options_free(r.o);
    return bad;
}
