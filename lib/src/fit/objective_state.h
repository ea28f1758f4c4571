/* Internal: the objective's state, shared by its files (objective.c: construction and
 * evaluation; parametrisation.c: internal scale; overrides.c: --fix/--bound;
 * solid_angle.c: MERL cell weights; objective_stderr.c: standard errors; residual.c:
 * form names) and by metrics.c (the guarded logarithm). */
#ifndef BF_OBJECTIVE_STATE_H
#define BF_OBJECTIVE_STATE_H

#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stddef.h>

#include "brdfit/metrics.h"
#include "brdfit/objective.h"

/* The passes' workspaces (objective_ws.c). */
#include "models/scale.h"
#include "objective_ws.h"

struct bf_objective {
    const bf_model *model; /* not owned: must outlive the objective */
    bf_samples *samples;   /* not owned, not to be changed while the objective lives */
    const bf_geometry *geom;
    bf_residual residual;
    int threads;  /* for the objective's own passes (standard errors) */
    size_t n;     /* samples */
    int C, P, nz; /* channels, model-vector length, free (internal) entries */

    /* Per model-vector entry k (P each). */
    double *lo, *hi; /* effective bounds in model space (closed: open ends nudged in) */
    unsigned char *fixed;
    double *fixval;  /* value of fixed entries */
    bf_scale *scale; /* internal scale actually used (after the LOG fallback) */
    int *zpos;       /* position in z, or -1 when fixed */

    /* Per internal entry j (nz each). */
    int *kidx;         /* model-vector entry */
    double *zlo, *zhi; /* internal bounds */

    double *sw;       /* NULL, or per-sample sqrt of the combined weight */
    double *delta;    /* C floors of the relative form */
    double *meas_t;   /* NULL, or n*C terms bf_obj_form_meas (log and cbrt forms) */
    size_t nvalid;    /* samples above the horizon */
    size_t npos;      /* residuals above the horizon with a positive weight (the
                               criteria's N, metrics.h) */
    double sum_log_w; /* sum of ln w over those residuals (0 unweighted) */
    double wsum;      /* sum of w over them (npos unweighted) */

    /* Energy constraint: colour parameters summed per channel; channel c's entry is
     * color_off + c * color_step (step 0 for a mono parameter: one value for all). */
    int ncolor;
    int *color_off, *color_step;

    bf_obj_ws_list *ws; /* the passes' workspaces (see above) */

    bf_problem problem;
};

/* ---- Residual forms (inline: they run once per residual) -----------------------------
 * ln(1 + u), with u floored at -1 + 1e-12 so that a negative measurement (u < -1) gives a
 * large negative but finite value, not NaN. Computed as log(v) - ((v - 1) - u) / v with
 * v = 1 + u (the rounding of v corrected to first order): within 1 ulp of log1p, and
 * libm's log with a division costs three quarters of its log1p, the largest single cost
 * of a pass over a MERL table (3.3 M of them). */
#define BF_OBJ_LOG_FLOOR (-1.0 + 1e-12)
static inline double bf_obj_log1p(double u)
{
    if (!(u > BF_OBJ_LOG_FLOOR))
        u = BF_OBJ_LOG_FLOOR;
    const double v = 1.0 + u;
    if (!(v <= DBL_MAX)) /* Inf (NaN is caught above) */
        return v;
    return log(v) - ((v - 1.0) - u) / v;
}

/* The cube root has an infinite slope at 0, which would put Inf in the Jacobian wherever
 * the model is 0 (and f c = 0 is common: dark colours, zero lobes). Below |u| = eps we
 * use the odd cubic cbrt(eps) (4t - t^3)/3, t = u/eps, which meets cbrt in value and
 * slope at |u| = eps (C1), is monotone, and has slope (4/3) eps^(-2/3) (1.3e6) at 0.
 * eps = 1e-9 (f cos in 1/sr): darker than any measurement, so the residual differs from
 * cbrt(f c) - cbrt(m c) only where both are black. Negative u keeps its sign. */
#define BF_OBJ_CBRT_EPS 1e-9
#define BF_OBJ_CBRT_EPS3 1e-3 /* cbrt(BF_OBJ_CBRT_EPS) */
static inline double bf_obj_cbrt(double u, double *d)
{
    if (fabs(u) >= BF_OBJ_CBRT_EPS) {
        double r = cbrt(u);
        if (d)
            *d = r / (3.0 * u);
        return r;
    }
    double t = u / BF_OBJ_CBRT_EPS;
    if (d)
        *d = BF_OBJ_CBRT_EPS3 / BF_OBJ_CBRT_EPS * (4.0 - 3.0 * t * t) / 3.0;
    return BF_OBJ_CBRT_EPS3 * (4.0 * t - t * t * t) / 3.0;
}

/* The measurement's own term of the log and cbrt forms (ln(1 + m c), cbrt(m c)), which
 * the objective computes once per residual rather than at every evaluation; 0 for the
 * other forms. */
static inline double bf_obj_form_meas(bf_residual form, double mm, double c)
{
    switch (form) {
    case BF_RESIDUAL_LOG: return bf_obj_log1p(mm * c);
    case BF_RESIDUAL_CBRT: return bf_obj_cbrt(mm * c, NULL);
    default: return 0.0;
    }
}

/* r(f) for one model value f against the measurement mm at cosine c (= N.L), and
 * *drdf = dr/df; t = bf_obj_form_meas(form, mm, c). delta is the channel's floor for the
 * relative form. Finite for every finite input, negative measurements included. */
static inline double bf_obj_form_t(bf_residual form, double f, double mm, double c, double delta, double t,
                                   double *drdf)
{
    switch (form) {
    case BF_RESIDUAL_COSINE: *drdf = c; return (f - mm) * c;
    case BF_RESIDUAL_LOG: {
        double u = f * c;
        *drdf = u > BF_OBJ_LOG_FLOOR ? c / (1.0 + u) : 0.0;
        return bf_obj_log1p(u) - t;
    }
    case BF_RESIDUAL_CBRT: {
        double d;
        double r = bf_obj_cbrt(f * c, &d) - t;
        *drdf = d * c;
        return r;
    }
    case BF_RESIDUAL_RELATIVE: {
        double s = 1.0 / (fabs(mm) + delta);
        *drdf = s;
        return (f - mm) * s;
    }
    case BF_RESIDUAL_LINEAR:
    default: *drdf = 1.0; return f - mm;
    }
}

/* ---- Internal parametrisation (parametrisation.c) ---------------------------------- */
/* Chooses the scale of each entry from the model's hint and the effective bounds, and
 * fills zpos, kidx, zlo, zhi and nz. */
void bf_obj_setup_scale(bf_objective *o);

/* ---- Overrides (overrides.c) ---------------------------------------------------------
 * Fills lo, hi, fixed, fixval from the model's bounds and the overrides, in order (a
 * later override of the same entry replaces an earlier one). */
bf_status bf_obj_apply_overrides(bf_objective *o, const bf_override *ov, int nov, bf_error *err);

/* ---- Solid-angle weights (solid_angle.c) ---------------------------------------------
 * n weights, one per sample, from its MERL cell's extent; mean 1 over the samples above
 * the horizon. BF_ERR_ARG without a MERL origin. */
bf_status bf_obj_solid_angle_weights(bf_samples *s, const bf_geometry *g, double *w, bf_error *err);

/* ---- Evaluation (objective.c) --------------------------------------------------------
 * The columns of a Jacobian the passes below differentiate by: column j is model-vector
 * entry idx[j] times scale[j] (for the internal Jacobian, the free entries and the chain
 * rule dx/dz; for standard errors, the free entries in model space). */
typedef struct bf_obj_cols {
    int n;
    const int *idx;
    const double *scale;
} bf_obj_cols;

/* Residuals r0..r1-1 at the model vector x, and when jac is not NULL their Jacobian
 * over cols: jac[(r - r0) * cols->n + j] = dres/dx[cols->idx[j]] * cols->scale[j].
 * Returns 0, or -1 when out of memory. */
int bf_obj_eval_x(const bf_objective *o, const double *x, const bf_obj_cols *cols, size_t r0, size_t r1, double *res,
                  double *jac);

/* What a fused pass of bf_problem.normal (solve.h) is asked: the loss (NULL: none), the
 * threads (the result does not depend on their count), the columns (as bf_obj_eval_x's),
 * and for the metrics whether they carry the samples' scene weights. */
typedef struct bf_obj_pass {
    const bf_loss *loss;
    int threads;
    bf_obj_cols cols;
    int weighted;
} bf_obj_pass;

/* Where it goes: *ssq = sum g^2 of the loss-weighted residuals; jtr = J'g (cols.n) and
 * jtj = J'J (cols.n x cols.n, full), and the metrics' sums (metrics_impl.h) of the
 * model's values, each NULL when not wanted. */
struct bf_metric_sums;
typedef struct bf_obj_pass_out {
    double *ssq, *jtr, *jtj;
    struct bf_metric_sums *metrics;
} bf_obj_pass_out;

/* The fused pass at the model vector x, nothing of size n x cols.n stored. Returns 0, or
 * -1 when out of memory. */
int bf_obj_normal_x(const bf_objective *o, const double *x, const bf_obj_pass *req, const bf_obj_pass_out *out);

/* ---- The end of a fit (objective_stderr.c) ---------------------------------------------
 * What the end of a fit asks of its last pass: the scene's weights in the metrics or
 * not, the k free parameters the criteria count, and the internal entries left out of
 * the standard errors (held, nz flags; NULL: none; entries on a bound or without
 * effect, NaN there) and of the correlations (held_corr: entries without effect). */
typedef struct bf_final_want {
    int weighted, k;
    const unsigned char *held, *held_corr;
} bf_final_want;

/* Where it goes, each NULL when not wanted: the metrics, the standard errors (P, model
 * order), corr the correlations (nz x nz over the free entries, NaN where one of the
 * pair is undetermined), cov the P x P covariance of the model's entries from the
 * standard errors' pass (bf_fit_result's). */
typedef struct bf_final_out {
    bf_metrics *metrics;
    double *se, *corr, *cov;
} bf_final_out;

/* Standard errors (as bf_objective_stderr), the metrics (as bf_metrics_compute_weighted
 * with want->k free parameters) and the criteria of the objective's residuals without a
 * loss (bf_metrics_criteria) at x, from one pass. out->metrics and out->se are needed. */
bf_status bf_obj_final(const bf_objective *o, const double *x, const bf_final_want *want, const bf_final_out *out,
                       bf_error *err);

#endif
