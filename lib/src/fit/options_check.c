/* The couplings of a run's options, checked once every option is in (brdfit/options.h):
 * a criterion that needs a likelihood, the method registry, the tradeoff's lists. Apart
 * from run_options.c, which holds the values, so that the task-specific checks it calls
 * (tradeoff_options.c) depend on it and not the other way round. */
#include "run_options.h"
#include "tradeoff_options.h"

bf_status bf_options_check(const bf_options *o, bf_error *err)
{
    char name[64], loss[64];
    /* A criterion needs a likelihood, and a robust loss has none (metrics.h). */
    if ((o->task == BF_TASK_COMPARE || o->task == BF_TASK_SELECT) && o->loss.kind != BF_LOSS_NONE &&
        o->rank_by != BF_RANK_CV && o->rank_by != BF_RANK_ERROR)
        return bf_fail(err, BF_ERR_ARG,
                       "%s %s needs the likelihood of the residuals, and a robust loss (%s) has none: rank by cv or "
                       "error",
                       option_spelled(o, "rank", name, sizeof name), bf_compare_rank_name(o->rank_by),
                       option_spelled(o, "loss", loss, sizeof loss));
    if (o->task == BF_TASK_READ)
        return BF_OK;
    /* The method, its local method and the constraint against the method registry. */
    bf_fit_options f;
    options_fit_get(o, &f);
    bf_status rc = bf_solver_options_check(&f.solver, err);
    /* The tradeoff's lists, once every option is in (tradeoff_options.c). */
    if (rc == BF_OK && o->task == BF_TASK_TRADEOFF)
        rc = options_tradeoff_check(o, err);
    return rc;
}

bf_status bf_options_check_models(const bf_options *o, const char *const *specs, int n, bf_error *err)
{
    for (int k = 0; k < n; k++) {
        bf_model *m = NULL;
        bf_status rc = bf_model_new(specs[k], 1, &m, err);
        if (rc != BF_OK)
            return rc;
        /* fix and bound against each model: bad usage before any data is read. */
        rc = bf_overrides_check(m, 0, o->overrides, o->noverrides, err);
        bf_model_free(m);
        if (rc != BF_OK)
            return rc;
    }
    return BF_OK;
}
