/* Internal: the sums behind bf_metrics (metrics.h), shared by the metrics pass
 * (metrics.c) and the objective's final pass (objective_normal.c), which gathers them
 * beside the standard errors' J'J. */
#ifndef BF_METRICS_IMPL_H
#define BF_METRICS_IMPL_H

#include <math.h>
#include <stddef.h>

#include "brdfit/metrics.h"
#include "objective_state.h"

typedef struct bf_metric_sums {
    double ssr, scos, slog, srel, maxe;
    double wsum, wrel; /* sums of the weights behind ssr.. and srel */
    size_t n, nrel;
} bf_metric_sums;

/* One value: model f, measurement mv, cos theta_i cs, weight w > 0 (1 unweighted: then
 * w * x is x exactly), and dl = ln(1 + f cs) - ln(1 + mv cs) as bf_obj_log1p gives it. */
static inline void bf_metric_add_dl(bf_metric_sums *p, double fv, double mv, double cs, double w, double dl)
{
    const double d = fv - mv;
    p->ssr += w * (d * d);
    p->scos += w * ((d * cs) * (d * cs));
    p->slog += w * (dl * dl);
    p->wsum += w;
    if (mv != 0.0) {
        const double q = d / fabs(mv);
        p->srel += w * (q * q);
        p->wrel += w;
        p->nrel++;
    }
    if (fabs(d) > p->maxe)
        p->maxe = fabs(d);
    p->n++;
}

static inline void bf_metric_add(bf_metric_sums *p, double fv, double mv, double cs, double w)
{
    bf_metric_add_dl(p, fv, mv, cs, w, bf_obj_log1p(fv * cs) - bf_obj_log1p(mv * cs));
}

/* The metrics' chunks: BF_METRIC_CHUNK samples each, summed in this order by
 * bf_metric_chunk, whoever computes the model's values (the metrics pass, or the
 * objective's final pass beside the standard errors), so both give the same bits. */
#define BF_METRIC_CHUNK 4096

/* One chunk's values: cnt samples of C channels; f and mv the model's and the measured
 * (cnt * C values, sample-major), dl (NULL: computed from them) the log differences as
 * bf_metric_add_dl takes them, cs the samples' cos theta_i (0 below the horizon: not
 * counted), w their weights (NULL: all 1). */
typedef struct bf_metric_vals {
    const double *f, *mv, *dl;
    const double *cs, *w;
    size_t cnt;
    int C;
} bf_metric_vals;

/* p += the sums of one chunk's values. */
void bf_metric_chunk(bf_metric_sums *p, const bf_metric_vals *v);

/* t += p (chunks added in a fixed order). */
void bf_metric_sums_add(bf_metric_sums *t, const bf_metric_sums *p);
/* The metrics from the whole set's sums; BF_ERR_ARG when no value counted. */
bf_status bf_metric_sums_finish(const bf_metric_sums *t, int k, int weighted, bf_metrics *out, bf_error *err);

#endif
