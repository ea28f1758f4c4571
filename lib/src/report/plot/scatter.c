/* Scatter plots of labelled points with a Pareto front (compare's error against k and
 * against work, tradeoff's error against cost). */
#include "plot/scatter.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/sized.h"

BF_SIZED_INIT_ZERO(bf_plot_axes)

plot *plot_scatter(const plot_scatter_spec *sp)
{
    plot *p = plot_new(sp->title);
    int n = sp->n, *ord = malloc((size_t)(n > 0 ? n : 1) * sizeof *ord), m = 0;
    double *fx = malloc(2 * (size_t)(n > 0 ? n : 1) * sizeof *fx);
    /* A log axis says so: its ticks alone may not show it (a range under two decades). */
    char xt[256], yt[256];
    snprintf(xt, sizeof xt, "%s%s", sp->x_title, sp->log_x ? ", log scale" : "");
    snprintf(yt, sizeof yt, "%s%s", sp->y_title, sp->log_y ? ", log scale" : "");
    int fail = !p || !ord || !fx || plot_axis(p, PLOT_X, xt, sp->log_x) < 0 || plot_axis(p, PLOT_Y, yt, sp->log_y) < 0;
    if (!fail && sp->integer_x)
        plot_axis_integer(p, PLOT_X);
    /* Every point, labelled. */
    plot_series *s = fail ? NULL : plot_add(p, sp->points_name, PLOT_MARKERS, (size_t)n, sp->x, sp->y);
    fail |= !s;
    if (!fail) {
        s->rgb[0] = 0.0, s->rgb[1] = 0.447, s->rgb[2] = 0.698;
        s->marker_size = 1.1;
        if (sp->labels)
            fail |= plot_point_labels(s, sp->labels) < 0;
    }
    /* The front, in x order (insertion sort: a few points). */
    for (int i = 0; !fail && i < n; i++) {
        if (!sp->front || !sp->front[i] || !isfinite(sp->x[i]) || !isfinite(sp->y[i]))
            continue;
        int k = m++;
        while (k > 0 && sp->x[ord[k - 1]] > sp->x[i])
            ord[k] = ord[k - 1], k--;
        ord[k] = i;
    }
    if (!fail && m > 0) {
        double *fy = fx + m;
        for (int k = 0; k < m; k++) {
            fx[k] = sp->x[ord[k]];
            fy[k] = sp->y[ord[k]];
        }
        plot_series *f =
            plot_add(p, sp->front_name ? sp->front_name : "Pareto front", PLOT_LINE_MARKERS, (size_t)m, fx, fy);
        if (!(fail = !f)) {
            f->rgb[0] = 0.835, f->rgb[1] = 0.369, f->rgb[2] = 0.0;
            f->marker_size = 0.8;
        }
    }
    if (!fail && sp->chosen >= 0 && sp->chosen < n) {
        plot_series *c = plot_add(p, sp->chosen_name, PLOT_MARKERS, 1, sp->x + sp->chosen, sp->y + sp->chosen);
        if (!(fail = !c)) {
            c->marker = PLOT_RING;
            c->marker_size = 1.2;
        }
    }
    free(ord);
    free(fx);
    if (fail) {
        plot_free(p);
        return NULL;
    }
    return p;
}

void plot_scatter_axes(const plot *p, const plot_scatter_spec *sp, int width, int height, bf_plot_axes *axes)
{
    bf_plot_axes a;
    bf_plot_axes_init(&a);
    plot_layout l;
    if (plot_layout_compute(p, width, height, &l) == 0) {
        a.x_lo = l.axis[PLOT_X].lo;
        a.x_hi = l.axis[PLOT_X].hi;
        a.y_lo = l.axis[PLOT_Y].lo;
        a.y_hi = l.axis[PLOT_Y].hi;
    }
    a.log_x = sp->log_x;
    a.log_y = sp->log_y;
    for (int i = 0; i < sp->n; i++)
        a.drawn += isfinite(sp->x[i]) && isfinite(sp->y[i]) && !(sp->log_x && !(sp->x[i] > 0.0)) &&
                   !(sp->log_y && !(sp->y[i] > 0.0));
    bf_sized_copy(axes, &a, sizeof a); /* as far as the caller's size reaches (docs/api.md) */
}
