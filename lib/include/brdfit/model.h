/* Parametric BRDF models: configured from a spec string ("walter:fresnel=dielectric",
 * "microfacet:D=ggx,G=smith_ggx,F=schlick,lobes=2") and a channel count, each exposes
 * its parameter table and evaluates values and analytic gradients over many samples.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_MODEL_H
#define BRDFIT_MODEL_H

#include <stddef.h>
#include "brdfit/error.h"
#include "brdfit/geometry.h"
#include "brdfit/limits.h"

#ifdef __cplusplus
extern "C" {
#endif

#define BF_MAX_LOBES 8

/* How an optimizer should see a parameter: exponents span decades, so they are
 * best searched in log space (log1p where the lower bound is 0). */
typedef enum bf_scale { BF_SCALE_LINEAR = 0, BF_SCALE_LOG, BF_SCALE_LOG1P } bf_scale;

/* What a parameter does, declared by each family with the parameter: code that must
 * know (the data-driven start, mono=specular) asks the role, never the name. */
typedef enum bf_param_role {
    BF_ROLE_NONE = 0,             /* not declared (a test fails on it) */
    BF_ROLE_DIFFUSE,              /* the diffuse colour or albedo: rho_d, base_color */
    BF_ROLE_DIFFUSE_SHAPE,        /* shapes the diffuse term: Oren-Nayar sigma, subsurface */
    BF_ROLE_WEIGHT,               /* a lobe's weight or colour: rho_s, sheen, clearcoat */
    BF_ROLE_ROUGHNESS,            /* lobe width as a slope roughness, wider when larger: alpha, m */
    BF_ROLE_PERCEPTUAL_ROUGHNESS, /* its square is the slope roughness: Disney's roughness */
    BF_ROLE_EXPONENT,             /* a cosine power, narrower when larger: n, nu, nv, s, gamma */
    BF_ROLE_FALLOFF,              /* 1 / (1 + b (1 - cos)) falloff, narrower when larger: ABC's b */
    BF_ROLE_SLOPE_SPREAD,         /* a spread of tan(theta_h), wider when larger: Brady's beta */
    BF_ROLE_F0,                   /* Fresnel reflectance at normal incidence */
    BF_ROLE_IOR,                  /* index of refraction of a Fresnel term */
    BF_ROLE_EDGE_TINT,            /* a conductor's edge tint (Gulbrandsen's g) */
    BF_ROLE_ORIENTATION,          /* an azimuth: Heidrich-Seidel's thread direction */
    BF_ROLE_SHAPE                 /* any other shape of a lobe (Lafortune's C, ABC's c, ...) */
} bf_param_role;

/* "diffuse", "weight", "roughness", ... ("none" for BF_ROLE_NONE). */
BF_API const char *bf_param_role_name(bf_param_role role);

typedef struct bf_param_info {
    const char *name; /* "rho_s", or "rho_s_2" for lobe 2 when lobes > 1 */
    union {
        int color;                             /* 1: one value per channel; 0: one scalar */
        int colour BF_DEPRECATED("use color"); /* the same, as spelled before 0.1 */
    };
    double lo, hi;        /* bounds */
    int lo_open, hi_open; /* 1 where the bound itself is excluded, e.g. brady a in (0, 3] */
    double def;           /* default value */
    bf_scale scale;
    int lobe; /* 0 for parameters outside the lobes, k >= 1 for lobe k */
    int mono; /* 1: a colour parameter that the spec option mono ties across
                           channels: one value for every channel (color is then 0) */
    bf_param_role role;
} bf_param_info;

typedef struct bf_option_info {
    const char *name;          /* "fresnel" */
    const char *const *values; /* NULL-terminated; values[0] is the default */
    int quiet_default;         /* 1: the canonical spec names the option only away from values[0],
                                  so specs stored before the option existed keep their bytes */
} bf_option_info;

/* What `brdfit models` shows about a family, independent of its configuration. */
typedef struct bf_family_info {
    const char *name;
    const char *summary;
    const char *reference;
    const bf_option_info *options; /* terminated by an entry with name NULL */
    int lobes;                     /* accepts lobes=K */
    int anisotropic;
} bf_family_info;

BF_API int bf_family_count(void);
BF_API const bf_family_info *bf_family_get(int i);
/* Every family with its parameters (bounds, defaults, scales, roles), options and sizes,
 * as the JSON text `brdfit models --json` prints; malloc'd (free it), NULL when out of
 * memory. */
BF_API char *bf_models_json(void);

/* A model list as `brdfit fit -m` takes it, split into specs: a comma starts a new model
 * only where the next token has no '=' or has a ':' of its own, so option lists stay
 * whole ("lambert,microfacet:D=ggx,G=smith_ggx,walter" is three models); an entry "all"
 * stands for every family with its default options, in the order of bf_family_get.
 * *specs is one block (the n pointers and their texts), freed with bf_free. The specs
 * are not checked here (bf_model_new does that). BF_ERR_ARG for an empty list or entry. */
BF_API bf_status bf_model_list_split(const char *list, char ***specs, int *n, bf_error *err);

typedef struct bf_model bf_model;

/* 1 <= channels <= BF_MAX_CHANNELS. Returns NULL and fills err on unknown model, option or value.
 *
 * Besides the family's options and lobes=K, every spec accepts mono=WHAT, which ties
 * colour parameters across channels (one value for all of them: a white highlight
 * on coloured data costs one parameter instead of C): WHAT is "specular" (every colour
 * parameter but the first, the diffuse colour), "all", or parameter names joined by '+'
 * ("rho_s+rho_s_2"). The canonical spec writes it last. */
BF_API bf_status bf_model_new(const char *spec, int channels, bf_model **out, bf_error *err);
BF_API void bf_model_free(bf_model *m);

BF_API const char *bf_model_name(const bf_model *m);                    /* family name, e.g. "walter" */
BF_API const bf_family_info *bf_model_family(const bf_model *m);        /* its family's description */
BF_API const char *bf_model_spec(const bf_model *m);                    /* canonical spec with every option */
BF_API const char *bf_model_option(const bf_model *m, const char *key); /* NULL if none */
BF_API int bf_model_channels(const bf_model *m);
BF_API int bf_model_lobes(const bf_model *m);
BF_API int bf_model_reciprocal(const bf_model *m);
BF_API int bf_model_energy_conserving(const bf_model *m);

/* Named parameters (a colour parameter is one entry) and their place in the vector. */
BF_API int bf_model_nparams(const bf_model *m);
BF_API const bf_param_info *bf_model_param(const bf_model *m, int i);
BF_API int bf_model_param_offset(const bf_model *m, int i);
BF_API int bf_model_find_param(const bf_model *m, const char *name); /* -1 if absent */

/* The name of model-vector entry k (0 <= k < bf_model_nvalues): "alpha", or "rho_d[c]"
 * for channel c of a colour parameter when the model has several channels (the
 * spelling --fix and --bound take). Returns buf. */
BF_API const char *bf_model_entry_name(const bf_model *m, int k, char *buf, size_t size);

/* Length P of the model vector: color_count * C + scalar_count, fixed entries included
 * (the free parameters of a fit are fewer when some are fixed: bf_fit_result). */
BF_API int bf_model_nvalues(const bf_model *m);
BF_API void bf_model_defaults(const bf_model *m, double *x);
/* BF_ERR_RANGE naming the parameter when a value is NaN, Inf or out of bounds. */
BF_API bf_status bf_model_check(const bf_model *m, const double *x, bf_error *err);

/* values[i*C + c] for every sample i and channel c. grad (NULL: none) is the row-major
 * Jacobian: grad[(i*C + c)*P + k] = d values[i*C + c] / d x[k]. Thread-safe. */
BF_API void bf_model_eval(const bf_model *m, const double *x, const bf_geometry *g, double *values, double *grad);
/* The same for samples [i0, i1) only, for callers that split the work (threads,
 * chunks): outputs start at sample i0, i.e. values[(i - i0)*C + c] and
 * grad[((i - i0)*C + c)*P + k], so a buffer for (i1 - i0) samples suffices. */
BF_API void bf_model_eval_range(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1,
                                double *values, double *grad);

#ifdef __cplusplus
}
#endif
#endif
