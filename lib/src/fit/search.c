/* The search for a fit's optimum (search.h; docs/fitting.md has the figures behind
 * every number here).
 *
 * One start (options->starts 1) is the data-driven start solved on prob, as brdfit did
 * before it searched. Plain multistart (options->screen 0): the data-driven start, then
 * starts-1 drawn uniformly within the bounds in the internal space (so uniformly in log
 * for log-scale parameters), each solved on prob; the best wins, ties to the earlier.
 *
 * The screened search (the default) spends its starts where they are cheap:
 *  1. The screening set: the data itself up to BF_FIT_SCREEN_SAMPLES samples, else a
 *     seeded stratified subsample of that many.
 *  2. Candidates: max(options->screen, 4 K) random points (K: the starts besides the
 *     data-driven one), each scored by its cost on the screening set.
 *  3. Starts solved to convergence there: the data-driven start; "switches", the
 *     data-driven start with each weight parameter that starts on its lower bound turned
 *     on (half its range; then all of them at once: Disney's sheen and clearcoat start at
 *     0, where no gradient turns them on); half of K from the cheapest candidates, half
 *     from the others in the order they were drawn (the cheapest alone crowd into one
 *     basin: measured, docs/fitting.md).
 *  4. Revive: at the best of them, each parameter on a bound that silences others
 *     (silence.h) is moved inward (half way, then nine tenths of the way to its other
 *     bound), the silenced entries left where they are or a tenth of their range inside
 *     a bound they sit on, and solved again (at most SCREEN_REVIVES solves).
 *  5. When the screening set is not prob: the data-driven start and the best PROMOTE
 *     other optima there (distinct from each other and from the data-driven start's by
 *     more than BF_FIT_AT_BEST, and within PROMOTE_WINDOW of the best) are solved on
 *     prob, then the best is revived there (half way only; PROB_REVIVES solves: a basin
 *     that a thousand samples do not show, such as the clearcoat of the MDL car paint,
 *     is found there). The screening set ranks
 *     close optima only roughly; one more than 10% worse there has not been better on the
 *     data in any bundled case, and solving it costs a pass over the presolve for nothing.
 * starts counts the starts of 3 (or of plain multistart), starts_at_best those whose
 * final cost is within BF_FIT_AT_BEST (relative) of the best of them.
 *
 * Start k's solve gets the seed bf_splitmix64(seed + k + 1)'s first output (stochastic
 * back-end methods); the random draws come from splitmix64 seeded with the fit's seed,
 * in order. Every pass sums fixed chunks in a fixed order, so the result is a function
 * of the data, the options and the seed alone, whatever the thread count. */
#include "search.h"

#include "brdfit/prep.h"

#include "base/big_alloc.h"
#include "progress.h"
#include "silence.h"
#include "base/rng.h"

#include <stdlib.h>
#include <string.h>

#define PROMOTE 2          /* screened optima solved on prob besides the data-driven start */
#define PROMOTE_WINDOW 0.1 /* ... if their cost on the screening set is within 10% of the best */
#define SCREEN_REVIVES 4   /* revive solves on the screening set */
#define PROB_REVIVES 4     /* and on prob, when it is another (one place a parameter: half way) */
#define DISTINCT 1e-6      /* a revived optimum replaces the best when lower by this (relative) */
#define SNAP 1e-4          /* hand-over: entries this close to a bound (of their range) go onto it */

int bf_fit_search_starts(const bf_fit_options *o, size_t n)
{
    if (o->starts > 0)
        return o->starts;
    /* About BF_FIT_SCREEN_WORK sample-solves on the screening set: a small data set
     * affords more starts at the same cost. (One start per free entry as a floor was
     * measured too: one case of 280 better, at 1.3x the time of the bundled compares.) */
    size_t k = BF_FIT_SCREEN_WORK / (n > 0 ? n : 1);
    return k < BF_FIT_STARTS ? BF_FIT_STARTS : k > BF_FIT_STARTS_MAX ? BF_FIT_STARTS_MAX : (int)k;
}

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

static double cost_at(const bf_problem *p, const bf_solver_options *so, const double *z)
{
    double ssq = NAN;
    if (bf_problem_normal(p, z, &so->loss, so->threads, &ssq, NULL, NULL) != 0)
        return NAN;
    return isfinite(ssq) ? 0.5 * ssq : NAN;
}

/* A final cost at the best one: within BF_FIT_AT_BEST of it (relative), or within what
 * rounding leaves of an exact fit (residuals of 1e-10 each: noiseless data). */
static int at_best(double cost, double best, const bf_problem *p)
{
    return isfinite(cost) && cost - best <= BF_FIT_AT_BEST * best + 1e-20 * (double)p->nres;
}

static void add_counts(bf_presolve_info *c, const bf_solution *sol)
{
    c->iterations += sol->iterations;
    c->evaluations += sol->evaluations;
    c->seconds += sol->seconds;
}

/* Solves p from z (in place) with start k's seed, as the next solve of w's phase. *cost:
 * the final cost, NaN when the solve is not usable. Returns an error only for the first
 * start of a search (bad options or a back end that cannot run); a later start the back
 * end fails on is just unusable. */
static bf_status solve_start(const bf_problem *p, const bf_fit_options *o, bf_fit_watch *w, int k, double *z,
                             bf_solution *sol, double *cost, uint64_t *seed, bf_presolve_info *counts, int *cancelled,
                             bf_error *err)
{
    bf_solver_options so = o->solver;
    bf_fit_watch_solve(w, &so);
    uint64_t sseed = o->seed + (uint64_t)k + 1;
    so.seed = bf_splitmix64(&sseed);
    *seed = so.seed;
    *cost = NAN;
    bf_error e2;
    bf_status rc = bf_solve(p, &so, z, sol, k == 0 ? err : &e2);
    if (rc != BF_OK)
        return k == 0 ? rc : BF_OK;
    add_counts(counts, sol);
    if (sol->stop == BF_STOP_CANCELLED) {
        *cancelled = 1; /* its point is not an optimum: the search ends here */
        return BF_OK;
    }
    int usable = sol->usable && isfinite(sol->final_cost);
    for (int j = 0; j < p->npar && usable; j++)
        usable = isfinite(z[j]);
    if (usable)
        *cost = sol->final_cost;
    return BF_OK;
}

/* Keeps z as the search's best when its cost is lower (ties to the earlier). */
static void consider(bf_search *s, const double *z, const bf_solution *sol, double cost, uint64_t seed)
{
    if (!isfinite(cost) || (s->have_best && !(cost < s->best.final_cost)))
        return;
    s->best = *sol;
    s->best_seed = seed;
    memcpy(s->z, z, (size_t)s->prob->npar * sizeof *s->z);
    s->have_best = 1;
}

/* ---- Plain multistart --------------------------------------------------------------- */

static bf_status plain(bf_search *s, int starts, bf_error *err)
{
    const bf_problem *p = s->prob;
    const int nz = p->npar;
    double *z = malloc(((size_t)nz + 1) * sizeof *z), *costs = malloc(((size_t)starts + 1) * sizeof *costs);
    if (!z || !costs) {
        free(z), free(costs);
        return bf_fail(err, BF_ERR_NOMEM, "fit: out of memory");
    }
    uint64_t draw = s->options->seed;
    bf_status rc = BF_OK;
    for (int k = 0; k < starts; k++) {
        if (k == 0)
            memcpy(z, s->z0, (size_t)nz * sizeof *z);
        else
            random_start(p, s->z0, &draw, z);
        bf_solution sol;
        uint64_t seed;
        if ((rc = solve_start(p, s->options, s->watch, k, z, &sol, &costs[k], &seed, &s->on_prob, &s->cancelled,
                              err)) != BF_OK ||
            s->cancelled)
            break;
        if (k == 0)
            s->first = sol;
        s->starts = k + 1;
        consider(s, z, &sol, costs[k], seed);
    }
    for (int k = 0; rc == BF_OK && s->have_best && k < s->starts; k++)
        s->starts_at_best += at_best(costs[k], s->best.final_cost, p);
    free(z);
    free(costs);
    return rc;
}

/* ---- Revive ------------------------------------------------------------------------- */

/* At *zb (solution *sb of p, cost in sb->final_cost), each model parameter on a bound
 * that silences others is moved inward, half way and then nine tenths of the way to its
 * other bound, the silenced entries left where they are (or just inside a bound they sit
 * on), and solved again; a better optimum replaces *zb and *sb. At most max solves.
 * Returns the solves run. */
static int revive(const bf_problem *p, const bf_objective *o, const bf_problem *dp, const bf_fit_options *opt,
                  bf_fit_watch *w, int k0, double *zb, bf_solution *sb, uint64_t *seed, int max, int places,
                  bf_presolve_info *counts, int *cancelled)
{
    const int nz = p->npar;
    const bf_model *m = o->model;
    bf_silence sil;
    bf_error e2;
    /* Only a bound silences: none reached, nothing to revive (and no pass spent). */
    int bounds = 0;
    for (int j = 0; j < nz; j++)
        bounds += bf_silence_at_bound(p, zb, j) != 0;
    if (max <= 0 || !bounds || bf_silence_find(dp, o, zb, &opt->solver.loss, opt->solver.threads, &sil, &e2) != BF_OK)
        return 0;
    int runs = 0;
    double *z = malloc(((size_t)nz + 1) * sizeof *z);
    const int np = bf_model_nparams(m);
    for (int i = 0; z && sil.nsilent > 0 && i < np && runs < max && !*cancelled; i++) {
        int gates = 0;
        for (int q = 0; q < nz; q++)
            gates += sil.silent[q] && sil.gate[q] == i;
        if (!gates)
            continue;
        for (int place = 0; place < places && runs < max; place++) {
            memcpy(z, zb, (size_t)nz * sizeof *z);
            for (int q = 0; q < nz; q++) {
                const double lo = p->lo[q], span = p->hi[q] - p->lo[q];
                if (sil.bound[q] && bf_silence_param_of(m, o->kidx[q]) == i)
                    z[q] = lo + (place == 0 ? 0.5 : sil.bound[q] < 0 ? 0.9 : 0.1) * span;
                else if (sil.silent[q] && sil.gate[q] == i && sil.bound[q])
                    z[q] = lo + (sil.bound[q] < 0 ? 0.1 : 0.9) * span;
            }
            bf_solution sol;
            double cost;
            uint64_t sd;
            if (solve_start(p, opt, w, k0 + runs, z, &sol, &cost, &sd, counts, cancelled, &e2) != BF_OK || *cancelled)
                break;
            runs++;
            if (isfinite(cost) && cost < sb->final_cost * (1.0 - DISTINCT)) {
                *sb = sol;
                *seed = sd;
                memcpy(zb, z, (size_t)nz * sizeof *zb);
            }
        }
    }
    free(z);
    bf_silence_free(&sil);
    return runs;
}

/* ---- The screened search ------------------------------------------------------------ */

/* Switches: z0 with each weight parameter whose entries all start on their lower bound
 * turned on (half their range), then all of them on together (when more than one).
 * Writes up to nparams + 1 points into out; returns how many. */
static int switches(const bf_problem *p, const bf_objective *o, const double *z0, double *out)
{
    const int nz = p->npar;
    const bf_model *m = o->model;
    int n = 0, on = 0;
    double *all = out + (size_t)bf_model_nparams(m) * nz;
    memcpy(all, z0, (size_t)nz * sizeof *all);
    for (int i = 0; i < bf_model_nparams(m); i++) {
        if (bf_model_param(m, i)->role != BF_ROLE_WEIGHT)
            continue;
        double *c = out + (size_t)n * nz;
        memcpy(c, z0, (size_t)nz * sizeof *c);
        int entries = 0, low = 0;
        for (int q = 0; q < nz; q++) {
            if (bf_silence_param_of(m, o->kidx[q]) != i)
                continue;
            entries++;
            if (bf_silence_at_bound(p, z0, q) < 0) {
                low++;
                c[q] = all[q] = p->lo[q] + 0.5 * (p->hi[q] - p->lo[q]);
            }
        }
        if (entries > 0 && low == entries)
            n++, on++;
    }
    if (on > 1)
        memmove(out + (size_t)n++ * nz, all, (size_t)nz * sizeof *out);
    return n;
}

typedef struct scored {
    double cost;
    int index;
} scored;

/* Cheapest first, NaN last, ties by index (a total order: qsort's result is unique). */
static int by_cost(const void *a, const void *b)
{
    const scored *x = a, *y = b;
    int xn = isnan(x->cost), yn = isnan(y->cost);
    if (xn != yn)
        return xn - yn;
    if (!xn && x->cost != y->cost)
        return x->cost < y->cost ? -1 : 1;
    return x->index - y->index;
}

bf_status bf_fit_subsample_objective(bf_samples *s, size_t n, uint64_t seed, const bf_model *m,
                                     const bf_objective_options *oo, bf_samples **ps, bf_objective **pobj,
                                     bf_error *err)
{
    unsigned char *keep = bf_big_malloc(s->n + 1);
    if (!keep)
        return bf_fail(err, BF_ERR_NOMEM, "fit: out of memory for a subsample of %zu samples", n);
    bf_status rc = bf_samples_subsample_mask(s, n, seed, keep, err);
    if (rc == BF_OK)
        rc = bf_samples_copy(s, keep, ps, err);
    free(keep);
    if (rc == BF_OK)
        rc = bf_objective_new(m, *ps, oo, pobj, err);
    return rc;
}

static bf_status screened(bf_search *s, bf_error *err)
{
    const bf_fit_options *o = s->options;
    const bf_problem *prob = s->prob;
    const bf_objective *pobj = s->objective;
    const bf_model *m = pobj->model;
    const int nz = prob->npar, np = bf_model_nparams(m);
    bf_samples *ss = NULL;
    bf_objective *sobj = NULL;
    const bf_problem *sp = prob;
    const bf_objective *so = pobj;
    bf_status rc = BF_OK;
    if (s->samples->n > BF_FIT_SCREEN_SAMPLES) {
        /* Its own stream of the seed: not the presolve's subsample. */
        if ((rc = bf_fit_subsample_objective(s->samples, BF_FIT_SCREEN_SAMPLES, o->seed ^ 0x5c5c5c5c5c5c5c5cull, m,
                                             s->objective_options, &ss, &sobj, err)) != BF_OK)
            return rc;
        sp = bf_objective_problem(sobj);
        so = sobj;
    }
    const size_t nS = ss ? ss->n : s->samples->n;
    s->screen.samples = nS;                    /* the data itself when small: its solves are the search's */
    const int N = bf_fit_search_starts(o, nS); /* every start solved: z0, switches, candidates */
    const int M = o->screen > 4 * N ? o->screen : 4 * N;
    s->candidates = M;
    /* Points: z0, the switches (up to np + 1), the M candidates. */
    const int nmax = 1 + np + 1 + M;
    double *pts = malloc(((size_t)nmax * nz + 1) * sizeof *pts);
    scored *cand = malloc(((size_t)M + 1) * sizeof *cand);
    scored *solved = malloc(((size_t)nmax + 1) * sizeof *solved);
    int *order = malloc(((size_t)nmax + 1) * sizeof *order);
    unsigned char *taken = calloc((size_t)M + 1, 1);
    double *zp = malloc(((size_t)nz + 1) * sizeof *zp);
    if (!pts || !cand || !solved || !order || !taken || !zp) {
        rc = bf_fail(err, BF_ERR_NOMEM, "fit: out of memory");
        goto done;
    }
    memcpy(pts, s->z0, (size_t)nz * sizeof *pts);
    int nsw = switches(sp, so, s->z0, pts + nz);
    if (nsw > N - 1) /* as many as the starts allow, the first parameters first */
        nsw = N - 1;
    const int K = N - 1 - nsw;
    double *cz = pts + (size_t)(1 + nsw) * nz; /* the candidates */
    uint64_t draw = o->seed;
    bf_fit_watch_phase(s->watch, BF_PHASE_CANDIDATES, M, nS);
    for (int j = 0; j < M; j++) {
        if (o->solver.cancel && *o->solver.cancel) {
            s->cancelled = 1;
            goto done;
        }
        random_start(sp, s->z0, &draw, cz + (size_t)j * nz);
        cand[j].cost = cost_at(sp, &o->solver, cz + (size_t)j * nz);
        cand[j].index = j;
        if (bf_fit_watch_candidate(s->watch, j, cand[j].cost)) {
            s->cancelled = 1;
            goto done;
        }
    }
    qsort(cand, (size_t)M, sizeof *cand, by_cost);
    /* What is solved, in order: z0, the switches, the cheapest half of K, then the rest
     * of K from the other candidates in the order they were drawn. */
    int n = 0;
    for (int t = 0; t < 1 + nsw; t++)
        order[n++] = t;
    const int cheap = (K + 1) / 2;
    for (int t = 0; t < cheap && t < M; t++) {
        taken[cand[t].index] = 1;
        order[n++] = 1 + nsw + cand[t].index;
    }
    for (int j = 0; j < M && n < 1 + nsw + K; j++)
        if (!taken[j])
            order[n++] = 1 + nsw + j;
    bf_fit_watch_phase(s->watch, BF_PHASE_SCREEN, n + SCREEN_REVIVES, nS); /* the starts, then the revives */
    for (int t = 0; t < n; t++) {
        double *z = pts + (size_t)order[t] * nz;
        bf_solution sol;
        uint64_t seed;
        if ((rc = solve_start(sp, o, s->watch, t, z, &sol, &solved[t].cost, &seed, &s->screen, &s->cancelled, err)) !=
                BF_OK ||
            s->cancelled)
            goto done;
        solved[t].index = t; /* ties go to the earlier solve, as consider() keeps them */
        if (t == 0)
            s->first = sol;
        if (sp == prob)
            consider(s, z, &sol, solved[t].cost, seed);
    }
    s->starts = n;
    qsort(solved, (size_t)n, sizeof *solved, by_cost);
    for (int t = 0; t < n; t++)
        s->starts_at_best += at_best(solved[t].cost, solved[0].cost, sp);
    if (!isfinite(solved[0].cost))
        goto done; /* no usable start: the driver reports the first one's reason */

    /* Revive the best on the screening set. */
    {
        double *zb = pts + (size_t)order[solved[0].index] * nz;
        bf_solution sb;
        memset(&sb, 0, sizeof sb);
        sb.final_cost = solved[0].cost;
        if (sp == prob)
            sb = s->best;
        uint64_t seed = s->best_seed;
        revive(sp, so, sp, o, s->watch, n, zb, &sb, &seed, SCREEN_REVIVES, 2, &s->screen, &s->cancelled);
        if (s->cancelled)
            goto done;
        solved[0].cost = sb.final_cost;
        if (sp == prob)
            consider(s, zb, &sb, sb.final_cost, seed);
    }
    if (sp == prob)
        goto done;

    /* Promote: the data-driven start and the best PROMOTE distinct screened optima (chosen
     * first, so that the progress reports count them), then (presolved) the revives. */
    int promote[PROMOTE], npromote = 0, k = n + SCREEN_REVIVES;
    for (int t = 0; t < n && npromote < PROMOTE; t++) {
        if (!isfinite(solved[t].cost) || order[solved[t].index] == 0)
            continue;
        if (solved[t].cost > solved[0].cost * (1.0 + PROMOTE_WINDOW))
            break;   /* sorted: the rest are worse still */
        int dup = 0; /* the same optimum as an earlier one, or as the data-driven start's */
        for (int u = 0; u < n && !dup; u++)
            dup = (u < t || order[solved[u].index] == 0) && isfinite(solved[u].cost) &&
                  fabs(solved[u].cost - solved[t].cost) <= BF_FIT_AT_BEST * solved[t].cost;
        if (!dup)
            promote[npromote++] = t;
    }
    bf_fit_watch_phase(s->watch, s->presolved ? BF_PHASE_PRESOLVE : BF_PHASE_DATA,
                       1 + npromote + (s->presolved ? PROB_REVIVES : 0), s->samples->n);
    for (int q = -1; q < npromote; q++) {
        if (q >= 0)
            memcpy(zp, pts + (size_t)order[solved[promote[q]].index] * nz, (size_t)nz * sizeof *zp);
        else
            memcpy(zp, s->z0, (size_t)nz * sizeof *zp);
        bf_solution sol;
        double cost;
        uint64_t seed;
        if ((rc = solve_start(prob, o, s->watch, q < 0 ? 0 : k++, zp, &sol, &cost, &seed, &s->on_prob, &s->cancelled,
                              err)) != BF_OK ||
            s->cancelled)
            goto done;
        if (q < 0)
            s->first = sol;
        consider(s, zp, &sol, cost, seed);
    }
    if (s->have_best && s->presolved)
        revive(prob, pobj, sp, o, s->watch, k, s->z, &s->best, &s->best_seed, PROB_REVIVES, 1, &s->on_prob,
               &s->cancelled);

done:
    free(pts);
    free(cand);
    free(solved);
    free(order);
    free(taken);
    free(zp);
    s->screen_objective = sobj; /* the driver's, until bf_fit_search_clear */
    s->screen_samples = ss;
    return rc;
}

int bf_fit_search_handover(const bf_search *s, double *z, unsigned char *hold)
{
    const bf_problem *p = s->prob;
    const bf_fit_options *o = s->options;
    const int nz = p->npar;
    double *zs = malloc(((size_t)nz + 1) * sizeof *zs);
    if (!zs)
        return 0;
    memcpy(zs, z, (size_t)nz * sizeof *zs);
    int snapped = 0;
    for (int j = 0; j < nz; j++) {
        const double span = p->hi[j] - p->lo[j];
        if (!isfinite(span) || bf_silence_at_bound(p, z, j))
            continue;
        if (z[j] - p->lo[j] <= SNAP * span)
            zs[j] = p->lo[j], snapped++;
        else if (p->hi[j] - z[j] <= SNAP * span)
            zs[j] = p->hi[j], snapped++;
    }
    if (snapped) {
        const double c0 = cost_at(p, &o->solver, z), c1 = cost_at(p, &o->solver, zs);
        /* Accepted when the data cannot tell the two points apart: the cost rises by less
         * than one unit of chi-square, c0 / (n - k) with the residuals' own variance. */
        const double dof = (double)p->nres - nz;
        if (isfinite(c1) && dof > 0.0 && c1 - c0 <= c0 / dof)
            memcpy(z, zs, (size_t)nz * sizeof *z);
    }
    free(zs);
    const bf_objective *so = s->screen_objective ? s->screen_objective : s->objective;
    bf_silence sil;
    bf_error e2;
    int held = 0;
    if (bf_silence_find(bf_objective_problem(so), so, z, &o->solver.loss, o->solver.threads, &sil, &e2) != BF_OK)
        return 0;
    for (int j = 0; j < nz; j++) {
        hold[j] = sil.silent[j] || (o->solver.constant && o->solver.constant[j]);
        held += sil.silent[j];
    }
    bf_silence_free(&sil);
    return held;
}

void bf_fit_search_clear(bf_search *s)
{
    bf_objective_free(s->screen_objective);
    bf_samples_free(s->screen_samples);
    s->screen_objective = NULL;
    s->screen_samples = NULL;
}

bf_status bf_fit_search(bf_search *s, bf_error *err)
{
    s->screen_objective = NULL;
    s->screen_samples = NULL;
    s->have_best = s->cancelled = 0;
    s->starts = s->starts_at_best = s->candidates = 0;
    memset(&s->on_prob, 0, sizeof s->on_prob);
    memset(&s->screen, 0, sizeof s->screen);
    memset(&s->first, 0, sizeof s->first);
    const int starts = bf_fit_search_starts(s->options, s->samples->n);
    if (starts <= 1 || s->options->screen <= 0) {
        bf_fit_watch_phase(s->watch, s->presolved ? BF_PHASE_PRESOLVE : BF_PHASE_DATA, starts > 1 ? starts : 1,
                           s->samples->n);
        return plain(s, starts > 1 ? starts : 1, err);
    }
    return screened(s, err);
}
