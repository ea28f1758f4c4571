/* brdfit render: pictures of a model (or a MERL table) as PNG or EXR.
 *   sphere (default)  --params P.json [--light T,P ...] [--view T,P]
 *   --slice           --params P.json [--incidence A,B,...] [--data FILE [data options]] [--plane-tol D]
 *   --half-diff       --params P.json | --data T.binary  [--phi-d D]
 *
 * Decisions:
 *  - EXR holds linear values (f, or radiance for the sphere); PNG holds display values:
 *    --tonemap clamp (exposure * v, clipped; the sphere's default), reinhard
 *    (e/(1+e)), or log (--decades decades below the maximum; the half/difference
 *    image's default, as BRDF papers show it), then sRGB-encoded to 8 bits. Slice plots
 *    are drawn for display and written as they are.
 *  - The default light is at theta 45, phi 0 (the highlight off-centre, shading visible);
 *    the default view is straight down +z. Angles in degrees; render.h defines frames.
 *  - --size N or WxH (default 256; slice plots 640x480).
 *  - Exit 2 for bad usage, 1 for bad data or an unwritable image; no partial file. */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "brdfit/image.h"
#include "brdfit/io.h"
#include "brdfit/limits.h"
#include "brdfit/render.h"
#include "args.h"
#include "cli.h"
#include "commands.h"
#include "data_options.h"

static const char cmd[] = "brdfit render";

#define MAX_LIGHTS 16

static const cli_option modes[] = {
    {"--slice", 0, NULL, "in-plane slices: log10 f against theta_o (-90..90, + on the mirror side)", NULL},
    {"--half-diff", 0, NULL, "theta_h (x, 0..90) by theta_d (y, 0..90 downwards) at a fixed phi_d", NULL},
};
static const cli_option own[] = {
    {"--params", 0, "FILE", "the model and its parameters (a brdfit fit result; - for standard input)", "file"},
    {"--output", 'o', "FILE", "the image: .png or .exr (- for standard output, with --to)", "file"},
    {"--to", 0, "png|exr", "image format (default: by the output's extension)", NULL},
    {"--light", 0, "THETA,PHI", "a directional light, degrees (repeatable; default 45,0)", NULL},
    {"--view", 0, "THETA,PHI", "towards the camera, degrees (default 0,0: looking down +z)", NULL},
    {"--size", 0, "N|WxH", "image size (default 256; slices 640x480)", NULL},
    {"--exposure", 0, "E", "multiplies values before the PNG mapping (default 1)", NULL},
    {"--tonemap", 0, "clamp|reinhard|log", "PNG mapping (default: clamp; log for --half-diff)", NULL},
    {"--decades", 0, "D", "range of the log mapping (default 4)", NULL},
    {"--incidence", 0, "A,B,...", "slice incidence angles (default 0,30,60)", NULL},
    {"--data", 0, "FILE", "slices: measured samples to overlay; half-diff: a MERL table", "file"},
    {"--plane-tol", 0, "D", "slices: overlay samples within D degrees of the plane (default 2)", NULL},
    {"--phi-d", 0, "D", "half-diff: phi_d in degrees (default 90)", NULL},
};
static const cli_group mode_group = CLI_GROUP("modes (default: a lit sphere of the model)", modes);
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&mode_group, &own_group, &data_options_reading, &data_options_preprocessing};
const cli_command cli_render = {
    "brdfit", "render", "--params P.json [--slice|--half-diff] [options] -o OUT.png|OUT.exr",
    "render pictures of a model or a MERL table",
    "A lit sphere, in-plane slices with measured samples overlaid, or a half-diff image, as PNG (tone mapped) or "
    "EXR (linear values).",
    NULL, groups, sizeof groups / sizeof groups[0],
};

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
    return args_size(s, 1, 16384, w, h);
}

/* The image is held whole (floats, then the encoder's copy): about 16 bytes a pixel.
 * Refuse what the machine cannot hold rather than be killed for it. */
static int image_fits(int width, int height)
{
    const double need = 16.0 * width * height;
    const size_t have = bf_memory_available();
    if (have != SIZE_MAX && need > (double)have) {
        fprintf(stderr, "%s: a %dx%d image needs about %.3g MiB, %.3g MiB available%s\n", cmd, width, height,
                need / 1048576.0, (double)have / 1048576.0, getenv("BRDFIT_MEMORY") ? " (BRDFIT_MEMORY)" : "");
        return 0;
    }
    return 1;
}

int cmd_render(int argc, char **argv)
{
    data_options dopt;
    memset(&dopt, 0, sizeof dopt);
    const char *params = NULL, *data = NULL, *out_path = NULL;
    bf_dir lights[MAX_LIGHTS], view = {0.0, 0.0};
    int nlights = 0, slice = 0, halfdiff = 0, width = 0, height = 0, tonemap = -1;
    double exposure = 1.0, decades = 4.0, plane_tol = 2.0, phi_d = 90.0;
    double incidence[BF_SLICE_MAX_INCIDENCE] = {0.0, 30.0, 60.0};
    int nincidence = 3;

    int to = 0;
    cli_args args;
    int p = cli_parse(&cli_render, argc, argv, &args);
    if (p != CLI_OK)
        return p == CLI_EXIT ? 0 : 2;
    for (int i = 0; i < args.n; i++) {
        const char *a = args.v[i].name, *v = args.v[i].value;
        if (!a) {
            fprintf(stderr, "%s: unexpected argument '%s' (see brdfit render --help)\n", cmd, v);
            goto usage;
        }
        if (!strcmp(a, "--slice")) {
            slice = 1;
            continue;
        }
        if (!strcmp(a, "--half-diff")) {
            halfdiff = 1;
            continue;
        }
        int d = data_options_parse(&dopt, a, v, cmd);
        if (d < 0)
            goto usage;
        if (d > 0)
            continue;
        int ok = 1;
        if (!strcmp(a, "--params"))
            params = v;
        else if (!strcmp(a, "--data"))
            data = v;
        else if (!strcmp(a, "--output"))
            out_path = v;
        else if (!strcmp(a, "--to"))
            ok = (to = !strcmp(v, "png") ? BF_IMAGE_PNG : !strcmp(v, "exr") ? BF_IMAGE_EXR : 0) != 0;
        else if (!strcmp(a, "--light")) {
            if (nlights >= MAX_LIGHTS) {
                fprintf(stderr, "%s: at most %d lights\n", cmd, MAX_LIGHTS);
                goto usage;
            }
            ok = parse_dir(v, &lights[nlights++]);
        } else if (!strcmp(a, "--view"))
            ok = parse_dir(v, &view);
        else if (!strcmp(a, "--size"))
            ok = parse_size(v, &width, &height);
        else if (!strcmp(a, "--exposure"))
            ok = parse_double(v, &exposure) && exposure > 0.0;
        else if (!strcmp(a, "--decades"))
            ok = parse_double(v, &decades) && decades > 0.0;
        else if (!strcmp(a, "--plane-tol"))
            ok = parse_double(v, &plane_tol) && plane_tol >= 0.0;
        else if (!strcmp(a, "--phi-d"))
            ok = parse_double(v, &phi_d);
        else if (!strcmp(a, "--tonemap")) {
            tonemap = !strcmp(v, "clamp") ? BF_TONEMAP_CLAMP : !strcmp(v, "reinhard") ? BF_TONEMAP_REINHARD
                      : !strcmp(v, "log")  ? BF_TONEMAP_LOG : -2;
            ok = tonemap != -2;
        } else if (!strcmp(a, "--incidence")) {
            char buf[512], *save = NULL;
            snprintf(buf, sizeof buf, "%s", v);
            nincidence = 0;
            for (char *t = strtok_r(buf, ",", &save); t && ok; t = strtok_r(NULL, ",", &save)) {
                double x;
                ok = nincidence < BF_SLICE_MAX_INCIDENCE && parse_double(t, &x) && x >= 0.0 && x < 90.0;
                if (ok)
                    incidence[nincidence++] = x;
            }
            ok = ok && nincidence > 0;
        }
        if (!ok) {
            fprintf(stderr, "%s: bad value '%s' for %s\n", cmd, v, a);
            goto usage;
        }
    }
    cli_args_free(&args);
    if (slice && halfdiff) {
        fprintf(stderr, "%s: --slice and --half-diff exclude each other\n", cmd);
        return 2;
    }
    if (!out_path) {
        fprintf(stderr, "%s: -o OUT.png|OUT.exr is required\n", cmd);
        return 2;
    }
    int fmt = to ? to : bf_image_format_of(out_path);
    if (!fmt) {
        fprintf(stderr, "%s: %s: unknown image format (use .png or .exr, or --to)\n", cmd, out_path);
        return 2;
    }
    if (halfdiff ? (!params == !data) : !params) {
        fprintf(stderr, "%s: %s\n", cmd,
                halfdiff ? "--half-diff takes --params P.json or --data T.binary (one of them)"
                         : "--params P.json is required");
        return 2;
    }
    if (data && !slice && !halfdiff) {
        fprintf(stderr, "%s: --data is for --slice or --half-diff\n", cmd);
        return 2;
    }
    if (width == 0) {
        width = slice ? 640 : 256;
        height = slice ? 480 : 256;
    }
    if (!slice && !halfdiff && width != height) {
        fprintf(stderr, "%s: the sphere image is square: --size N\n", cmd);
        return 2;
    }
    if (nlights == 0)
        lights[nlights++] = (bf_dir){45.0, 0.0};
    if (!image_fits(width, height))
        return 1; /* the request is well formed; this machine cannot hold it */
    const bf_path_use in[] = {{"--params file", params}, {"--data file", data}, {"--scene file", dopt.scene}},
                      out[] = {{"-o", out_path}};
    int bad = args_check_outputs(cmd, in, 3, out, 1);
    if (bad)
        return bad;

    bf_error err;
    bf_model *m = NULL;
    double *x = NULL;
    bf_samples *s = NULL;
    float *rgb = NULL;
    int status = 1, rc = BF_OK;
    if (params && bf_params_read(params, &m, &x, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        goto done;
    }
    if (data) {
        if (halfdiff) {
            /* Cells as read: preprocessing would reshape the table. */
            if (bf_samples_read_merl(data, 0, &s, &err) != BF_OK) {
                fprintf(stderr, "%s: %s\n", cmd, err.msg);
                goto done;
            }
        } else if (!(s = data_options_load(&dopt, data, NULL, cmd)))
            goto done;
    }
    size_t n = (size_t)width * (size_t)height * 3;
    if (!(rgb = malloc(n * sizeof *rgb))) {
        fprintf(stderr, "%s: out of memory for a %dx%d image\n", cmd, width, height);
        goto done;
    }
    if (slice) {
        bf_slice_options so = {width, height, incidence, nincidence, s, plane_tol};
        rc = bf_render_slice(m, x, &so, rgb, NULL, &err);
    } else if (halfdiff) {
        rc = m ? bf_render_halfdiff_model(m, x, width, height, phi_d, rgb, &err)
               : bf_render_halfdiff_merl(s, width, height, phi_d, rgb, &err);
        if (tonemap < 0)
            tonemap = BF_TONEMAP_LOG;
    } else {
        bf_sphere_options so = {width, view, lights, nlights};
        rc = bf_render_sphere(m, x, &so, rgb, &err);
    }
    if (rc != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        status = rc == BF_ERR_ARG ? 2 : 1;
        goto done;
    }
    if (fmt == BF_IMAGE_PNG && !slice)
        bf_tonemap(rgb, n, tonemap < 0 ? BF_TONEMAP_CLAMP : (bf_tonemap_mode)tonemap, exposure, decades);
    if (bf_image_write_rgb_as(out_path, fmt, width, height, rgb, &err) != BF_OK) {
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
usage:
    cli_args_free(&args);
    return 2;
}
