/* Internal: the structure of "rho_d/pi + sum_k rho_s_k S_k" models (the families that
 * bf_eval_diffuse_lobes evaluates), for callers that work with the lobe shapes
 * themselves: the objective's fused pass builds J'J from S_k and its derivatives
 * directly, without the C x P gradient rows per sample that bf_model_eval writes. */
#ifndef BF_MODELS_LOBES_H
#define BF_MODELS_LOBES_H

#include "brdfit/model.h"

#define BF_LOBE_BLOCK 128 /* at most this many samples per bf_model_lobe_shape call */
#define BF_MAX_LOBE_SCALARS 8

typedef struct bf_lobe_layout {
    int lobes;                 /* K configured lobes (0: diffuse only) */
    int diffuse;               /* model-vector entry of rho_d for channel 0 (channel c: + c) */
    int weight[BF_MAX_LOBES];  /* entry of lobe k's rho_s for channel 0 (channel c: + c) */
    int scalar[BF_MAX_LOBES];  /* entry of lobe k's first scalar; the others follow */
    int nscalar[BF_MAX_LOBES]; /* lobe k's scalars */
} bf_lobe_layout;

/* 1 with the layout when m itself (not through mono ties: see bf_model_untied) is such a
 * model, else 0. */
int bf_model_lobe_layout(const bf_model *m, bf_lobe_layout *out);

/* The model a mono-tied model evaluates (its entries expanded: inner entry k is entry
 * map[k] of m), or m itself with map NULL when nothing is tied. */
const bf_model *bf_model_untied(const bf_model *m, const int **map);

/* Lobe k's (0-based) shape over samples [i0, i0 + cnt) of a stored geometry or view,
 * cnt <= BF_LOBE_BLOCK: S[j] and, when dS is not NULL, dS[q * BF_LOBE_BLOCK + j] = dS/d
 * (scalar q of the lobe). Samples below the horizon get 0. */
void bf_model_lobe_shape(const bf_model *m, const double *x, int k, const bf_geometry *g, size_t i0, size_t cnt,
                         double *S, double *dS);

#endif
