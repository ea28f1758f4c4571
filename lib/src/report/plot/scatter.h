/* Scatter plots of labelled points with a Pareto front, as compare's report and
 * tradeoff draw them: every point (blue circles, each with its label), the front's
 * points joined in x order (vermillion), and one chosen point ringed. */
#ifndef BRDFIT_PLOT_SCATTER_H
#define BRDFIT_PLOT_SCATTER_H

#include "plot/plot.h"

typedef struct plot_scatter_spec {
    const char *title, *x_title, *y_title; /* markup */
    int log_x, log_y, integer_x;
    int n;
    const double *x, *y;                  /* n points; NaN: not drawn */
    const int *front;                     /* n flags, or NULL */
    const char *const *labels;            /* n labels (entries may be NULL), or NULL */
    const char *points_name, *front_name; /* legend entries ("Pareto front" if NULL) */
    int chosen;                           /* a point to ring, -1: none */
    const char *chosen_name;
} plot_scatter_spec;

/* NULL when out of memory. */
plot *plot_scatter(const plot_scatter_spec *sp);
/* The axes the plot gets at width x height, and the points it draws, into *axes as far
 * as its size reaches (set by bf_plot_axes_init). */
void plot_scatter_axes(const plot *p, const plot_scatter_spec *sp, int width, int height, bf_plot_axes *axes);

#endif
