/* The fitting objective: a model, a sample set and a residual form become a bf_problem
 * over well-scaled internal parameters. Fixed parameters, bound overrides and the
 * internal parametrisation (log space for roughness and exponents) live here, not in
 * the models and not in the back ends.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_OBJECTIVE_H
#define BRDFIT_OBJECTIVE_H

#include <stddef.h>

#include "brdfit/error.h"
#include "brdfit/model.h"
#include "brdfit/samples.h"
#include "brdfit/solve.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Residual forms, per sample and channel (c = cos theta_i = N.L, f the model, m the
 * measurement, w the sample weight, times sqrt(w) when weights are used):
 *   linear   f - m
 *   cosine   (f - m) c
 *   log      ln(1 + f c) - ln(1 + m c)
 *   cbrt     cbrt(f c) - cbrt(m c)
 *   relative (f - m) / (|m| + delta), delta a small floor (documented where defined) */
typedef enum bf_residual {
    BF_RESIDUAL_LINEAR = 0,
    BF_RESIDUAL_COSINE,
    BF_RESIDUAL_LOG,
    BF_RESIDUAL_CBRT,
    BF_RESIDUAL_RELATIVE,
} bf_residual;

BF_API bf_status bf_residual_parse(const char *name, bf_residual *out, bf_error *err);
BF_API const char *bf_residual_name(bf_residual r);

/* --fix NAME=VALUE and --bound NAME=LO:HI. NAME is a parameter name (every channel of a
 * colour parameter) or NAME[c] (channel c only). Frozen (docs/api.md): a small value
 * struct, passed in arrays. */
typedef struct bf_override {
    char name[48];
    int channel; /* -1: all channels */
    int fix;     /* 1: fixed at value; 0: bounds lo..hi */
    double value, lo, hi;
} bf_override;

BF_API bf_status bf_override_parse_fix(const char *text, bf_override *out, bf_error *err);
BF_API bf_status bf_override_parse_bound(const char *text, bf_override *out, bf_error *err);

/* Checks overrides against model m before any data is read (channels <= 0: the
 * channel count is not known yet, channel indices unchecked): an unknown parameter, a
 * channel index on a scalar, a value or bounds outside the model's bounds, lo >= hi,
 * and two overrides of one entry (--fix alpha with --bound alpha, or two --fix
 * rho_d[1]): BF_ERR_ARG or BF_ERR_RANGE with a one-line message. */
BF_API bf_status bf_overrides_check(const bf_model *m, int channels, const bf_override *ov, int n, bf_error *err);

/* Set up with bf_objective_options_init (its size: docs/api.md), then change what differs. */
typedef struct bf_objective_options {
    size_t size; /* sizeof, set by bf_objective_options_init */
    bf_residual residual;
    int solid_angle; /* weight samples by the solid angle they stand for (MERL cells:
                              from the cell's extent in theta_h, theta_d, phi_d); needs a
                              MERL origin, else BF_ERR_ARG */
    int use_weights; /* multiply by the samples' own weights when they have some
                              (a scene's weights, s->scene_weight, always apply) */
    const bf_override *overrides;
    int noverrides;
    int threads; /* threads for the objective's own passes (standard errors);
                              the back ends take theirs from bf_solver_options */
} bf_objective_options;

/* Sets the size and the defaults: the linear residual, the samples' own weights
 * (use_weights 1, as bf_fit), no solid-angle weights, no overrides, threads 0 (one). */
BF_API void bf_objective_options_init_size(bf_objective_options *o, size_t size);
static inline void bf_objective_options_init(bf_objective_options *o)
{
    bf_objective_options_init_size(o, sizeof *o);
}

typedef struct bf_objective bf_objective;

/* The model's channel count must equal the samples'. Validates overrides (unknown
 * parameter, channel out of range, value or bounds outside the model's bounds, lo >= hi)
 * with one-line errors. Computes the sample geometry if needed. o NULL: a zeroed
 * struct's settings (linear residual, the samples' own weights not used); o's size not
 * set by its init: BF_ERR_ARG. */
BF_API bf_status bf_objective_new(const bf_model *m, bf_samples *s, const bf_objective_options *o, bf_objective **out,
                                  bf_error *err);
BF_API void bf_objective_free(bf_objective *obj);

/* The problem over the internal vector z (free parameters only, in their internal
 * scale). nres = samples * channels. Valid as long as obj lives. */
BF_API const bf_problem *bf_objective_problem(const bf_objective *obj);
BF_API int bf_objective_nz(const bf_objective *obj);

/* Model vector x (bf_model_nvalues entries) <-> internal z. to_internal clamps x into the
 * effective bounds first; to_model writes every entry of x, fixed ones included. */
BF_API void bf_objective_to_internal(const bf_objective *obj, const double *x, double *z);
BF_API void bf_objective_to_model(const bf_objective *obj, const double *z, double *x);

/* Effective bounds in model space (after overrides; fixed: lo = hi = value), and which
 * model-vector entries are fixed. */
BF_API void bf_objective_bounds(const bf_objective *obj, double *lo, double *hi);
BF_API int bf_objective_fixed(const bf_objective *obj, int k);

/* Standard errors of the model parameters at x (model vector), from the Jacobian of
 * the residuals with respect to the model parameters: s^2 (J^T J)^-1 with
 * s^2 = sum r^2 / (n - k). 0 for fixed parameters; NaN where J^T J is singular there
 * (a parameter the data do not determine). */
BF_API bf_status bf_objective_stderr(const bf_objective *obj, const double *x, double *se, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
