/* The objective's fused pass (bf_problem.normal, solve.h): sum g^2, J'g and J'J of the
 * loss-weighted residuals in one sweep over the samples, nothing of size n x p stored.
 *
 * The samples are cut into fixed chunks (the same for every thread count); each chunk
 * keeps its own sums, over the whole model vector, and the chunks are added in chunk
 * order, so the result does not depend on the threads. The sums are taken to the
 * requested columns once at the end: J_z = J_x[:, cols] diag(colscale), so
 * J_z'J_z = D (J_x'J_x)[cols, cols] D.
 *
 * Two ways through a chunk:
 *  - lobe models ("rho_d/pi + sum_k rho_s_k S_k", models/lobes.h): per block the lobe
 *    shapes S_k and their derivatives, then per residual its few non-zero Jacobian
 *    entries (its channel's rho_d and rho_s_k, and every lobe scalar) straight into a
 *    small per-channel J'J. A mono-tied model is summed over its untied entries and the
 *    sums folded onto the tied ones at the end (J_tied = J_untied M, so
 *    J_tied'J_tied = M' J_untied'J_untied M).
 *  - any other model: its values and full gradient rows per block (bf_model_eval_range),
 *    then per channel the columns its rows use, gathered, and each sum one dot product. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "metrics_impl.h"
#include "models/lobes.h"
#include "objective_state.h"
#include "base/parallel.h"

enum { NORMAL_CHUNK = BF_METRIC_CHUNK }; /* samples: the metrics' chunks (metrics_impl.h) */
#define BLOCK_DOUBLES 16384              /* gradient scratch of the generic path: about 128 KiB */

typedef struct normal_job {
    const bf_objective *o;
    const bf_model *m; /* the model evaluated: o->model, or its untied form */
    const double *x;   /* m's vector */
    int P;             /* m's vector length */
    int lobe_path;
    bf_lobe_layout lay;
    const bf_loss *loss;
    int want_jac, want_jtj;
    double *part;          /* per chunk: ssq, jtr (P), jtj (P^2, lower triangle) */
    bf_metric_sums *msum;  /* NULL, or per chunk: the metrics' sums (metrics_impl.h) */
    const double *mweight; /* the metrics' weights (a scene's), NULL: all 1 */
    int failed;
} normal_job;

static size_t normal_part(int P)
{
    return 1 + (size_t)P + (size_t)P * (size_t)P;
}

/* The final pass keeps a chunk's model values (and, for the log form, the metrics' log
 * differences) and cosines, and sums the metrics from them in bf_metric_chunk's order,
 * so that they equal bf_metrics_compute's to the bit. */
typedef struct metric_buf {
    size_t i0, C;   /* the chunk's first sample; channels */
    double *f, *dl; /* per value of the chunk; dl only for the log form */
    double *cs;     /* per sample: cos theta_i, 0 below the horizon */
} metric_buf;

/* One value kept (the final pass only). raw is the residual form's value: for the log
 * form it is the metrics' log difference itself (the objective's measurement term is
 * bf_obj_log1p(m c) too), which saves two logarithms. */
static inline __attribute__((always_inline)) void metric_value(metric_buf *mb, bf_residual form, size_t i, size_t ch,
                                                               double f, double cs, double raw)
{
    const size_t r = (i - mb->i0) * mb->C + ch;
    mb->f[r] = f;
    if (form == BF_RESIDUAL_LOG)
        mb->dl[r] = raw;
    mb->cs[i - mb->i0] = cs;
}

/* One residual: its loss-weighted value g, the scale s of its Jacobian row (w dr/df
 * dg/dr) and the form's own value raw (before the weight and the loss). */
typedef struct resid {
    double g, s, raw;
} resid;

/* The residual of measurement value[r] for model value f at cosine cs, for one residual
 * form: the form is a constant in each call of the switches below, so the compiler drops
 * its switch from the loops. */
static inline __attribute__((always_inline)) resid residual_at(const normal_job *j, bf_residual form, size_t r,
                                                               size_t ch, double f, double w, double cs)
{
    const bf_objective *o = j->o;
    const double mm = o->samples->value[r];
    const double t = o->meas_t ? o->meas_t[r] : bf_obj_form_meas(form, mm, cs);
    double d, dg = 1.0;
    resid out;
    out.raw = bf_obj_form_t(form, f, mm, cs, o->delta[ch], t, &d);
    out.g = w * out.raw;
    if (j->loss && j->loss->kind != BF_LOSS_NONE)
        out.g = bf_loss_residual(j->loss, out.g, &dg);
    out.s = w * d * dg;
    return out;
}

/* sum a[k] b[k] in four interleaved partial sums (a fixed order: the same bits every
 * time, and independent additions the processor can overlap). */
static double dot(const double *restrict a, const double *restrict b, size_t n)
{
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    size_t k = 0;
    for (; k + 4 <= n; k += 4) {
        s0 += a[k] * b[k];
        s1 += a[k + 1] * b[k + 1];
        s2 += a[k + 2] * b[k + 2];
        s3 += a[k + 3] * b[k + 3];
    }
    for (; k < n; k++)
        s0 += a[k] * b[k];
    return (s0 + s1) + (s2 + s3);
}

/* One chunk of the pass: its samples i0 .. i1-1, the workspace it holds while it runs,
 * its sums (*ssq; jtr and jtj over the model vector, jtj's lower triangle, jtj NULL when
 * not wanted) and its metric values (NULL when not wanted). */
typedef struct chunk_ctx {
    const normal_job *j;
    bf_obj_ws *ws;
    size_t i0, i1;
    double *ssq, *jtr, *jtj;
    metric_buf *ms;
} chunk_ctx;

/* One block of a chunk's samples: cnt of them from ib, and their geometry. */
typedef struct block_at {
    const bf_geometry *gv;
    size_t ib, cnt;
} block_at;

/* ---- Lobe models ------------------------------------------------------------------- */

/* Per chunk: per channel, the sums over the local entries u of a residual of that
 * channel (u = 0 rho_d[c], 1 .. K rho_s_k[c], then every lobe's scalars in order), and
 * one block's Jacobian columns over those entries, and the block's lobe shapes S_k and
 * their derivatives dS_k (per scalar of the lobe). */
typedef struct lobe_sums {
    int L;       /* local entries */
    double *tr;  /* C * L */
    double *tj;  /* C * L * L, lower triangle */
    double *col; /* (L + 2) * BF_LOBE_BLOCK: the columns, then g and s of the block */
    const double (*S)[BF_LOBE_BLOCK];
    const double (*dS)[BF_MAX_LOBE_SCALARS * BF_LOBE_BLOCK];
} lobe_sums;

/* One block of one channel: the residuals (form a constant in each call of the switch
 * in lobe_channels, so the compiler drops its switch from the loop), then the block's
 * Jacobian columns, then each of the sums as one dot product over the block. */
static inline __attribute__((always_inline)) double lobe_block(const chunk_ctx *cc, bf_residual form, size_t ch,
                                                               const block_at *bk, const lobe_sums *ls)
{
    const normal_job *j = cc->j;
    const bf_objective *o = j->o;
    const bf_lobe_layout *lay = &j->lay;
    const size_t C = (size_t)o->C, ib = bk->ib, cnt = bk->cnt;
    const int K = lay->lobes, L = ls->L;
    const double(*S)[BF_LOBE_BLOCK] = ls->S;
    const double(*dS)[BF_MAX_LOBE_SCALARS * BF_LOBE_BLOCK] = ls->dS;
    metric_buf *ms = cc->ms;
    const double *restrict sw = o->sw, *restrict lz = bk->gv->lz, *restrict vz = bk->gv->vz;
    double *restrict col = ls->col, *restrict g = col + (size_t)L * BF_LOBE_BLOCK, *restrict sc = g + BF_LOBE_BLOCK;
    double wk[BF_MAX_LOBES];
    for (int k = 0; k < K; k++)
        wk[k] = j->x[lay->weight[k] + (int)ch];
    const double fd = j->x[lay->diffuse + (int)ch] * (1.0 / M_PI);
    double ssq = 0.0;
    for (size_t q = 0; q < cnt; q++) {
        g[q] = sc[q] = 0.0;
        if (!(lz[q] > 0.0 && vz[q] > 0.0))
            continue; /* below the horizon: residual 0, Jacobian row 0 */
        const size_t i = ib + q;
        double f = fd;
        for (int k = 0; k < K; k++)
            f += wk[k] * S[k][q];
        const resid rr = residual_at(j, form, i * C + ch, ch, f, sw ? sw[i] : 1.0, lz[q]);
        g[q] = rr.g;
        sc[q] = rr.s;
        ssq += g[q] * g[q];
        if (ms)
            metric_value(ms, form, i, ch, f, lz[q], rr.raw);
    }
    if (!j->want_jac)
        return ssq;
    /* The columns: d f / d rho_d = 1/pi, d f / d rho_s_k = S_k, d f / d scalar = rho_s_k
     * dS_k, each times the row's scale s. */
    for (size_t q = 0; q < cnt; q++)
        col[q] = sc[q] * (1.0 / M_PI);
    int u = 1 + K;
    for (int k = 0; k < K; k++) {
        double *ck = col + (size_t)(1 + k) * BF_LOBE_BLOCK;
        for (size_t q = 0; q < cnt; q++)
            ck[q] = sc[q] * S[k][q];
        for (int v = 0; v < lay->nscalar[k]; v++, u++) {
            double *cu = col + (size_t)u * BF_LOBE_BLOCK;
            const double *d = dS[k] + (size_t)v * BF_LOBE_BLOCK;
            for (size_t q = 0; q < cnt; q++)
                cu[q] = sc[q] * wk[k] * d[q];
        }
    }
    double *tr = ls->tr + ch * (size_t)L, *tj = ls->tj ? ls->tj + ch * (size_t)L * (size_t)L : NULL;
    for (int a = 0; a < L; a++) {
        const double *ca = col + (size_t)a * BF_LOBE_BLOCK;
        tr[a] += dot(ca, g, cnt);
        for (int b = 0; tj && b <= a; b++)
            tj[a * L + b] += dot(ca, col + (size_t)b * BF_LOBE_BLOCK, cnt);
    }
    return ssq;
}

static double lobe_channels(const chunk_ctx *cc, const block_at *bk, const lobe_sums *ls)
{
    double ssq = 0.0;
    const bf_objective *o = cc->j->o;
    for (size_t ch = 0; ch < (size_t)o->C; ch++)
        switch (o->residual) {
        case BF_RESIDUAL_LOG: ssq += lobe_block(cc, BF_RESIDUAL_LOG, ch, bk, ls); break;
        default: ssq += lobe_block(cc, o->residual, ch, bk, ls); break;
        }
    return ssq;
}

/* The model entry of local entry u of channel ch. */
static int lobe_entry(const bf_lobe_layout *lay, int u, int ch)
{
    if (u == 0)
        return lay->diffuse + ch;
    if (u <= lay->lobes)
        return lay->weight[u - 1] + ch;
    u -= 1 + lay->lobes;
    for (int k = 0; k < lay->lobes; k++) {
        if (u < lay->nscalar[k])
            return lay->scalar[k] + u;
        u -= lay->nscalar[k];
    }
    return -1; /* not reached */
}

/* A chunk's sums. 0, or -1 when out of memory. */
static int lobe_chunk(const chunk_ctx *cc)
{
    const normal_job *j = cc->j;
    const bf_objective *o = j->o;
    const bf_lobe_layout *lay = &j->lay;
    const int K = lay->lobes, C = o->C, P = j->P;
    const size_t i0 = cc->i0, i1 = cc->i1;
    double *jtr = cc->jtr, *jtj = cc->jtj;
    int L = 1 + K;
    for (int k = 0; k < K; k++)
        L += lay->nscalar[k];
    const size_t ntr = (size_t)C * (size_t)L, ntj = ntr * (size_t)L;
    double S[BF_MAX_LOBES][BF_LOBE_BLOCK], dS[BF_MAX_LOBES][BF_MAX_LOBE_SCALARS * BF_LOBE_BLOCK];
    lobe_sums ls = {L,
                    bf_obj_ws_buf(cc->ws, BF_WS_TR, ntr * sizeof(double)),
                    j->want_jtj ? bf_obj_ws_buf(cc->ws, BF_WS_TJ, ntj * sizeof(double)) : NULL,
                    bf_obj_ws_buf(cc->ws, BF_WS_COL, ((size_t)L + 2) * BF_LOBE_BLOCK * sizeof(double)),
                    (const double(*)[BF_LOBE_BLOCK])S,
                    (const double(*)[BF_MAX_LOBE_SCALARS * BF_LOBE_BLOCK]) dS};
    if (!ls.tr || !ls.col || (j->want_jtj && !ls.tj))
        return -1;
    memset(ls.tr, 0, ntr * sizeof(double));
    if (ls.tj)
        memset(ls.tj, 0, ntj * sizeof(double));
    double ssq = 0.0;
    bf_geometry_block gb;
    for (size_t ib = i0; ib < i1; ib += BF_LOBE_BLOCK) {
        const size_t cnt = i1 - ib < BF_LOBE_BLOCK ? i1 - ib : BF_LOBE_BLOCK;
        const block_at bk = {bf_geometry_view(o->geom, ib, cnt, &gb), ib, cnt};
        for (int k = 0; k < K; k++)
            bf_model_lobe_shape(j->m, j->x, k, bk.gv, 0, cnt, S[k], j->want_jac ? dS[k] : NULL);
        ssq += lobe_channels(cc, &bk, &ls);
    }
    if (j->want_jac) { /* local entries to model entries (lower triangle of the chunk's sums) */
        for (int ch = 0; ch < C; ch++)
            for (int a = 0; a < L; a++) {
                const int ka = lobe_entry(lay, a, ch);
                jtr[ka] += ls.tr[(size_t)ch * (size_t)L + (size_t)a];
                for (int b = 0; ls.tj && b <= a; b++) {
                    const int kb = lobe_entry(lay, b, ch);
                    const double v = ls.tj[((size_t)ch * (size_t)L + (size_t)a) * (size_t)L + (size_t)b];
                    jtj[ka >= kb ? (size_t)ka * (size_t)P + (size_t)kb : (size_t)kb * (size_t)P + (size_t)ka] += v;
                }
            }
    }
    *cc->ssq = ssq;
    return 0;
}

/* ---- Any model --------------------------------------------------------------------- */

/* Scratch of one chunk's blocks: per residual of the block its loss-weighted value g
 * and the scale s of its gradient row (J = s dF/dx; 0 below the horizon), and one
 * channel's non-zero Jacobian columns gathered column by column. */
typedef struct block_scratch {
    double *vals, *grad; /* blk * C, blk * C * P */
    double *g, *s;       /* blk * C */
    double *jc;          /* (P + 1) * blk */
    int *cols;           /* P */
    uint64_t *used;      /* P */
} block_scratch;

static inline __attribute__((always_inline)) double block_residuals(const chunk_ctx *cc, bf_residual form,
                                                                    const block_at *bk, block_scratch *b)
{
    const normal_job *j = cc->j;
    const bf_objective *o = j->o;
    const bf_geometry *gv = bk->gv;
    const size_t C = (size_t)o->C, ib = bk->ib, cnt = bk->cnt;
    metric_buf *ms = cc->ms;
    double ssq = 0.0;
    for (size_t q = 0; q < cnt; q++) {
        const size_t i = ib + q;
        if (!bf_geometry_valid(gv, q)) { /* residual 0, Jacobian row 0 */
            for (size_t ch = 0; ch < C; ch++)
                b->g[q * C + ch] = b->s[q * C + ch] = 0.0;
            continue;
        }
        const double w = o->sw ? o->sw[i] : 1.0, cs = gv->lz[q];
        for (size_t ch = 0; ch < C; ch++) {
            const size_t li = q * C + ch;
            const resid rr = residual_at(j, form, i * C + ch, ch, b->vals[li], w, cs);
            b->s[li] = rr.s;
            ssq += rr.g * rr.g;
            b->g[li] = rr.g;
            if (ms)
                metric_value(ms, form, i, ch, b->vals[li], cs, rr.raw);
        }
    }
    return ssq;
}

/* J'g and J'J of one block, a channel at a time: a channel's rows touch only some
 * columns (in a colour fit, its own colour parameters and the scalars), which are
 * gathered into columns of cnt values, so each entry of the sums is one dot product. */
static void block_normal(const normal_job *j, size_t cnt, block_scratch *b, double *jtr, double *jtj)
{
    const size_t C = (size_t)j->o->C, P = (size_t)j->P;
    for (size_t ch = 0; ch < C; ch++) {
        /* The columns some row of this channel uses: per column, the OR of its entries'
         * bits without the sign (so -0 counts as 0, and NaN and Inf as non-zero), which
         * needs no branch per entry. */
        memset(b->used, 0, P * sizeof *b->used);
        for (size_t q = 0; q < cnt; q++) {
            const size_t li = q * C + ch;
            if (b->s[li] == 0.0)
                continue; /* below the horizon, or no effect on the cost */
            const double *gr = b->grad + li * P;
            for (size_t a = 0; a < P; a++) {
                uint64_t bits;
                memcpy(&bits, &gr[a], sizeof bits);
                b->used[a] |= bits & 0x7fffffffffffffffull;
            }
        }
        int m = 0;
        for (size_t a = 0; a < P; a++)
            if (b->used[a])
                b->cols[m++] = (int)a;
        /* The rows' used entries, scaled, into columns of cnt values (one sweep over the
         * rows), then g of this channel's rows after them. */
        double *gc = b->jc + (size_t)m * cnt;
        for (size_t q = 0; q < cnt; q++) {
            const size_t li = q * C + ch;
            const double sv = b->s[li], *gr = b->grad + li * P;
            for (int u = 0; u < m; u++)
                b->jc[(size_t)u * cnt + q] = sv != 0.0 ? sv * gr[b->cols[u]] : 0.0;
            gc[q] = b->g[li];
        }
        for (int u = 0; u < m; u++) {
            const double *cu = b->jc + (size_t)u * cnt;
            const size_t a = (size_t)b->cols[u];
            jtr[a] += dot(cu, gc, cnt);
            if (jtj)
                for (int v = 0; v <= u; v++)
                    jtj[a * P + (size_t)b->cols[v]] += dot(cu, b->jc + (size_t)v * cnt, cnt);
        }
    }
}

static int generic_chunk(const chunk_ctx *cc)
{
    const normal_job *j = cc->j;
    const bf_objective *o = j->o;
    const size_t C = (size_t)o->C, P = (size_t)j->P, i0 = cc->i0, i1 = cc->i1;
    bf_obj_ws *ws = cc->ws;
    size_t blk = BLOCK_DOUBLES / (C * (j->want_jac ? P + 1 : 1));
    blk = blk < 1 ? 1 : blk > BF_GEOMETRY_BLOCK ? BF_GEOMETRY_BLOCK : blk;
    block_scratch b = {bf_obj_ws_buf(ws, BF_WS_VALS, blk * C * sizeof(double)),
                       j->want_jac ? bf_obj_ws_buf(ws, BF_WS_GRAD, blk * C * P * sizeof(double)) : NULL,
                       bf_obj_ws_buf(ws, BF_WS_G, blk * C * sizeof(double)),
                       bf_obj_ws_buf(ws, BF_WS_S, blk * C * sizeof(double)),
                       bf_obj_ws_buf(ws, BF_WS_JC, (P + 1) * blk * sizeof(double)),
                       bf_obj_ws_buf(ws, BF_WS_COLS, P * sizeof(int)),
                       bf_obj_ws_buf(ws, BF_WS_USED, P * sizeof(uint64_t))};
    double ssq = 0.0;
    if (!b.vals || !b.g || !b.s || !b.jc || !b.cols || !b.used || (j->want_jac && !b.grad))
        return -1;
    bf_geometry_block gb;
    for (size_t ib = i0; ib < i1; ib += blk) {
        const size_t cnt = i1 - ib < blk ? i1 - ib : blk;
        const block_at bk = {bf_geometry_view(o->geom, ib, cnt, &gb), ib, cnt};
        bf_model_eval_range(j->m, j->x, bk.gv, 0, cnt, b.vals, b.grad);
        switch (o->residual) {
        case BF_RESIDUAL_LOG: ssq += block_residuals(cc, BF_RESIDUAL_LOG, &bk, &b); break;
        default: ssq += block_residuals(cc, o->residual, &bk, &b); break;
        }
        if (j->want_jac)
            block_normal(j, cnt, &b, cc->jtr, cc->jtj);
    }
    *cc->ssq = ssq;
    return 0;
}

/* ---- The pass ---------------------------------------------------------------------- */

/* The chunk's metric buffer from its workspace. 0, or -1 when out of memory. */
static int chunk_metric_buf(bf_obj_ws *ws, size_t i0, size_t i1, size_t C, metric_buf *mb)
{
    *mb = (metric_buf){i0, C, NULL, NULL, NULL};
    mb->f = bf_obj_ws_buf(ws, BF_WS_MBUF, (i1 - i0) * (2 * C + 1) * sizeof(double));
    if (!mb->f)
        return -1;
    mb->dl = mb->f + (i1 - i0) * C;
    mb->cs = mb->dl + (i1 - i0) * C;
    memset(mb->cs, 0, (i1 - i0) * sizeof *mb->cs);
    return 0;
}

static void normal_chunk(void *ctx, size_t c)
{
    normal_job *j = ctx;
    const size_t n = j->o->n, i0 = c * NORMAL_CHUNK, i1 = i0 + NORMAL_CHUNK < n ? i0 + NORMAL_CHUNK : n;
    const size_t C = (size_t)j->o->C;
    double *out = j->part + c * normal_part(j->P);
    metric_buf mbuf;
    chunk_ctx cc = {j, bf_obj_ws_get(j->o->ws), i0, i1, out, out + 1, j->want_jtj ? out + 1 + j->P : NULL, NULL};
    if (!cc.ws) {
        j->failed = 1;
        return;
    }
    if (j->msum) {
        if (chunk_metric_buf(cc.ws, i0, i1, C, &mbuf)) {
            bf_obj_ws_put(j->o->ws, cc.ws);
            j->failed = 1;
            return;
        }
        cc.ms = &mbuf;
    }
    int bad = j->lobe_path ? lobe_chunk(&cc) : generic_chunk(&cc);
    if (!bad && cc.ms)
        bf_metric_chunk(&j->msum[c], &(bf_metric_vals){mbuf.f, j->o->samples->value + i0 * C,
                                                       j->o->residual == BF_RESIDUAL_LOG ? mbuf.dl : NULL, mbuf.cs,
                                                       j->mweight ? j->mweight + i0 : NULL, i1 - i0, (int)C});
    bf_obj_ws_put(j->o->ws, cc.ws);
    if (bad)
        j->failed = 1; /* written only as 1, by any thread */
}

/* One pass's state: the job its chunks share, the untied vector, and the pass's own
 * sums. */
typedef struct normal_pass {
    normal_job j;
    const int *map;     /* entry k of j.m is entry map[k] of the model's; NULL: the same */
    int PM;             /* the model's vector length */
    size_t nchunks, ps; /* chunks, and the doubles of each one's part */
    bf_obj_ws *ws;
    double *sum;         /* the chunks' parts added */
    double *ftr, *ftj;   /* J'g and J'J over the model's entries (PM, PM x PM) */
    double xs[256], *xu; /* the untied vector: xs when it fits */
} normal_pass;

/* The untied model and vector, and the pass's buffers, zeroed (the chunks add into their
 * parts). 0, or -1 when out of memory. */
static int pass_setup(normal_pass *p, const bf_objective *o, const double *x, const bf_obj_pass *req,
                      const bf_obj_pass_out *out)
{
    const bf_model *m = bf_model_untied(o->model, &p->map);
    const int P = bf_model_nvalues(m);
    p->nchunks = (o->n + NORMAL_CHUNK - 1) / NORMAL_CHUNK;
    p->ps = normal_part(P);
    p->j = (normal_job){.o = o,
                        .m = m,
                        .P = P,
                        .loss = req->loss,
                        .want_jac = out->jtr != NULL || out->jtj != NULL,
                        .want_jtj = out->jtj != NULL};
    normal_job *j = &p->j;
    j->lobe_path = bf_model_lobe_layout(m, &j->lay);
    p->xu = (size_t)P <= 256 ? p->xs : malloc((size_t)P * sizeof *p->xu);
    p->PM = o->P;
    const size_t PM = (size_t)p->PM, nchunks = p->nchunks, ps = p->ps;
    p->ws = bf_obj_ws_get(o->ws);
    p->sum = p->ftr = p->ftj = NULL;
    if (p->ws) {
        j->part = bf_obj_ws_buf(p->ws, BF_WS_PART, (nchunks * ps + 1) * sizeof(double));
        p->sum = bf_obj_ws_buf(p->ws, BF_WS_SUM, ps * sizeof *p->sum);
        j->msum = out->metrics ? bf_obj_ws_buf(p->ws, BF_WS_MSUM, (nchunks + 1) * sizeof *j->msum) : NULL;
        p->ftr = j->want_jac ? bf_obj_ws_buf(p->ws, BF_WS_FTR, PM * sizeof *p->ftr) : NULL;
        p->ftj = out->jtj ? bf_obj_ws_buf(p->ws, BF_WS_FTJ, PM * PM * sizeof *p->ftj) : NULL;
    }
    j->mweight = req->weighted ? o->samples->scene_weight : NULL;
    if (!p->ws || !p->xu || !j->part || !p->sum || (out->metrics && !j->msum) || (j->want_jac && !p->ftr) ||
        (out->jtj && !p->ftj))
        return -1;
    memset(j->part, 0, (nchunks * ps + 1) * sizeof(double));
    memset(p->sum, 0, ps * sizeof *p->sum);
    if (j->msum)
        memset(j->msum, 0, (nchunks + 1) * sizeof *j->msum);
    if (p->ftr)
        memset(p->ftr, 0, PM * sizeof *p->ftr);
    if (p->ftj)
        memset(p->ftj, 0, PM * PM * sizeof *p->ftj);
    for (int k = 0; k < P; k++)
        p->xu[k] = x[p->map ? p->map[k] : k];
    j->x = p->xu;
    return 0;
}

/* The chunks' sums added in chunk order (the result independent of the threads). */
static void pass_sum(const normal_pass *p, const bf_obj_pass_out *out)
{
    for (size_t c = 0; c < p->nchunks; c++) {
        const double *part = p->j.part + c * p->ps;
        for (size_t e = 0; e < (p->j.want_jac ? p->ps : 1); e++)
            p->sum[e] += part[e];
    }
    *out->ssq = p->sum[0];
    if (out->metrics) {
        memset(out->metrics, 0, sizeof *out->metrics);
        for (size_t c = 0; c < p->nchunks; c++)
            bf_metric_sums_add(out->metrics, &p->j.msum[c]);
    }
}

/* Untied entries folded onto the model's, then the requested columns taken. */
static void pass_columns(const normal_pass *p, const bf_obj_cols *cols, const bf_obj_pass_out *out)
{
    const int P = p->j.P, *map = p->map;
    const size_t PM = (size_t)p->PM;
    const double *sum = p->sum;
    double *ftr = p->ftr, *ftj = p->ftj, *jtr = out->jtr, *jtj = out->jtj;
    for (int a = 0; p->j.want_jac && a < P; a++) {
        const int ka = map ? map[a] : a;
        ftr[ka] += sum[1 + a];
        for (int b = 0; jtj && b <= a; b++) {
            const int kb = map ? map[b] : b;
            const double v = sum[1 + P + (size_t)a * (size_t)P + (size_t)b];
            ftj[(size_t)ka * PM + (size_t)kb] += v;
            if (a != b) /* the untied sums are symmetric: the upper half too */
                ftj[(size_t)kb * PM + (size_t)ka] += v;
        }
    }
    const int n = cols->n, *idx = cols->idx;
    const double *scale = cols->scale;
    for (int a = 0; jtr && a < n; a++)
        jtr[a] = ftr[idx[a]] * scale[a];
    for (int a = 0; jtj && a < n; a++)
        for (int b = 0; b < n; b++)
            jtj[a * n + b] = ftj[(size_t)idx[a] * PM + (size_t)idx[b]] * scale[a] * scale[b];
}

int bf_obj_normal_x(const bf_objective *o, const double *x, const bf_obj_pass *req, const bf_obj_pass_out *out)
{
    normal_pass p;
    int bad = pass_setup(&p, o, x, req, out);
    if (!bad) {
        bf_parallel_for(p.nchunks, req->threads, normal_chunk, &p.j);
        bad = p.j.failed ? -1 : 0;
    }
    if (!bad) {
        pass_sum(&p, out);
        pass_columns(&p, &req->cols, out);
    }
    if (p.xu != p.xs)
        free(p.xu);
    bf_obj_ws_put(o->ws, p.ws);
    return bad;
}
