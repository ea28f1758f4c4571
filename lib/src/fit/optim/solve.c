/* The optimizer front door: robust losses (shared by every back end) and bf_solve, which
 * validates a problem, clamps the start into the bounds and dispatches to a back end. */
#include "brdfit/solve.h"
#include "backends.h"
#include "base/sized.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* Ceres floors rho' at the smallest normal double so that it never reaches zero; we do
 * the same so both back ends weight residuals identically. */
static double floor_d1(double v)
{
    return v > DBL_MIN ? v : DBL_MIN;
}

double bf_loss_eval(const bf_loss *l, double s, double *d1)
{
    const double a = l ? l->scale : 1.0;
    const bf_loss_kind kind = l ? l->kind : BF_LOSS_NONE;
    double rho, drho;
    switch (kind) {
    case BF_LOSS_HUBER: {
        const double b = a * a;
        if (s > b) {
            const double r = sqrt(s);
            rho = 2.0 * a * r - b;
            drho = floor_d1(a / r);
        } else {
            rho = s;
            drho = 1.0;
        }
        break;
    }
    case BF_LOSS_CAUCHY: {
        const double b = a * a, sum = 1.0 + s / b;
        rho = b * log1p(s / b); /* = b log(sum), exact for small s */
        drho = floor_d1(1.0 / sum);
        break;
    }
    case BF_LOSS_SOFT_L1: {
        const double b = a * a, t = sqrt(1.0 + s / b);
        rho = 2.0 * s / (t + 1.0); /* = 2 b (t - 1) without the cancellation at small s */
        drho = floor_d1(1.0 / t);
        break;
    }
    case BF_LOSS_ARCTAN: {
        const double b = 1.0 / (a * a);
        rho = a * atan2(s, a);
        drho = floor_d1(1.0 / (1.0 + s * s * b));
        break;
    }
    case BF_LOSS_NONE:
    default:
        rho = s;
        drho = 1.0;
        break;
    }
    if (d1)
        *d1 = drho;
    return rho;
}

bf_status bf_loss_parse(const char *text, bf_loss *out, bf_error *err)
{
    static const struct {
        const char *name;
        bf_loss_kind kind;
    } names[] = {
        {"none", BF_LOSS_NONE},       {"huber", BF_LOSS_HUBER},   {"cauchy", BF_LOSS_CAUCHY},
        {"soft_l1", BF_LOSS_SOFT_L1}, {"arctan", BF_LOSS_ARCTAN},
    };
    if (!out)
        return bf_fail(err, BF_ERR_ARG, "bf_loss_parse: no output");
    out->kind = BF_LOSS_NONE;
    out->scale = 1.0;
    if (!text) /* no loss asked for: plain least squares */
        return BF_OK;
    const char *colon = strchr(text, ':');
    size_t len = colon ? (size_t)(colon - text) : strlen(text);
    int found = -1;
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (strlen(names[i].name) == len && strncasecmp(text, names[i].name, len) == 0)
            found = (int)i;
    if (found < 0)
        return bf_fail(err, BF_ERR_ARG,
                       "unknown loss \"%s\" (known: none, huber, cauchy, soft_l1, arctan, "
                       "optionally with :SCALE)",
                       text);
    double scale = 1.0;
    if (colon) {
        if (names[found].kind == BF_LOSS_NONE)
            return bf_fail(err, BF_ERR_ARG, "loss \"%s\": \"none\" takes no scale", text);
        char *end = NULL;
        scale = strtod(colon + 1, &end);
        if (end == colon + 1 || *end != '\0')
            return bf_fail(err, BF_ERR_ARG, "loss \"%s\": scale is not a number", text);
        if (!(scale > 0.0) || !isfinite(scale))
            return bf_fail(err, BF_ERR_ARG, "loss \"%s\": scale must be finite and > 0", text);
    }
    out->kind = names[found].kind;
    out->scale = scale;
    return BF_OK;
}

const char *bf_stop_name(bf_stop stop)
{
    switch (stop) {
    case BF_STOP_CONVERGED: return "converged";
    case BF_STOP_ITERATIONS: return "iteration_limit";
    case BF_STOP_TIME: return "time_limit";
    case BF_STOP_CANCELLED: return "cancelled";
    case BF_STOP_FAILED: return "failed";
    }
    return "?";
}

int bf_solver_cancelled(const bf_solver_options *o, int iteration, double cost)
{
    if (o->cancel && *o->cancel)
        return 1;
    return o->progress && o->progress(o->progress_user, iteration, cost) != 0;
}

BF_SIZED_INIT_ZERO(bf_problem)

BF_SIZED_INIT_ZERO(bf_solver_options)

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
