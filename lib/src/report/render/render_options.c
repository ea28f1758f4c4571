/* brdfit render's defaults, limits and checks (render.h), in one place for the command
 * and every front end: the sphere's ranges, the memory a picture needs, the display
 * mapping and the half/difference picture's options. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "base/sized.h"
#include "brdfit/limits.h"
#include "brdfit/render.h"

/* bf_sphere_options with the library's defaults (a whole struct of this version). */
static void sphere_options_defaults(bf_sphere_options *o)
{
    static const bf_dir light = {45.0, 0.0};
    o->resolution = 256;
    o->lights = &light;
    o->nlights = 1;
}

BF_SIZED_INIT(bf_sphere_options, sphere_options_defaults)

#define PLOT_MIN_SIDE 40 /* a figure smaller has no room for its axes */

static const char *const tonemap_names[] = {"clamp", "reinhard", "log"};
#define NTONEMAPS ((int)(sizeof tonemap_names / sizeof *tonemap_names))

static int tonemap_known(bf_tonemap_mode mode)
{
    return (int)mode >= 0 && (int)mode < NTONEMAPS;
}

bf_status bf_tonemap_parse(const char *name, bf_tonemap_mode *out, bf_error *err)
{
    for (int i = 0; name && i < NTONEMAPS; i++)
        if (!strcmp(name, tonemap_names[i])) {
            *out = (bf_tonemap_mode)i;
            return BF_OK;
        }
    return bf_fail(err, BF_ERR_ARG, "unknown tone map '%s' (clamp, reinhard or log)", name ? name : "(null)");
}

const char *bf_tonemap_name(bf_tonemap_mode mode)
{
    return tonemap_known(mode) ? tonemap_names[mode] : NULL;
}

bf_status bf_sphere_options_check(const bf_sphere_options *o, bf_error *err)
{
    if (o && bf_sized_check(o, sizeof *o, "bf_sphere_options", err) != BF_OK)
        return BF_ERR_ARG;
    if (!o || o->resolution < 1 || o->nlights < 1 || !o->lights)
        return bf_fail(err, BF_ERR_ARG, "sphere render: need a size >= 1 and at least one light");
    if (o->resolution > BF_RENDER_MAX_SIDE)
        return bf_fail(err, BF_ERR_ARG, "sphere render: size %d is above %d pixels", o->resolution, BF_RENDER_MAX_SIDE);
    if (o->nlights > BF_RENDER_MAX_LIGHTS)
        return bf_fail(err, BF_ERR_ARG, "at most %d lights", BF_RENDER_MAX_LIGHTS);
    if (!isfinite(o->view.theta) || !isfinite(o->view.phi))
        return bf_fail(err, BF_ERR_ARG, "sphere render: the view (%g, %g) is not a finite direction", o->view.theta,
                       o->view.phi);
    for (int k = 0; k < o->nlights; k++)
        if (!isfinite(o->lights[k].theta) || !isfinite(o->lights[k].phi))
            return bf_fail(err, BF_ERR_ARG, "sphere render: light %d (%g, %g) is not a finite direction", k + 1,
                           o->lights[k].theta, o->lights[k].phi);
    return BF_OK;
}

bf_status bf_render_memory_check(int width, int height, bf_error *err)
{
    /* The image is held whole (floats, then the encoder's copy): about 16 bytes a pixel.
     * Refuse what the machine cannot hold rather than be killed for it. */
    const double need = 16.0 * width * height;
    const size_t have = bf_memory_available();
    if (have != SIZE_MAX && need > (double)have)
        return bf_fail(err, BF_ERR_NOMEM, "a %dx%d image needs about %.3g MiB, %.3g MiB available%s", width, height,
                       need / 1048576.0, (double)have / 1048576.0, getenv("BRDFIT_MEMORY") ? " (BRDFIT_MEMORY)" : "");
    return BF_OK;
}

/* bf_tonemap_options with the library's defaults (a whole struct of this version). */
static void tonemap_options_defaults(bf_tonemap_options *o)
{
    o->mode = BF_TONEMAP_CLAMP;
    o->exposure = 1.0;
    o->decades = 4.0;
}

BF_SIZED_INIT(bf_tonemap_options, tonemap_options_defaults)

bf_status bf_tonemap_options_check(const bf_tonemap_options *o, bf_error *err)
{
    if (!o)
        return bf_fail(err, BF_ERR_ARG, "tone map: no options");
    if (bf_sized_check(o, sizeof *o, "bf_tonemap_options", err) != BF_OK)
        return BF_ERR_ARG;
    if (!tonemap_known(o->mode))
        return bf_fail(err, BF_ERR_ARG, "tone map: unknown mode %d", (int)o->mode);
    if (!(isfinite(o->exposure) && o->exposure > 0.0))
        return bf_fail(err, BF_ERR_ARG, "tone map: exposure must be a finite number above 0, got %g", o->exposure);
    if (!(isfinite(o->decades) && o->decades > 0.0))
        return bf_fail(err, BF_ERR_ARG, "tone map: decades must be a finite number above 0, got %g", o->decades);
    return BF_OK;
}

bf_status bf_tonemap_apply(float *v, size_t n, const bf_tonemap_options *o, bf_error *err)
{
    bf_status rc = bf_tonemap_options_check(o, err);
    if (rc != BF_OK)
        return rc;
    if (n && !v)
        return bf_fail(err, BF_ERR_ARG, "tone map: no values");
    bf_tonemap(v, n, o->mode, o->exposure, o->decades);
    return BF_OK;
}

/* bf_halfdiff_options with the library's defaults: the image the sphere's size. */
static void halfdiff_options_defaults(bf_halfdiff_options *o)
{
    bf_sphere_options so;
    bf_sphere_options_init(&so);
    o->width = o->height = so.resolution;
    o->phi_d = 90.0;
    o->tonemap = BF_TONEMAP_LOG;
    o->plot_width = 480;
    o->plot_height = 400;
}

BF_SIZED_INIT(bf_halfdiff_options, halfdiff_options_defaults)

bf_status bf_halfdiff_options_check(const bf_halfdiff_options *o, bf_error *err)
{
    if (!o)
        return bf_fail(err, BF_ERR_ARG, "half/difference image: no options");
    if (bf_sized_check(o, sizeof *o, "bf_halfdiff_options", err) != BF_OK)
        return BF_ERR_ARG;
    if (o->width < 1 || o->height < 1 || o->width > BF_RENDER_MAX_SIDE || o->height > BF_RENDER_MAX_SIDE)
        return bf_fail(err, BF_ERR_ARG, "half/difference image: bad size %dx%d (each side 1 to %d)", o->width,
                       o->height, BF_RENDER_MAX_SIDE);
    if (!isfinite(o->phi_d))
        return bf_fail(err, BF_ERR_ARG, "half/difference image: phi_d is not finite");
    if (!tonemap_known(o->tonemap))
        return bf_fail(err, BF_ERR_ARG, "half/difference image: unknown tone map %d", (int)o->tonemap);
    if (o->plot_width < PLOT_MIN_SIDE || o->plot_height < PLOT_MIN_SIDE)
        return bf_fail(err, BF_ERR_ARG, "a half-diff plot must be at least %dx%d", PLOT_MIN_SIDE, PLOT_MIN_SIDE);
    if (o->plot_width > BF_RENDER_MAX_SIDE || o->plot_height > BF_RENDER_MAX_SIDE)
        return bf_fail(err, BF_ERR_ARG, "a half-diff plot must be at most %dx%d", BF_RENDER_MAX_SIDE,
                       BF_RENDER_MAX_SIDE);
    return BF_OK;
}
