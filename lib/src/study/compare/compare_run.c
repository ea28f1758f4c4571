/* Running a comparison's fits: every model on every material, several at once (see
 * compare.h, bf_compare_run).
 *
 * Decisions:
 *  - The fits run on bf_parallel_for (parallel.h), one chunk per material x model in
 *    slot order, jobs threads (the calling one included). Each fit writes only its own
 *    slot, so nothing depends on which thread runs it or when it finishes.
 *  - Cancellation is a flag the caller sets (from a SIGINT handler, say): it is read
 *    before each fit starts; a fit that sees it set is skipped and stays NOT_RUN. A
 *    running fit is never stopped halfway, so whatever finished is a whole result.
 *  - The slots are filled and the progress callback called under one lock, so the
 *    callback sees finished slots and its calls never overlap; the fits themselves run
 *    outside it.
 *  - The --threads budget is shared: each fit gets threads / jobs solver threads (at
 *    least 1); the results do not depend on it (fit.h).
 *  - Wall time (seconds) covers the fit and its cross-validation; it decides nothing. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/compare.h"
#include "base/cancel.h"
#include "base/parallel.h"
#include "compare/compare_run.h"
#include "run_options.h"
#include "brdfit/clock.h"

typedef struct run {
    bf_compare *c;
    bf_samples *const *samples;
    bf_fit_options fo; /* the caller's, with the solver threads of one job */
    compare_hooks h;
    const bf_cancel_flag *cancel;
    pthread_mutex_t lock;
    int done, total;
} run;

/* Fits slot idx (and cross-validates it when asked); fills it and reports under the lock. */
static void fit_one(void *arg, size_t chunk)
{
    run *r = arg;
    /* Read by every fitting thread while a signal handler may set them (the handler should
     * store atomically too: see cmd/cmd_compare.c). */
    if (bf_cancel_is_set(r->h.finish) || bf_cancel_is_set(r->cancel))
        return;
    bf_compare *c = r->c;
    const int idx = (int)chunk, i = idx / c->nmodels, j = idx % c->nmodels;
    bf_fit_result *res = malloc(sizeof *res);
    bf_error err;
    bf_fit_options fo = r->fo; /* its progress reports say which fit this is */
    fo.model = j;
    if (fo.report_materials) {
        fo.material = i;
        fo.material_name = c->materials[i].data;
    }
    const double t0 = bf_now_seconds();
    bf_status rc = res ? bf_fit_with(r->samples[i], c->models[j], &fo, res, &err)
                       : bf_fail(&err, BF_ERR_NOMEM, "out of memory for a fit's result");
    bf_cv_result cv = {.error = NAN};
    if (rc == BF_OK && c->folds > 0 && res->ok) {
        rc = bf_fit_cv_with(r->samples[i], c->models[j], &fo, c->folds, fo.seed, &cv, &err);
        if (rc != BF_OK)
            bf_fit_result_clear(res);
    }
    const double seconds = bf_now_seconds() - t0;

    pthread_mutex_lock(&r->lock);
    bf_compare_fit *f = &c->materials[i].fits[j];
    c->results[idx] = res;
    if (rc == BF_OK) {
        f->state = res->ok ? BF_CMP_OK : BF_CMP_FAILED;
        f->metrics = res->metrics;
        f->seconds = seconds;
        f->work = bf_compare_work(res);
        f->cv_error = cv.error;
        f->result = res;
    } else {
        f->state = BF_CMP_ERROR;
        snprintf(f->message, sizeof f->message, "%s", err.msg);
    }
    r->done++;
    if (r->h.progress)
        r->h.progress(r->h.user, c, i, j, r->done, r->total);
    pthread_mutex_unlock(&r->lock);
}

bf_status bf_compare_run(bf_compare *c, bf_samples *const *samples, const bf_options *o, bf_compare_progress progress,
                         void *user, bf_error *err)
{
    bf_status rc = bf_compare_set_options(c, o, err);
    if (rc == BF_OK)
        rc = bf_options_check(o, err);
    if (rc != BF_OK)
        return rc;
    bf_fit_options fo;
    options_fit_get(o, &fo);
    fo.report_materials = 1;
    const compare_hooks h = {progress, user, o->finish};
    rc = compare_run_with(c, samples, &fo, o->jobs, &h, err);
    if (rc == BF_OK) /* the published fits beside the fits that ran (compare_reference.c) */
        rc = compare_check_references(c, samples, &fo, err);
    return rc;
}

bf_status compare_run_with(bf_compare *c, bf_samples *const *samples, const bf_fit_options *fo, int jobs,
                           const compare_hooks *h, bf_error *err)
{
    bf_error local;
    if (!err)
        err = &local;
    if (!c || !c->materials || !samples || !fo)
        return bf_fail(err, BF_ERR_ARG, "compare: no table, samples or fit options");
    if (c->results)
        return bf_fail(err, BF_ERR_ARG, "compare: the fits have already been run");
    for (int i = 0; i < c->nmaterials; i++) {
        if (!samples[i])
            return bf_fail(err, BF_ERR_ARG, "compare: no samples for %s", c->materials[i].data);
        /* Computed on first use: computed here, before the threads share it. */
        const bf_geometry *g;
        bf_status rc = bf_samples_geometry(samples[i], &g, err);
        if (rc != BF_OK)
            return rc;
        c->materials[i].samples = samples[i]->n;
        c->materials[i].channels = samples[i]->channels;
    }
    run r = {.c = c,
             .samples = samples,
             .fo = *fo,
             .h = h ? *h : (compare_hooks){0},
             .cancel = fo->solver.cancel,
             .total = c->nmaterials * c->nmodels};
    if (!(c->results = calloc((size_t)r.total, sizeof *c->results)))
        return bf_fail(err, BF_ERR_NOMEM, "compare: out of memory for %d fits", r.total);
    jobs = jobs < 1 ? 1 : jobs > r.total ? r.total : jobs;
    r.fo.solver.threads = fo->solver.threads / jobs > 1 ? fo->solver.threads / jobs : 1;
    pthread_mutex_init(&r.lock, NULL);
    bf_parallel_for((size_t)r.total, jobs, fit_one, &r);
    pthread_mutex_destroy(&r.lock);
    c->interrupted = r.done < r.total;
    return BF_OK;
}

int bf_compare_count(const bf_compare *c, bf_compare_state s)
{
    int n = 0;
    for (int i = 0; i < c->nmaterials; i++)
        for (int j = 0; j < c->nmodels; j++)
            n += c->materials[i].fits[j].state == s;
    return n;
}
