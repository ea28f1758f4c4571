/* Internal: what a model family implements, and the configured model it fills in.
 * Each family lives in its own file and exports one `const bf_family`;
 * models/families.def is the only list of them all (registry.c expands it). */
#ifndef BF_FAMILY_H
#define BF_FAMILY_H

#include "brdfit/model.h"

#define BF_MAX_OPTIONS 4
#define BF_MAX_PARAMS 64
#define BF_NAME_LEN 32
#define BF_BLOCK 128 /* samples per block in the lobe driver */

typedef struct bf_family bf_family;

struct bf_model {
    const bf_family *family;
    int channels;
    int lobes;
    int opt[BF_MAX_OPTIONS]; /* chosen value index for each of the family's options */
    int reciprocal, energy_conserving;

    int nparam;
    bf_param_info param[BF_MAX_PARAMS];
    char names[BF_MAX_PARAMS][BF_NAME_LEN];
    int offset[BF_MAX_PARAMS];
    int nfree;

    /* Filled by bf_model_add_param for the lobe driver: entry of each lobe's colour
     * weight (rho_s) and how many scalars follow it. */
    int lobe_first[BF_MAX_LOBES + 1];
    int lobe_nscalar[BF_MAX_LOBES + 1];
    /* 1 when lobe k has colour parameters after its weight (a conductor's r and g): its
     * shape then differs by channel, and the driver calls the lobe function once per
     * channel with that channel's values in the scalars. */
    int lobe_chroma[BF_MAX_LOBES + 1];

    char spec[160];

    /* The spec option mono (see model.h): the parameters it names have color 0 and mono
     * 1 here, and the family's evaluator runs on `inner`, the same model without the tie,
     * through a vector expanded by xmap (inner entry -> entry here). NULL/0 otherwise. */
    char mono[64];
    struct bf_model *inner;
    int *xmap;
};

/* Shape of lobe k over samples [i0, i0 + cnt): S[j] for j < cnt and, when dS is not
 * NULL, dS[s * BF_BLOCK + j] = dS / d(scalar s of the lobe), scalars in table order.
 * `s` holds the lobe's scalar values (for a lobe_chroma lobe: one channel's values of
 * its colour parameters). Invalid samples (below the horizon) may be left
 * with any finite or non-finite value: the driver overwrites them with 0.
 * Eight flat arguments on purpose: the fused pass calls it for every block of every
 * lobe, and a struct to fill per call would only move the same values through memory. */
typedef void (*bf_lobe_fn)(const bf_model *m, int lobe, const double *s, const bf_geometry *g, size_t i0, size_t cnt,
                           double *S, double *dS);

struct bf_family {
    bf_family_info info;
    /* Adds the parameters for m->lobes and m->opt (via bf_model_add_param) and sets
     * reciprocal / energy_conserving. Returns BF_OK or an error. */
    bf_status (*configure)(bf_model *m, bf_error *err);
    /* Evaluator over samples [i0, i1), outputs relative to i0 (as bf_model_eval_range): either the
     * family's own, or bf_eval_diffuse_lobes together with a `lobe` shape. */
    void (*eval)(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1, double *values,
                 double *grad);
    bf_lobe_fn lobe; /* only for bf_eval_diffuse_lobes */
    /* 1: channel c's value and gradient depend on channel c's colour entries and the
     * scalars alone, never on another channel's entries (no luminance tint, no shared
     * normalisation). With every scalar fixed (or none, as in sgd) a fit of C channels is
     * then C independent fits, and the driver runs it so (docs/fitting.md, "Independent
     * channels"). 0 (the default): the channels are one problem. lambert qualifies but
     * leaves it 0: its linear fit gains nothing, and C searches would cost C times the
     * starts and change its stored results. */
    int channels_independent;
};

/* Appends a parameter with its role (model.h); name gets "_k" appended for lobe k when
 * m->lobes > 1. Positional on purpose: a family's configure reads as its parameter table,
 * one call a row and one argument a column (bf_model_add_rows takes whole tables). */
bf_status bf_model_add_param(bf_model *m, const char *name, int color, double lo, double hi, double def, bf_scale scale,
                             int lobe, bf_param_role role, bf_error *err);
/* Same, with open bounds. */
bf_status bf_model_add_param_open(bf_model *m, const char *name, int color, double lo, int lo_open, double hi,
                                  int hi_open, double def, bf_scale scale, int lobe, bf_param_role role, bf_error *err);

/* A table of parameters the way the artist-facing families declare them: outside the
 * lobes, linear, in [lo, 1]; `color` 1 for a colour. */
typedef struct bf_param_row {
    const char *name;
    int color;
    double lo, def;
    bf_param_role role;
} bf_param_row;
bf_status bf_model_add_rows(bf_model *m, const bf_param_row *rows, int n, bf_error *err);

/* For a family's own evaluator: when sample i is below the horizon, zeroes its C values
 * and (rows not NULL) its C gradient rows of P entries, and returns 1. */
static inline int bf_eval_skip_invalid(const bf_geometry *g, size_t i, int C, int P, double *out, double *rows)
{
    if (bf_geometry_valid(g, i))
        return 0;
    for (int c = 0; c < C; c++)
        out[c] = 0.0;
    if (rows)
        for (int k = 0; k < C * P; k++)
            rows[k] = 0.0;
    return 1;
}

/* The parameter of the chosen Fresnel term (BF_FRESNEL_* in terms.h): f0 [0, 1] for
 * schlick, ior [1, 100] (log scale) for dielectric, none for none, colour r [1e-3, 0.99] and g
 * [1e-3, 1] for conductor. */
bf_status bf_model_add_fresnel_param(bf_model *m, int kind, int lobe, bf_error *err);

/* The shared driver for families with a `lobe` function. Expects the table laid out as
 * rho_d (colour), then for each lobe k: rho_s (colour) followed by its scalars. */
void bf_eval_diffuse_lobes(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1,
                           double *values, double *grad);

/* Option index helpers for configure functions. */
int bf_model_opt(const bf_model *m, const char *key); /* chosen value index, -1 if no such option */

#endif
