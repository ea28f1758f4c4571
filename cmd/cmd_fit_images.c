/* brdfit fit-images: per-pixel normals and model parameters from a stack of photographs
 * under known lights (brdfit/photo.h; docs/images.md).
 *
 * Decisions:
 *  - STACK is a DiLiGenT folder or a JSON stack file; -m takes one registry model.
 *  - --normals fit (default) | flat | FILE.exr; --share NAME,... fits those parameters once
 *    per material cluster (--clusters K, default 1), the rest per pixel.
 *  - The outputs go to one folder, written whole or not at all (Ctrl-C or an error leaves
 *    none); an existing folder is replaced only when it is empty or a previous output.
 *  - Progress on a terminal (a bar); --threads changes no result, only the time.
 *  - Exit 2 for bad usage (an unknown model or shared parameter too), 1 for bad input or an
 *    unwritable output, 130 after Ctrl-C. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "brdfit/clock.h"
#include "brdfit/photo.h"
#include "args.h"
#include "cli.h"
#include "commands.h"
#include "interrupt.h"

static const char cmd[] = "brdfit fit-images";

typedef struct fit_images_args {
    const char *stack, *model, *out, *normals, *share, *scale, *tile;
    int clusters, threads, relit, seed;
    char *command_line;
} fit_images_args;

static const cli_option own[] = {
    {"--model", 'm', "MODEL", "the model fitted per pixel (brdfit models; default walter)", "model",
     CLI_STRING_AT(fit_images_args, model)},
    {"--output", 'o', "DIR", "the output folder (normals.exr, a map per parameter, fit.json, ...)", "dir",
     CLI_STRING_AT(fit_images_args, out)},
    {"--normals", 0, "fit|flat|FILE",
     "fit the normals (default), take the sample's plane (+z), or read\n"
     "them from an image of unit vectors in the camera frame",
     NULL, CLI_STRING_AT(fit_images_args, normals)},
    {"--share", 0, "NAME,...", "parameters fitted once per material cluster, not per pixel", NULL,
     CLI_STRING_AT(fit_images_args, share)},
    {"--clusters", 0, "K", "material clusters (k-means on the albedo) for --share (default 1)", NULL,
     CLI_INT_AT(fit_images_args, clusters, 1, BF_PHOTO_MAX_CLUSTERS)},
    {"--scale", 0, "auto|S",
     "values are multiplied by S before fitting; auto: the 99th percentile\n"
     "albedo becomes 0.8 (default: the stack's; DiLiGenT auto, JSON 1)",
     NULL, CLI_STRING_AT(fit_images_args, scale)},
    {"--tile", 0, "I/N", "fit band I of N bands of rows only (job arrays), merged by\nbrdfit merge-images", NULL,
     CLI_STRING_AT(fit_images_args, tile)},
    {"--relit", 0, "N", "relit comparisons written (default 3)", NULL,
     CLI_INT_AT(fit_images_args, relit, 0, BF_PHOTO_MAX_RELIT)},
    {"--seed", 0, "N", "seed of the start's clusters (default 0)", NULL,
     CLI_INT_AT(fit_images_args, seed, 0, 2147483647)},
    {"--threads", 0, "N", "threads (default: every core); results do not depend on it", NULL,
     CLI_INT_AT(fit_images_args, threads, 1, BF_PHOTO_MAX_THREADS)},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group};
const cli_command cli_fit_images = {
    "brdfit",
    "fit-images",
    "STACK -m MODEL -o OUTDIR [options]",
    "fit normals and a model per pixel to photographs under known lights",
    "STACK is a DiLiGenT folder (filenames.txt, light_directions.txt, light_intensities.txt, mask.png, 16-bit "
    "PNG images) or a JSON stack file (images in any format OpenImageIO reads, directional or point lights, "
    "exposures, an orthographic or pinhole camera, a mask, black level and saturation). Each pixel gets a normal "
    "and the model's parameters; shadowed, saturated and dark outlying samples are left out and counted.\n\n"
    "OUTDIR gets normals.exr (camera frame: x right, y up, z towards the camera), one EXR per parameter, "
    "error.exr, the Lambertian baseline's normals and albedo, fit.json (counts, relit errors of the model and of "
    "the baseline, per image too), normals.png, albedo.png, relit comparisons, and for -m gltf a textured glTF "
    "material. docs/images.md gives the formats and conventions. Ctrl-C stops the fit with nothing written "
    "(exit status 130).",
    "file",
    groups,
    sizeof groups / sizeof groups[0],
};

static int take_stack(void *ctx, const char *v, const char *c)
{
    fit_images_args *a = ctx;
    if (a->stack) {
        fprintf(stderr, "%s: one stack at a time ('%s' and '%s')\n", c, a->stack, v);
        return -1;
    }
    a->stack = v;
    return 0;
}

/* The options into o: 0, or 2 after a one-line error. The ranges, the parsing of
 * --normals, --scale and --tile and the messages are the library's (photo.h); the
 * model and the shared names are usage, checked before any image is read. */
static int settle(const fit_images_args *a, bf_photo_options *o)
{
    bf_photo_options_init(o);
    if (!a->stack || !a->out) {
        fprintf(stderr, "%s: %s is required (see %s --help)\n", cmd, !a->stack ? "STACK" : "-o OUTDIR", cmd);
        return 2;
    }
    if (a->model)
        o->model = a->model;
    o->share = a->share;
    o->clusters = a->clusters;
    o->threads = a->threads;
    o->relit_images = a->relit;
    o->seed = (uint64_t)a->seed;
    bf_error err;
    if ((a->normals && bf_photo_options_set_normals(o, a->normals, &err) != BF_OK) ||
        bf_photo_options_check(o, &err) != BF_OK ||
        (a->scale && bf_photo_options_set_scale(o, a->scale, &err) != BF_OK) ||
        (a->tile && bf_photo_options_set_tile(o, a->tile, &err) != BF_OK)) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return 2;
    }
    return 0;
}

typedef struct progress_state {
    int tty, last;
    double t0;
} progress_state;

static void progress(void *ctx, double done)
{
    progress_state *ps = ctx;
    int pct = (int)(100.0 * done);
    if (pct == ps->last)
        return;
    ps->last = pct;
    char bar[31];
    for (int k = 0; k < 30; k++)
        bar[k] = k < pct * 30 / 100 ? '#' : '.';
    bar[30] = '\0';
    double el = bf_now_seconds() - ps->t0;
    fprintf(stderr, "\r%s: [%s] %3d%% pixels, %.0f s", cmd, bar, pct, el);
    fflush(stderr);
}

static int run(const fit_images_args *a, const bf_photo_options *o0)
{
    bf_error err;
    bf_stack *s = NULL;
    if (bf_photo_check_output(a->out, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return 1;
    }
    if (bf_stack_read(a->stack, &s, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return 1;
    }
    bf_photo_options o = *o0;
    progress_state ps = {isatty(STDERR_FILENO), -1, bf_now_seconds()};
    if (ps.tty && !cli_quiet()) {
        o.progress = progress;
        o.progress_user = &ps;
    }
    o.cancel = &interrupt_flag;
    struct sigaction old;
    interrupt_catch(&old);
    bf_photo_result *r = NULL;
    bf_status rc = bf_photo_fit(s, &o, &r, &err);
    interrupt_release(&old);
    if (ps.tty && o.progress && ps.last >= 0)
        fputc('\n', stderr);
    int status = 0;
    if (rc != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        status = 1;
    } else if (r->cancelled) {
        fprintf(stderr, "%s: interrupted: nothing written\n", cmd);
        status = 130;
    } else if (bf_photo_write(r, s, &o, a->out, a->command_line, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        status = 1;
    } else if (!cli_quiet()) {
        fprintf(stderr,
                "%s: %zu pixels x %d images, %s: relit error %.4g (Lambertian %.4g, ratio %.3f); %zu samples used, "
                "%zu shadowed, %zu saturated, %zu dark; %.2f s -> %s\n",
                cmd, r->counts.pixels, s->nimages, o.model, r->relit_rms, r->lambert_rms,
                r->lambert_rms > 0 ? r->relit_rms / r->lambert_rms : 0.0, r->counts.samples, r->counts.shadowed,
                r->counts.saturated, r->counts.dark, r->seconds, a->out);
    }
    bf_photo_result_free(r);
    bf_stack_free(s);
    return status;
}

int cmd_fit_images(int argc, char **argv)
{
    fit_images_args a = {.clusters = 1, .relit = 3};
    cli_args args;
    int p = cli_parse(&cli_fit_images, argc, argv, &args);
    if (p != CLI_OK)
        return p == CLI_EXIT ? 0 : 2;
    void *const targets[] = {&a};
    int bad = cli_take(&cli_fit_images, targets, CLI_COUNT(targets), &args, take_stack, &a, cmd) < 0 ? 2 : 0;
    cli_args_free(&args);
    bf_photo_options o;
    if (bad || (bad = settle(&a, &o)) != 0)
        return bad;
    args_append_word(&a.command_line, "brdfit");
    for (int i = 0; i < argc; i++) {
        if (!strcmp(argv[i], "--threads")) { /* changes no result: left out */
            i++;
            continue;
        }
        args_append_word(&a.command_line, argv[i]);
    }
    int status = run(&a, &o);
    free(a.command_line);
    return status;
}
