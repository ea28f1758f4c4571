/* The NLopt back end: minimises F(x) = 1/2 sum rho(r_i^2) through NLopt's C API.
 *
 * The cost and its gradient come from the problem's fused pass (bf_problem_normal: the
 * residuals and their Jacobian rows reduced chunk by chunk, nothing of size
 * nres x npar stored, chunks summed in a fixed order), so the cost and gradient, and
 * hence the whole solve, are bit-for-bit identical for any o->threads.
 *
 * Constant parameters are removed from the vector NLopt sees (lo = hi would break
 * BOBYQA, whose trust region needs hi - lo > 0); they stay at their start values.
 *
 * Counting: iterations = objective calls made by NLopt (NLopt has no iteration count of
 * its own); evaluations = those plus the one evaluation of the start's cost.
 *
 * Randomness: stochastic methods (GN_CRS2_LM, GN_ISRES, G_MLSL_LDS) draw from NLopt's
 * generator, which nlopt_srand(o->seed) seeds before every solve. That generator is
 * NLopt's global state (per thread when NLopt is built with thread-local storage, else
 * per process): concurrent solves in one process must not rely on each other's seeds. */
#include "brdfit/solve.h"
#include "backends.h"
#include "brdfit/clock.h"

#include <math.h>
#include <nlopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* NLopt's constant for a method of the registry (methods.c holds the names, which are
 * NLopt's own: NLopt maps them back). NLOPT_NUM_ALGORITHMS for a registry entry NLopt
 * does not know: caught by a test. */
static nlopt_algorithm nl_of(const bf_method_info *m)
{
    nlopt_algorithm a = nlopt_algorithm_from_string(m->name);
    return (int)a < 0 ? NLOPT_NUM_ALGORITHMS : a;
}

typedef struct nl_state {
    const bf_problem *p;
    bf_loss loss;
    int threads;
    int npar, nfree;
    int *freeidx;  /* free index -> problem index */
    double *xfull; /* problem vector: constants at their start, the rest from NLopt */
    double *gfull; /* gradient over the problem vector */
    /* bookkeeping */
    int evals, failures;
    double best;
    double *xbest;
    /* Cancelling (bf_solver_options.cancel and .progress): the running optimizer, stopped
     * with nlopt_force_stop. */
    const bf_solver_options *o;
    nlopt_opt running;
    int cancelled;
} nl_state;

/* Cost at the free vector z (and its gradient when grad is not NULL). A failed or
 * non-finite evaluation gives HUGE_VAL and a zero gradient, so NLopt never sees NaN. */
static double evaluate(nl_state *st, const double *z, double *grad)
{
    for (int j = 0; j < st->nfree; j++)
        st->xfull[st->freeidx[j]] = z[j];
    st->evals++;
    double ssq = 0.0;
    int ok = bf_problem_normal(st->p, st->xfull, &st->loss, st->threads, &ssq, grad ? st->gfull : NULL, NULL) == 0;
    double cost = 0.5 * ssq;
    if (grad)
        for (int j = 0; j < st->nfree; j++) {
            grad[j] = st->gfull[st->freeidx[j]];
            if (!isfinite(grad[j]))
                ok = 0;
        }
    if (!ok || !isfinite(cost)) {
        st->failures++;
        if (grad)
            memset(grad, 0, (size_t)st->nfree * sizeof *grad);
        return HUGE_VAL;
    }
    if (cost < st->best) {
        st->best = cost;
        memcpy(st->xbest, z, (size_t)st->nfree * sizeof *z);
    }
    if (st->running && !st->cancelled && bf_solver_cancelled(st->o, st->evals, cost)) {
        st->cancelled = 1;
        nlopt_force_stop(st->running);
    }
    return cost;
}

static double nl_objective(unsigned n, const double *z, double *grad, void *data)
{
    (void)n;
    return evaluate(data, z, grad);
}

/* The problem's inequality constraint c(x) <= 0 over the free vector. */
static double nl_constraint(unsigned n, const double *z, double *grad, void *data)
{
    nl_state *st = data;
    (void)n;
    for (int j = 0; j < st->nfree; j++)
        st->xfull[st->freeidx[j]] = z[j];
    if (grad)
        memset(st->gfull, 0, (size_t)st->npar * sizeof *st->gfull);
    double c = st->p->constraint(st->p->user, st->xfull, grad ? st->gfull : NULL);
    int ok = isfinite(c);
    if (grad) {
        for (int j = 0; j < st->nfree; j++) {
            grad[j] = st->gfull[st->freeidx[j]];
            if (!isfinite(grad[j]))
                ok = 0;
        }
        if (!ok)
            memset(grad, 0, (size_t)st->nfree * sizeof *grad);
    }
    return ok ? c : HUGE_VAL; /* a failed constraint counts as violated */
}

static void state_free(nl_state *st)
{
    free(st->freeidx);
    free(st->xfull);
    free(st->gfull);
    free(st->xbest);
}

static int state_init(nl_state *st, const bf_problem *p, const bf_solver_options *o, const double *x)
{
    memset(st, 0, sizeof *st);
    st->p = p;
    st->o = o;
    st->loss = o->loss;
    st->threads = o->threads > 1 ? o->threads : 1;
    st->npar = p->npar;
    const size_t np = (size_t)p->npar;
    st->freeidx = malloc(np * sizeof *st->freeidx);
    st->xfull = malloc(np * sizeof *st->xfull);
    st->gfull = malloc(np * sizeof *st->gfull);
    st->xbest = malloc(np * sizeof *st->xbest);
    if (!st->freeidx || !st->xfull || !st->gfull || !st->xbest)
        return -1;
    memcpy(st->xfull, x, np * sizeof *x);
    for (int k = 0; k < p->npar; k++)
        if (!(o->constant && o->constant[k]))
            st->freeidx[st->nfree++] = k;
    st->best = HUGE_VAL;
    return 0;
}

static const char *result_text(nlopt_result r)
{
    switch (r) {
    case NLOPT_SUCCESS: return "NLOPT_SUCCESS";
    case NLOPT_STOPVAL_REACHED: return "NLOPT_STOPVAL_REACHED";
    case NLOPT_FTOL_REACHED: return "NLOPT_FTOL_REACHED: relative change of cost below ftol_rel";
    case NLOPT_XTOL_REACHED: return "NLOPT_XTOL_REACHED: relative change of parameters below xtol_rel";
    case NLOPT_MAXEVAL_REACHED: return "NLOPT_MAXEVAL_REACHED: evaluation limit reached";
    case NLOPT_MAXTIME_REACHED: return "NLOPT_MAXTIME_REACHED: time limit reached";
    case NLOPT_FAILURE: return "NLOPT_FAILURE";
    case NLOPT_INVALID_ARGS: return "NLOPT_INVALID_ARGS";
    case NLOPT_OUT_OF_MEMORY: return "NLOPT_OUT_OF_MEMORY";
    case NLOPT_ROUNDOFF_LIMITED: return "NLOPT_ROUNDOFF_LIMITED: rounding errors limited progress";
    case NLOPT_FORCED_STOP: return "NLOPT_FORCED_STOP";
    default: return "NLOPT result unknown";
    }
}

/* Applies the stopping criteria shared by the main and the local optimizer. */
static int set_tolerances(nlopt_opt opt, const bf_solver_options *o)
{
    const double ftol = o->function_tolerance > 0 ? o->function_tolerance : 1e-10;
    const double xtol = o->parameter_tolerance > 0 ? o->parameter_tolerance : 1e-10;
    return nlopt_set_ftol_rel(opt, ftol) > 0 && nlopt_set_xtol_rel(opt, xtol) > 0;
}

/* One solve, shared by its phases (choose_method, check_start, make_free_vector,
 * configure, run, copy_out): the inputs, the method, the free vector and its bounds,
 * the NLopt objects and what the run gave. */
typedef struct nl_solve {
    const bf_problem *p;
    const bf_solver_options *o;
    double *x;
    bf_solution *s;
    bf_error *err;
    const bf_method_info *alg, *local;
    int constrained;
    nl_state st;
    double *z, *zlo, *zhi; /* over the free parameters */
    nlopt_opt opt, lopt;
    /* the run */
    nlopt_result res;
    double f;
    const char *nlmsg;
} nl_solve;

/* The method (and MLSL's local one) from the options, named in s->algorithm. */
static bf_status choose_method(nl_solve *sv)
{
    const bf_solver_options *o = sv->o;
    bf_solution *s = sv->s;
    bf_solver_options chk = *o;
    chk.backend = BF_BACKEND_NLOPT;
    if (bf_solver_options_check(&chk, sv->err) != BF_OK)
        return BF_ERR_ARG;
    const bf_method_info *alg = bf_method_find(BF_BACKEND_NLOPT, o->algorithm);
    sv->alg = alg;
    snprintf(s->algorithm, sizeof s->algorithm, "%s", alg->name);
    if (nl_of(alg) == NLOPT_G_MLSL_LDS) {
        sv->local = bf_method_find(BF_BACKEND_NLOPT,
                                   o->local_algorithm && *o->local_algorithm ? o->local_algorithm : "LD_LBFGS");
        snprintf(s->algorithm, sizeof s->algorithm, "%s+%s", alg->name, sv->local->name);
    }
    sv->constrained = o->use_constraint && sv->p->constraint;
    return BF_OK;
}

/* Finite bounds for a global method, and a finite start, clamped into the bounds. */
static bf_status check_start(nl_solve *sv)
{
    const bf_problem *p = sv->p;
    const bf_solver_options *o = sv->o;
    double *x = sv->x;
    for (int k = 0; k < p->npar; k++) {
        const int fixed = o->constant && o->constant[k];
        const double lo = p->lo ? p->lo[k] : -INFINITY, hi = p->hi ? p->hi[k] : INFINITY;
        if ((sv->alg->caps & BF_METHOD_GLOBAL) && !fixed && !(isfinite(lo) && isfinite(hi)))
            return bf_fail(sv->err, BF_ERR_ARG, "NLopt global method %s needs finite bounds; parameter %d has [%g, %g]",
                           sv->alg->name, k, lo, hi);
        x[k] = x[k] < lo ? lo : x[k] > hi ? hi : x[k];
        if (!isfinite(x[k]))
            return bf_fail(sv->err, BF_ERR_RANGE, "NLopt: start value of parameter %d is not finite", k);
    }
    return BF_OK;
}

/* The evaluation state, and the start and bounds of the free parameters (z, zlo, zhi).
 * Frees what it made when it fails. */
static bf_status make_free_vector(nl_solve *sv)
{
    const bf_problem *p = sv->p;
    if (state_init(&sv->st, p, sv->o, sv->x) != 0) {
        state_free(&sv->st);
        return bf_fail(sv->err, BF_ERR_NOMEM, "NLopt: out of memory for %zu residuals x %d parameters", p->nres,
                       p->npar);
    }
    const int nfree = sv->st.nfree;
    double *z = malloc((size_t)(nfree > 0 ? nfree : 1) * 3 * sizeof *z);
    if (!z) {
        state_free(&sv->st);
        return bf_fail(sv->err, BF_ERR_NOMEM, "NLopt: out of memory");
    }
    double *zlo = z + nfree, *zhi = zlo + nfree;
    for (int j = 0; j < nfree; j++) {
        const int k = sv->st.freeidx[j];
        z[j] = sv->x[k];
        zlo[j] = p->lo ? p->lo[k] : -INFINITY;
        zhi[j] = p->hi ? p->hi[k] : INFINITY;
    }
    sv->z = z;
    sv->zlo = zlo;
    sv->zhi = zhi;
    return BF_OK;
}

/* The optimizer (and MLSL's local one): objective, bounds, stopping criteria and the
 * constraint. */
static bf_status configure(nl_solve *sv)
{
    const bf_solver_options *o = sv->o;
    const int nfree = sv->st.nfree;
    nlopt_opt opt = sv->opt = nlopt_create(nl_of(sv->alg), (unsigned)nfree);
    if (!opt)
        return bf_fail(sv->err, BF_ERR_NOMEM, "NLopt: cannot create %s", sv->alg->name);
    const int maxeval = o->max_iterations > 0 ? o->max_iterations : (sv->alg->caps & BF_METHOD_GLOBAL) ? 20000 : 2000;
    int setup = nlopt_set_min_objective(opt, nl_objective, &sv->st) > 0 && nlopt_set_lower_bounds(opt, sv->zlo) > 0 &&
                nlopt_set_upper_bounds(opt, sv->zhi) > 0 && set_tolerances(opt, o) &&
                nlopt_set_maxeval(opt, maxeval) > 0 &&
                (o->max_seconds <= 0 || nlopt_set_maxtime(opt, o->max_seconds) > 0);
    if (setup && sv->constrained)
        setup = nlopt_add_inequality_constraint(opt, nl_constraint, &sv->st, 1e-12) > 0;
    if (setup && sv->local) {
        sv->lopt = nlopt_create(nl_of(sv->local), (unsigned)nfree);
        setup = sv->lopt && set_tolerances(sv->lopt, o) && nlopt_set_local_optimizer(opt, sv->lopt) > 0;
    }
    if (!setup)
        return bf_fail(sv->err, BF_ERR_ARG, "NLopt: cannot set up %s (%s)", sv->s->algorithm,
                       nlopt_get_errmsg(opt) ? nlopt_get_errmsg(opt) : "invalid settings");
    return BF_OK;
}

/* NLopt from z, seeded; the iterations are the objective calls it made. */
static void run(nl_solve *sv)
{
    nlopt_srand((unsigned long)sv->o->seed);
    const int evals_before = sv->st.evals;
    sv->f = HUGE_VAL;
    sv->st.running = sv->opt;
    sv->res = nlopt_optimize(sv->opt, sv->z, &sv->f);
    sv->st.running = NULL;
    sv->nlmsg = nlopt_get_errmsg(sv->opt);
    sv->s->iterations = sv->st.evals - evals_before;
}

/* The run's point into x (clamped into the bounds) when it is usable, and why it stopped
 * into s. */
static void copy_out(nl_solve *sv)
{
    bf_solution *s = sv->s;
    const nl_state *st = &sv->st;
    const nlopt_result res = sv->res;
    const int nfree = st->nfree;
    double *z = sv->z;
    double f = sv->f;
    /* NLopt's answer, unless (unconstrained) a better point was evaluated, or NLopt
     * failed: then the best point seen, which is feasible only without a constraint. */
    int zfinite = 1;
    for (int j = 0; j < nfree; j++)
        zfinite &= isfinite(z[j]) != 0;
    if (!zfinite || !isfinite(f))
        f = HUGE_VAL;
    if (!sv->constrained && st->best < f) {
        memcpy(z, st->xbest, (size_t)nfree * sizeof *z);
        f = st->best;
    }
    const int usable = isfinite(f) && (res > 0 || res == NLOPT_ROUNDOFF_LIMITED || f < s->initial_cost);
    int w = snprintf(s->termination, sizeof s->termination, "%s",
                     st->cancelled && res == NLOPT_FORCED_STOP ? "NLOPT_FORCED_STOP: cancelled by the caller"
                                                               : result_text(res));
    if (res < 0 && sv->nlmsg && w > 0 && (size_t)w < sizeof s->termination)
        w += snprintf(s->termination + w, sizeof s->termination - (size_t)w, " (%s)", sv->nlmsg);
    if (st->failures && w > 0 && (size_t)w < sizeof s->termination)
        w += snprintf(s->termination + w, sizeof s->termination - (size_t)w,
                      "; %d evaluation(s) failed or were not finite", st->failures);
    if (!usable && w > 0 && (size_t)w < sizeof s->termination)
        snprintf(s->termination + w, sizeof s->termination - (size_t)w, "; no improvement, start kept");
    if (usable) {
        for (int j = 0; j < nfree; j++) {
            const double v = z[j] < sv->zlo[j] ? sv->zlo[j] : z[j] > sv->zhi[j] ? sv->zhi[j] : z[j];
            sv->x[st->freeidx[j]] = v;
        }
        s->final_cost = f;
    }
    s->usable = usable;
    s->stop = st->cancelled && res == NLOPT_FORCED_STOP ? BF_STOP_CANCELLED
              : !usable                                 ? BF_STOP_FAILED
              : res == NLOPT_MAXEVAL_REACHED            ? BF_STOP_ITERATIONS
              : res == NLOPT_MAXTIME_REACHED            ? BF_STOP_TIME
                                                        : BF_STOP_CONVERGED;
}

/* From the start's cost: nothing to do when it is not finite or nothing is free, else
 * configure, run and copy out. */
static bf_status solve_from_start(nl_solve *sv)
{
    bf_solution *s = sv->s;
    s->initial_cost = evaluate(&sv->st, sv->z, NULL);
    s->final_cost = s->initial_cost;
    if (!isfinite(s->initial_cost)) {
        snprintf(s->termination, sizeof s->termination,
                 "the cost at the start is not finite (the residual function failed or gave NaN/Inf)");
        s->stop = BF_STOP_FAILED;
        return BF_OK;
    }
    if (sv->st.nfree == 0) {
        s->usable = 1;
        snprintf(s->termination, sizeof s->termination, "no free parameters: every one is constant");
        return BF_OK;
    }
    bf_status rc = configure(sv);
    if (rc == BF_OK) {
        run(sv);
        copy_out(sv);
    }
    nlopt_destroy(sv->lopt);
    nlopt_destroy(sv->opt);
    return rc;
}

bf_status bf_solve_nlopt(const bf_problem *p, const bf_solver_options *o, double *x, bf_solution *s, bf_error *err)
{
    const double t0 = bf_now_seconds();
    bf_solver_options defaults;
    bf_solution scratch;
    if (!s)
        s = &scratch;
    memset(s, 0, sizeof *s);
    snprintf(s->backend, sizeof s->backend, "nlopt");
    if (!o) {
        bf_solver_options_init(&defaults);
        o = &defaults;
    }
    if (!p || !p->eval || !x || p->npar < 1 || p->nres < 1)
        return bf_fail(err, BF_ERR_ARG, "NLopt: empty problem or no start vector");

    nl_solve sv = {.p = p, .o = o, .x = x, .s = s, .err = err};
    bf_status rc;
    if ((rc = choose_method(&sv)) != BF_OK || (rc = check_start(&sv)) != BF_OK || (rc = make_free_vector(&sv)) != BF_OK)
        return rc;
    rc = solve_from_start(&sv);
    s->evaluations = sv.st.evals;
    s->seconds = bf_now_seconds() - t0;
    free(sv.z);
    state_free(&sv.st);
    return rc;
}
