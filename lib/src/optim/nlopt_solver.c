/* The NLopt back end: minimises F(x) = 1/2 sum rho(r_i^2) through NLopt's C API.
 *
 * Residuals (and, when NLopt asks for a gradient, Jacobian rows) are evaluated in fixed
 * chunks of BF_NLOPT_CHUNK rows, so memory is O(chunk * npar) per thread, never
 * O(nres * npar); each chunk reduces its rows to a partial cost and a partial J^T (rho' r),
 * and the partials are summed in chunk order on the calling thread. Chunk boundaries do
 * not depend on the thread count, so the cost and gradient, and hence the whole solve,
 * are bit-for-bit identical for any o->threads.
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

#include <math.h>
#include <nlopt.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

#define BF_NLOPT_CHUNK 8192
#define BF_NLOPT_MAX_THREADS 256

enum { ALG_GLOBAL = 1, ALG_CONSTRAINTS = 2, ALG_GRADIENT = 4 };

static const struct nl_alg {
    const char *name;
    nlopt_algorithm alg;
    int flags;
} nl_algs[] = {
    {"LD_LBFGS", NLOPT_LD_LBFGS, ALG_GRADIENT},
    {"LD_SLSQP", NLOPT_LD_SLSQP, ALG_GRADIENT | ALG_CONSTRAINTS},
    {"LD_MMA", NLOPT_LD_MMA, ALG_GRADIENT | ALG_CONSTRAINTS},
    {"LN_BOBYQA", NLOPT_LN_BOBYQA, 0},
    {"LN_COBYLA", NLOPT_LN_COBYLA, ALG_CONSTRAINTS},
    {"LN_NELDERMEAD", NLOPT_LN_NELDERMEAD, 0},
    {"LN_SBPLX", NLOPT_LN_SBPLX, 0},
    {"GN_DIRECT_L", NLOPT_GN_DIRECT_L, ALG_GLOBAL},
    {"GN_CRS2_LM", NLOPT_GN_CRS2_LM, ALG_GLOBAL},
    {"GN_ISRES", NLOPT_GN_ISRES, ALG_GLOBAL | ALG_CONSTRAINTS},
    {"G_MLSL_LDS", NLOPT_G_MLSL_LDS, ALG_GLOBAL},
};
#define NL_NALGS (sizeof nl_algs / sizeof nl_algs[0])

static const struct nl_alg *find_alg(const char *name)
{
    for (size_t i = 0; i < NL_NALGS; i++)
        if (strcasecmp(name, nl_algs[i].name) == 0)
            return &nl_algs[i];
    return NULL;
}

/* "A, B, C" of the methods whose flags include `need` and exclude `avoid`. */
static void alg_list(char *buf, size_t size, int need, int avoid)
{
    size_t used = 0;
    buf[0] = '\0';
    for (size_t i = 0; i < NL_NALGS; i++) {
        if ((nl_algs[i].flags & need) != need || (nl_algs[i].flags & avoid))
            continue;
        int w = snprintf(buf + used, size - used, "%s%s", used ? ", " : "", nl_algs[i].name);
        if (w < 0 || (size_t)w >= size - used)
            break;
        used += (size_t)w;
    }
}

typedef struct nl_state nl_state;

/* What a pool thread gets: the state and its thread index. */
typedef struct nl_worker_arg {
    nl_state *st;
    int t;
} nl_worker_arg;

struct nl_state {
    const bf_problem *p;
    bf_loss loss;
    int npar, nfree;
    int *freeidx;        /* free index -> problem index */
    double *xfull;       /* problem vector: constants at their start, the rest from NLopt */
    double *gfull;       /* gradient over the problem vector */
    size_t nchunks;
    double *csum;        /* per chunk: cost, then npar gradient entries */
    unsigned char *cfail;
    int want_grad;
    int nthreads;
    double **res, **jac; /* per thread chunk buffers */
    /* worker pool: threads 1 .. nthreads-1 wait for a new generation, thread 0 is the caller */
    pthread_t *tid;
    nl_worker_arg *args;
    int nstarted;
    int nbuf;            /* entries of res and jac (nthreads may shrink below it) */
    int pool_live;       /* mutex and condition variables initialised */
    pthread_mutex_t mu;
    pthread_cond_t go, done;
    unsigned long gen;
    int pending, quit;
    /* bookkeeping */
    int evals, failures;
    double best;
    double *xbest;
};

/* One chunk: residuals (and Jacobian rows), reduced to its partial cost and gradient. */
static void chunk_eval(nl_state *st, int t, size_t c)
{
    const bf_problem *p = st->p;
    const int np = st->npar;
    const size_t r0 = c * BF_NLOPT_CHUNK;
    const size_t r1 = r0 + BF_NLOPT_CHUNK < p->nres ? r0 + BF_NLOPT_CHUNK : p->nres;
    const size_t m = r1 - r0;
    double *res = st->res[t];
    double *jac = st->want_grad ? st->jac[t] : NULL;
    double *out = st->csum + c * (size_t)(np + 1);
    if (p->eval(p->ctx, st->xfull, r0, r1, res, jac) != 0) {
        st->cfail[c] = 1;
        return;
    }
    st->cfail[c] = 0;
    double cost = 0.0;
    if (jac)
        memset(out + 1, 0, (size_t)np * sizeof *out);
    const int plain = st->loss.kind == BF_LOSS_NONE;
    for (size_t i = 0; i < m; i++) {
        const double r = res[i];
        double d1 = 1.0;
        cost += plain ? r * r : bf_loss_eval(&st->loss, r * r, &d1);
        if (jac) {
            /* d/dx 1/2 rho(r^2) = rho'(r^2) r dr/dx */
            const double w = d1 * r;
            const double *J = jac + i * (size_t)np;
            for (int k = 0; k < np; k++)
                out[1 + k] += w * J[k];
        }
    }
    out[0] = 0.5 * cost;
}

static void run_chunks(nl_state *st, int t)
{
    for (size_t c = (size_t)t; c < st->nchunks; c += (size_t)st->nthreads)
        chunk_eval(st, t, c);
}

static void *pool_worker(void *arg)
{
    nl_worker_arg *a = arg;
    nl_state *st = a->st;
    unsigned long seen = 0;
    for (;;) {
        pthread_mutex_lock(&st->mu);
        while (st->gen == seen && !st->quit)
            pthread_cond_wait(&st->go, &st->mu);
        if (st->quit) {
            pthread_mutex_unlock(&st->mu);
            return NULL;
        }
        seen = st->gen;
        pthread_mutex_unlock(&st->mu);
        run_chunks(st, a->t);
        pthread_mutex_lock(&st->mu);
        if (--st->pending == 0)
            pthread_cond_signal(&st->done);
        pthread_mutex_unlock(&st->mu);
    }
}

/* Starts nthreads-1 workers; on a failed pthread_create runs with those it has. */
static void pool_start(nl_state *st)
{
    st->nstarted = 0;
    if (st->nthreads <= 1)
        return;
    pthread_mutex_init(&st->mu, NULL);
    pthread_cond_init(&st->go, NULL);
    pthread_cond_init(&st->done, NULL);
    st->pool_live = 1;
    for (int t = 1; t < st->nthreads; t++) {
        st->args[t].st = st;
        st->args[t].t = t;
        if (pthread_create(&st->tid[t], NULL, pool_worker, &st->args[t]) != 0)
            break;
        st->nstarted++;
    }
    /* Fewer threads than asked: the chunk stride shrinks, the sums stay the same. */
    st->nthreads = st->nstarted + 1;
}

static void pool_stop(nl_state *st)
{
    if (!st->pool_live)
        return;
    pthread_mutex_lock(&st->mu);
    st->quit = 1;
    pthread_cond_broadcast(&st->go);
    pthread_mutex_unlock(&st->mu);
    for (int t = 1; t <= st->nstarted; t++)
        pthread_join(st->tid[t], NULL);
    pthread_cond_destroy(&st->done);
    pthread_cond_destroy(&st->go);
    pthread_mutex_destroy(&st->mu);
}

/* Cost at the free vector z (and its gradient when grad is not NULL). A failed or
 * non-finite evaluation gives HUGE_VAL and a zero gradient, so NLopt never sees NaN. */
static double evaluate(nl_state *st, const double *z, double *grad)
{
    const int np = st->npar;
    for (int j = 0; j < st->nfree; j++)
        st->xfull[st->freeidx[j]] = z[j];
    st->want_grad = grad != NULL;
    st->evals++;
    if (st->nthreads > 1) {
        pthread_mutex_lock(&st->mu);
        st->gen++;
        st->pending = st->nthreads - 1;
        pthread_cond_broadcast(&st->go);
        pthread_mutex_unlock(&st->mu);
        run_chunks(st, 0);
        pthread_mutex_lock(&st->mu);
        while (st->pending > 0)
            pthread_cond_wait(&st->done, &st->mu);
        pthread_mutex_unlock(&st->mu);
    } else {
        run_chunks(st, 0);
    }
    double cost = 0.0;
    int ok = 1;
    if (grad)
        memset(st->gfull, 0, (size_t)np * sizeof *st->gfull);
    for (size_t c = 0; c < st->nchunks; c++) { /* fixed order: reproducible sums */
        const double *in = st->csum + c * (size_t)(np + 1);
        if (st->cfail[c]) {
            ok = 0;
            break;
        }
        cost += in[0];
        if (grad)
            for (int k = 0; k < np; k++)
                st->gfull[k] += in[1 + k];
    }
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
    double c = st->p->constraint(st->p->ctx, st->xfull, grad ? st->gfull : NULL);
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
    pool_stop(st);
    for (int t = 0; t < st->nbuf; t++) {
        free(st->res[t]);
        free(st->jac[t]);
    }
    free(st->res);
    free(st->jac);
    free(st->tid);
    free(st->args);
    free(st->freeidx);
    free(st->xfull);
    free(st->gfull);
    free(st->csum);
    free(st->cfail);
    free(st->xbest);
}

static int state_init(nl_state *st, const bf_problem *p, const bf_solver_options *o, const double *x)
{
    memset(st, 0, sizeof *st);
    st->p = p;
    st->loss = o->loss;
    st->npar = p->npar;
    st->nchunks = (p->nres + BF_NLOPT_CHUNK - 1) / BF_NLOPT_CHUNK;
    int threads = o->threads > 1 ? o->threads : 1;
    if (threads > BF_NLOPT_MAX_THREADS)
        threads = BF_NLOPT_MAX_THREADS;
    if ((size_t)threads > st->nchunks) /* more threads than chunks would idle */
        threads = (int)st->nchunks;
    st->nthreads = threads;
    const size_t np = (size_t)p->npar;
    const size_t rows = p->nres < BF_NLOPT_CHUNK ? p->nres : BF_NLOPT_CHUNK;
    st->freeidx = malloc(np * sizeof *st->freeidx);
    st->xfull = malloc(np * sizeof *st->xfull);
    st->gfull = malloc(np * sizeof *st->gfull);
    st->xbest = malloc(np * sizeof *st->xbest);
    st->csum = malloc(st->nchunks * (np + 1) * sizeof *st->csum);
    st->cfail = calloc(st->nchunks, 1);
    st->res = calloc((size_t)threads, sizeof *st->res);
    st->jac = calloc((size_t)threads, sizeof *st->jac);
    st->tid = calloc((size_t)threads, sizeof *st->tid);
    st->args = calloc((size_t)threads, sizeof *st->args);
    if (!st->freeidx || !st->xfull || !st->gfull || !st->xbest || !st->csum || !st->cfail ||
        !st->res || !st->jac || !st->tid || !st->args)
        return -1;
    st->nbuf = threads;
    for (int t = 0; t < threads; t++) {
        st->res[t] = malloc(rows * sizeof **st->res);
        st->jac[t] = malloc(rows * np * sizeof **st->jac);
        if (!st->res[t] || !st->jac[t])
            return -1;
    }
    memcpy(st->xfull, x, np * sizeof *x);
    for (int k = 0; k < p->npar; k++)
        if (!(o->constant && o->constant[k]))
            st->freeidx[st->nfree++] = k;
    st->best = HUGE_VAL;
    pool_start(st);
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

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Applies the stopping criteria shared by the main and the local optimizer. */
static int set_tolerances(nlopt_opt opt, const bf_solver_options *o)
{
    const double ftol = o->function_tolerance > 0 ? o->function_tolerance : 1e-10;
    const double xtol = o->parameter_tolerance > 0 ? o->parameter_tolerance : 1e-10;
    return nlopt_set_ftol_rel(opt, ftol) > 0 && nlopt_set_xtol_rel(opt, xtol) > 0;
}

int bf_solve_nlopt(const bf_problem *p, const bf_solver_options *o, double *x, bf_solution *s,
                   bf_error *err)
{
    const double t0 = now_seconds();
    bf_solver_options defaults;
    bf_solution scratch;
    if (!s)
        s = &scratch;
    memset(s, 0, sizeof *s);
    snprintf(s->backend, sizeof s->backend, "nlopt");
    if (!o) {
        memset(&defaults, 0, sizeof defaults);
        o = &defaults;
    }
    if (!p || !p->eval || !x || p->npar < 1 || p->nres < 1)
        return bf_fail(err, BF_ERR_ARG, "NLopt: empty problem or no start vector");

    char list[256];
    const char *name = o->algorithm ? o->algorithm : "LD_LBFGS";
    const struct nl_alg *alg = find_alg(name);
    if (!alg) {
        alg_list(list, sizeof list, 0, 0);
        return bf_fail(err, BF_ERR_ARG, "unknown NLopt algorithm \"%s\" (known: %s)", name, list);
    }
    snprintf(s->algorithm, sizeof s->algorithm, "%s", alg->name);
    const struct nl_alg *local = NULL;
    if (alg->alg == NLOPT_G_MLSL_LDS) {
        const char *lname = o->local_algorithm ? o->local_algorithm : "LD_LBFGS";
        local = find_alg(lname);
        if (!local || (local->flags & ALG_GLOBAL)) {
            alg_list(list, sizeof list, 0, ALG_GLOBAL);
            return bf_fail(err, BF_ERR_ARG,
                           "G_MLSL_LDS: \"%s\" is not a local NLopt method (known: %s)", lname, list);
        }
        snprintf(s->algorithm, sizeof s->algorithm, "%s+%s", alg->name, local->name);
    }
    if (o->use_constraint && !(alg->flags & ALG_CONSTRAINTS)) {
        alg_list(list, sizeof list, ALG_CONSTRAINTS, 0);
        return bf_fail(err, BF_ERR_ARG, "NLopt method %s does not take constraints (those that do: %s)",
                       alg->name, list);
    }
    const int constrained = o->use_constraint && p->constraint;
    for (int k = 0; k < p->npar; k++) {
        const int fixed = o->constant && o->constant[k];
        const double lo = p->lo ? p->lo[k] : -INFINITY, hi = p->hi ? p->hi[k] : INFINITY;
        if ((alg->flags & ALG_GLOBAL) && !fixed && !(isfinite(lo) && isfinite(hi)))
            return bf_fail(err, BF_ERR_ARG,
                           "NLopt global method %s needs finite bounds; parameter %d has [%g, %g]",
                           alg->name, k, lo, hi);
        x[k] = x[k] < lo ? lo : x[k] > hi ? hi : x[k];
        if (!isfinite(x[k]))
            return bf_fail(err, BF_ERR_RANGE, "NLopt: start value of parameter %d is not finite", k);
    }

    nl_state st;
    if (state_init(&st, p, o, x) != 0) {
        state_free(&st);
        return bf_fail(err, BF_ERR_NOMEM, "NLopt: out of memory for %zu residuals x %d parameters",
                       p->nres, p->npar);
    }
    const int nfree = st.nfree;
    double *z = malloc((size_t)(nfree > 0 ? nfree : 1) * 3 * sizeof *z);
    if (!z) {
        state_free(&st);
        return bf_fail(err, BF_ERR_NOMEM, "NLopt: out of memory");
    }
    double *zlo = z + nfree, *zhi = zlo + nfree;
    for (int j = 0; j < nfree; j++) {
        const int k = st.freeidx[j];
        z[j] = x[k];
        zlo[j] = p->lo ? p->lo[k] : -INFINITY;
        zhi[j] = p->hi ? p->hi[k] : INFINITY;
    }

    s->initial_cost = evaluate(&st, z, NULL);
    s->final_cost = s->initial_cost;
    int rc = BF_OK;
    if (!isfinite(s->initial_cost)) {
        snprintf(s->termination, sizeof s->termination,
                 "the cost at the start is not finite (the residual function failed or gave NaN/Inf)");
        goto done;
    }
    if (nfree == 0) {
        s->usable = 1;
        snprintf(s->termination, sizeof s->termination, "no free parameters: every one is constant");
        goto done;
    }

    nlopt_opt opt = nlopt_create(alg->alg, (unsigned)nfree);
    nlopt_opt lopt = NULL;
    if (!opt) {
        rc = bf_fail(err, BF_ERR_NOMEM, "NLopt: cannot create %s", alg->name);
        goto done;
    }
    const int maxeval = o->max_iterations > 0 ? o->max_iterations : (alg->flags & ALG_GLOBAL) ? 20000 : 2000;
    int setup = nlopt_set_min_objective(opt, nl_objective, &st) > 0 &&
                nlopt_set_lower_bounds(opt, zlo) > 0 && nlopt_set_upper_bounds(opt, zhi) > 0 &&
                set_tolerances(opt, o) && nlopt_set_maxeval(opt, maxeval) > 0 &&
                (o->max_seconds <= 0 || nlopt_set_maxtime(opt, o->max_seconds) > 0);
    if (setup && constrained)
        setup = nlopt_add_inequality_constraint(opt, nl_constraint, &st, 1e-12) > 0;
    if (setup && local) {
        lopt = nlopt_create(local->alg, (unsigned)nfree);
        setup = lopt && set_tolerances(lopt, o) && nlopt_set_local_optimizer(opt, lopt) > 0;
    }
    if (!setup) {
        rc = bf_fail(err, BF_ERR_ARG, "NLopt: cannot set up %s (%s)", s->algorithm,
                     nlopt_get_errmsg(opt) ? nlopt_get_errmsg(opt) : "invalid settings");
        nlopt_destroy(lopt);
        nlopt_destroy(opt);
        goto done;
    }
    nlopt_srand((unsigned long)o->seed);
    const int evals_before = st.evals;
    double f = HUGE_VAL;
    const nlopt_result res = nlopt_optimize(opt, z, &f);
    const char *nlmsg = nlopt_get_errmsg(opt);
    s->iterations = st.evals - evals_before;

    /* NLopt's answer, unless (unconstrained) a better point was evaluated, or NLopt
     * failed: then the best point seen, which is feasible only without a constraint. */
    int zfinite = 1;
    for (int j = 0; j < nfree; j++)
        zfinite &= isfinite(z[j]) != 0;
    if (!zfinite || !isfinite(f))
        f = HUGE_VAL;
    if (!constrained && st.best < f) {
        memcpy(z, st.xbest, (size_t)nfree * sizeof *z);
        f = st.best;
    }
    const int usable = isfinite(f) && (res > 0 || res == NLOPT_ROUNDOFF_LIMITED || f < s->initial_cost);
    int w = snprintf(s->termination, sizeof s->termination, "%s", result_text(res));
    if (res < 0 && nlmsg && w > 0 && (size_t)w < sizeof s->termination)
        w += snprintf(s->termination + w, sizeof s->termination - (size_t)w, " (%s)", nlmsg);
    if (st.failures && w > 0 && (size_t)w < sizeof s->termination)
        w += snprintf(s->termination + w, sizeof s->termination - (size_t)w,
                      "; %d evaluation(s) failed or were not finite", st.failures);
    if (!usable && w > 0 && (size_t)w < sizeof s->termination)
        snprintf(s->termination + w, sizeof s->termination - (size_t)w, "; no improvement, start kept");
    if (usable) {
        for (int j = 0; j < nfree; j++) {
            const double v = z[j] < zlo[j] ? zlo[j] : z[j] > zhi[j] ? zhi[j] : z[j];
            x[st.freeidx[j]] = v;
        }
        s->final_cost = f;
    }
    s->usable = usable;
    nlopt_destroy(lopt);
    nlopt_destroy(opt);

done:
    s->evaluations = st.evals;
    s->seconds = now_seconds() - t0;
    free(z);
    state_free(&st);
    return rc;
}
