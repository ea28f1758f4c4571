/* A model vector judged as a fit judges its own solution (fit_impl.h,
 * bf_fit_evaluate_with): the objective the fit minimised and the metrics its result
 * reports, from the objective's own passes, so that a published fit (brdfit compare
 * --reference) and brdfit's are measured by one rule.
 *
 * Decisions:
 *  - The objective is made as the fit makes its own (fit.c, fit_open): the fit options'
 *    residual, weights and overrides, its passes on the solver's threads.
 *  - The cost is one fused pass with the fit's robust loss: 1/2 sum g^2, which is the
 *    solvers' final_cost. The metrics are the pass the end of a fit makes
 *    (objective_stderr.c, final_pass): no loss, the scene's weights when the fit's
 *    metrics carry them, then the same sums finished, so the same point gives the same
 *    bits. Nothing is checked against the bounds: x is evaluated as it is. */
#include "fit_impl.h"
#include "metrics_impl.h"
#include "objective_state.h"

#include <math.h>

bf_status bf_fit_evaluate_with(bf_samples *s, const bf_model *m, const double *x, const bf_fit_options *o, double *cost,
                               bf_metrics *metrics, bf_error *err)
{
    if (!s || !m || !x || !o || !cost || !metrics)
        return bf_fail(err, BF_ERR_ARG, "evaluate: no samples, model, values, options or outputs");
    if (bf_model_channels(m) != s->channels)
        return bf_fail(err, BF_ERR_ARG, "%s has %d channel%s, the data %d", bf_model_spec(m), bf_model_channels(m),
                       bf_model_channels(m) == 1 ? "" : "s", s->channels);
    bf_objective_options oo = o->objective; /* as fit_open makes the fit's */
    if (oo.threads < 1)
        oo.threads = o->solver.threads;
    bf_objective *obj = NULL;
    bf_status rc = bf_objective_new(m, s, &oo, &obj, err);
    if (rc != BF_OK)
        return rc;
    const int weighted = o->weighted_metrics || s->scene_weight != NULL;
    const bf_loss *loss = o->solver.loss.kind != BF_LOSS_NONE ? &o->solver.loss : NULL;
    double ssq = NAN, wssr = NAN;
    bf_metric_sums sums;
    const bf_obj_pass with_loss = {loss, obj->threads, {0, NULL, NULL}, 0};
    const bf_obj_pass plain = {NULL, obj->threads, {0, NULL, NULL}, weighted};
    if (bf_obj_normal_x(obj, x, &with_loss, &(bf_obj_pass_out){&ssq, NULL, NULL, NULL}) ||
        bf_obj_normal_x(obj, x, &plain, &(bf_obj_pass_out){&wssr, NULL, NULL, &sums}))
        rc = bf_fail(err, BF_ERR_NOMEM, "evaluate: out of memory for a pass over the samples");
    if (rc == BF_OK)
        rc = bf_metric_sums_finish(&sums, obj->nz, weighted && s->scene_weight, metrics, err);
    if (rc == BF_OK) {
        bf_metrics_criteria(metrics, obj->npos, obj->nz, wssr, obj->sum_log_w);
        if (loss) /* no Gaussian likelihood is maximised under a robust loss (fit.c) */
            metrics->loglik = metrics->aic = metrics->aicc = metrics->bic = NAN;
        *cost = 0.5 * ssq;
    }
    bf_objective_free(obj);
    return rc;
}
