/* Fit error as users compare it.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_METRICS_H
#define BRDFIT_METRICS_H

#include <stddef.h>

#include "brdfit/error.h"
#include "brdfit/model.h"
#include "brdfit/samples.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Errors, over every sample and channel (n values), f the model and m the measurement,
 * c = cos theta_i:
 *   rmse      sqrt(mean (f - m)^2)
 *   rmse_cos  sqrt(mean ((f - m) c)^2)
 *   rmse_log  sqrt(mean (ln(1 + f c) - ln(1 + m c))^2)
 *   rmse_rel  sqrt(mean ((f - m) / |m|)^2) over values with m != 0
 *   max_err   max |f - m|
 * bf_metrics_compute does not apply sample weights (metrics compare fits, whatever the
 * objective was).
 *
 * Weighted (bf_metrics_compute_weighted with weighted = 1: w_i the samples' scene
 * weights, scene.h; the data's own weights never count here): every mean becomes
 * sum w e^2 / sum w over the values with w > 0 (negative weights count as 0, as in the
 * objective), and max_err and n cover only those values. With every weight 1 (or no
 * weights) the results equal the unweighted ones exactly; with integer weights the
 * means and max_err equal those of the set with each sample repeated w times.
 *
 * Information criteria belong to a fit, not to a pair of model and data: they come from
 * the likelihood of what the fit minimised (bf_fit fills them; docs/criteria.md). With
 * r_i the residual of the fitted form (log, linear, cosine, cbrt, relative) and w_i the
 * objective's weight of that residual (sample, solid-angle and scene weights together),
 * the noise model is r_i ~ N(0, sigma^2 / w_i), independent, over the N residuals with
 * w_i > 0; at its maximum, sigma^2 = WSSR / N with WSSR = sum w_i r_i^2, and
 *   loglik = -N/2 (ln(2 pi WSSR / N) + 1) + 1/2 sum ln w_i
 *   aic    = -2 loglik + 2 (k + 1)
 *   aicc   = aic + 2 (k + 1)(k + 2) / (N - k - 2)     (NaN when N <= k + 2)
 *   bic    = -2 loglik + (k + 1) ln N
 * k the free parameters (after --fix and mono= ties), + 1 for sigma. A robust loss
 * minimises no Gaussian likelihood: then every criterion is NaN (undefined). Models
 * compare by them only on the same samples, residual form and weights. Frozen
 * (docs/api.md): embedded in results (bf_fit_result, bf_compare_fit, ...). */
typedef struct bf_metrics {
    size_t n;
    int k;
    double rmse, rmse_cos, rmse_log, rmse_rel, max_err;
    int weighted; /* 1: computed with the samples' scene weights */
    /* Criteria (NaN from bf_metrics_compute; bf_fit fills them). */
    size_t crit_n; /* N: residuals with a positive weight */
    double loglik, aic, aicc, bic;
} bf_metrics;

/* The criteria above from N, k, WSSR and sum ln w_i (NaN where undefined: WSSR not
 * finite, N = 0). An exact fit has WSSR / N floored at DBL_MIN so the values stay
 * finite. */
BF_API void bf_metrics_criteria(bf_metrics *m, size_t n, int k, double wssr, double sum_log_w);

/* threads: 0 or 1 for one; the result is the same for any count. */
BF_API bf_status bf_metrics_compute(const bf_model *m, const double *x, bf_samples *s, int k, int threads,
                                    bf_metrics *out, bf_error *err);
/* The same; weighted = 1 applies the samples' scene weights (if they have any) as above. */
BF_API bf_status bf_metrics_compute_weighted(const bf_model *m, const double *x, bf_samples *s, int k, int threads,
                                             int weighted, bf_metrics *out, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
