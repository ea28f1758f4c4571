/* A scatter plot without text (the caller captions the axes from bf_scatter_range):
 * a white canvas, a black frame, points as 5x5 squares, highlighted ones in red and
 * joined by a red line in x order (a Pareto front reads as a staircase-like path). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/render.h"

typedef struct plot {
    float *rgb;
    int w, h;
} plot;

static void put(plot *p, int x, int y, const double c[3])
{
    if (x < 0 || y < 0 || x >= p->w || y >= p->h)
        return;
    float *px = p->rgb + 3 * ((size_t)y * (size_t)p->w + (size_t)x);
    px[0] = (float)c[0];
    px[1] = (float)c[1];
    px[2] = (float)c[2];
}

/* Bresenham: good enough for a few segments. */
static void line(plot *p, int x0, int y0, int x1, int y1, const double c[3])
{
    int dx = abs(x1 - x0), dy = -abs(y1 - y0), sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1, e = dx + dy;
    for (;;) {
        put(p, x0, y0, c);
        if (x0 == x1 && y0 == y1)
            return;
        int e2 = 2 * e;
        if (e2 >= dy) {
            e += dy;
            x0 += sx;
        }
        if (e2 <= dx) {
            e += dx;
            y0 += sy;
        }
    }
}

/* The axis range of the usable values, padded by 5% (log: in log10), never empty. */
static void axis_range(int n, const double *v, int logscale, double *lo, double *hi)
{
    double a = INFINITY, b = -INFINITY;
    for (int i = 0; i < n; i++) {
        double t = logscale ? (v[i] > 0 ? log10(v[i]) : NAN) : v[i];
        if (!isfinite(t))
            continue;
        a = fmin(a, t);
        b = fmax(b, t);
    }
    if (!(a <= b))
        a = b = 0.0;
    double pad = b > a ? 0.05 * (b - a) : (logscale ? 0.5 : (a != 0.0 ? 0.5 * fabs(a) : 1.0));
    *lo = a - pad;
    *hi = b + pad;
}

int bf_render_scatter(int n, const double *x, const double *y, const int *highlight,
                      const bf_scatter_options *o, float *rgb, bf_scatter_range *range, bf_error *err)
{
    if (!o || !rgb || n < 0 || (n > 0 && (!x || !y)) || o->width < 40 || o->height < 40)
        return bf_fail(err, BF_ERR_ARG, "scatter plot: bad arguments (images at least 40x40)");
    plot p = {rgb, o->width, o->height};
    for (size_t k = 0; k < 3 * (size_t)o->width * (size_t)o->height; k++)
        rgb[k] = 1.0f;
    bf_scatter_range r;
    memset(&r, 0, sizeof r);
    axis_range(n, x, o->log_x, &r.x_lo, &r.x_hi);
    axis_range(n, y, o->log_y, &r.y_lo, &r.y_hi);
    r.x0 = 10;
    r.y0 = 10;
    r.x1 = o->width - 11;
    r.y1 = o->height - 11;

    static const double black[3] = {0, 0, 0}, grey[3] = {0.35, 0.35, 0.35}, red[3] = {0.85, 0.1, 0.1};
    line(&p, r.x0, r.y0, r.x1, r.y0, black);
    line(&p, r.x1, r.y0, r.x1, r.y1, black);
    line(&p, r.x1, r.y1, r.x0, r.y1, black);
    line(&p, r.x0, r.y1, r.x0, r.y0, black);

    /* Pixel positions; -1 for points that cannot be drawn (NaN, or <= 0 on a log axis). */
    int *px = malloc(2 * (size_t)(n > 0 ? n : 1) * sizeof *px);
    if (!px)
        return bf_fail(err, BF_ERR_NOMEM, "scatter plot: out of memory");
    for (int i = 0; i < n; i++) {
        double tx = o->log_x ? (x[i] > 0 ? log10(x[i]) : NAN) : x[i];
        double ty = o->log_y ? (y[i] > 0 ? log10(y[i]) : NAN) : y[i];
        if (!isfinite(tx) || !isfinite(ty)) {
            px[2 * i] = px[2 * i + 1] = -1;
            continue;
        }
        px[2 * i] = r.x0 + (int)lround((tx - r.x_lo) / (r.x_hi - r.x_lo) * (r.x1 - r.x0));
        px[2 * i + 1] = r.y1 - (int)lround((ty - r.y_lo) / (r.y_hi - r.y_lo) * (r.y1 - r.y0));
        r.drawn++;
    }
    /* The highlighted path, in x order (insertion sort: a handful of points). */
    int *ord = malloc((size_t)(n > 0 ? n : 1) * sizeof *ord), m = 0;
    if (!ord) {
        free(px);
        return bf_fail(err, BF_ERR_NOMEM, "scatter plot: out of memory");
    }
    for (int i = 0; i < n; i++) {
        if (!highlight || !highlight[i] || px[2 * i] < 0)
            continue;
        int k = m++;
        while (k > 0 && px[2 * ord[k - 1]] > px[2 * i])
            ord[k] = ord[k - 1], k--;
        ord[k] = i;
    }
    for (int k = 1; k < m; k++)
        line(&p, px[2 * ord[k - 1]], px[2 * ord[k - 1] + 1], px[2 * ord[k]], px[2 * ord[k] + 1], red);
    for (int i = 0; i < n; i++) {
        if (px[2 * i] < 0)
            continue;
        const double *c = highlight && highlight[i] ? red : grey;
        for (int dy = -2; dy <= 2; dy++)
            for (int dx = -2; dx <= 2; dx++)
                put(&p, px[2 * i] + dx, px[2 * i + 1] + dy, c);
    }
    free(ord);
    free(px);
    if (range)
        *range = r;
    return BF_OK;
}
