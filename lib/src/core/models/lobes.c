/* The shared evaluator for "rho_d/pi + sum_k rho_s_k * S_k" models: each family only
 * computes its scalar lobe shapes S_k and their derivatives over a block of samples;
 * this driver spreads them over the channels and writes the Jacobian rows. */
#include "family.h"
#include "lobes.h"

#include <math.h>
#include <string.h>

_Static_assert(BF_LOBE_BLOCK == BF_BLOCK, "lobe shapes are laid out in blocks of BF_BLOCK samples");

/* Lobes actually configured (0 for a diffuse-only model). */
static int lobe_count(const bf_model *m)
{
    int K = 0;
    while (K < m->lobes && m->lobe_first[K + 1] != 0)
        K++;
    return K;
}

int bf_model_lobe_layout(const bf_model *m, bf_lobe_layout *out)
{
    if (m->inner || m->family->eval != bf_eval_diffuse_lobes)
        return 0;
    memset(out, 0, sizeof *out);
    out->lobes = lobe_count(m);
    out->diffuse = m->offset[0];
    for (int k = 1; k <= out->lobes; k++) {
        int first = m->lobe_first[k];
        out->weight[k - 1] = m->offset[first];
        out->scalar[k - 1] = m->offset[first + 1];
        out->nscalar[k - 1] = m->lobe_nscalar[k];
        if (m->lobe_nscalar[k] > BF_MAX_LOBE_SCALARS || m->lobe_chroma[k])
            return 0; /* a shape per channel: only bf_eval_diffuse_lobes handles it */
    }
    return 1;
}

const bf_model *bf_model_untied(const bf_model *m, const int **map)
{
    *map = m->inner ? m->xmap : NULL;
    return m->inner ? m->inner : m;
}

/* A bf_lobe_fn's arguments with the model vector: the fused pass's per-block call. */
void bf_model_lobe_shape(const bf_model *m, const double *x, int k, const bf_geometry *g, size_t i0, size_t cnt,
                         double *S, double *dS)
{
    int first = m->lobe_first[k + 1];
    m->family->lobe(m, k + 1, x + m->offset[first + 1], g, i0, cnt, S, dS);
    for (size_t j = 0; j < cnt; j++) /* the lobe functions may leave anything there */
        if (!bf_geometry_valid(g, i0 + j)) {
            S[j] = 0.0;
            for (int q = 0; dS && q < m->lobe_nscalar[k + 1]; q++)
                dS[q * BF_BLOCK + j] = 0.0;
        }
}

/* A lobe_chroma lobe's scalars for channel c: its colour parameters' channel-c values. */
static void chroma_scalars(const bf_model *m, const double *x, int k, int c, double *s)
{
    int first = m->lobe_first[k];
    for (int q = 0; q < m->lobe_nscalar[k]; q++) {
        int p = first + 1 + q;
        s[q] = x[m->offset[p] + (m->param[p].color ? c : 0)];
    }
}

void bf_eval_diffuse_lobes(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1,
                           double *values, double *grad)
{
    const int C = m->channels, P = m->nfree;
    const int K = lobe_count(m);
    double S[BF_MAX_LOBES][BF_BLOCK];
    double dS[BF_MAX_LOBES][BF_MAX_LOBE_SCALARS * BF_BLOCK];
    double sc[BF_MAX_LOBE_SCALARS];
    /* The layout in locals: stores into values and grad may alias anything the compiler
     * cannot see is private, and would otherwise reload m's arrays for every entry. */
    int weight[BF_MAX_LOBES], scalars[BF_MAX_LOBES], nscalar[BF_MAX_LOBES], chroma[BF_MAX_LOBES];
    int entry[BF_MAX_LOBES][BF_MAX_LOBE_SCALARS], per_channel[BF_MAX_LOBES][BF_MAX_LOBE_SCALARS];
    int any_chroma = 0;
    for (int k = 0; k < K; k++) {
        int first = m->lobe_first[k + 1];
        weight[k] = m->offset[first];
        scalars[k] = m->offset[first + 1];
        nscalar[k] = m->lobe_nscalar[k + 1];
        chroma[k] = m->lobe_chroma[k + 1];
        any_chroma |= chroma[k];
        for (int q = 0; q < nscalar[k]; q++) {
            entry[k][q] = m->offset[first + 1 + q];
            per_channel[k][q] = m->param[first + 1 + q].color;
        }
    }
    const int diffuse = m->offset[0];

    for (size_t b0 = i0; b0 < i1; b0 += BF_BLOCK) {
        size_t cnt = i1 - b0 < BF_BLOCK ? i1 - b0 : BF_BLOCK;
        for (int k = 0; k < K; k++)
            if (!chroma[k])
                m->family->lobe(m, k + 1, x + scalars[k], g, b0, cnt, S[k], grad ? dS[k] : NULL);
        /* Channel-major, so a lobe whose shape depends on the channel is evaluated once
         * per channel into the same buffers. */
        for (int c = 0; c < C; c++) {
            double w[BF_MAX_LOBES];
            int e[BF_MAX_LOBES][BF_MAX_LOBE_SCALARS];
            for (int k = 0; k < K; k++) {
                if (any_chroma && chroma[k]) {
                    chroma_scalars(m, x, k + 1, c, sc);
                    m->family->lobe(m, k + 1, sc, g, b0, cnt, S[k], grad ? dS[k] : NULL);
                }
                w[k] = x[weight[k] + c];
                for (int q = 0; q < nscalar[k]; q++)
                    e[k][q] = entry[k][q] + (per_channel[k][q] ? c : 0);
            }
            const double diffuse_value = x[diffuse + c] * (1.0 / M_PI);
            for (size_t j = 0; j < cnt; j++) {
                size_t i = b0 + j;
                int valid = bf_geometry_valid(g, i);
                double f = 0.0;
                if (valid) {
                    f = diffuse_value;
                    for (int k = 0; k < K; k++)
                        f += w[k] * S[k][j];
                }
                values[(i - i0) * (size_t)C + (size_t)c] = f;
                if (!grad)
                    continue;
                double *row = grad + (((i - i0) * (size_t)C) + (size_t)c) * (size_t)P;
                memset(row, 0, (size_t)P * sizeof *row);
                if (!valid)
                    continue;
                row[diffuse + c] = 1.0 / M_PI;
                for (int k = 0; k < K; k++) {
                    row[weight[k] + c] = S[k][j];
                    for (int q = 0; q < nscalar[k]; q++)
                        row[e[k][q]] = w[k] * dS[k][q * BF_BLOCK + j];
                }
            }
        }
    }
}
