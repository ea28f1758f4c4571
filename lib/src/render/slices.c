/* In-plane BRDF slices drawn as a plot: log10 f against signed theta_o, one line per
 * incidence angle and channel, measured samples as dots. Plain pixel drawing; no text. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/render.h"
#include "colour.h"

typedef struct canvas {
    float *px;
    int w, h;
} canvas;

static void put(canvas *c, int x, int y, const double col[3])
{
    if (x < 0 || y < 0 || x >= c->w || y >= c->h)
        return;
    float *p = c->px + 3 * ((size_t)y * (size_t)c->w + (size_t)x);
    for (int k = 0; k < 3; k++)
        p[k] = (float)col[k];
}

static void vline(canvas *c, int x, int ya, int yb, const double col[3])
{
    if (ya > yb) {
        int t = ya;
        ya = yb;
        yb = t;
    }
    for (int y = ya; y <= yb; y++)
        put(c, x, y, col);
}

static void hline(canvas *c, int xa, int xb, int y, const double col[3])
{
    for (int x = xa; x <= xb; x++)
        put(c, x, y, col);
}

/* Channel ch of nch curves, lightened (mixed with white) for later incidence angles. */
static void curve_colour(int ch, int nch, int k, int nk, double shade, double col[3])
{
    static const double rgb[3][3] = {{0.85, 0.0, 0.0}, {0.0, 0.6, 0.0}, {0.0, 0.0, 0.85}};
    double base[3] = {0.0, 0.0, 0.0};
    if (nch == 3)
        memcpy(base, rgb[ch], sizeof base);
    double t = nk > 1 ? 0.6 * k / (nk - 1) : 0.0;
    for (int q = 0; q < 3; q++)
        col[q] = (base[q] + (1.0 - base[q]) * t) * shade;
}

/* In-plane viewing direction for a signed theta_o (degrees): positive on the mirror side. */
static void view_angles(double signed_to, double *to, double *po)
{
    *to = fabs(signed_to);
    *po = signed_to >= 0.0 ? 180.0 : 0.0;
}

int bf_render_slice(const bf_model *m, const double *x, const bf_slice_options *o, float *rgb,
                    bf_slice_range *range, bf_error *err)
{
    if (!o || o->width < 32 || o->height < 32)
        return bf_fail(err, BF_ERR_ARG, "slice plot: the image must be at least 32x32 pixels");
    if (o->nincidence < 1 || o->nincidence > BF_SLICE_MAX_INCIDENCE || !o->incidence)
        return bf_fail(err, BF_ERR_ARG, "slice plot: 1 to %d incidence angles", BF_SLICE_MAX_INCIDENCE);
    for (int k = 0; k < o->nincidence; k++)
        if (!(o->incidence[k] >= 0.0 && o->incidence[k] < 90.0))
            return bf_fail(err, BF_ERR_ARG, "slice plot: incidence angle %g is not in [0, 90)", o->incidence[k]);

    canvas c = {rgb, o->width, o->height};
    for (size_t q = 0; q < (size_t)c.w * (size_t)c.h * 3; q++)
        rgb[q] = 1.0f;
    /* Plot area, leaving room for the tick marks. */
    int mx = c.w / 12 > 10 ? c.w / 12 : 10, my = c.h / 12 > 10 ? c.h / 12 : 10;
    int x0 = mx, x1 = c.w - 1 - mx / 2, y0 = my / 2, y1 = c.h - 1 - my;
    int ncol = x1 - x0 + 1, nk = o->nincidence, C = bf_model_channels(m);
    int nch = C == 3 ? 3 : 1;

    size_t n = (size_t)ncol * (size_t)nk;
    double *ang = malloc(4 * n * sizeof *ang), *f = malloc(n * (size_t)C * sizeof *f);
    double *lv = malloc(n * 3 * sizeof *lv);
    bf_geometry *g = NULL;
    int status = BF_OK;
    if (!ang || !f || !lv) {
        status = bf_fail(err, BF_ERR_NOMEM, "slice plot: out of memory");
        goto done;
    }
    for (int k = 0; k < nk; k++)
        for (int i = 0; i < ncol; i++) {
            size_t q = (size_t)k * (size_t)ncol + (size_t)i;
            double to, po;
            view_angles(-90.0 + 180.0 * i / (ncol - 1), &to, &po);
            ang[q] = o->incidence[k] * (M_PI / 180.0);
            ang[n + q] = 0.0;
            ang[2 * n + q] = to * (M_PI / 180.0);
            ang[3 * n + q] = po * (M_PI / 180.0);
        }
    if (!(g = bf_geometry_from_angles(n, ang, ang + n, ang + 2 * n, ang + 3 * n, err))) {
        status = err ? err->code : BF_ERR_NOMEM;
        goto done;
    }
    bf_model_eval(m, x, g, f, NULL);
    double vmin = INFINITY, vmax = 0.0;
    for (size_t q = 0; q < n; q++) {
        bf_channels_to_rgb(f + q * (size_t)C, C, lv + 3 * q);
        for (int ch = 0; ch < nch; ch++) {
            double v = lv[3 * q + (size_t)ch];
            if (v > 0.0 && isfinite(v)) {
                vmin = fmin(vmin, v);
                vmax = fmax(vmax, v);
            }
        }
    }
    /* Whole decades around the positive values, at most 8 of them. */
    double hi = vmax > 0.0 ? ceil(log10(vmax)) : 0.0;
    double lo = vmax > 0.0 ? floor(log10(vmin)) : -1.0;
    if (lo < hi - 8.0)
        lo = hi - 8.0;
    if (lo >= hi)
        lo = hi - 1.0;

    const double black[3] = {0, 0, 0}, faint[3] = {0.85, 0.85, 0.85};
#define XPIX(t) ((int)lround(x0 + ((t) + 90.0) / 180.0 * (x1 - x0)))
#define YPIX(l) ((int)lround(y1 - ((l) - lo) / (hi - lo) * (y1 - y0)))
    for (int k = 0; k < nk; k++) /* mirror directions */
        vline(&c, XPIX(o->incidence[k]), y0, y1, faint);
    for (int k = 0; k < nk; k++)
        for (int ch = 0; ch < nch; ch++) {
            double col[3];
            curve_colour(ch, nch, k, nk, 1.0, col);
            int prev = -1;
            for (int i = 0; i < ncol; i++) {
                double v = lv[3 * ((size_t)k * (size_t)ncol + (size_t)i) + (size_t)ch];
                if (!(v > 0.0) || !isfinite(v) || log10(v) < lo) {
                    prev = -1; /* the line breaks where f is 0 or below the axis */
                    continue;
                }
                int y = YPIX(log10(v));
                vline(&c, x0 + i, prev >= 0 ? (prev + y) / 2 : y, y, col);
                if (prev >= 0)
                    vline(&c, x0 + i - 1, prev, (prev + y) / 2, col);
                prev = y;
            }
        }
    size_t overlaid = 0;
    bf_samples *s = o->samples;
    for (size_t q = 0; s && q < s->n; q++) {
        double dir[4]; /* theta_i, phi_i, theta_o, phi_o */
        bf_samples_direction(s, q, dir);
        int k = 0;
        while (k < nk && !(fabs(dir[0] - o->incidence[k]) <= o->plane_tol))
            k++;
        if (k == nk)
            continue;
        double d = (dir[3] - dir[1]) * (M_PI / 180.0);
        double off = asin(fmin(1.0, fabs(sin(dir[2] * (M_PI / 180.0)) * sin(d)))) * (180.0 / M_PI);
        if (!(off <= o->plane_tol) || !(dir[2] < 90.0))
            continue;
        double t = cos(d) < 0.0 ? dir[2] : -dir[2];
        double sv[3];
        bf_channels_to_rgb(s->value + q * (size_t)s->channels, s->channels, sv);
        int sch = s->channels == 3 ? 3 : 1, drawn = 0;
        for (int ch = 0; ch < sch; ch++) {
            if (!(sv[ch] > 0.0) || !isfinite(sv[ch]) || log10(sv[ch]) < lo || log10(sv[ch]) > hi)
                continue;
            double col[3];
            curve_colour(ch, sch, k, nk, 0.5, col);
            int px = XPIX(t), py = YPIX(log10(sv[ch]));
            for (int dy = -1; dy <= 1; dy++)
                hline(&c, px - 1, px + 1, py + dy, col);
            drawn = 1;
        }
        overlaid += (size_t)drawn;
    }
    /* Frame and ticks last, so they stay visible. */
    hline(&c, x0 - 1, x1 + 1, y0 - 1, black);
    hline(&c, x0 - 1, x1 + 1, y1 + 1, black);
    vline(&c, x0 - 1, y0 - 1, y1 + 1, black);
    vline(&c, x1 + 1, y0 - 1, y1 + 1, black);
    for (int t = -90; t <= 90; t += 30)
        vline(&c, XPIX((double)t), y1 + 2, y1 + (t == 0 ? 9 : 5), black);
    for (double l = lo; l <= hi + 0.5; l += 1.0)
        hline(&c, x0 - 6, x0 - 2, YPIX(l), black);
#undef XPIX
#undef YPIX
    if (range) {
        range->log10_lo = lo;
        range->log10_hi = hi;
        range->x0 = x0;
        range->y0 = y0;
        range->x1 = x1;
        range->y1 = y1;
        range->overlaid = overlaid;
    }
done:
    bf_geometry_free(g);
    free(ang);
    free(f);
    free(lv);
    return status;
}
