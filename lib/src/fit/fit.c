/* The fit driver: model, objective, data-driven start, seeded multistart over the
 * chosen back end, then metrics and standard errors at the best solution.
 *
 * Multistart: start 0 is the data-driven start (or the caller's); starts 1 .. N-1 are
 * drawn uniformly within the objective's bounds in its internal space (so uniformly in
 * log for log-scale parameters), from splitmix64 (Steele, Lea & Flood 2014) seeded with
 * the fit's seed, drawing the internal coordinates in order, start after start. Start k
 * gives stochastic back-end methods the seed bf_splitmix64(seed + k + 1)'s first output.
 * Starts run one after another, each solve using the requested threads, so the result
 * is a function of the seed and the thread count alone. The best usable final cost wins;
 * ties go to the earlier start.
 *
 * Presolve (bf_fit_options.presolve): on a large data set the starts are solved on a
 * seeded stratified subsample (bf_samples_subsample_mask, seeded with the fit's seed),
 * and only the best of them on all samples, from where the subsample's solve ended. A
 * pass over the subsample costs a thirtieth of one over a MERL table, and far from the
 * optimum a subsample steers as well as the whole set; near it the whole set's solve
 * needs a few Gauss-Newton steps. Both objectives have the same internal space (the
 * bounds and scales come from the model and the overrides, not from the data). The
 * reported solution is the whole set's; the presolve's counts go apart. */
#include "brdfit/fit.h"
#include "brdfit/prep.h"

#include "big_alloc.h"
#include "diagnostics.h"
#include "../rng.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* One random start: uniform in [lo, hi] per internal coordinate; an unbounded side
 * (not expected from the model tables, but allowed by bf_problem) spans 1 unit (or
 * |z0|) beyond the start. */
static void random_start(const bf_problem *p, const double *z0, uint64_t *state, double *z)
{
    for (int k = 0; k < p->npar; k++) {
        double span = fabs(z0[k]) > 1.0 ? fabs(z0[k]) : 1.0;
        double lo = isfinite(p->lo[k]) ? p->lo[k] : z0[k] - span;
        double hi = isfinite(p->hi[k]) ? p->hi[k] : z0[k] + span;
        z[k] = lo + bf_uniform01(state) * (hi - lo);
        if (z[k] > hi) /* rounding */
            z[k] = hi;
    }
}

/* The cost 1/2 sum r^2 at z when nothing is free to solve for (every parameter fixed). */
static bf_status plain_cost(const bf_problem *p, const double *z, double *cost, bf_error *err)
{
    enum { CHUNK = 4096 };
    double *r = malloc(CHUNK * sizeof *r);
    if (!r)
        return bf_fail(err, BF_ERR_NOMEM, "fit: out of memory");
    double c = 0.0;
    for (size_t r0 = 0; r0 < p->nres; r0 += CHUNK) {
        size_t r1 = r0 + CHUNK < p->nres ? r0 + CHUNK : p->nres;
        if (p->eval(p->ctx, z, r0, r1, r, NULL) != 0) {
            c = NAN;
            break;
        }
        for (size_t i = 0; i < r1 - r0; i++)
            c += 0.5 * r[i] * r[i];
    }
    free(r);
    *cost = c;
    return BF_OK;
}

static bf_status fixed_only(const bf_problem *p, const double *z, bf_solution *sol, bf_error *err)
{
    memset(sol, 0, sizeof *sol);
    double cost = NAN;
    int rc = plain_cost(p, z, &cost, err);
    if (rc != BF_OK)
        return rc;
    sol->initial_cost = sol->final_cost = cost;
    sol->evaluations = 1;
    snprintf(sol->backend, sizeof sol->backend, "none");
    snprintf(sol->algorithm, sizeof sol->algorithm, "none");
    sol->usable = isfinite(cost);
    snprintf(sol->termination, sizeof sol->termination, "%s",
             sol->usable ? "every parameter fixed: nothing to solve" : "every parameter fixed, and the cost is not finite");
    return BF_OK;
}

static bf_status alloc_result(bf_fit_result *r, int P, bf_error *err)
{
    r->x = calloc((size_t)P + 1, sizeof *r->x);
    r->stderr_ = calloc((size_t)P + 1, sizeof *r->stderr_);
    r->fixed = calloc((size_t)P + 1, 1);
    if (!r->x || !r->stderr_ || !r->fixed)
        return bf_fail(err, BF_ERR_NOMEM, "fit: out of memory");
    return BF_OK;
}

/* Samples of the presolve for n samples (0: none). */
static size_t presolve_samples(const bf_fit_options *o, size_t n)
{
    if (o->presolve < 0)
        return 0;
    if (o->presolve > 0)
        return (size_t)o->presolve < n ? (size_t)o->presolve : 0;
    return n >= BF_FIT_PRESOLVE_MIN ? BF_FIT_PRESOLVE_SAMPLES : 0;
}

/* The presolve's subsample of s and its objective (same options), or an error. */
static bf_status presolve_objective(bf_samples *s, size_t pn, const bf_fit_options *o, const bf_model *m,
                              const bf_objective_options *oo, bf_samples **ps, bf_objective **pobj, bf_error *err)
{
    unsigned char *keep = bf_big_malloc(s->n + 1);
    if (!keep)
        return bf_fail(err, BF_ERR_NOMEM, "fit: out of memory for the presolve");
    bf_status rc = bf_samples_subsample_mask(s, pn, o->seed, keep, err);
    if (rc == BF_OK)
        rc = bf_samples_copy(s, keep, ps, err);
    free(keep);
    if (rc == BF_OK)
        rc = bf_objective_new(m, *ps, oo, pobj, err);
    return rc;
}

bf_status bf_fit(bf_samples *s, const char *spec, const bf_fit_options *o, bf_fit_result *r, bf_error *err)
{
    double t0 = bf_now_seconds();
    memset(r, 0, sizeof *r);
    if (!s || !o)
        return bf_fail(err, BF_ERR_ARG, "fit: no samples or no options");
    if (s->n == 0)
        return bf_fail(err, BF_ERR_ARG, "fit: no samples");
    bf_status rc = bf_model_new(spec, s->channels, &r->model, err);
    if (rc != BF_OK)
        return rc;
    const bf_model *m = r->model;
    const int P = bf_model_nvalues(m);
    rc = alloc_result(r, P, err);
    if (rc != BF_OK) {
        bf_fit_result_clear(r);
        return rc;
    }
    bf_objective_options oo = o->objective; /* its own passes use the solver's threads */
    if (oo.threads < 1)
        oo.threads = o->solver.threads;
    bf_objective *obj;
    if ((rc = bf_objective_new(m, s, &oo, &obj, err)) != BF_OK) {
        bf_fit_result_clear(r);
        return rc;
    }
    const bf_problem *full = bf_objective_problem(obj);
    const int nz = bf_objective_nz(obj);
    bf_samples *ps = NULL;
    bf_objective *pobj = NULL;
    double *corr = NULL;
    const bf_problem *prob = full; /* where the starts are solved */
    const int starts = o->starts > 1 ? o->starts : 1;
    double *x0 = malloc(((size_t)P + 1) * sizeof *x0);
    double *z0 = malloc(((size_t)nz + 1) * sizeof *z0);
    double *z = malloc(((size_t)nz + 1) * sizeof *z);
    double *zbest = malloc(((size_t)nz + 1) * sizeof *zbest);
    double *lo = malloc(((size_t)P + 1) * sizeof *lo), *hi = malloc(((size_t)P + 1) * sizeof *hi);
    if (!x0 || !z0 || !z || !zbest || !lo || !hi) {
        rc = bf_fail(err, BF_ERR_NOMEM, "fit: out of memory");
        goto done;
    }
    const size_t pn = nz > 0 ? presolve_samples(o, s->n) : 0;
    if (pn > 0) {
        if ((rc = presolve_objective(s, pn, o, m, &oo, &ps, &pobj, err)) != BF_OK)
            goto done;
        prob = bf_objective_problem(pobj);
    }

    /* The start, clamped into the effective bounds and with fixed values applied. */
    if (o->start)
        memcpy(x0, o->start, (size_t)P * sizeof *x0);
    else if ((rc = bf_fit_initial_guess(m, s, x0, err)) != BF_OK)
        goto done;
    for (int k = 0; k < P; k++) {
        if (!isfinite(x0[k])) { /* a NaN start would clamp to a bound; say so instead */
            rc = bf_fail(err, BF_ERR_RANGE, "fit: start value %d is not finite", k);
            goto done;
        }
    }
    /* Clamped in model space (fixed entries have lo = hi), so that a failed fit reports
     * exactly this start rather than its round trip through the internal scale. */
    bf_objective_bounds(obj, lo, hi);
    for (int k = 0; k < P; k++)
        x0[k] = x0[k] < lo[k] ? lo[k] : x0[k] > hi[k] ? hi[k] : x0[k];
    bf_objective_to_internal(obj, x0, z0);

    bf_solver_options so = o->solver;
    uint64_t best_seed = 0;
    int have_best = 0;
    bf_solution sol, first;
    memset(&first, 0, sizeof first);
    uint64_t draw = o->seed;
    for (int k = 0; k < starts; k++) {
        if (k == 0)
            memcpy(z, z0, (size_t)nz * sizeof *z);
        else
            random_start(prob, z0, &draw, z);
        uint64_t sseed = o->seed + (uint64_t)k + 1;
        so.seed = bf_splitmix64(&sseed);
        if (nz == 0)
            rc = fixed_only(prob, z, &sol, err);
        else
            rc = bf_solve(prob, &so, z, &sol, err);
        if (rc != BF_OK && k == 0)
            goto done; /* bad options or a back end that cannot run at all */
        r->starts = k + 1;
        if (rc != BF_OK) { /* a random start the back end failed on: just not usable */
            rc = BF_OK;
            continue;
        }
        if (k == 0)
            first = sol;
        if (pobj) {
            r->presolve.iterations += sol.iterations;
            r->presolve.evaluations += sol.evaluations;
            r->presolve.seconds += sol.seconds;
        }
        for (int j = 0; j < nz && sol.usable; j++)
            sol.usable = isfinite(z[j]);
        if (sol.usable && isfinite(sol.final_cost) && (!have_best || sol.final_cost < r->solution.final_cost)) {
            r->solution = sol;
            best_seed = so.seed;
            memcpy(zbest, z, (size_t)nz * sizeof *z);
            have_best = 1;
        }
        if (nz == 0)
            break; /* every start is the same point */
    }
    if (pobj && have_best) {
        /* The whole set, from the best presolved point. Unless told otherwise it stops at
         * a relative cost change of 1e-9 rather than 1e-10: with the hundreds of
         * thousands of samples a presolve needs, that leaves the parameters within
         * sqrt(1e-9 n) (0.06 for a MERL table's 3.3 M residuals) of their standard errors
         * of the optimum, and saves a pass over all of them. */
        r->presolve.samples = pn;
        memcpy(z, zbest, (size_t)nz * sizeof *z);
        so.seed = best_seed;
        if (!(so.function_tolerance > 0.0))
            so.function_tolerance = 1e-9;
        if ((rc = bf_solve(full, &so, z, &sol, err)) != BF_OK)
            goto done;
        for (int j = 0; j < nz && sol.usable; j++)
            sol.usable = isfinite(z[j]);
        r->solution = sol;
        have_best = sol.usable && isfinite(sol.final_cost);
        if (have_best)
            memcpy(zbest, z, (size_t)nz * sizeof *z);
        else
            first = sol; /* the reason below is the whole set's */
    }
    r->ok = have_best;
    if (have_best) {
        bf_objective_to_model(obj, zbest, r->x);
    } else {
        /* No usable start: report the start and why the first solve failed. */
        r->solution = first;
        r->solution.usable = 0;
        if (!isfinite(first.final_cost) || !first.termination[0])
            snprintf(r->solution.termination, sizeof r->solution.termination,
                     "no start gave a finite cost (values too large for this residual?)%s%.80s",
                     first.termination[0] ? "; back end: " : "", first.termination);
        memcpy(r->x, x0, (size_t)P * sizeof *x0);
    }
    for (int k = 0; k < P; k++)
        r->fixed[k] = (unsigned char)(bf_objective_fixed(obj, k) != 0);
    corr = malloc(((size_t)nz * (size_t)nz + 1) * sizeof *corr);
    if ((rc = bf_obj_final(obj, r->x, o->weighted_metrics, nz, &r->metrics, r->stderr_, corr, err)) != BF_OK)
        goto done;
    if (o->solver.loss.kind != BF_LOSS_NONE) /* no Gaussian likelihood was maximised */
        r->metrics.loglik = r->metrics.aic = r->metrics.aicc = r->metrics.bic = NAN;
    r->samples = s->n;
    r->threads = o->solver.threads > 1 ? o->solver.threads : 1;
    r->seed = o->seed;
    r->residual = o->objective.residual;
    bf_fit_diagnose(obj, s, o, corr, r);

done:
    free(corr);
    free(x0);
    free(z0);
    free(z);
    free(zbest);
    free(lo);
    free(hi);
    bf_objective_free(pobj);
    bf_samples_free(ps);
    bf_objective_free(obj);
    if (rc != BF_OK) {
        bf_fit_result_clear(r);
        return rc;
    }
    r->seconds = bf_now_seconds() - t0;
    return BF_OK;
}

void bf_fit_result_clear(bf_fit_result *r)
{
    if (!r)
        return;
    bf_model_free(r->model);
    free(r->x);
    free(r->stderr_);
    free(r->fixed);
    memset(r, 0, sizeof *r);
}
