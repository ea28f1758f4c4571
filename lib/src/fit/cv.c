/* K-fold cross-validation of a fit (fit.h, bf_fit_cv): held-out error of the fitted
 * objective. Each fold is held out in turn; the rest is fitted with the caller's
 * options (so with their presolve, starts and seed); the fitted parameters are then
 * put to an objective over the held-out samples with the same residual form and
 * weights, whose sum of w r^2 (without a robust loss) and sum of w over its residuals
 * are pooled over the folds: error = sqrt(sum w r^2 / sum w). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/big_alloc.h"
#include "base/sized.h"
#include "brdfit/fit.h"
#include "brdfit/prep.h"
#include "fit_impl.h"
#include "objective_state.h"
#include "run_options.h"

/* The held-out samples' sum of w r^2 and sum of w at the model vector x. */
static bf_status held_out(bf_samples *test, const bf_model *m, const double *x, const bf_fit_options *o, double *wssr,
                          double *wsum, bf_error *err)
{
    bf_objective_options oo = o->objective;
    if (oo.threads < 1)
        oo.threads = o->solver.threads;
    bf_objective *obj;
    bf_status rc = bf_objective_new(m, test, &oo, &obj, err);
    if (rc != BF_OK)
        return rc;
    const int nz = bf_objective_nz(obj);
    double *z = malloc(((size_t)nz + 1) * sizeof *z);
    if (!z) {
        rc = bf_fail(err, BF_ERR_NOMEM, "cross-validation: out of memory");
    } else {
        bf_objective_to_internal(obj, x, z);
        if (bf_problem_normal(bf_objective_problem(obj), z, NULL, oo.threads, wssr, NULL, NULL) != 0)
            rc = bf_fail(err, BF_ERR_NOMEM, "cross-validation: out of memory");
        *wsum = obj->wsum;
    }
    free(z);
    bf_objective_free(obj);
    return rc;
}

bf_status bf_fit_cv(bf_samples *s, const char *spec, const bf_options *o, int folds, bf_cv_result *out, bf_error *err)
{
    if (!out || bf_sized_check(out, sizeof *out, "bf_cv_result", err) != BF_OK)
        return BF_ERR_ARG;
    /* Every member of this version lies within the first version's size. */
    bf_cv_result_init(out);
    if (!o)
        return bf_fail(err, BF_ERR_ARG, "cross-validation: no options");
    bf_status rc = bf_options_check(o, err);
    if (rc != BF_OK)
        return rc;
    bf_fit_options fo;
    options_fit_get(o, &fo);
    return bf_fit_cv_with(s, spec, &fo, folds, fo.seed, out, err);
}

bf_status bf_fit_cv_with(bf_samples *s, const char *spec, const bf_fit_options *o, int folds, uint64_t seed,
                         bf_cv_result *out, bf_error *err)
{
    bf_cv_result_init(out);
    out->error = NAN;
    if (!s || !o || !out)
        return bf_fail(err, BF_ERR_ARG, "cross-validation: no samples or no options");
    if (folds < 2 || folds > BF_CV_MAX_FOLDS)
        return bf_fail(err, BF_ERR_ARG, "cross-validation: %d folds (2 to %d)", folds, BF_CV_MAX_FOLDS);
    if (s->n < (size_t)folds)
        return bf_fail(err, BF_ERR_ARG, "cross-validation: %zu samples for %d folds", s->n, folds);
    out->folds = folds;
    unsigned char *fold = bf_big_malloc(s->n + 1), *keep = bf_big_malloc(s->n + 1);
    if (!fold || !keep) {
        free(fold);
        free(keep);
        return bf_fail(err, BF_ERR_NOMEM, "cross-validation: out of memory for %zu samples", s->n);
    }
    bf_status rc = bf_samples_folds(s, folds, seed, fold, err);
    double wssr = 0.0, wsum = 0.0;
    for (int k = 0; k < folds && rc == BF_OK; k++) {
        out->fold_error[k] = NAN;
        for (size_t i = 0; i < s->n; i++)
            keep[i] = fold[i] != k;
        bf_samples *train, *test = NULL;
        rc = bf_samples_copy(s, keep, &train, err);
        for (size_t i = 0; i < s->n; i++)
            keep[i] = !keep[i];
        if (rc == BF_OK && (rc = bf_samples_copy(s, keep, &test, err)) != BF_OK)
            bf_samples_free(train);
        if (rc != BF_OK)
            break;
        bf_fit_result r;
        bf_fit_options fo = *o; /* its progress reports name the fold */
        fo.fold = k + 1;
        rc = bf_fit_with(train, spec, &fo, &r, err);
        if (rc == BF_OK) {
            double fw = NAN, fs = NAN;
            if (!r.ok) {
                out->failed++;
            } else if ((rc = held_out(test, r.model, r.x, o, &fw, &fs, err)) == BF_OK) {
                out->fold_error[k] = fs > 0.0 ? sqrt(fw / fs) : NAN;
                wssr += fw;
                wsum += fs;
            }
            bf_fit_result_clear(&r);
        }
        bf_samples_free(train);
        bf_samples_free(test);
    }
    free(fold);
    free(keep);
    if (rc == BF_OK && out->failed == 0 && wsum > 0.0)
        out->error = sqrt(wssr / wsum);
    return rc;
}

/* No folds run yet: no error. */
static void cv_result_defaults(bf_cv_result *r)
{
    r->error = NAN;
}

BF_SIZED_INIT(bf_cv_result, cv_result_defaults)
