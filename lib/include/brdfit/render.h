/* Pictures of a model or a measurement as float RGB buffers (pure computation; image.h
 * writes them): a lit sphere, in-plane slice plots, and the theta_h x theta_d image.
 * Buffers are width*height*3 floats, row-major from the top row. Every model channel
 * count is shown as RGB: C = 1 as grey, C = 3 as is, any other C as the mean of its
 * channels (grey). Angles are in degrees. */
#ifndef BRDFIT_RENDER_H
#define BRDFIT_RENDER_H

#include <stddef.h>

#include "brdfit/error.h"
#include "brdfit/model.h"
#include "brdfit/samples.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A direction in world space: theta from +z, phi from +x towards +y. */
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
 * zero where L or V is below the local horizon, and exactly 0 outside the disc. */
typedef struct bf_sphere_options {
    int size;              /* image is size x size */
    bf_dir view;           /* towards the camera */
    const bf_dir *lights;  /* towards each light */
    int nlights;           /* >= 1 */
} bf_sphere_options;

int bf_render_sphere(const bf_model *m, const double *x, const bf_sphere_options *o, float *rgb,
                     bf_error *err);
/* The same sphere of a measured MERL table (read with its origin): each pixel's pair of
 * directions takes the value of the cell MERL's own lookup picks (half/difference
 * angles, phi_d folded by reciprocity); 0 where that cell is invalid. */
int bf_render_sphere_merl(const bf_samples *merl, const bf_sphere_options *o, float *rgb, bf_error *err);

/* ---- In-plane slices -------------------------------------------------------------
 * For each incidence angle theta_i (light at phi_i = 0), f at viewing directions in the
 * plane of incidence, theta_o signed from -90 to 90 on the x axis: positive theta_o on
 * the mirror side (phi_o = 180), negative on the light's side (phi_o = 0), so the
 * specular peak sits at +theta_i. The y axis is log10 f over whole decades covering the
 * curves' positive values (at most 8 decades down from the top). Drawn on white: a
 * black frame, x ticks every 30 degrees (0 longer), y ticks every decade, a faint grey
 * line at each incidence's mirror angle; one line per incidence angle and channel (red,
 * green, blue for RGB; black otherwise), lighter for later incidence angles. No text:
 * the axes are fixed (x) or whole decades (y); bf_slice_range says which. Measured
 * samples, when given, are drawn as 3x3 dots in a darker shade of their curve: those
 * whose theta_i lies within plane_tol of an incidence angle and whose viewing direction
 * lies within plane_tol of the plane of incidence. */
#define BF_SLICE_MAX_INCIDENCE 16
typedef struct bf_slice_options {
    int width, height;
    const double *incidence; /* degrees, in [0, 90) */
    int nincidence;          /* 1 .. BF_SLICE_MAX_INCIDENCE */
    bf_samples *samples;     /* NULL, or measured samples to overlay (same channel count
                                or any: shown as the model's channels are) */
    double plane_tol;        /* degrees */
} bf_slice_options;

/* The plot's y range in log10 f, for a caption; and where the plot area lies. */
typedef struct bf_slice_range {
    double log10_lo, log10_hi;
    int x0, y0, x1, y1;      /* plot area in pixels, inclusive (x0,y0 top-left) */
    size_t overlaid;         /* measured samples drawn */
} bf_slice_range;

int bf_render_slice(const bf_model *m, const double *x, const bf_slice_options *o, float *rgb,
                    bf_slice_range *range, bf_error *err);

/* ---- theta_h x theta_d image -----------------------------------------------------
 * Column i: theta_h = (i + 0.5)/width * 90; row j (from the top): theta_d = (j + 0.5)/
 * height * 90; phi_d fixed, phi_h = 0 (Rusinkiewicz; the convention of MERL tables).
 * Values are f (linear, per channel). From a model, or from a MERL table read with
 * bf_samples_read_merl: the cell containing (theta_h, theta_d, phi_d) (MERL's own
 * lookup), 0 where that cell is invalid or was not read. */
int bf_render_halfdiff_model(const bf_model *m, const double *x, int width, int height,
                             double phi_d, float *rgb, bf_error *err);
int bf_render_halfdiff_merl(const bf_samples *merl, int width, int height, double phi_d,
                            float *rgb, bf_error *err);

/* L and V (unit, local frame) at half/difference angles in radians, phi_h = 0: L is the
 * difference vector rotated by theta_h about y, V its mirror about H. */
void bf_halfdiff_dirs(double theta_h, double theta_d, double phi_d, double L[3], double V[3]);

/* ---- Scatter plot ----------------------------------------------------------------
 * n points (x[i], y[i]) on white inside a black frame (10 px margin), no text: the axes
 * span the drawable values padded by 5% (log axes in log10; points <= 0 or NaN there are
 * left out); highlight (NULL: none) marks points drawn in red and joined in x order,
 * the rest grey. bf_scatter_range says what the axes span, for a caption. */
typedef struct bf_scatter_options {
    int width, height;     /* >= 40 each */
    int log_x, log_y;      /* 1: log10 axis */
} bf_scatter_options;
typedef struct bf_scatter_range {
    double x_lo, x_hi, y_lo, y_hi; /* axis ends (log10 of the value on a log axis) */
    int x0, y0, x1, y1;            /* plot area in pixels, inclusive */
    int drawn;                     /* points drawn */
} bf_scatter_range;
int bf_render_scatter(int n, const double *x, const double *y, const int *highlight,
                      const bf_scatter_options *o, float *rgb, bf_scatter_range *range, bf_error *err);

/* ---- Display mapping for 8-bit images ------------------------------------------
 * In place over n floats: CLAMP: exposure * v (the PNG writer clamps to [0, 1]);
 * REINHARD: e/(1 + e) with e = exposure * v; LOG: log10(e) mapped from
 * [log10(max e) - decades, log10(max e)] to [0, 1] (0 for v <= 0), max over the buffer. */
typedef enum bf_tonemap_mode { BF_TONEMAP_CLAMP = 0, BF_TONEMAP_REINHARD, BF_TONEMAP_LOG } bf_tonemap_mode;
void bf_tonemap(float *v, size_t n, bf_tonemap_mode mode, double exposure, double decades);

#ifdef __cplusplus
}
#endif
#endif
