/* Pictures of a model or a measurement as float RGB buffers (pure computation; image.h
 * writes them): a lit sphere and the theta_h x theta_d image; and in-plane slice plots,
 * figures drawn with Cairo and written as PNG, SVG or PDF.
 * Buffers are width*height*3 floats, row-major from the top row. Every model channel
 * count is shown as RGB: C = 1 as grey, C = 3 as is, any other C as the mean of its
 * channels (grey). Angles are in degrees.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_RENDER_H
#define BRDFIT_RENDER_H

#include <stddef.h>

#include "brdfit/formats.h"
#include "brdfit/error.h"
#include "brdfit/model.h"
#include "brdfit/samples.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A direction in world space: theta from +z, phi from +x towards +y. Frozen
 * (docs/api.md): a small value struct. */
typedef struct bf_dir {
    double theta, phi;
} bf_dir;

/* ---- Lit sphere ------------------------------------------------------------------
 * A unit sphere seen orthographically by a camera looking along -w, where w is the view
 * direction (default theta 0: the camera above the sphere on +z, looking down). Image
 * axes: right u = d w / d theta normalised (theta = 0: +x), up = w x u (theta = 0: +y).
 * Each pixel inside the disc is the surface point n = sx u + sy up + sqrt(1 - r^2) w;
 * its local frame is normal n, tangent t = world +x projected onto the tangent plane
 * (world +y where n is within 1e-6 of +-x), bitangent n x t. Each light is directional
 * with intensity 1, from direction L in world space:
 *   radiance = sum_lights f(L_local, V_local) cos(theta_L), V = w,
 * zero where L or V is below the local horizon, and exactly 0 outside the disc.
 * Callers set it up with bf_sphere_options_init (size: docs/api.md). */
typedef struct bf_sphere_options {
    size_t size;          /* sizeof, set by bf_sphere_options_init */
    int resolution;       /* image is resolution x resolution */
    bf_dir view;          /* towards the camera */
    const bf_dir *lights; /* towards each light */
    int nlights;          /* >= 1 */
} bf_sphere_options;

/* brdfit render's defaults: 256 x 256, viewed from +z (0, 0), one light at (45, 0)
 * (lights points to the library's own copy). */
BF_API void bf_sphere_options_init_size(bf_sphere_options *o, size_t size);
static inline void bf_sphere_options_init(bf_sphere_options *o)
{
    bf_sphere_options_init_size(o, sizeof *o);
}

BF_API bf_status bf_render_sphere(const bf_model *m, const double *x, const bf_sphere_options *o, float *rgb,
                                  bf_error *err);
/* The same sphere of a measured MERL table (read with its origin): each pixel's pair of
 * directions takes the value of the cell MERL's own lookup picks (half/difference
 * angles, phi_d folded by reciprocity); 0 where that cell is invalid. */
BF_API bf_status bf_render_sphere_merl(const bf_samples *merl, const bf_sphere_options *o, float *rgb, bf_error *err);

/* ---- Plots -----------------------------------------------------------------------
 * Plots (slices here, compare's and tradeoff's figures) are drawn with Cairo: title,
 * axis titles with units, 1-2-5 ticks (decades labelled 10^k on log axes), padded
 * ranges that never collapse, a legend, labelled points. Written as PNG (width x
 * height pixels), SVG or PDF (width x height points) through bf_outfile (io.h): a
 * failed write leaves no partial file. */
typedef enum bf_plot_format { BF_PLOT_BY_NAME = 0, BF_PLOT_PNG = 1, BF_PLOT_SVG, BF_PLOT_PDF } bf_plot_format;
/* By the name's extension (.png, .svg, .pdf, case-insensitive), 0 otherwise. */
BF_API int bf_plot_format_of(const char *path);
/* "png", "svg", "pdf" as --to/--format names take them, into *out; BF_ERR_ARG for any
 * other name. */
BF_API bf_status bf_plot_format_parse(const char *name, bf_plot_format *out, bf_error *err);

/* What a plot's axes span (data units, not log10) and how many points it drew.
 * Callers set it up with bf_plot_axes_init; the library fills what lies within its size
 * (docs/api.md). */
typedef struct bf_plot_axes {
    size_t size; /* sizeof, set by bf_plot_axes_init */
    double x_lo, x_hi, y_lo, y_hi;
    int log_x, log_y;
    int drawn;
} bf_plot_axes;

/* Zeroes *a and sets its size. */
BF_API void bf_plot_axes_init_size(bf_plot_axes *a, size_t size);
static inline void bf_plot_axes_init(bf_plot_axes *a)
{
    bf_plot_axes_init_size(a, sizeof *a);
} /* the program's size */

/* ---- In-plane slices -------------------------------------------------------------
 * For each incidence angle theta_i (light at phi_i = 0), f at viewing directions in the
 * plane of incidence, theta_o signed from -90 to 90 on the x axis (ticks every 30
 * degrees): positive theta_o on the mirror side (phi_o = 180), negative on the light's
 * side (phi_o = 0), so the specular peak sits at +theta_i (a dotted guide line). The y
 * axis is f on a log axis: the curves' positive values (and the overlaid samples'),
 * at most 8 decades down from the largest and, with in-plane samples, at most one decade
 * below the lowest of them, padded; or log10_lo..log10_hi when given
 * (log10_lo < log10_hi: a range shared by several plots). Colour tells the incidence
 * angle; for RGB, the line style (solid, dashed, dotted) and the sample marker (circle,
 * square, triangle) the channel; the legend says both. Incidence angles whose curves are
 * the same (a Lambert surface) are drawn once, in the first one's colour, and named
 * together. Measured samples, when given, are drawn as translucent markers under the
 * curves: those whose theta_i lies within plane_tol of an incidence angle and whose
 * viewing direction lies within plane_tol of the plane of incidence; of an incidence
 * angle with more than 90, one per degree of theta_o (the nearest the degree's centre).
 * Callers set the options up with bf_slice_options_init (size: docs/api.md). */
#define BF_SLICE_MAX_INCIDENCE 16
typedef struct bf_slice_options {
    size_t size; /* sizeof, set by bf_slice_options_init */
    int width, height;
    const double *incidence;   /* degrees, in [0, 90) */
    int nincidence;            /* 1 .. BF_SLICE_MAX_INCIDENCE */
    bf_samples *samples;       /* NULL, or measured samples to overlay (same channel count
                                or any: shown as the model's channels are) */
    double plane_tol;          /* degrees */
    const char *title;         /* NULL: "In-plane slices of MODEL" */
    double log10_lo, log10_hi; /* the y axis (log10 f) when log10_lo < log10_hi */
} bf_slice_options;

/* brdfit render --slice's defaults: 640 x 480, incidence 0, 30 and 60 degrees (incidence
 * points to the library's own copy), no samples, plane_tol 2, the default title, the y
 * range from the data. */
BF_API void bf_slice_options_init_size(bf_slice_options *o, size_t size);
static inline void bf_slice_options_init(bf_slice_options *o)
{
    bf_slice_options_init_size(o, sizeof *o);
} /* the program's size */

/* The plot's y range in log10 f, and the samples overlaid (in the plane) and drawn.
 * Callers set it up with bf_slice_range_init; the library fills what lies within its
 * size (docs/api.md). */
typedef struct bf_slice_range {
    size_t size; /* sizeof, set by bf_slice_range_init */
    double log10_lo, log10_hi;
    size_t overlaid; /* measured samples in the plane of an incidence angle */
    size_t shown;    /* of those, drawn (dense ones: one per degree of theta_o) */
} bf_slice_range;

/* Zeroes *r and sets its size. */
BF_API void bf_slice_range_init_size(bf_slice_range *r, size_t size);
static inline void bf_slice_range_init(bf_slice_range *r)
{
    bf_slice_range_init_size(r, sizeof *r);
} /* the program's size */

/* Incidence angles the data has: for each wanted angle, the nearest theta_i (below 90)
 * of any sample, to 0.1 degree; duplicates dropped, ascending. out holds
 * BF_SLICE_MAX_INCIDENCE; returns how many (0: no samples, or none below 90). */
BF_API int bf_slice_incidences(const bf_samples *s, const double *want, int nwant, double *out);

/* The data's extent in log10 f (curves and in-plane samples, limited as above),
 * so that several plots can share one y range: BF_OK, *lo <= *hi. */
BF_API bf_status bf_slice_extent(const bf_model *m, const double *x, const bf_slice_options *o, double *log10_lo,
                                 double *log10_hi, bf_error *err);
/* The slice plot written to path ("-": standard output) in format (BF_PLOT_BY_NAME: by
 * the extension); range may be NULL. */
BF_API bf_status bf_render_slice(const bf_model *m, const double *x, const bf_slice_options *o, const char *path,
                                 int format, bf_slice_range *range, bf_error *err);

/* ---- theta_h x theta_d image -----------------------------------------------------
 * Column i: theta_h = ((i + 0.5)/width)^2 * 90 (even in sqrt(theta_h), as MERL tables
 * index it); row j (from the top): theta_d = (j + 0.5)/height * 90; phi_d fixed, phi_h = 0 (Rusinkiewicz; the convention of MERL tables).
 * Values are f (linear, per channel). From a model, or from a MERL table read with
 * bf_samples_read_merl: the cell containing (theta_h, theta_d, phi_d) (MERL's own
 * lookup), 0 where that cell is invalid or was not read. */
BF_API bf_status bf_render_halfdiff_model(const bf_model *m, const double *x, int width, int height, double phi_d,
                                          float *rgb, bf_error *err);
BF_API bf_status bf_render_halfdiff_merl(const bf_samples *merl, int width, int height, double phi_d, float *rgb,
                                         bf_error *err);

/* The same image as a figure (a plot, PNG, SVG or PDF by format or the extension):
 * theta_h on a sqrt axis ticked in degrees, theta_d upwards, the mean of the channels on
 * a log colour scale from the image's 99th percentile down `decades`, a colour bar;
 * cells with no value grey. Of the model m (parameters x), or of the MERL table merl
 * when m is NULL. width x height: the figure, pixels (PNG) or points. */
BF_API bf_status bf_render_halfdiff_plot(const bf_model *m, const double *x, const bf_samples *merl, double phi_d,
                                         double decades, int width, int height, const char *path, int format,
                                         bf_error *err);

/* L and V (unit, local frame) at half/difference angles in radians, phi_h = 0: L is the
 * difference vector rotated by theta_h about y, V its mirror about H. */
BF_API void bf_halfdiff_dirs(double theta_h, double theta_d, double phi_d, double L[3], double V[3]);

/* ---- Display mapping for 8-bit images ------------------------------------------
 * In place over n floats: CLAMP: exposure * v (the PNG writer clamps to [0, 1]);
 * REINHARD: e/(1 + e) with e = exposure * v; LOG: log10(e) mapped from
 * [log10(max e) - decades, log10(max e)] to [0, 1] (0 for v <= 0), max over the buffer. */
typedef enum bf_tonemap_mode { BF_TONEMAP_CLAMP = 0, BF_TONEMAP_REINHARD, BF_TONEMAP_LOG } bf_tonemap_mode;
BF_API void bf_tonemap(float *v, size_t n, bf_tonemap_mode mode, double exposure, double decades);

/* An exposure from the data: 1 / the given percentile (0..100, interpolated) of the
 * brightest channel of the npx RGB pixels that are > 0 (a sphere's background and its
 * unlit side left out), so that CLAMP shows that share of the lit pixels unclipped.
 * 1 when no pixel is > 0; NaN when out of memory. */
BF_API double bf_exposure_percentile(const float *rgb, size_t npx, double percentile);

/* The mapping's names, as brdfit render --tonemap takes them: "clamp", "reinhard", "log"
 * into *out; BF_ERR_ARG listing them for any other name. */
BF_API bf_status bf_tonemap_parse(const char *name, bf_tonemap_mode *out, bf_error *err);
BF_API const char *bf_tonemap_name(bf_tonemap_mode mode); /* NULL for an unknown mode */

/* ---- brdfit render's defaults, limits and checks ---------------------------------
 * What a front end takes from the library rather than restating it: the defaults (each
 * struct's init), the limits below, and checks that refuse what is out of range with a
 * one-line message before any picture is allocated. */
#define BF_RENDER_MAX_SIDE 16384 /* pixels (points, for SVG and PDF) a side of a picture */
#define BF_RENDER_MAX_LIGHTS 16  /* lights of a sphere */

/* A sphere's options within range: resolution 1 to BF_RENDER_MAX_SIDE, 1 to
 * BF_RENDER_MAX_LIGHTS lights (at most: "at most 16 lights"), finite angles.
 * bf_render_sphere and bf_render_sphere_merl check them. */
BF_API bf_status bf_sphere_options_check(const bf_sphere_options *o, bf_error *err);

/* Whether this machine can hold a width x height picture while it is drawn and written:
 * about 16 bytes a pixel (the floats, then the encoder's copy), against
 * bf_memory_available. BF_ERR_NOMEM "a WxH image needs about N MiB, M MiB available"
 * when it cannot (" (BRDFIT_MEMORY)" when that variable set the limit). */
BF_API bf_status bf_render_memory_check(int width, int height, bf_error *err);

/* The display mapping of an 8-bit image (a PNG): mode, exposure and decades as
 * bf_tonemap takes them. Callers set it up with bf_tonemap_options_init (size:
 * docs/api.md). */
typedef struct bf_tonemap_options {
    size_t size;          /* sizeof, set by bf_tonemap_options_init */
    bf_tonemap_mode mode; /* a sphere's (a half/difference image's: bf_halfdiff_options.tonemap) */
    double exposure;      /* multiplies the values first; > 0 */
    double decades;       /* LOG's range below the maximum, and the half/difference figure's
                             colour scale; > 0 */
} bf_tonemap_options;

/* brdfit render's defaults: BF_TONEMAP_CLAMP, exposure 1, 4 decades. */
BF_API void bf_tonemap_options_init_size(bf_tonemap_options *o, size_t size);
static inline void bf_tonemap_options_init(bf_tonemap_options *o)
{
    bf_tonemap_options_init_size(o, sizeof *o);
}
/* A known mode, exposure and decades finite and > 0. */
BF_API bf_status bf_tonemap_options_check(const bf_tonemap_options *o, bf_error *err);
/* bf_tonemap over n floats with o, once o passes bf_tonemap_options_check. */
BF_API bf_status bf_tonemap_apply(float *v, size_t n, const bf_tonemap_options *o, bf_error *err);

/* The theta_h x theta_d picture's options (bf_render_halfdiff_model, _merl and _plot
 * take them as arguments). Callers set it up with bf_halfdiff_options_init (size:
 * docs/api.md). */
typedef struct bf_halfdiff_options {
    size_t size;                 /* sizeof, set by bf_halfdiff_options_init */
    int width, height;           /* the image, pixels */
    double phi_d;                /* degrees */
    bf_tonemap_mode tonemap;     /* its display mapping (bf_tonemap_options.mode) */
    int plot_width, plot_height; /* the figure (bf_render_halfdiff_plot), pixels or points */
} bf_halfdiff_options;

/* brdfit render --half-diff's defaults: the sphere's size (256 x 256), phi_d 90, the log
 * mapping (as BRDF papers show the image), a 480 x 400 figure. */
BF_API void bf_halfdiff_options_init_size(bf_halfdiff_options *o, size_t size);
static inline void bf_halfdiff_options_init(bf_halfdiff_options *o)
{
    bf_halfdiff_options_init_size(o, sizeof *o);
}
/* The image 1 to BF_RENDER_MAX_SIDE a side, phi_d finite, a known mapping, the figure
 * 40 to BF_RENDER_MAX_SIDE a side ("a half-diff plot must be at least 40x40"). */
BF_API bf_status bf_halfdiff_options_check(const bf_halfdiff_options *o, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
