/* The fit driver: model, objective, data-driven start, the search for the optimum
 * (search.c: the starts, screened or not), then metrics and standard errors at the best
 * solution.
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

#include "base/sized.h"
#include "fit_impl.h"
#include "run_options.h"

#include "diagnostics.h"
#include "fit_channels.h"
#include "lobe_order.h"
#include "progress.h"
#include "search.h"
#include "silence.h"
#include "brdfit/clock.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
        if (p->eval(p->user, z, r0, r1, r, NULL) != 0) {
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
    bf_status rc = plain_cost(p, z, &cost, err);
    if (rc != BF_OK)
        return rc;
    sol->initial_cost = sol->final_cost = cost;
    sol->evaluations = 1;
    snprintf(sol->backend, sizeof sol->backend, "none");
    snprintf(sol->algorithm, sizeof sol->algorithm, "none");
    sol->usable = isfinite(cost);
    sol->stop = sol->usable ? BF_STOP_CONVERGED : BF_STOP_FAILED;
    snprintf(sol->termination, sizeof sol->termination, "%s",
             sol->usable ? "every parameter fixed: nothing to solve"
                         : "every parameter fixed, and the cost is not finite");
    return BF_OK;
}

static bf_status alloc_result(bf_fit_result *r, int P, bf_error *err)
{
    r->x = calloc((size_t)P + 1, sizeof *r->x);
    r->stderr_ = calloc((size_t)P + 1, sizeof *r->stderr_);
    r->fixed = calloc((size_t)P + 1, 1);
    r->inactive = calloc((size_t)P + 1, 1);
    r->inactive_gate = malloc(((size_t)P + 1) * sizeof *r->inactive_gate);
    for (int k = 0; r->inactive_gate && k < P; k++)
        r->inactive_gate[k] = -1;
    if (!r->x || !r->stderr_ || !r->fixed || !r->inactive || !r->inactive_gate)
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

/* What the fit's phases share. */
typedef struct fit_run {
    bf_samples *s;
    const bf_fit_options *o;
    bf_fit_result *r;
    bf_objective_options oo; /* o->objective; its own passes use the solver's threads */
    bf_fit_watch watch;
    bf_objective *obj; /* all samples' */
    const bf_problem *full;
    int P, nz;              /* the model's values, the free (internal) entries */
    size_t pn;              /* the presolve's samples (0: none) */
    bf_subsample pre;       /* the presolve's subsample (NULL members: none) */
    const bf_problem *prob; /* where the starts are solved */
    double *x0, *z0;        /* the start, in model and internal space */
    double *lo, *hi;        /* the effective bounds (model space) */
    double *z, *zbest;      /* scratch, and the best point (nz each) */
    bf_search sr;
    bf_solution first; /* the first solve's, for the reason of a failed fit */
    uint64_t best_seed;
    int have_best, cancelled;
    unsigned char *held; /* held_entries' flags (NULL: none) */
    int nsilent;
    double *corr;
    bf_fit_result *ch; /* run channel by channel (fit_channels.h): each channel's fit; else NULL */
} fit_run;

/* The start in model space (x0, clamped into the effective bounds lo..hi, fixed values
 * applied) and internal space (z0): the caller's, or the data-driven one read off
 * `from`. Clamped in model space (fixed entries have lo = hi), so that a failed fit
 * reports exactly this start rather than its round trip through the internal scale. */
static bf_status start_point(const fit_run *f, bf_samples *from, bf_error *err)
{
    const bf_fit_options *o = f->o;
    const bf_objective *obj = f->obj;
    const bf_model *m = obj->model;
    const int P = bf_model_nvalues(m);
    double *x0 = f->x0, *lo = f->lo, *hi = f->hi;
    bf_status rc;
    if (o->start)
        memcpy(x0, o->start, (size_t)P * sizeof *x0);
    else if ((rc = bf_fit_initial_guess(m, from, x0, err)) != BF_OK)
        return rc;
    for (int k = 0; k < P; k++)
        if (!isfinite(x0[k])) /* a NaN start would clamp to a bound; say so instead */
            return bf_fail(err, BF_ERR_RANGE, "fit: start value %d is not finite", k);
    bf_objective_bounds(obj, lo, hi);
    for (int k = 0; k < P; k++)
        x0[k] = x0[k] < lo[k] ? lo[k] : x0[k] > hi[k] ? hi[k] : x0[k];
    bf_objective_to_internal(obj, x0, f->z0);
    return BF_OK;
}

/* Cancelled (bf_solver_options.cancel or .progress): no fit. The result holds the start
 * x0 and says why; no metrics, no warnings but that, and the writers refuse it. */
static void cancelled_result(bf_fit_result *r, const bf_fit_options *o, const bf_objective *obj, const double *x0,
                             size_t n)
{
    const int P = bf_model_nvalues(r->model);
    memset(&r->solution, 0, sizeof r->solution);
    r->solution.stop = BF_STOP_CANCELLED;
    snprintf(r->solution.backend, sizeof r->solution.backend, "%s", bf_backend_name(o->solver.backend));
    snprintf(r->solution.termination, sizeof r->solution.termination, "cancelled by the caller");
    r->solution.initial_cost = r->solution.final_cost = NAN;
    memcpy(r->x, x0, (size_t)P * sizeof *x0);
    for (int k = 0; k < P; k++) {
        r->fixed[k] = (unsigned char)(bf_objective_fixed(obj, k) != 0);
        r->stderr_[k] = NAN;
    }
    r->samples = n;
    r->threads = o->solver.threads > 1 ? o->solver.threads : 1;
    r->seed = o->seed;
    r->residual = o->objective.residual;
    bf_fit_warn(r, BF_WARN_CANCELLED, "the fit was cancelled by the caller: no parameters were fitted");
}

/* Entries on a bound and entries without effect at the optimum f->zbest (silence.h),
 * found on objective po: the standard errors leave both out, and k the second. f->held
 * gets 2 nz flags (held, then silent; malloc'd), f->r the inactive entries, f->nsilent
 * their count. */
static bf_status held_entries(fit_run *f, const bf_objective *po, bf_error *err)
{
    const bf_objective *obj = f->obj;
    const bf_fit_options *o = f->o;
    bf_fit_result *r = f->r;
    const int nz = bf_objective_nz(obj);
    bf_silence sil;
    bf_status rc =
        bf_silence_find(bf_objective_problem(po), po, f->zbest, &o->solver.loss, o->solver.threads, &sil, err);
    if (rc != BF_OK)
        return rc;
    unsigned char *h = malloc(2 * (size_t)nz + 1);
    if (!h) {
        bf_silence_free(&sil);
        return bf_fail(err, BF_ERR_NOMEM, "fit: out of memory");
    }
    for (int j = 0; j < nz; j++) {
        h[j] = sil.bound[j] != 0 || sil.silent[j];
        h[nz + j] = sil.silent[j];
        r->inactive[obj->kidx[j]] = sil.silent[j];
        r->inactive_gate[obj->kidx[j]] = sil.silent[j] ? sil.gate[j] : -1;
    }
    f->nsilent = sil.nsilent;
    f->held = h;
    bf_silence_free(&sil);
    return BF_OK;
}

/* What the search did, for the result (the presolve's solves when it ran on one). */
static void search_figures(bf_fit_result *r, const bf_search *sr)
{
    r->starts = sr->starts;
    r->starts_at_best = sr->starts_at_best;
    r->candidates = sr->candidates;
    r->screen = sr->screen;
    if (sr->presolved) {
        r->presolve.iterations = sr->on_prob.iterations;
        r->presolve.evaluations = sr->on_prob.evaluations;
        r->presolve.seconds = sr->on_prob.seconds;
    }
}

/* The whole set, from the best presolved point f->zbest, which becomes the solution's
 * point when it is usable (f->z: scratch). Unless told otherwise it stops at a relative
 * cost change of 1e-9 rather than 1e-10: with the hundreds of thousands of samples a
 * presolve needs, that leaves the parameters within sqrt(1e-9 n) (0.06 for a MERL table's
 * 3.3 M residuals) of their standard errors of the optimum, and saves a pass over all of
 * them. Entries the hand-over holds (search.h) stay where the presolve left them. */
static bf_status solve_whole_set(fit_run *f, bf_solution *sol, bf_error *err)
{
    const int nz = f->full->npar; /* the free entries */
    double *z = f->z, *zbest = f->zbest;
    bf_solver_options so = f->o->solver;
    bf_fit_watch_solve(f->sr.watch, &so);
    memcpy(z, zbest, (size_t)nz * sizeof *z);
    so.seed = f->best_seed;
    if (!(so.function_tolerance > 0.0))
        so.function_tolerance = 1e-9;
    unsigned char *hold = calloc((size_t)nz + 1, 1);
    if (hold && bf_fit_search_handover(&f->sr, z, hold) > 0)
        so.constant = hold;
    bf_status rc = bf_solve(f->full, &so, z, sol, err);
    free(hold);
    if (rc != BF_OK)
        return rc;
    for (int j = 0; j < nz && sol->usable; j++)
        sol->usable = isfinite(z[j]);
    if (sol->usable && isfinite(sol->final_cost))
        memcpy(zbest, z, (size_t)nz * sizeof *z);
    return BF_OK;
}

bf_status bf_fit(bf_samples *s, const char *spec, const bf_options *o, bf_fit_result *r, bf_error *err)
{
    /* Every member of this version lies within the first version's size, so the library
     * fills r itself; a member added later must be filled only within r->size. */
    if (!r || bf_sized_check(r, sizeof *r, "bf_fit_result", err) != BF_OK)
        return BF_ERR_ARG;
    memset((char *)r + sizeof r->size, 0, sizeof *r - sizeof r->size);
    if (!o)
        return bf_fail(err, BF_ERR_ARG, "fit: no options");
    if (o->task == BF_TASK_READ)
        return bf_fail(err, BF_ERR_ARG, "fit: options for reading only (make them for BF_TASK_FIT)");
    bf_status rc = bf_options_check(o, err);
    if (rc != BF_OK)
        return rc;
    if (o->start) { /* the start must be this model's vector */
        bf_model *m = NULL;
        if ((rc = bf_model_new(spec, s ? s->channels : 1, &m, err)) != BF_OK)
            return rc;
        const int n = bf_model_nvalues(m);
        bf_model_free(m);
        if (n != o->nstart)
            return bf_fail(err, BF_ERR_ARG, "%s: the start has %d values, the model %d", spec, o->nstart, n);
    }
    bf_fit_options fo;
    options_fit_get(o, &fo);
    return bf_fit_with(s, spec, &fo, r, err);
}

/* The run's model, the result's arrays and the objective of all samples (f->s, f->o and
 * f->r set, the rest zero). On an error r is cleared (but when the model could not be
 * made) and the run holds nothing to free. */
static bf_status fit_open(fit_run *f, const char *spec, bf_error *err)
{
    bf_fit_result *r = f->r;
    const bf_fit_options *o = f->o;
    bf_status rc = bf_model_new(spec, f->s->channels, &r->model, err);
    if (rc != BF_OK)
        return rc;
    f->P = bf_model_nvalues(r->model);
    rc = alloc_result(r, f->P, err);
    if (rc != BF_OK) {
        bf_fit_result_clear(r);
        return rc;
    }
    f->oo = o->objective; /* its own passes use the solver's threads */
    if (f->oo.threads < 1)
        f->oo.threads = o->solver.threads;
    if ((rc = bf_objective_new(r->model, f->s, &f->oo, &f->obj, err)) != BF_OK) {
        bf_fit_result_clear(r);
        return rc;
    }
    f->full = bf_objective_problem(f->obj);
    f->nz = bf_objective_nz(f->obj);
    bf_fit_watch_init(&f->watch, o, spec);
    f->prob = f->full;
    return BF_OK;
}

/* The points' room, the presolve's subsample, and the start. */
static bf_status fit_prepare(fit_run *f, bf_error *err)
{
    const int P = f->P, nz = f->nz;
    f->x0 = malloc(((size_t)P + 1) * sizeof *f->x0);
    f->z0 = malloc(((size_t)nz + 1) * sizeof *f->z0);
    f->z = malloc(((size_t)nz + 1) * sizeof *f->z);
    f->zbest = malloc(((size_t)nz + 1) * sizeof *f->zbest);
    f->lo = malloc(((size_t)P + 1) * sizeof *f->lo), f->hi = malloc(((size_t)P + 1) * sizeof *f->hi);
    if (!f->x0 || !f->z0 || !f->z || !f->zbest || !f->lo || !f->hi)
        return bf_fail(err, BF_ERR_NOMEM, "fit: out of memory");
    f->pn = nz > 0 ? presolve_samples(f->o, f->s->n) : 0;
    if (f->pn > 0) {
        bf_status rc = bf_fit_subsample_objective(f->s, f->pn, f->o->seed, f->r->model, &f->oo, &f->pre, err);
        if (rc != BF_OK)
            return rc;
        f->prob = bf_objective_problem(f->pre.objective);
    }
    /* The start is read off the presolve's subsample where there is one: the starts are
     * solved there. */
    return start_point(f, f->pre.samples ? f->pre.samples : f->s, err);
}

/* The search for the best point on f->prob (search.c); with every parameter fixed, the
 * start alone. */
static bf_status fit_search(fit_run *f, bf_error *err)
{
    bf_fit_result *r = f->r;
    bf_status rc;
    if (f->nz == 0) {
        /* Every parameter fixed: one point, nothing to search. */
        bf_solution sol;
        if ((rc = fixed_only(f->prob, f->z0, &sol, err)) != BF_OK)
            return rc;
        f->first = r->solution = sol;
        r->starts = 1;
        memcpy(f->zbest, f->z0, (size_t)f->nz * sizeof *f->z);
        f->have_best = sol.usable && isfinite(sol.final_cost);
        r->starts_at_best = f->have_best;
        return BF_OK;
    }
    f->sr = (bf_search){.samples = f->pre.samples ? f->pre.samples : f->s,
                        .options = f->o,
                        .objective_options = &f->oo,
                        .objective = f->pre.objective ? f->pre.objective : f->obj,
                        .prob = f->prob,
                        .presolved = f->pre.objective != NULL,
                        .z0 = f->z0,
                        .z = f->zbest,
                        .watch = &f->watch};
    if ((rc = bf_fit_search(&f->sr, err)) != BF_OK)
        return rc;
    f->have_best = f->sr.have_best;
    f->first = f->sr.first;
    if (f->have_best) {
        r->solution = f->sr.best;
        f->best_seed = f->sr.best_seed;
    }
    f->cancelled = f->sr.cancelled;
    search_figures(r, &f->sr);
    return BF_OK;
}

/* Presolved: the best point solved on all samples (solve_whole_set). */
static bf_status fit_whole_set(fit_run *f, bf_error *err)
{
    if (!f->pre.objective || !f->have_best || f->cancelled)
        return BF_OK;
    bf_fit_result *r = f->r;
    r->presolve.samples = f->pn;
    bf_fit_watch_phase(&f->watch, BF_PHASE_DATA, 1, f->s->n);
    bf_solution sol;
    bf_status rc = solve_whole_set(f, &sol, err);
    if (rc != BF_OK)
        return rc;
    f->cancelled = sol.stop == BF_STOP_CANCELLED;
    r->solution = sol;
    f->have_best = sol.usable && isfinite(sol.final_cost);
    if (!f->have_best)
        f->first = sol; /* the reason below is the whole set's */
    return BF_OK;
}

/* The result's point: the best one, its lobes in order; with no usable start, the start
 * and why the first solve failed. Then which values were fixed. */
static void result_point(fit_run *f)
{
    bf_fit_result *r = f->r;
    const bf_solution *first = &f->first;
    r->ok = f->have_best;
    if (f->have_best) {
        bf_objective_to_model(f->obj, f->zbest, r->x);
        /* Lobes numbered narrowest first, whichever start found them (lobe_order.h). */
        bf_fit_order_lobes(f->obj, r->x);
        bf_objective_to_internal(f->obj, r->x, f->zbest);
    } else {
        /* No usable start: report the start and why the first solve failed. */
        r->solution = *first;
        r->solution.usable = 0;
        if (!isfinite(first->final_cost) || !first->termination[0])
            snprintf(r->solution.termination, sizeof r->solution.termination,
                     "no start gave a finite cost (values too large for this residual?)%s%.80s",
                     first->termination[0] ? "; back end: " : "", first->termination);
        memcpy(r->x, f->x0, (size_t)f->P * sizeof *f->x0);
    }
    for (int k = 0; k < f->P; k++)
        r->fixed[k] = (unsigned char)(bf_objective_fixed(f->obj, k) != 0);
}

/* The metrics, standard errors, covariance and diagnostics at the result's point. */
static bf_status result_figures(fit_run *f, bf_error *err)
{
    bf_fit_result *r = f->r;
    const bf_fit_options *o = f->o;
    const int P = f->P, nz = f->nz;
    bf_status rc;
    /* Entries on a bound and entries without effect (silence.h): the standard errors
     * leave both out, and k the second. */
    /* On the screening set where there is one: which entries a bound silences is a matter
     * of the model, which a thousand samples show as well as all of them. */
    const bf_objective *po = f->sr.screen_objective ? f->sr.screen_objective
                             : f->pre.objective     ? f->pre.objective
                                                    : f->obj;
    if (f->have_best && nz > 0 && !f->ch && (rc = held_entries(f, po, err)) != BF_OK)
        return rc;
    if (!(f->corr = malloc(((size_t)nz * (size_t)nz + 1) * sizeof *f->corr)))
        return bf_fail(err, BF_ERR_NOMEM, "fit: out of memory for the correlations");
    /* Samples a scene weighted are judged over its directions, as it weighs them,
     * however they reached the fit. */
    const int weighted = o->weighted_metrics || f->s->scene_weight != NULL;
    if (!(r->covariance = malloc(((size_t)P * (size_t)P + 1) * sizeof *r->covariance)))
        return bf_fail(err, BF_ERR_NOMEM, "fit: out of memory for the covariance");
    const bf_final_want want = {weighted, nz - f->nsilent, f->held, f->held ? f->held + nz : NULL};
    const bf_final_out out = {&r->metrics, r->stderr_, f->corr, r->covariance};
    if ((rc = bf_obj_final(f->obj, r->x, &want, &out, err)) != BF_OK)
        return rc;
    if (o->solver.loss.kind != BF_LOSS_NONE) /* no Gaussian likelihood was maximised */
        r->metrics.loglik = r->metrics.aic = r->metrics.aicc = r->metrics.bic = NAN;
    r->samples = f->s->n;
    r->threads = o->solver.threads > 1 ? o->solver.threads : 1;
    r->seed = o->seed;
    r->residual = o->objective.residual;
    if (f->ch) { /* the channels' own search warnings, then what the merged point shows */
        bf_fit_channels_warn(f->ch, f->s, r);
        bf_fit_diagnose_model(f->obj, f->s, o, f->corr, r);
    } else {
        bf_fit_diagnose(f->obj, f->s, o, f->corr, r);
    }
    return BF_OK;
}

/* The result from what the search found: the cancelled one, or its point and figures. */
static bf_status fit_result(fit_run *f, bf_error *err)
{
    if (f->cancelled) {
        cancelled_result(f->r, f->o, f->obj, f->x0, f->s->n);
        return BF_OK;
    }
    result_point(f);
    return result_figures(f, err);
}

/* Each channel of f->s fitted alone into f->ch[c] (fit_channels.h), one after another;
 * stops after a cancelled one (*done: the channels fitted). */
static bf_status fit_channels_each(fit_run *f, const char *spec, int *done, bf_error *err)
{
    const bf_fit_options *o = f->o;
    bf_fit_options oc = *o;
    bf_model *m1 = NULL;
    bf_override *ov = malloc(((size_t)o->objective.noverrides + 1) * sizeof *ov);
    double *start = malloc(((size_t)f->P + 1) * sizeof *start);
    bf_status rc = ov && start ? bf_model_new(spec, 1, &m1, err) : bf_fail(err, BF_ERR_NOMEM, "fit: out of memory");
    oc.objective.overrides = ov;
    oc.start = o->start ? start : NULL;
    *done = 0;
    for (int c = 0; rc == BF_OK && c < f->s->channels; c++) {
        bf_samples *sc = NULL;
        if ((rc = bf_fit_channels_options(o, f->r->model, m1, c, &oc)) == BF_OK &&
            (rc = bf_fit_channels_samples(f->s, c, &sc, err)) == BF_OK)
            rc = bf_fit_with(sc, spec, &oc, &f->ch[c], err);
        bf_samples_free(sc);
        if (rc == BF_OK)
            *done = c + 1;
        if (rc == BF_OK && f->ch[c].solution.stop == BF_STOP_CANCELLED)
            break;
    }
    bf_model_free(m1);
    free(ov);
    free(start);
    return rc;
}

/* Channel by channel (fit_channels.h): each channel fitted alone, their results merged
 * into f->r, and the held entries of the merged point (on a bound: read off it; without
 * effect: the channels' inactive entries) for result_figures, which computes the
 * metrics, standard errors and warnings over all channels as for any fit. A cancelled
 * channel cancels the fit (f->x0: the start, as a cancelled fit reports). */
static bf_status fit_separately(fit_run *f, const char *spec, bf_error *err)
{
    const int C = f->s->channels, P = f->P, nz = f->nz;
    bf_fit_result *r = f->r;
    f->ch = calloc((size_t)C, sizeof *f->ch);
    f->x0 = malloc(((size_t)P + 1) * sizeof *f->x0);
    f->z0 = malloc(((size_t)nz + 1) * sizeof *f->z0);
    f->zbest = malloc(((size_t)nz + 1) * sizeof *f->zbest);
    f->lo = malloc(((size_t)P + 1) * sizeof *f->lo), f->hi = malloc(((size_t)P + 1) * sizeof *f->hi);
    f->held = malloc(2 * (size_t)nz + 1);
    if (!f->ch || !f->x0 || !f->z0 || !f->zbest || !f->lo || !f->hi || !f->held) {
        free(f->ch), f->ch = NULL;
        return bf_fail(err, BF_ERR_NOMEM, "fit: out of memory");
    }
    for (int c = 0; c < C; c++)
        bf_fit_result_init(&f->ch[c]);
    int done = 0;
    bf_status rc = fit_channels_each(f, spec, &done, err);
    if (rc != BF_OK)
        return rc;
    if (done < C || f->ch[C - 1].solution.stop == BF_STOP_CANCELLED) {
        f->cancelled = 1;
        return start_point(f, f->s, err);
    }
    bf_fit_channels_merge(f->ch, C, r);
    f->have_best = r->ok;
    for (int k = 0; k < P; k++)
        r->fixed[k] = (unsigned char)(bf_objective_fixed(f->obj, k) != 0);
    bf_objective_to_internal(f->obj, r->x, f->zbest);
    f->nsilent = 0;
    for (int j = 0; j < nz; j++) {
        const unsigned char silent = r->inactive[f->obj->kidx[j]];
        f->held[j] = bf_silence_at_bound(f->full, f->zbest, j) != 0 || silent;
        f->held[nz + j] = silent;
        f->nsilent += silent;
    }
    return BF_OK;
}

static void fit_close(fit_run *f)
{
    for (int c = 0; f->ch && c < f->s->channels; c++)
        bf_fit_result_clear(&f->ch[c]);
    free(f->ch);
    bf_fit_search_clear(&f->sr);
    free(f->held);
    free(f->corr);
    free(f->x0);
    free(f->z0);
    free(f->z);
    free(f->zbest);
    free(f->lo);
    free(f->hi);
    bf_objective_free(f->pre.objective);
    bf_samples_free(f->pre.samples);
    bf_objective_free(f->obj);
}

bf_status bf_fit_with(bf_samples *s, const char *spec, const bf_fit_options *o, bf_fit_result *r, bf_error *err)
{
    double t0 = bf_now_seconds();
    bf_fit_result_init(r);
    if (!s || !o)
        return bf_fail(err, BF_ERR_ARG, "fit: no samples or no options");
    if (s->n == 0)
        return bf_fail(err, BF_ERR_ARG, "fit: no samples");
    fit_run f = {.s = s, .o = o, .r = r};
    bf_status rc = fit_open(&f, spec, err);
    if (rc != BF_OK)
        return rc;
    if (bf_fit_channels_separable(f.obj)) {
        if ((rc = fit_separately(&f, spec, err)) == BF_OK)
            rc = f.cancelled ? (cancelled_result(r, o, f.obj, f.x0, s->n), BF_OK) : result_figures(&f, err);
    } else if ((rc = fit_prepare(&f, err)) == BF_OK && (rc = fit_search(&f, err)) == BF_OK &&
               (rc = fit_whole_set(&f, err)) == BF_OK) {
        rc = fit_result(&f, err);
    }
    fit_close(&f);
    if (rc != BF_OK) {
        bf_fit_result_clear(r);
        return rc;
    }
    r->seconds = bf_now_seconds() - t0;
    if (r->solution.stop != BF_STOP_CANCELLED)
        bf_fit_watch_done(&f.watch, &r->solution, s->n);
    return BF_OK;
}

BF_SIZED_INIT_ZERO(bf_fit_result)

void bf_fit_result_clear(bf_fit_result *r)
{
    if (!r)
        return;
    bf_model_free(r->model);
    free(r->x);
    free(r->stderr_);
    free(r->fixed);
    free(r->inactive);
    free(r->inactive_gate);
    free(r->covariance);
    const size_t size = r->size; /* the caller's: it stays ready for another fit */
    memset(r, 0, sizeof *r);
    r->size = size;
}
