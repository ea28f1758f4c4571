/* The optimizer layer: every back end sees only "n residuals, p parameters, bounds, a
 * function that fills residuals and the Jacobian". No model or data types here.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_SOLVE_H
#define BRDFIT_SOLVE_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "brdfit/error.h"

#ifdef __cplusplus
extern "C" {
#endif

struct bf_loss;

/* Set up with bf_problem_init (its size: docs/api.md), then filled in. */
typedef struct bf_problem {
    size_t size;           /* sizeof, set by bf_problem_init */
    size_t nres;           /* residuals */
    int npar;              /* parameters */
    const double *lo, *hi; /* npar bounds each (-INFINITY / INFINITY where unbounded) */
    /* Residuals r0 .. r1-1 at x and, when jac is not NULL, their Jacobian rows:
     * jac[(r - r0) * npar + k] = d res[r - r0] / d x[k]. Called concurrently for
     * disjoint ranges (threads), so it must not write shared state. Returns 0, or
     * non-zero to abort the solve. */
    int (*eval)(void *user, const double *x, size_t r0, size_t r1, double *res, double *jac);
    void *user; /* every callback's first argument */
    /* Optional inequality constraint c(x) <= 0 with its gradient (grad may be NULL), used
     * by the NLopt methods that accept constraints (LD_SLSQP, LD_MMA, GN_ISRES). */
    double (*constraint)(void *user, const double *x, double *grad);
    /* Optional fused pass, which every back end prefers to eval: one sweep over all
     * residuals that never stores the Jacobian (a full MERL table has 3.3 M residuals).
     * With each residual r made g = bf_loss_residual(loss, r) and J its Jacobian row (of
     * g): *ssq = sum g^2; jtr (NULL: not wanted) = sum g J (npar); jtj (NULL: not
     * wanted) = sum J'J (npar x npar, row-major, both triangles). The result must not
     * depend on `threads` (sum fixed chunks in a fixed order). A non-finite residual or
     * Jacobian entry shows as a non-finite *ssq or diagonal. Returns 0, or non-zero to
     * abort (out of memory). NULL: the back ends build the same sums from eval. */
    int (*normal)(void *user, const double *x, const struct bf_loss *loss, int threads, double *ssq, double *jtr,
                  double *jtj);
} bf_problem;

/* Zeroes p and sets its size. */
BF_API void bf_problem_init_size(bf_problem *p, size_t size);
static inline void bf_problem_init(bf_problem *p)
{
    bf_problem_init_size(p, sizeof *p);
}

typedef enum bf_loss_kind {
    BF_LOSS_NONE = 0, /* plain least squares */
    BF_LOSS_HUBER,
    BF_LOSS_CAUCHY,
    BF_LOSS_SOFT_L1,
    BF_LOSS_ARCTAN,
} bf_loss_kind;

/* A robust loss rho(s) of the squared residual s, with scale a (Ceres' definitions:
 * huber: s <= a^2 ? s : 2 a sqrt(s) - a^2; cauchy: a^2 log(1 + s/a^2); soft_l1:
 * 2 a^2 (sqrt(1 + s/a^2) - 1); arctan: a atan(s/a)). The cost is 1/2 sum rho(r_i^2).
 * Frozen (docs/api.md): a value embedded in bf_solver_options. */
typedef struct bf_loss {
    bf_loss_kind kind;
    double scale;
} bf_loss;

/* Parses "huber:0.1", "cauchy", "none" ... (scale 1 when omitted). */
BF_API bf_status bf_loss_parse(const char *text, bf_loss *out, bf_error *err);
/* rho(s) and rho'(s); rho' is floored at DBL_MIN, so a residual never loses its weight
 * entirely. */
BF_API double bf_loss_eval(const bf_loss *l, double s, double *d1);

/* The residual every back end minimises in place of r: g = sign(r) sqrt(rho(r^2)), so
 * that 1/2 sum g^2 is the robust cost 1/2 sum rho(r^2) and sum g dg/dx its exact
 * gradient, while the Gauss-Newton model of g stays positive semi-definite (a loss on
 * the squared norm of a whole block, as ceres::LossFunction applies it, would be
 * rho(sum r^2)). *dg = dg/dr = rho'(r^2) |r| / g (1 at r = 0). l NULL or kind NONE: g = r. */
static inline double bf_loss_residual(const bf_loss *l, double r, double *dg)
{
    if (!l || l->kind == BF_LOSS_NONE) {
        *dg = 1.0;
        return r;
    }
    double d1, g = sqrt(bf_loss_eval(l, r * r, &d1));
    if (!(g > 0.0)) {
        *dg = 1.0;
        return r;
    }
    *dg = d1 * fabs(r) / g;
    return copysign(g, r);
}

/* The fused sums of bf_problem.normal for any problem: its own normal when it has one,
 * else built from eval over fixed chunks of residuals on `threads` threads (summed in
 * chunk order, so independent of the thread count). Same contract as normal. */
BF_API int bf_problem_normal(const bf_problem *p, const double *x, const bf_loss *loss, int threads, double *ssq,
                             double *jtr, double *jtj);

typedef enum bf_backend { BF_BACKEND_CERES = 0, BF_BACKEND_NLOPT } bf_backend;

/* ---- The method registry: one table of every back end's methods ------------------- */

/* What a method can do (bf_method_info.caps). */
enum {
    BF_METHOD_GRADIENT = 1u << 0,    /* uses the analytic gradient */
    BF_METHOD_BOUNDS = 1u << 1,      /* keeps parameters inside their bounds */
    BF_METHOD_CONSTRAINTS = 1u << 2, /* takes the inequality constraint (--constrain-energy) */
    BF_METHOD_GLOBAL = 1u << 3,      /* global search: needs finite bounds, many evaluations */
    BF_METHOD_LOSSES = 1u << 4,      /* minimises a robust loss (--loss) */
    BF_METHOD_LOCAL = 1u << 5,       /* can be G_MLSL_LDS's local method */
    BF_METHOD_DEFAULT = 1u << 6,     /* its back end's default */
};

/* Library data (bf_method_get, bf_method_find ...): read through the pointer, never
 * copied or allocated by a program; fields are only added at the end (docs/api.md). */
typedef struct bf_method_info {
    const char *name; /* "lm", "dogleg", "LD_LBFGS" ... */
    bf_backend backend;
    unsigned caps; /* BF_METHOD_* */
    const char *summary;
} bf_method_info;

BF_API int bf_method_count(void);
BF_API const bf_method_info *bf_method_get(int i);
BF_API const char *bf_backend_name(bf_backend b); /* "ceres", "nlopt" */
BF_API bf_status bf_backend_parse(const char *text, bf_backend *out, bf_error *err);
/* The back end's default method. */
BF_API const bf_method_info *bf_method_default(bf_backend backend);
/* A back end's method by name (NULL or "": its default; NLopt names in any case, Ceres'
 * "levenberg_marquardt" for lm); NULL when it has none of that name. */
BF_API const bf_method_info *bf_method_find(bf_backend backend, const char *name);
/* "ceres", "ceres:dogleg", "dogleg", "nlopt", "nlopt:LN_BOBYQA", "LN_BOBYQA": the back end
 * and the method (a back end alone: its default). */
BF_API bf_status bf_method_parse(const char *text, bf_backend *backend, const bf_method_info **method, bf_error *err);
/* "A, B, C": a back end's methods whose caps hold every bit of need and none of avoid,
 * into buf; returns the length written. */
BF_API size_t bf_method_list(bf_backend backend, unsigned need, unsigned avoid, char *buf, size_t size);

/* Progress of a solve: called after each iteration (Ceres) or each evaluation (NLopt)
 * with its number and the cost there; a non-zero return cancels the solve (and the fit
 * it belongs to). Called from the solving thread. */
typedef int (*bf_progress_fn)(void *user, int iteration, double cost);

/* Set up with bf_solver_options_init (its size: docs/api.md), then change what differs. */
typedef struct bf_solver_options {
    size_t size; /* sizeof, set by bf_solver_options_init */
    bf_backend backend;
    /* Ceres: "lm" (Levenberg-Marquardt, default) or "dogleg". NLopt: LD_LBFGS, LD_SLSQP,
     * LD_MMA, LN_BOBYQA, LN_NELDERMEAD, LN_SBPLX, GN_DIRECT_L, GN_CRS2_LM, GN_ISRES,
     * G_MLSL_LDS (default LD_LBFGS). NULL: the default. */
    const char *algorithm;
    const char *local_algorithm; /* NLopt G_MLSL_LDS: its local method (default LD_LBFGS) */
    const char *linear_solver;   /* Ceres: dense_qr, dense_normal_cholesky (default), ... */
    int max_iterations;          /* 0: default (Ceres 100 iterations; NLopt 2000 evaluations,
                                    20000 for global methods) */
    double function_tolerance;   /* 0: defaults (1e-10 relative change of cost) */
    double gradient_tolerance;   /* 0: default (1e-12) */
    double parameter_tolerance;  /* 0: default (1e-10 relative) */
    double max_seconds;          /* 0: no limit */
    bf_loss loss;
    int threads;                   /* 0 or 1: one thread */
    uint64_t seed;                 /* stochastic NLopt methods */
    const unsigned char *constant; /* NULL, or npar flags: hold these parameters at their start */
    int use_constraint;            /* apply problem->constraint where the method supports it */
    bf_progress_fn progress;       /* NULL, or called as the solve goes (above) */
    void *progress_user;           /* its first argument */
    /* NULL, or a flag that another thread (or a signal handler) sets non-zero to cancel:
     * read at every iteration or evaluation, never written by the library. */
    const bf_cancel_flag *cancel;
} bf_solver_options;

/* Zeroes o and sets its size: every default is a zero's (above), so Ceres' lm on one
 * thread, no loss, the default tolerances and iteration limit, no time limit. */
BF_API void bf_solver_options_init_size(bf_solver_options *o, size_t size);
static inline void bf_solver_options_init(bf_solver_options *o)
{
    bf_solver_options_init_size(o, sizeof *o);
}

/* The method, the local method and the constraint of o against the registry, before any
 * work: BF_OK, or BF_ERR_ARG with a message listing what would do (or saying that o's
 * size was not set by its init). */
BF_API bf_status bf_solver_options_check(const bf_solver_options *o, bf_error *err);

/* Why a solve stopped (bf_solution.stop; bf_solution.termination says it for people). */
typedef enum bf_stop {
    BF_STOP_CONVERGED = 0, /* a tolerance was met, or nothing was free to move */
    BF_STOP_ITERATIONS,    /* the iteration limit (NLopt: evaluations) */
    BF_STOP_TIME,          /* the time limit */
    BF_STOP_CANCELLED,     /* the progress callback or the cancel flag */
    BF_STOP_FAILED,        /* the back end failed (the start is kept) */
} bf_stop;

/* "converged", "iteration_limit", "time_limit", "cancelled", "failed" ("?" out of range). */
BF_API const char *bf_stop_name(bf_stop stop);

/* 1 when the solver options' cancel flag is set or the callback asks to stop (given the
 * iteration and cost); the back ends' common test. */
BF_API int bf_solver_cancelled(const bf_solver_options *o, int iteration, double cost);

/* Frozen (docs/api.md): embedded in bf_fit_result, filled whole by bf_solve. */
typedef struct bf_solution {
    double initial_cost, final_cost; /* 1/2 sum rho(r^2) */
    int iterations;                  /* back-end iterations (NLopt: evaluations) */
    int evaluations;                 /* residual (and Jacobian) evaluations of the whole set */
    double seconds;                  /* wall time */
    char backend[16];                /* "ceres", "nlopt" */
    char algorithm[48];              /* as run, e.g. "levenberg_marquardt", "LD_LBFGS" */
    bf_stop stop;                    /* why it stopped */
    char termination[160];           /* why it stopped, one line, for people */
    int usable;                      /* 1: x is a finite solution (converged or hit a limit
                                        with a finite cost); 0: the solve failed */
} bf_solution;

/* Minimises from x (in: start, clamped into the bounds; out: solution, always finite:
 * the start if nothing better was found). Returns BF_OK when the back end ran, even if
 * it stopped on a limit (see s->usable and s->termination); an error for bad options
 * (unknown algorithm: the message lists the known ones; p's or o's size not set by its
 * init) or a failed back end. o NULL: bf_solver_options_init's defaults. Prints nothing. */
BF_API bf_status bf_solve(const bf_problem *p, const bf_solver_options *o, double *x, bf_solution *s, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
