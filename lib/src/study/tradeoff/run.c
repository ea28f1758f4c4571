/* One tradeoff row: subsample the training set, fit, time over repeats, judge on the
 * held-out test set.
 *
 * Decisions:
 *  - The subsample is bf_samples_prep's seeded stratified one (what `brdfit fit
 *    --subsample N --seed K` does), drawn from the training set only, so no test sample
 *    is ever fitted.
 *  - Repeats refit with the same options and seed: the fit is the same each time, so
 *    the minimum of the times is the fit's cost with the least interference from other
 *    work; the metrics come from the first. */
#include "brdfit/tradeoff.h"

#include "fit_impl.h"
#include "run_options.h"
#include "tradeoff/tradeoff_impl.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/prep.h"

static bf_status row_error(bf_tradeoff_row *row, bf_error *err)
{
    snprintf(row->message, sizeof row->message, "%s", err->msg);
    return err->code;
}

bf_status bf_tradeoff_run_row(bf_tradeoff *t, int i, bf_samples *train, bf_samples *test, const bf_options *base,
                              bf_error *err)
{
    bf_error local;
    if (!err)
        err = &local;
    if (i < 0 || i >= t->nrows)
        return bf_fail(err, BF_ERR_ARG, "tradeoff: no row %d", i);
    bf_tradeoff_row *row = &t->rows[i];
    row->ran = row->ok = 0;
    row->seconds = row->work = NAN;
    row->iterations = 0;
    free(row->warnings);
    row->warnings = NULL;
    row->nwarnings = 0;
    row->message[0] = '\0';
    memset(&row->train, 0, sizeof row->train);
    memset(&row->test, 0, sizeof row->test);

    bf_fit_options o;
    options_fit_get(base, &o);
    o.objective.residual = row->residual;
    o.starts = row->starts;
    if (bf_tradeoff_method_apply(row->method, &o.solver, err) != BF_OK)
        return row_error(row, err);

    bf_samples *fit_set = train, *sub = NULL;
    if (!row->all && row->samples < train->n) {
        if (bf_samples_copy(train, NULL, &sub, err) != BF_OK)
            return row_error(row, err);
        bf_prep p;
        memset(&p, 0, sizeof p);
        p.subsample = row->samples;
        p.seed = t->seed;
        if (bf_samples_prep(sub, &p, NULL, err) != BF_OK) {
            bf_samples_free(sub);
            return row_error(row, err);
        }
        fit_set = sub;
    }

    int repeats = t->repeats > 0 ? t->repeats : 1, rc = BF_OK;
    bf_fit_result best;
    memset(&best, 0, sizeof best);
    for (int k = 0; k < repeats; k++) {
        bf_fit_result r;
        if ((rc = bf_fit_with(fit_set, t->model, &o, &r, err)) != BF_OK)
            break;
        if (k == 0) {
            best = r;
            row->seconds = r.seconds;
        } else {
            if (r.seconds < row->seconds)
                row->seconds = r.seconds;
            bf_fit_result_clear(&r);
        }
    }
    if (rc == BF_OK) {
        row->ran = 1;
        row->ok = best.ok;
        row->iterations = best.solution.iterations;
        row->work = bf_compare_work(&best);
        row->train = best.metrics;
        if (best.nwarnings > 0 && (row->warnings = malloc((size_t)best.nwarnings * sizeof *row->warnings))) {
            memcpy(row->warnings, best.warnings, (size_t)best.nwarnings * sizeof *row->warnings);
            row->nwarnings = best.nwarnings;
        }
        /* Weighted like the training metrics (a scene's weights), so both judge alike. */
        rc = bf_metrics_compute_weighted(best.model, best.x, test, best.metrics.k, o.solver.threads, o.weighted_metrics,
                                         &row->test, err);
        if (rc != BF_OK)
            row->ran = row->ok = 0;
    }
    if (rc != BF_OK)
        row_error(row, err);
    if (best.model)
        bf_fit_result_clear(&best);
    bf_samples_free(sub);
    return rc;
}
