/* The slice plot's data and plot, for bf_render_slice, the report and the tests. */
#ifndef BRDFIT_RENDER_SLICES_H
#define BRDFIT_RENDER_SLICES_H

#include "brdfit/render.h"
#include "plot/plot.h"

typedef struct slice_data {
    int npoints, nch;          /* points per curve; channels shown (3 or 1) */
    double *theta;             /* npoints signed theta_o, degrees */
    double *f;                 /* nincidence * npoints * 3 values (as bf_channels_to_rgb) */
    size_t ns;                 /* in-plane samples */
    double *st, *sf;           /* their signed theta_o and 3 values each */
    int *sk;                   /* their incidence index */
    double log10_lo, log10_hi; /* the data's extent (bf_slice_extent) */
} slice_data;

bf_status slice_data_compute(const bf_model *m, const double *x, const bf_slice_options *o, slice_data *d,
                             bf_error *err);
void slice_data_clear(slice_data *d);
/* The plot bf_render_slice writes. */
bf_status slice_plot_build(const bf_model *m, const double *x, const bf_slice_options *o, plot **out,
                           bf_slice_range *range, bf_error *err);

#endif
