/* Half/difference images as figures: see halfdiff_figure.h. */
#include "render/halfdiff_figure.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/render.h"

/* Colour maps as anchor colours, linearly interpolated between evenly spaced anchors. */
static void interpolate(const unsigned char (*anchor)[3], int n, double t, unsigned char rgb[3])
{
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    double u = t * (n - 1);
    int k = (int)floor(u);
    if (k >= n - 1)
        k = n - 2;
    double f = u - k;
    for (int c = 0; c < 3; c++)
        rgb[c] = (unsigned char)lround((1.0 - f) * anchor[k][c] + f * anchor[k + 1][c]);
}

void halfdiff_sequential(double t, unsigned char rgb[3])
{
    /* viridis at 0, 1/8, ..., 1: dark to light, readable in grey and by most
     * colour-blind readers. */
    static const unsigned char v[9][3] = {{68, 1, 84},    {71, 44, 122}, {59, 81, 139},  {44, 113, 142}, {33, 144, 141},
                                          {39, 173, 129}, {92, 200, 99}, {170, 220, 50}, {253, 231, 37}};
    interpolate(v, 9, isnan(t) ? 0.0 : t, rgb);
}

void halfdiff_diverging(double t, unsigned char rgb[3])
{
    static const unsigned char d[7][3] = {{33, 102, 172},  {103, 169, 207}, {209, 229, 240}, {255, 255, 255},
                                          {253, 219, 199}, {239, 138, 98},  {178, 24, 43}};
    if (isnan(t)) {
        rgb[0] = rgb[1] = rgb[2] = HALFDIFF_NONE;
        return;
    }
    if (t == 0.0) { /* the centre exactly: equal values are white, whatever rounding does */
        rgb[0] = rgb[1] = rgb[2] = 255;
        return;
    }
    interpolate(d, 7, 0.5 * (t + 1.0), rgb);
}

void halfdiff_mean(const float *rgb, size_t n, double *out)
{
    for (size_t p = 0; p < n; p++)
        out[p] = ((double)rgb[3 * p] + rgb[3 * p + 1] + rgb[3 * p + 2]) / 3.0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int halfdiff_log_range(const double *v, size_t n, double percentile, double decades, double *log10_lo, double *log10_hi)
{
    double *pos = malloc((n ? n : 1) * sizeof *pos);
    if (!pos)
        return -1;
    size_t m = 0;
    for (size_t p = 0; p < n; p++)
        if (v[p] > 0.0 && isfinite(v[p]))
            pos[m++] = v[p];
    if (!m) {
        free(pos);
        return -1;
    }
    qsort(pos, m, sizeof *pos, cmp_double);
    size_t k = (size_t)floor(fmin(fmax(percentile, 0.0), 100.0) / 100.0 * (double)(m - 1) + 0.5);
    *log10_hi = log10(pos[k]);
    *log10_lo = *log10_hi - decades;
    free(pos);
    return 0;
}

void halfdiff_log2_ratio(const double *model, const double *measured, size_t n, double *out)
{
    for (size_t p = 0; p < n; p++)
        out[p] = !(measured[p] > 0.0) ? NAN : model[p] > 0.0 ? log2(model[p] / measured[p]) : -INFINITY;
}

/* Ticks of theta_h on the sqrt axis (x = sqrt(theta_h / 90)), labelled in degrees. */
static int theta_h_axis(plot *p)
{
    static const double deg[] = {0, 2, 5, 10, 20, 45, 90};
    static const char *const label[] = {"0\xc2\xb0",  "2\xc2\xb0",  "5\xc2\xb0", "10\xc2\xb0",
                                        "20\xc2\xb0", "45\xc2\xb0", "90\xc2\xb0"};
    double at[7];
    for (int i = 0; i < 7; i++)
        at[i] = sqrt(deg[i] / 90.0);
    if (plot_axis(p, PLOT_X, "half angle \xce\xb8_{h} (\xe2\x88\x9a scale)", 0) < 0 ||
        plot_axis(p, PLOT_Y, "difference angle \xce\xb8_{d} (\xc2\xb0)", 0) < 0 ||
        plot_axis_ticks(p, PLOT_X, 7, at, label) < 0)
        return -1;
    plot_axis_range(p, PLOT_X, 0.0, 1.0);
    plot_axis_range(p, PLOT_Y, 0.0, 90.0);
    plot_axis_step(p, PLOT_Y, 15.0);
    return 0;
}

/* A figure's colour scale: the map from a value to a colour (colour(v, a, b, rgb)), and
 * the bar beside the figure (its title, range, log or not, and table of colours). */
typedef struct scale {
    void (*color)(double v, double a, double b, unsigned char *rgb);
    double a, b;
    const char *bar;
    double lo, hi;
    int log;
    unsigned char lut[PLOT_LUT][3];
} scale;

/* sc's colour of v for every pixel, rows flipped so that theta_d grows upwards. */
static unsigned char *raster(const double *v, int w, int h, const scale *sc)
{
    unsigned char *px = malloc((size_t)w * (size_t)h * 3);
    for (int j = 0; px && j < h; j++)
        for (int i = 0; i < w; i++)
            sc->color(v[(size_t)(h - 1 - j) * (size_t)w + (size_t)i], sc->a, sc->b,
                      px + 3 * ((size_t)j * (size_t)w + (size_t)i));
    return px;
}

static void value_color(double v, double lo, double hi, unsigned char *rgb)
{
    if (!(v > 0.0)) { /* no value (or 0: nothing to put on a log scale) */
        rgb[0] = rgb[1] = rgb[2] = HALFDIFF_NONE;
        return;
    }
    halfdiff_sequential((log10(v) - lo) / (hi - lo), rgb);
}

static void ratio_color(double r, double span, double unused, unsigned char *rgb)
{
    (void)unused;
    halfdiff_diverging(isnan(r) ? NAN : r / span, rgb);
}

void halfdiff_ratio_raster(const double *r, int w, int h, double span, unsigned char *rgb)
{
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++)
            ratio_color(r[(size_t)(h - 1 - j) * (size_t)w + (size_t)i], span, 0.0,
                        rgb + 3 * ((size_t)j * (size_t)w + (size_t)i));
}

/* The figure around a w x h raster px (taken, and freed), with sc's colour bar. */
static plot *figure(const char *title, unsigned char *px, int w, int h, const scale *sc)
{
    plot *p = plot_new(title);
    if (!p || !px || theta_h_axis(p) < 0 || plot_raster(p, w, h, px) < 0 ||
        plot_color_bar(p, sc->bar, sc->lo, sc->hi, sc->log, sc->lut) < 0) {
        plot_free(p);
        p = NULL;
    }
    free(px);
    return p;
}

#define VALUE_BAR "BRDF f (sr^{-1})"
#define RATIO_BAR "log_{2}(model / measured)"

/* The log scale of values on [log10_lo, log10_hi]. */
static void value_scale(double log10_lo, double log10_hi, scale *sc)
{
    *sc = (scale){value_color, log10_lo, log10_hi, VALUE_BAR, pow(10.0, log10_lo), pow(10.0, log10_hi), 1, {{0}}};
    for (int k = 0; k < PLOT_LUT; k++)
        halfdiff_sequential((double)k / (PLOT_LUT - 1), sc->lut[k]);
}

/* The diverging scale of log2 ratios on +-span. */
static void ratio_scale(double span, scale *sc)
{
    *sc = (scale){ratio_color, span, 0.0, RATIO_BAR, -span, span, 0, {{0}}};
    for (int k = 0; k < PLOT_LUT; k++)
        halfdiff_diverging(2.0 * k / (PLOT_LUT - 1) - 1.0, sc->lut[k]);
}

plot *halfdiff_value_figure(const double *v, int w, int h, const char *title, double log10_lo, double log10_hi)
{
    scale sc;
    value_scale(log10_lo, log10_hi, &sc);
    return figure(title, raster(v, w, h, &sc), w, h, &sc);
}

plot *halfdiff_ratio_figure(const double *r, int w, int h, const char *title, double span)
{
    scale sc;
    ratio_scale(span, &sc);
    return figure(title, raster(r, w, h, &sc), w, h, &sc);
}

void halfdiff_angles(const double dir[4], double *theta_h, double *theta_d)
{
    const double rad = M_PI / 180.0;
    double L[3] = {sin(dir[0] * rad) * cos(dir[1] * rad), sin(dir[0] * rad) * sin(dir[1] * rad), cos(dir[0] * rad)};
    double V[3] = {sin(dir[2] * rad) * cos(dir[3] * rad), sin(dir[2] * rad) * sin(dir[3] * rad), cos(dir[2] * rad)};
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    if (!(H[0] * H[0] + H[1] * H[1] + H[2] * H[2] > 1e-24)) {
        *theta_h = *theta_d = NAN;
        return;
    }
    /* atan2 rather than acos: exact near the mirror direction, where acos(hz) loses
     * theta_h, and the sqrt axis stretches small theta_h most. */
    *theta_h = atan2(hypot(H[0], H[1]), H[2]) / rad;
    /* The angle between L and H from both its sine and cosine: exact near 0 too. */
    double cx = L[1] * H[2] - L[2] * H[1], cy = L[2] * H[0] - L[0] * H[2], cz = L[0] * H[1] - L[1] * H[0];
    *theta_d = atan2(sqrt(cx * cx + cy * cy + cz * cz), L[0] * H[0] + L[1] * H[1] + L[2] * H[2]) / rad;
}

typedef struct keyed {
    double key;
    size_t i;
} keyed;

static int cmp_keyed(const void *a, const void *b)
{
    const keyed *x = a, *y = b;
    if (x->key != y->key)
        return x->key < y->key ? -1 : 1;
    return (x->i > y->i) - (x->i < y->i);
}

size_t halfdiff_point_order(size_t n, const double *key, size_t *idx)
{
    keyed *k = malloc((n ? n : 1) * sizeof *k);
    size_t m = 0;
    if (!k) { /* out of memory: by index, which is deterministic too */
        for (size_t p = 0; p < n; p++)
            if (!isnan(key[p]))
                idx[m++] = p;
        return m;
    }
    for (size_t p = 0; p < n; p++)
        if (!isnan(key[p]))
            k[m++] = (keyed){key[p], p};
    qsort(k, m, sizeof *k, cmp_keyed);
    for (size_t p = 0; p < m; p++)
        idx[p] = k[p].i;
    free(k);
    return m;
}

/* The samples a points figure draws: n of them at half angle th and difference angle td
 * (degrees), value v, drawn in order of key (NaN: left out). */
typedef struct samples_on_axes {
    size_t n;
    const double *th, *td, *v, *key;
} samples_on_axes;

/* The points figure: the table figure's axes and colour bar over a one-cell grey raster
 * (no sample there), and one marker per sample, in sc's colour. */
static plot *points(const samples_on_axes *in, const char *title, const scale *sc)
{
    const size_t n = in->n;
    const double *th = in->th, *td = in->td, *v = in->v;
    size_t *idx = malloc((n ? n : 1) * sizeof *idx);
    double *xy = malloc(2 * (n ? n : 1) * sizeof *xy);
    unsigned char *rgb = malloc(3 * (n ? n : 1)), *grey = malloc(3);
    plot *p = NULL;
    if (idx && xy && rgb && grey) {
        grey[0] = grey[1] = grey[2] = HALFDIFF_NONE;
        p = figure(title, grey, 1, 1, sc);
        grey = NULL; /* figure took it */
    }
    if (p) {
        /* A little beyond 0..90: samples on an edge (theta_d 0, theta_h 0 or 90, as 1-D
         * slices have) show whole rather than half hidden under the frame. */
        plot_axis_range(p, PLOT_X, -0.02, 1.02);
        plot_axis_range(p, PLOT_Y, -2.0, 92.0);
        size_t m = halfdiff_point_order(n, in->key, idx);
        double *x = xy, *y = xy + m;
        for (size_t k = 0; k < m; k++) {
            size_t i = idx[k];
            x[k] = sqrt(fmin(fmax(th[i], 0.0), 90.0) / 90.0);
            y[k] = fmin(fmax(td[i], 0.0), 90.0);
            sc->color(v[i], sc->a, sc->b, rgb + 3 * k);
        }
        plot_series *s = plot_add(p, NULL, PLOT_MARKERS, m, x, y);
        if (s) {
            /* Full size (5 px across at 340x280) when few, smaller as they get many,
             * so that a few thousand still show as points rather than a blot. */
            s->marker_size = m > 400 ? fmax(0.4, sqrt(400.0 / (double)m)) : 1.0;
        }
        if (!s || plot_point_colors(s, rgb) < 0) {
            plot_free(p);
            p = NULL;
        }
    }
    free(idx);
    free(xy);
    free(rgb);
    free(grey);
    return p;
}

/* Whether sample i has a place on the axes. */
static int placeable(const double *th, const double *td, size_t i)
{
    return isfinite(th[i]) && isfinite(td[i]);
}

plot *halfdiff_value_points(size_t n, const double *theta_h, const double *theta_d, const double *v, const char *title,
                            double log10_lo, double log10_hi)
{
    double *key = malloc((n ? n : 1) * sizeof *key);
    if (!key)
        return NULL;
    for (size_t i = 0; i < n; i++)
        key[i] = placeable(theta_h, theta_d, i) && v[i] > 0.0 && isfinite(v[i]) ? v[i] : NAN;
    scale sc;
    value_scale(log10_lo, log10_hi, &sc);
    plot *p = points(&(samples_on_axes){n, theta_h, theta_d, v, key}, title, &sc);
    free(key);
    return p;
}

plot *halfdiff_ratio_points(size_t n, const double *theta_h, const double *theta_d, const double *r, const char *title,
                            double span)
{
    double *key = malloc((n ? n : 1) * sizeof *key);
    if (!key)
        return NULL;
    for (size_t i = 0; i < n; i++)
        key[i] = placeable(theta_h, theta_d, i) && !isnan(r[i]) ? fabs(r[i]) : NAN;
    scale sc;
    ratio_scale(span, &sc);
    plot *p = points(&(samples_on_axes){n, theta_h, theta_d, r, key}, title, &sc);
    free(key);
    return p;
}

/* Positional, as bf_render_halfdiff_model and _merl: the source, the angle and scale,
 * the figure's size and its file (bf_halfdiff_options carries the command's defaults). */
bf_status bf_render_halfdiff_plot(const bf_model *m, const double *x, const bf_samples *merl, double phi_d,
                                  double decades, int width, int height, const char *path, int format, bf_error *err)
{
    enum { PX = 180 }; /* two columns and rows per MERL cell */
    int fmt = format ? format : bf_plot_format_of(path);
    if (!fmt)
        return bf_fail(err, BF_ERR_ARG, "%s: unknown plot format (.png, .svg or .pdf)", path ? path : "-");
    if (!(decades > 0.0))
        return bf_fail(err, BF_ERR_ARG, "half/difference plot: decades must be > 0");
    if (width < 40 || height < 40 || width > BF_RENDER_MAX_SIDE || height > BF_RENDER_MAX_SIDE)
        return bf_fail(err, BF_ERR_ARG, "half/difference plot: bad size %dx%d (each side 40 to %d)", width, height,
                       BF_RENDER_MAX_SIDE);
    const size_t npx = (size_t)PX * PX;
    float *rgb = malloc(3 * npx * sizeof *rgb);
    double *v = malloc(npx * sizeof *v);
    if (!rgb || !v) {
        free(rgb);
        free(v);
        return bf_fail(err, BF_ERR_NOMEM, "half/difference plot: out of memory");
    }
    bf_status rc = m ? bf_render_halfdiff_model(m, x, PX, PX, phi_d, rgb, err)
                     : bf_render_halfdiff_merl(merl, PX, PX, phi_d, rgb, err);
    double lo, hi;
    if (rc == BF_OK) {
        halfdiff_mean(rgb, npx, v);
        if (halfdiff_log_range(v, npx, 99.0, decades, &lo, &hi) < 0) {
            lo = -decades; /* nothing positive: every cell shows as no value */
            hi = 0.0;
        }
        char title[512];
        snprintf(title, sizeof title, "\xce\xb8_{h} \xc3\x97 \xce\xb8_{d} of %s at \xcf\x86_{d} = %g\xc2\xb0",
                 m ? bf_model_spec(m) : "the measurement", phi_d);
        plot *p = halfdiff_value_figure(v, PX, PX, title, lo, hi);
        if (!p)
            rc = bf_fail(err, BF_ERR_NOMEM, "half/difference plot: out of memory");
        else if (plot_note(p, "mean of the channels; scale: the 99th percentile and down; grey: no value") < 0)
            rc = bf_fail(err, BF_ERR_NOMEM, "half/difference plot: out of memory");
        if (rc == BF_OK)
            rc = plot_write(p, path, (bf_plot_format)fmt, width, height, err);
        plot_free(p);
    }
    free(rgb);
    free(v);
    return rc;
}
