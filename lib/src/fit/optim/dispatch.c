/* The optimizer front door: bf_solve validates a problem, clamps the start into the
 * bounds and dispatches to a back end (the robust losses: loss.c; what the back ends
 * share of the options: solver_options.c). */
#include "brdfit/solve.h"
#include "backends.h"
#include "base/sized.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

bf_status bf_solve(const bf_problem *p, const bf_solver_options *o, double *x, bf_solution *s, bf_error *err)
{
    bf_solver_options defaults;
    bf_solution scratch;
    if (!s)
        s = &scratch;
    memset(s, 0, sizeof *s);
    if (!o) {
        bf_solver_options_init(&defaults);
        o = &defaults;
    }
    /* The first versions are today's structs: nothing smaller is one. */
    if (p && bf_sized_check(p, sizeof *p, "bf_problem", err) != BF_OK)
        return BF_ERR_ARG;
    if (bf_sized_check(o, sizeof *o, "bf_solver_options", err) != BF_OK)
        return BF_ERR_ARG;
    if (!p || !p->eval || !x)
        return bf_fail(err, BF_ERR_ARG, "bf_solve: no problem, residual function or start vector");
    if (p->npar < 1)
        return bf_fail(err, BF_ERR_ARG, "bf_solve: the problem has %d parameters (need at least 1)", p->npar);
    if (p->nres < 1)
        return bf_fail(err, BF_ERR_ARG, "bf_solve: the problem has no residuals");
    if (o->threads < 0)
        return bf_fail(err, BF_ERR_ARG, "bf_solve: thread count %d is negative", o->threads);
    if (o->loss.kind != BF_LOSS_NONE && !(o->loss.scale > 0.0 && isfinite(o->loss.scale)))
        return bf_fail(err, BF_ERR_ARG, "bf_solve: loss scale %g must be finite and > 0", o->loss.scale);
    const int n = p->npar;
    for (int k = 0; k < n; k++) {
        const double lo = p->lo ? p->lo[k] : -INFINITY, hi = p->hi ? p->hi[k] : INFINITY;
        if (isnan(lo) || isnan(hi) || lo > hi)
            return bf_fail(err, BF_ERR_RANGE, "bf_solve: parameter %d has bounds [%g, %g]", k, lo, hi);
        if (isnan(x[k]))
            return bf_fail(err, BF_ERR_RANGE, "bf_solve: start value of parameter %d is NaN", k);
        double v = x[k] < lo ? lo : x[k] > hi ? hi : x[k];
        if (!isfinite(v))
            return bf_fail(err, BF_ERR_RANGE,
                           "bf_solve: start value of parameter %d is %g and its bounds do not make it finite", k, x[k]);
        x[k] = v;
    }

    double *start = malloc((size_t)n * sizeof *start);
    if (!start)
        return bf_fail(err, BF_ERR_NOMEM, "bf_solve: out of memory");
    memcpy(start, x, (size_t)n * sizeof *start);

    bf_status rc;
    if (o->cancel && *o->cancel) { /* cancelled before it began: the start, untouched */
        free(start);
        s->stop = BF_STOP_CANCELLED;
        snprintf(s->termination, sizeof s->termination, "cancelled before the solve began");
        s->initial_cost = s->final_cost = NAN;
        return BF_OK;
    }
    switch (o->backend) {
    case BF_BACKEND_CERES: rc = bf_solve_ceres(p, o, x, s, err); break;
    case BF_BACKEND_NLOPT: rc = bf_solve_nlopt(p, o, x, s, err); break;
    default: free(start); return bf_fail(err, BF_ERR_ARG, "bf_solve: unknown back end %d", (int)o->backend);
    }

    /* Whatever the back end did, x leaves finite, inside the bounds, and with constant
     * parameters at their start values. */
    int finite = 1;
    for (int k = 0; k < n; k++)
        finite &= isfinite(x[k]) != 0;
    if (rc != BF_OK || !finite) {
        memcpy(x, start, (size_t)n * sizeof *x);
        if (rc == BF_OK) {
            s->final_cost = s->initial_cost;
            snprintf(s->termination, sizeof s->termination, "%s",
                     "the back end returned non-finite parameters; the start is kept");
        }
        s->usable = 0;
        s->stop = BF_STOP_FAILED;
    } else {
        for (int k = 0; k < n; k++) {
            if (p->lo && x[k] < p->lo[k])
                x[k] = p->lo[k];
            if (p->hi && x[k] > p->hi[k])
                x[k] = p->hi[k];
            if (o->constant && o->constant[k])
                x[k] = start[k];
        }
    }
    free(start);
    return rc;
}
