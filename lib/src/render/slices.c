/* In-plane BRDF slices as a plot (plot/plot.h): f on a log axis against signed
 * theta_o, one line per incidence angle and channel, measured samples as markers. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/render.h"
#include "colour.h"
#include "plot/plot.h"
#include "render/slices.h"

#define SLICE_POINTS 361 /* every half degree */
#define SLICE_MAX_SHOWN 400
#define SLICE_DECADES 8.0

/* In-plane viewing direction for a signed theta_o (degrees): positive on the mirror side. */
static void view_angles(double signed_to, double *to, double *po)
{
    *to = fabs(signed_to);
    *po = signed_to >= 0.0 ? 180.0 : 0.0;
}

static bf_status check(const bf_slice_options *o, bf_error *err)
{
    if (!o || o->nincidence < 1 || o->nincidence > BF_SLICE_MAX_INCIDENCE || !o->incidence)
        return bf_fail(err, BF_ERR_ARG, "slice plot: 1 to %d incidence angles", BF_SLICE_MAX_INCIDENCE);
    for (int k = 0; k < o->nincidence; k++)
        if (!(o->incidence[k] >= 0.0 && o->incidence[k] < 90.0))
            return bf_fail(err, BF_ERR_ARG, "slice plot: incidence angle %g is not in [0, 90)", o->incidence[k]);
    return BF_OK;
}

void slice_data_free(slice_data *d)
{
    if (!d)
        return;
    free(d->theta);
    free(d->f);
    free(d->st);
    free(d->sf);
    free(d->sk);
    memset(d, 0, sizeof *d);
}

/* The in-plane position of sample q: its incidence index (-1: none) and signed theta_o. */
static int in_plane(const bf_samples *s, size_t q, const bf_slice_options *o, double *t)
{
    double dir[4]; /* theta_i, phi_i, theta_o, phi_o */
    bf_samples_direction(s, q, dir);
    int k = 0;
    while (k < o->nincidence && !(fabs(dir[0] - o->incidence[k]) <= o->plane_tol))
        k++;
    if (k == o->nincidence)
        return -1;
    double d = (dir[3] - dir[1]) * (M_PI / 180.0);
    double off = asin(fmin(1.0, fabs(sin(dir[2] * (M_PI / 180.0)) * sin(d)))) * (180.0 / M_PI);
    if (!(off <= o->plane_tol) || !(dir[2] < 90.0))
        return -1;
    *t = cos(d) < 0.0 ? dir[2] : -dir[2];
    return k;
}

bf_status slice_data_compute(const bf_model *m, const double *x, const bf_slice_options *o, slice_data *d, bf_error *err)
{
    memset(d, 0, sizeof *d);
    int rc = check(o, err);
    if (rc != BF_OK)
        return rc;
    int nk = o->nincidence, C = bf_model_channels(m);
    d->nch = C == 3 ? 3 : 1;
    d->npoints = SLICE_POINTS;
    size_t n = (size_t)SLICE_POINTS * (size_t)nk;
    double *ang = malloc(4 * n * sizeof *ang), *f = malloc(n * (size_t)C * sizeof *f);
    d->theta = malloc(SLICE_POINTS * sizeof *d->theta);
    d->f = malloc(n * 3 * sizeof *d->f);
    bf_geometry *g = NULL;
    if (!ang || !f || !d->theta || !d->f) {
        rc = bf_fail(err, BF_ERR_NOMEM, "slice plot: out of memory");
        goto done;
    }
    for (int i = 0; i < SLICE_POINTS; i++)
        d->theta[i] = -90.0 + 180.0 * i / (SLICE_POINTS - 1);
    for (int k = 0; k < nk; k++)
        for (int i = 0; i < SLICE_POINTS; i++) {
            size_t q = (size_t)k * SLICE_POINTS + (size_t)i;
            double to, po;
            view_angles(d->theta[i], &to, &po);
            ang[q] = o->incidence[k] * (M_PI / 180.0);
            ang[n + q] = 0.0;
            ang[2 * n + q] = to * (M_PI / 180.0);
            ang[3 * n + q] = po * (M_PI / 180.0);
        }
    if ((rc = bf_geometry_from_angles(n, ang, ang + n, ang + 2 * n, ang + 3 * n, &g, err)) != BF_OK) {
        goto done;
    }
    bf_model_eval(m, x, g, f, NULL);
    for (size_t q = 0; q < n; q++)
        bf_channels_to_rgb(f + q * (size_t)C, C, d->f + 3 * q);
    /* The in-plane samples, values as the model's channels are shown. */
    const bf_samples *s = o->samples;
    if (s && s->n) {
        d->st = malloc(s->n * sizeof *d->st);
        d->sf = malloc(3 * s->n * sizeof *d->sf);
        d->sk = malloc(s->n * sizeof *d->sk);
        if (!d->st || !d->sf || !d->sk) {
            rc = bf_fail(err, BF_ERR_NOMEM, "slice plot: out of memory");
            goto done;
        }
        for (size_t q = 0; q < s->n; q++) {
            double t;
            int k = in_plane(s, q, o, &t);
            if (k < 0)
                continue;
            d->st[d->ns] = t;
            d->sk[d->ns] = k;
            bf_channels_to_rgb(s->value + q * (size_t)s->channels, s->channels, d->sf + 3 * d->ns);
            d->ns++;
        }
    }
    /* Extent: positive finite values, at most SLICE_DECADES below the largest. */
    double lo = INFINITY, hi = -INFINITY;
    for (size_t q = 0; q < n; q++)
        for (int ch = 0; ch < d->nch; ch++) {
            double v = d->f[3 * q + (size_t)ch];
            if (v > 0.0 && isfinite(v)) {
                lo = fmin(lo, log10(v));
                hi = fmax(hi, log10(v));
            }
        }
    for (size_t q = 0; q < d->ns; q++)
        for (int ch = 0; ch < d->nch; ch++) {
            double v = d->sf[3 * q + (size_t)ch];
            if (v > 0.0 && isfinite(v)) {
                lo = fmin(lo, log10(v));
                hi = fmax(hi, log10(v));
            }
        }
    if (!(lo <= hi))
        lo = hi = -1.0; /* nothing positive: an arbitrary decade */
    d->log10_lo = fmax(lo, hi - SLICE_DECADES);
    d->log10_hi = hi;
done:
    bf_geometry_free(g);
    free(ang);
    free(f);
    if (rc != BF_OK)
        slice_data_free(d);
    return rc;
}

bf_status bf_slice_extent(const bf_model *m, const double *x, const bf_slice_options *o, double *log10_lo,
                    double *log10_hi, bf_error *err)
{
    slice_data d;
    int rc = slice_data_compute(m, x, o, &d, err);
    if (rc == BF_OK) {
        *log10_lo = d.log10_lo;
        *log10_hi = d.log10_hi;
    }
    slice_data_free(&d);
    return rc;
}

static const char *const channel_name[3] = {"R", "G", "B"};
static const plot_dash channel_dash[3] = {PLOT_SOLID, PLOT_DASHED, PLOT_DOTTED};
static const plot_marker channel_marker[3] = {PLOT_CIRCLE, PLOT_SQUARE, PLOT_TRIANGLE};

/* A legend-only entry (no points). */
static int legend_entry(plot *p, const char *name, plot_style style, const double rgb[3], plot_dash dash,
                        plot_marker mk)
{
    plot_series *s = plot_add(p, name, style, 0, NULL, NULL);
    if (!s)
        return -1;
    memcpy(s->rgb, rgb, sizeof s->rgb);
    s->dash = dash;
    s->marker = mk;
    return 0;
}

static int build(const bf_slice_options *o, const slice_data *d, plot *p, bf_slice_range *range)
{
    char text[256];
    int nk = o->nincidence, nch = d->nch;
    double *y = malloc(SLICE_POINTS * sizeof *y);
    if (!y)
        return -1;
    double lo = d->log10_lo, hi = d->log10_hi;
    if (o->log10_lo < o->log10_hi) {
        lo = o->log10_lo;
        hi = o->log10_hi;
    } else {
        double a, b;
        plot_pad(pow(10.0, lo), pow(10.0, hi), 1, 1, &a, &b);
        lo = log10(a);
        hi = log10(b);
    }
    if (plot_axis(p, PLOT_X, "viewing angle \xce\xb8_{o} in the plane of incidence (\xc2\xb0; + mirror side)", 0) < 0 ||
        plot_axis(p, PLOT_Y, "BRDF f (sr^{-1})", 1) < 0) {
        free(y);
        return -1;
    }
    plot_axis_range(p, PLOT_X, -90.0, 90.0);
    plot_axis_step(p, PLOT_X, 30.0);
    plot_axis_range(p, PLOT_Y, pow(10.0, lo), pow(10.0, hi));
    int fail = 0;
    for (int k = 0; k < nk && !fail; k++) {
        double rgb[3], light[3];
        plot_palette(k, rgb);
        for (int q = 0; q < 3; q++)
            light[q] = 0.45 * rgb[q] + 0.55;
        fail |= plot_guide(p, PLOT_X, o->incidence[k], light) < 0; /* the mirror direction */
        for (int ch = 0; ch < nch && !fail; ch++) {
            for (int i = 0; i < SLICE_POINTS; i++)
                y[i] = d->f[3 * ((size_t)k * SLICE_POINTS + (size_t)i) + (size_t)ch];
            snprintf(text, sizeof text, "\xce\xb8_{i} = %g\xc2\xb0", o->incidence[k]);
            plot_series *s = plot_add(p, ch == 0 ? text : NULL, PLOT_LINE, SLICE_POINTS, d->theta, y);
            if (!(fail = !s)) {
                memcpy(s->rgb, rgb, sizeof s->rgb);
                s->dash = nch == 3 ? channel_dash[ch] : PLOT_SOLID;
            }
        }
    }
    free(y);
    if (fail)
        return -1;
    /* Channels, when they differ by line style. */
    const double black[3] = {0, 0, 0};
    for (int ch = 0; nch == 3 && ch < 3; ch++) {
        snprintf(text, sizeof text, "channel %s", channel_name[ch]);
        if (legend_entry(p, text, d->ns ? PLOT_LINE_MARKERS : PLOT_LINE, black, channel_dash[ch], channel_marker[ch]) <
            0)
            return -1;
    }
    /* Measured samples, thinned to SLICE_MAX_SHOWN per incidence angle. */
    size_t shown = 0;
    if (d->ns) {
        double *sx = malloc(2 * d->ns * sizeof *sx);
        if (!sx)
            return -1;
        double *sy = sx + d->ns;
        for (int k = 0; k < nk && !fail; k++) {
            size_t count = 0;
            for (size_t q = 0; q < d->ns; q++)
                count += d->sk[q] == k;
            size_t stride = count > SLICE_MAX_SHOWN ? (count + SLICE_MAX_SHOWN - 1) / SLICE_MAX_SHOWN : 1;
            double rgb[3];
            plot_palette(k, rgb);
            for (int ch = 0; ch < nch && !fail; ch++) {
                size_t n = 0, seen = 0;
                for (size_t q = 0; q < d->ns; q++) {
                    if (d->sk[q] != k || seen++ % stride)
                        continue;
                    sx[n] = d->st[q];
                    sy[n] = d->sf[3 * q + (size_t)ch];
                    n++;
                }
                if (ch == 0)
                    shown += n;
                plot_series *s = plot_add(p, NULL, PLOT_MARKERS, n, sx, sy);
                if (!(fail = !s)) {
                    memcpy(s->rgb, rgb, sizeof s->rgb);
                    s->alpha = 0.55;
                    s->marker = nch == 3 ? channel_marker[ch] : PLOT_CIRCLE;
                    s->marker_size = 0.7;
                }
            }
        }
        free(sx);
        if (fail)
            return -1;
        const double grey[3] = {0.35, 0.35, 0.35};
        if (shown < d->ns)
            snprintf(text, sizeof text, "measured (%zu of %zu)", shown, d->ns);
        else
            snprintf(text, sizeof text, "measured (%zu)", d->ns);
        if (legend_entry(p, text, PLOT_MARKERS, grey, PLOT_SOLID, PLOT_CIRCLE) < 0)
            return -1;
    }
    if (o->samples) {
        snprintf(text, sizeof text, "markers: measured samples within %g\xc2\xb0 of the plane of incidence%s",
                 o->plane_tol, d->ns ? "" : " (none)");
        if (plot_note(p, text) < 0)
            return -1;
    }
    if (range) {
        range->log10_lo = lo;
        range->log10_hi = hi;
        range->overlaid = d->ns;
        range->shown = shown;
    }
    return 0;
}

bf_status slice_plot_build(const bf_model *m, const double *x, const bf_slice_options *o, plot **out,
                     bf_slice_range *range, bf_error *err)
{
    *out = NULL;
    slice_data d;
    int rc = slice_data_compute(m, x, o, &d, err);
    if (rc != BF_OK)
        return rc;
    char title[512];
    if (o->title)
        snprintf(title, sizeof title, "%s", o->title);
    else
        snprintf(title, sizeof title, "In-plane slices of %s", bf_model_spec(m));
    plot *p = plot_new(title);
    if (!p || build(o, &d, p, range) < 0) {
        plot_free(p);
        rc = bf_fail(err, BF_ERR_NOMEM, "slice plot: out of memory");
    } else
        *out = p;
    slice_data_free(&d);
    return rc;
}

bf_status bf_render_slice(const bf_model *m, const double *x, const bf_slice_options *o, const char *path, int format,
                    bf_slice_range *range, bf_error *err)
{
    if (!o || o->width < 40 || o->height < 40)
        return bf_fail(err, BF_ERR_ARG, "slice plot: the plot must be at least 40x40");
    int fmt = format ? format : bf_plot_format_of(path);
    if (!fmt)
        return bf_fail(err, BF_ERR_ARG, "%s: unknown plot format (.png, .svg or .pdf)", path ? path : "-");
    plot *p;
    int rc = slice_plot_build(m, x, o, &p, range, err);
    if (rc == BF_OK)
        rc = plot_write(p, path, (bf_plot_format)fmt, o->width, o->height, err);
    plot_free(p);
    return rc;
}
