/* In-plane BRDF slices as a plot (plot/plot.h): f on a log axis against signed
 * theta_o, one line per incidence angle and channel, measured samples as markers. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/sized.h"
#include "brdfit/render.h"
#include "color.h"
#include "plot/plot.h"
#include "render/slices.h"

#define SLICE_POINTS 361 /* every half degree */
#define SLICE_BINS 180   /* overlaid samples: at most one per degree of theta_o and incidence */
#define SLICE_DECADES 8.0

/* In-plane viewing direction for a signed theta_o (degrees): positive on the mirror side. */
static void view_angles(double signed_to, double *to, double *po)
{
    *to = fabs(signed_to);
    *po = signed_to >= 0.0 ? 180.0 : 0.0;
}

/* bf_slice_options with the library's defaults (a whole struct of this version). */
static void slice_options_defaults(bf_slice_options *o)
{
    static const double incidence[] = {0.0, 30.0, 60.0};
    o->width = 640;
    o->height = 480;
    o->incidence = incidence;
    o->nincidence = 3;
    o->plane_tol = 2.0;
}

BF_SIZED_INIT(bf_slice_options, slice_options_defaults)

BF_SIZED_INIT_ZERO(bf_slice_range)

static bf_status check(const bf_slice_options *o, bf_error *err)
{
    if (o && bf_sized_check(o, sizeof *o, "bf_slice_options", err) != BF_OK)
        return BF_ERR_ARG;
    if (!o || o->nincidence < 1 || o->nincidence > BF_SLICE_MAX_INCIDENCE || !o->incidence)
        return bf_fail(err, BF_ERR_ARG, "slice plot: 1 to %d incidence angles", BF_SLICE_MAX_INCIDENCE);
    for (int k = 0; k < o->nincidence; k++)
        if (!(o->incidence[k] >= 0.0 && o->incidence[k] < 90.0))
            return bf_fail(err, BF_ERR_ARG, "slice plot: incidence angle %g is not in [0, 90)", o->incidence[k]);
    return BF_OK;
}

void slice_data_clear(slice_data *d)
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

bf_status slice_data_compute(const bf_model *m, const double *x, const bf_slice_options *o, slice_data *d,
                             bf_error *err)
{
    memset(d, 0, sizeof *d);
    bf_status rc = check(o, err);
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
    double sample_lo = INFINITY;
    for (size_t q = 0; q < d->ns; q++)
        for (int ch = 0; ch < d->nch; ch++) {
            double v = d->sf[3 * q + (size_t)ch];
            if (v > 0.0 && isfinite(v)) {
                sample_lo = fmin(sample_lo, log10(v));
                hi = fmax(hi, log10(v));
            }
        }
    lo = fmin(lo, sample_lo);
    if (!(lo <= hi))
        lo = hi = -1.0; /* nothing positive: an arbitrary decade */
    /* With measurements, a curve's dip far below all of them (a model dark at grazing
     * angles) would squeeze the data into a sliver: the axis ends a decade under them. */
    d->log10_lo = fmax(fmax(lo, hi - SLICE_DECADES), isfinite(sample_lo) ? sample_lo - 1.0 : -INFINITY);
    d->log10_hi = hi;
done:
    bf_geometry_free(g);
    free(ang);
    free(f);
    if (rc != BF_OK)
        slice_data_clear(d);
    return rc;
}

bf_status bf_slice_extent(const bf_model *m, const double *x, const bf_slice_options *o, double *log10_lo,
                          double *log10_hi, bf_error *err)
{
    slice_data d;
    bf_status rc = slice_data_compute(m, x, o, &d, err);
    if (rc == BF_OK) {
        *log10_lo = d.log10_lo;
        *log10_hi = d.log10_hi;
    }
    slice_data_clear(&d);
    return rc;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int bf_slice_incidences(const bf_samples *s, const double *want, int nwant, double *out)
{
    int n = 0;
    for (int w = 0; s && s->n && w < nwant && n < BF_SLICE_MAX_INCIDENCE; w++) {
        double best = NAN;
        for (size_t q = 0; q < s->n; q++) {
            double dir[4];
            bf_samples_direction(s, q, dir);
            if (dir[0] >= 0.0 && dir[0] < 90.0 && !(fabs(dir[0] - want[w]) >= fabs(best - want[w])))
                best = dir[0];
        }
        if (isnan(best))
            break; /* no sample has an incidence below 90 degrees */
        /* To a tenth of a degree: a readable label, still inside any plane tolerance. */
        double v = fmin(round(best * 10.0) / 10.0, 89.9);
        int seen = 0;
        for (int k = 0; k < n; k++)
            seen |= out[k] == v;
        if (!seen)
            out[n++] = v;
    }
    qsort(out, (size_t)n, sizeof *out, cmp_double);
    return n;
}

/* Curves that are the same (every channel within 1e-9 relative) as an earlier one:
 * group[k] is the first incidence with k's curve. A Lambert surface has one curve for
 * every incidence, drawn once and named for all of them, not hidden under the last. */
static void same_curves(const slice_data *d, int nk, int *group)
{
    size_t np = (size_t)d->npoints;
    for (int k = 0; k < nk; k++) {
        group[k] = k;
        for (int e = 0; e < k && group[k] == k; e++) {
            if (group[e] != e)
                continue;
            int same = 1;
            for (size_t i = 0; i < 3 * np && same; i++) {
                double a = d->f[3 * np * (size_t)k + i], b = d->f[3 * np * (size_t)e + i];
                same = a == b || fabs(a - b) <= 1e-9 * fmax(fabs(a), fabs(b));
            }
            if (same)
                group[k] = e;
        }
    }
}

/* Which in-plane samples are drawn: all of an incidence angle's when they are few (at
 * most SLICE_BINS / 2); else in each 1-degree bin of theta_o the sample nearest the bin's
 * centre (ties: the earlier). Dense data (a MERL table has thousands in the plane) would
 * otherwise bury the curves; an even spread over the angles keeps the data's shape.
 * shown[q] = 1 for those; returns how many. */
static size_t thin_samples(const slice_data *d, int nk, unsigned char *shown)
{
    size_t nb = (size_t)nk * SLICE_BINS, count = 0, per[BF_SLICE_MAX_INCIDENCE] = {0};
    size_t *pick = malloc(nb * sizeof *pick);
    if (!pick)
        return (size_t)-1;
    for (size_t b = 0; b < nb; b++)
        pick[b] = (size_t)-1;
    for (size_t q = 0; q < d->ns; q++)
        per[d->sk[q]]++;
    memset(shown, 0, d->ns);
    for (size_t q = 0; q < d->ns; q++)
        if (per[d->sk[q]] <= SLICE_BINS / 2) {
            shown[q] = 1;
            count++;
        }
    for (size_t q = 0; q < d->ns; q++) {
        if (shown[q])
            continue;
        double u = (d->st[q] + 90.0) / 180.0 * SLICE_BINS;
        int bin = (int)floor(u);
        bin = bin < 0 ? 0 : bin >= SLICE_BINS ? SLICE_BINS - 1 : bin;
        size_t b = (size_t)d->sk[q] * SLICE_BINS + (size_t)bin, *p = &pick[b];
        double off = fabs(u - (bin + 0.5));
        if (*p == (size_t)-1 || off < fabs((d->st[*p] + 90.0) / 180.0 * SLICE_BINS - (bin + 0.5)))
            *p = q;
    }
    for (size_t b = 0; b < nb; b++)
        if (pick[b] != (size_t)-1) {
            shown[pick[b]] = 1;
            count++;
        }
    free(pick);
    return count;
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

/* The measured samples of incidence group g (group[k] for each of the nk incidences; as
 * shown[] picks them), one series per channel, translucent under the curves; xy holds
 * 2 d->ns doubles. Returns how many samples, or -1. */
static long sample_series(plot *p, const slice_data *d, int nk, const int *group, int g, const unsigned char *shown,
                          double *xy)
{
    double *sx = xy, *sy = xy + d->ns;
    long count = 0;
    double rgb[3];
    plot_palette(g, rgb);
    for (int ch = 0; ch < d->nch; ch++) {
        size_t n = 0;
        for (size_t q = 0; q < d->ns; q++) {
            if (!shown[q] || d->sk[q] >= nk || group[d->sk[q]] != g)
                continue;
            sx[n] = d->st[q];
            sy[n] = d->sf[3 * q + (size_t)ch];
            n++;
        }
        if (ch == 0)
            count = (long)n;
        if (!n)
            continue;
        plot_series *s = plot_add(p, NULL, PLOT_MARKERS, n, sx, sy);
        if (!s)
            return -1;
        memcpy(s->rgb, rgb, sizeof s->rgb);
        s->alpha = 0.45;
        s->marker = d->nch == 3 ? channel_marker[ch] : PLOT_CIRCLE;
        s->marker_size = 0.6;
    }
    return count;
}

/* The legend name of incidence group g, its angles; returns how many. */
static int group_name(const bf_slice_options *o, const int *group, int g, char *text, size_t size)
{
    int members = 0;
    size_t at = (size_t)snprintf(text, size, "\xce\xb8_{i} = ");
    for (int k = 0; k < o->nincidence && at < size; k++)
        if (group[k] == g)
            at += (size_t)snprintf(text + at, size - at, "%s%g\xc2\xb0", members++ ? ", " : "", o->incidence[k]);
    return members;
}

/* The value range (the options' own, or the data's padded), the axes and a guide at
 * each incidence's mirror direction; 0, or -1 out of memory. */
static int axes(const bf_slice_options *o, const slice_data *d, const int *group, plot *p, double *lo, double *hi)
{
    *lo = d->log10_lo;
    *hi = d->log10_hi;
    if (o->log10_lo < o->log10_hi) {
        *lo = o->log10_lo;
        *hi = o->log10_hi;
    } else {
        double a, b;
        plot_pad(pow(10.0, *lo), pow(10.0, *hi), 1, 1, &a, &b);
        *lo = log10(a);
        *hi = log10(b);
    }
    if (plot_axis(p, PLOT_X, "viewing angle \xce\xb8_{o} in the plane of incidence (\xc2\xb0; + mirror side)", 0) < 0 ||
        plot_axis(p, PLOT_Y, "BRDF f (sr^{-1})", 1) < 0)
        return -1;
    plot_axis_range(p, PLOT_X, -90.0, 90.0);
    plot_axis_step(p, PLOT_X, 30.0);
    plot_axis_range(p, PLOT_Y, pow(10.0, *lo), pow(10.0, *hi));
    for (int k = 0; k < o->nincidence; k++) {
        double rgb[3], light[3];
        plot_palette(group[k], rgb);
        for (int q = 0; q < 3; q++)
            light[q] = 0.45 * rgb[q] + 0.55;
        if (plot_guide(p, PLOT_X, o->incidence[k], light) < 0) /* the mirror direction */
            return -1;
    }
    return 0;
}

/* The measured samples, one series per group of incidences, thinned; how many are
 * shown, or (size_t)-1 out of memory. */
static size_t measured(const slice_data *d, int nk, const int *group, plot *p)
{
    unsigned char *pick = malloc(d->ns);
    double *sx = malloc(2 * d->ns * sizeof *sx);
    size_t shown = pick && sx ? thin_samples(d, nk, pick) : (size_t)-1;
    for (int g = 0; g < nk && shown != (size_t)-1; g++)
        if (group[g] == g && sample_series(p, d, nk, group, g, pick, sx) < 0)
            shown = (size_t)-1;
    free(pick);
    free(sx);
    return shown;
}

/* The model's curves: one per group of incidences that give the same curve, one line
 * per channel, named by the group's angles; 0, or -1 out of memory. */
static int curves(const bf_slice_options *o, const slice_data *d, const int *group, plot *p)
{
    const int nk = o->nincidence, nch = d->nch;
    char text[256];
    double *y = malloc(SLICE_POINTS * sizeof *y);
    if (!y)
        return -1;
    int fail = 0;
    for (int k = 0; k < nk && !fail; k++) {
        if (group[k] != k)
            continue; /* the same curve as an earlier incidence: drawn and named there */
        double rgb[3];
        plot_palette(k, rgb);
        /* Said under the plot, not in the legend: a long entry would push the legend
         * into the plot area and make this panel unlike its neighbours. */
        if (group_name(o, group, k, text, sizeof text) > 1) {
            char note[320];
            snprintf(note, sizeof note, "%s: the same curve, drawn once", text);
            fail |= plot_note(p, note) < 0;
        }
        for (int ch = 0; ch < nch && !fail; ch++) {
            for (int i = 0; i < SLICE_POINTS; i++)
                y[i] = d->f[3 * ((size_t)k * SLICE_POINTS + (size_t)i) + (size_t)ch];
            plot_series *s = plot_add(p, ch == 0 ? text : NULL, PLOT_LINE, SLICE_POINTS, d->theta, y);
            if (!(fail = !s)) {
                memcpy(s->rgb, rgb, sizeof s->rgb);
                s->dash = nch == 3 ? channel_dash[ch] : PLOT_SOLID;
            }
        }
    }
    free(y);
    return fail ? -1 : 0;
}

/* The legend's entries for the channels (when they differ by line style) and the
 * measured samples, and the note on the markers; 0, or -1 out of memory. */
static int legend(const bf_slice_options *o, const slice_data *d, size_t shown, plot *p)
{
    char text[256];
    const double black[3] = {0, 0, 0};
    for (int ch = 0; d->nch == 3 && ch < 3; ch++) {
        snprintf(text, sizeof text, "channel %s", channel_name[ch]);
        if (legend_entry(p, text, d->ns ? PLOT_LINE_MARKERS : PLOT_LINE, black, channel_dash[ch], channel_marker[ch]) <
            0)
            return -1;
    }
    if (d->ns) {
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
                 o->plane_tol, d->ns ? (shown < d->ns ? ", one per degree of \xce\xb8_{o}" : "") : " (none)");
        if (plot_note(p, text) < 0)
            return -1;
    }
    return 0;
}

static int build(const bf_slice_options *o, const slice_data *d, plot *p, bf_slice_range *range)
{
    int group[BF_SLICE_MAX_INCIDENCE];
    double lo, hi;
    same_curves(d, o->nincidence, group);
    if (axes(o, d, group, p, &lo, &hi) < 0)
        return -1;
    /* Measured samples first, so the curves are drawn over them. */
    size_t shown = d->ns ? measured(d, o->nincidence, group, p) : 0;
    if (shown == (size_t)-1 || curves(o, d, group, p) < 0 || legend(o, d, shown, p) < 0)
        return -1;
    range->log10_lo = lo;
    range->log10_hi = hi;
    range->overlaid = d->ns;
    range->shown = shown;
    return 0;
}

bf_status slice_plot_build(const bf_model *m, const double *x, const bf_slice_options *o, plot **out,
                           bf_slice_range *range, bf_error *err)
{
    *out = NULL;
    if (range && bf_sized_check(range, sizeof *range, "bf_slice_range", err) != BF_OK)
        return BF_ERR_ARG;
    slice_data d;
    bf_status rc = slice_data_compute(m, x, o, &d, err);
    if (rc != BF_OK)
        return rc;
    bf_slice_range r;
    bf_slice_range_init(&r);
    char title[512];
    if (o->title)
        snprintf(title, sizeof title, "%s", o->title);
    else
        snprintf(title, sizeof title, "In-plane slices of %s", bf_model_spec(m));
    plot *p = plot_new(title);
    if (!p || build(o, &d, p, &r) < 0) {
        plot_free(p);
        rc = bf_fail(err, BF_ERR_NOMEM, "slice plot: out of memory");
    } else {
        *out = p;
        if (range)
            bf_sized_copy(range, &r, sizeof r);
    }
    slice_data_clear(&d);
    return rc;
}

bf_status bf_render_slice(const bf_model *m, const double *x, const bf_slice_options *o, const char *path, int format,
                          bf_slice_range *range, bf_error *err)
{
    if (o && bf_sized_check(o, sizeof *o, "bf_slice_options", err) != BF_OK)
        return BF_ERR_ARG;
    if (!o || o->width < 40 || o->height < 40)
        return bf_fail(err, BF_ERR_ARG, "slice plot: the plot must be at least 40x40");
    int fmt = format ? format : bf_plot_format_of(path);
    if (!fmt)
        return bf_fail(err, BF_ERR_ARG, "%s: unknown plot format (.png, .svg or .pdf)", path ? path : "-");
    plot *p;
    bf_status rc = slice_plot_build(m, x, o, &p, range, err);
    if (rc == BF_OK)
        rc = plot_write(p, path, (bf_plot_format)fmt, o->width, o->height, err);
    plot_free(p);
    return rc;
}
