/* Fit error as users compare it. */
#ifndef BRDFIT_METRICS_H
#define BRDFIT_METRICS_H

#include <stddef.h>

#include "brdfit/error.h"
#include "brdfit/model.h"
#include "brdfit/samples.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Over every sample and channel (n values), f the model and m the measurement,
 * c = cos theta_i:
 *   rmse      sqrt(mean (f - m)^2)
 *   rmse_cos  sqrt(mean ((f - m) c)^2)
 *   rmse_log  sqrt(mean (ln(1 + f c) - ln(1 + m c))^2)
 *   rmse_rel  sqrt(mean ((f - m) / |m|)^2) over values with m != 0
 *   max_err   max |f - m|
 *   aic = n ln(SSR/n) + 2k, bic = n ln(SSR/n) + k ln n, SSR = sum (f - m)^2, k free
 *   parameters. bf_metrics_compute does not apply sample weights (metrics compare fits,
 *   whatever the objective was).
 *
 * Weighted (bf_metrics_compute_weighted with weighted = 1: w_i the samples' scene
 * weights, scene.h; the data's own weights never count here): every mean becomes sum w e^2 / sum w over the values
 * with w > 0 (negative weights count as 0, as in the objective), max_err and n cover
 * only those values, and AIC/BIC use SSR/n = sum w (f - m)^2 / sum w. With every weight
 * 1 (or no weights) the results equal the unweighted ones exactly; with integer weights
 * the means and max_err equal those of the set with each sample repeated w times, while
 * n (and so AIC and BIC) counts each value once: weights say where error matters, not
 * how many measurements there were. */
typedef struct bf_metrics {
    size_t n;
    int k;
    double rmse, rmse_cos, rmse_log, rmse_rel, max_err, aic, bic;
    int weighted; /* 1: computed with the samples' scene weights */
} bf_metrics;

/* threads: 0 or 1 for one; the result is the same for any count. */
int bf_metrics_compute(const bf_model *m, const double *x, bf_samples *s, int k, int threads,
                       bf_metrics *out, bf_error *err);
/* The same; weighted = 1 applies the samples' scene weights (if they have any) as above. */
int bf_metrics_compute_weighted(const bf_model *m, const double *x, bf_samples *s, int k, int threads,
                                int weighted, bf_metrics *out, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
