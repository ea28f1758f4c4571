/* Half/difference images as figures (plot/plot.h): theta_h on a sqrt axis ticked in
 * degrees, theta_d upwards, a colour bar. Values (mean of the channels) on a log colour
 * scale that several figures share; differences as signed log2(model / measured) on a
 * diverging scale whose centre, 0, is white. For the report and its tests. */
#ifndef BRDFIT_RENDER_HALFDIFF_FIGURE_H
#define BRDFIT_RENDER_HALFDIFF_FIGURE_H

#include <stddef.h>

#include "plot/plot.h"

/* The colour of no value (nothing measured in that cell): a grey neither scale uses. */
#define HALFDIFF_NONE 150

/* Sequential scale (viridis), t in [0, 1] (clamped). */
void halfdiff_sequential(double t, unsigned char rgb[3]);
/* Diverging scale (ColorBrewer RdBu, blue below 0, red above), t in [-1, 1] (clamped);
 * exactly white at 0; NaN: HALFDIFF_NONE grey. */
void halfdiff_diverging(double t, unsigned char rgb[3]);

/* Per pixel, the mean of the 3 channels of n pixels. */
void halfdiff_mean(const float *rgb, size_t n, double *out);
/* The shared log scale: log10 of the given percentile (0..100, the nearest rank) of
 * the positive values, and `decades` below it; 0, or -1 when no value is positive (or
 * out of memory). A percentile under 100 keeps a few grazing cells (Fresnel makes them
 * the brightest) from darkening everything else. */
int halfdiff_log_range(const double *v, size_t n, double percentile, double decades, double *log10_lo,
                       double *log10_hi);
/* log2(model / measured) per pixel; NaN where measured <= 0 (no value); where the model
 * is <= 0 and the measurement is not, -infinity (the map clamps it). */
void halfdiff_log2_ratio(const double *model, const double *measured, size_t n, double *out);

/* A width x height figure of values v (w x h pixels, bf_render_halfdiff's layout: row 0
 * at theta_d 0) on [log10_lo, log10_hi]; NULL when out of memory. */
plot *halfdiff_value_figure(const double *v, int w, int h, const char *title, double log10_lo, double log10_hi);
/* The same of log2 ratios r, the scale +-span (span > 0). */
plot *halfdiff_ratio_figure(const double *r, int w, int h, const char *title, double span);

/* Scattered samples (not a table) as points on the same axes: x sqrt(theta_h / 90),
 * y theta_d, every phi_d together, over the "no value" grey (where nothing was
 * measured), with the same colour bars. theta_h and theta_d in degrees, n each; values
 * v on [log10_lo, log10_hi], log2 ratios r on +-span. A sample with no value (v <= 0,
 * r NaN, angles not finite) is left out. Drawn in a fixed order, so that the same input
 * gives the same bytes and what matters lies on top: values ascending (the few bright
 * highlight samples over the many dark ones), ratios by |r| ascending (the worst
 * misfits over the good ones); ties by index. The axes reach a little beyond 0 and 90
 * so that points on an edge (a 1-D slice at theta_d 0) show whole. Markers shrink as
 * 1/sqrt(count) past 400 of them, down to 40% at 2500; the caller thins many more
 * (they would only overplot). NULL when out of memory. */
plot *halfdiff_value_points(size_t n, const double *theta_h, const double *theta_d, const double *v, const char *title,
                            double log10_lo, double log10_hi);
plot *halfdiff_ratio_points(size_t n, const double *theta_h, const double *theta_d, const double *r, const char *title,
                            double span);
/* The half/difference angles (degrees, Rusinkiewicz) of directions in degrees (theta_i,
 * phi_i, theta_o, phi_o, as bf_samples_direction gives them): theta_h of H = L + V
 * normalised, theta_d between L and H. NaN when L and V cancel. */
void halfdiff_angles(const double dir[4], double *theta_h, double *theta_d);
/* The order halfdiff_*_points draw in: the indices of the m samples whose key is not
 * NaN, by key ascending, ties by index; m returned. idx holds n. */
size_t halfdiff_point_order(size_t n, const double *key, size_t *idx);

/* The raster halfdiff_ratio_figure draws (w x h RGB bytes, top row theta_d 90), for
 * the tests. */
void halfdiff_ratio_raster(const double *r, int w, int h, double span, unsigned char *rgb);

#endif
