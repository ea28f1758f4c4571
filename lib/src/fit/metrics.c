/* Fit error as users compare it (definitions in metrics.h).
 *
 * Only samples above the horizon count (n = those samples times C): the model is 0 below
 * it by definition, so a measurement there says nothing about the fit. The log form
 * floors 1 + m c at 1e-12 as the objective does (a negative measurement stays finite).
 * rmse_rel is NaN when every measured value is 0 (no relative error is defined).
 * Weighted, every sum carries the sample's weight and is divided by the sum of the
 * weights instead of the count (metrics.h). The criteria are a fit's: NaN here,
 * bf_metrics_criteria computes them for bf_fit; an exact fit's WSSR / N is floored at
 * DBL_MIN, so it gives a very negative finite value rather than -Inf. The pass runs over fixed chunks on `threads` threads and
 * adds the chunks' sums in order: the result does not depend on the thread count. */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/metrics.h"
#include "metrics_impl.h"
#include "base/parallel.h"

/* Sums over one chunk of samples, combined in chunk order afterwards. */
typedef struct partial {
    bf_metric_sums s;
    int failed; /* out of memory */
} partial;

typedef struct job {
    const bf_model *m;
    const double *x;
    const bf_geometry *g;
    const double *value;
    const double *weight; /* NULL: every weight 1 */
    size_t n;
    int C;
    partial *part;
} job;

void bf_metric_chunk(bf_metric_sums *p, const bf_metric_vals *v)
{
    const double *f = v->f, *mv = v->mv, *dl = v->dl, *cs = v->cs, *w = v->w;
    const size_t cnt = v->cnt;
    const int C = v->C;
    /* Summed on this thread's stack and stored once: neighbouring chunks' sums share
     * cache lines. */
    bf_metric_sums sums = *p;
    for (size_t i = 0; i < cnt; i++) {
        if (!(cs[i] > 0.0))
            continue;
        /* w * x with w = 1 is x exactly: unweighted results are unchanged. */
        const double wi = w ? (w[i] > 0.0 ? w[i] : 0.0) : 1.0;
        if (!(wi > 0.0))
            continue;
        for (int ch = 0; ch < C; ch++) {
            const size_t r = i * (size_t)C + (size_t)ch;
            if (dl)
                bf_metric_add_dl(&sums, f[r], mv[r], cs[i], wi, dl[r]);
            else
                bf_metric_add(&sums, f[r], mv[r], cs[i], wi);
        }
    }
    *p = sums;
}

static void chunk_sums(void *ctx, size_t c)
{
    job *j = ctx;
    partial *p = &j->part[c];
    size_t i0 = c * BF_METRIC_CHUNK, i1 = i0 + BF_METRIC_CHUNK < j->n ? i0 + BF_METRIC_CHUNK : j->n;
    const int C = j->C;
    double *f = malloc((i1 - i0) * ((size_t)C + 1) * sizeof *f);
    if (!f) {
        p->failed = 1;
        return;
    }
    double *cs = f + (i1 - i0) * (size_t)C;
    bf_geometry_block gb;
    for (size_t ib = i0; ib < i1; ib += BF_GEOMETRY_BLOCK) {
        size_t cnt = i1 - ib < BF_GEOMETRY_BLOCK ? i1 - ib : BF_GEOMETRY_BLOCK;
        const bf_geometry *gv = bf_geometry_view(j->g, ib, cnt, &gb);
        bf_model_eval_range(j->m, j->x, gv, 0, cnt, f + (ib - i0) * (size_t)C, NULL);
        for (size_t q = 0; q < cnt; q++)
            cs[ib - i0 + q] = bf_geometry_valid(gv, q) ? gv->lz[q] : 0.0;
    }
    bf_metric_chunk(&p->s, &(bf_metric_vals){f, j->value + i0 * (size_t)C, NULL, cs, j->weight ? j->weight + i0 : NULL,
                                             i1 - i0, C});
    free(f);
}

bf_status bf_metrics_compute(const bf_model *m, const double *x, bf_samples *s, int k, int threads, bf_metrics *out,
                             bf_error *err)
{
    return bf_metrics_compute_weighted(m, x, s, k, threads, 0, out, err);
}

/* 8 parameters: public API, each argument a separate choice of the caller. */
bf_status bf_metrics_compute_weighted(const bf_model *m, const double *x, bf_samples *s, int k, int threads,
                                      int weighted, bf_metrics *out, bf_error *err)
{
    memset(out, 0, sizeof *out);
    const int C = s->channels;
    if (bf_model_channels(m) != C)
        return bf_fail(err, BF_ERR_ARG, "metrics: model %s has %d channels but the samples have %d", bf_model_name(m),
                       bf_model_channels(m), C);
    const bf_geometry *g;
    bf_status rc = bf_samples_geometry(s, &g, err);
    if (rc != BF_OK)
        return rc;
    size_t nchunks = (s->n + BF_METRIC_CHUNK - 1) / BF_METRIC_CHUNK;
    job j = {m, x, g, s->value, weighted ? s->scene_weight : NULL, s->n, C, calloc(nchunks + 1, sizeof(partial))};
    if (!j.part)
        return bf_fail(err, BF_ERR_NOMEM, "metrics: out of memory");
    bf_parallel_for(nchunks, threads, chunk_sums, &j);
    bf_metric_sums t = {0};
    int failed = 0;
    for (size_t c = 0; c < nchunks; c++) {
        failed |= j.part[c].failed;
        bf_metric_sums_add(&t, &j.part[c].s);
    }
    free(j.part);
    if (failed)
        return bf_fail(err, BF_ERR_NOMEM, "metrics: out of memory for %zu values", s->n * (size_t)C);
    return bf_metric_sums_finish(&t, k, j.weight != NULL, out, err);
}

void bf_metric_sums_add(bf_metric_sums *t, const bf_metric_sums *p)
{
    t->ssr += p->ssr;
    t->scos += p->scos;
    t->slog += p->slog;
    t->srel += p->srel;
    t->wsum += p->wsum;
    t->wrel += p->wrel;
    t->maxe = p->maxe > t->maxe ? p->maxe : t->maxe;
    t->n += p->n;
    t->nrel += p->nrel;
}

bf_status bf_metric_sums_finish(const bf_metric_sums *t, int k, int weighted, bf_metrics *out, bf_error *err)
{
    memset(out, 0, sizeof *out);
    if (t->n == 0)
        return bf_fail(err, BF_ERR_ARG, "metrics: no samples above the horizon%s",
                       weighted ? " with a positive weight" : "");
    /* Unweighted, wsum counts the values exactly (sums of 1.0), so the means are per value. */
    double wn = t->wsum;
    out->n = t->n;
    out->k = k;
    out->weighted = weighted;
    out->rmse = sqrt(t->ssr / wn);
    out->rmse_cos = sqrt(t->scos / wn);
    out->rmse_log = sqrt(t->slog / wn);
    out->rmse_rel = t->nrel ? sqrt(t->srel / t->wrel) : NAN;
    out->max_err = t->maxe;
    out->loglik = out->aic = out->aicc = out->bic = NAN; /* a fit's (bf_metrics_criteria) */
    return BF_OK;
}

void bf_metrics_criteria(bf_metrics *m, size_t n, int k, double wssr, double sum_log_w)
{
    m->crit_n = n;
    m->loglik = m->aic = m->aicc = m->bic = NAN;
    if (n == 0 || !isfinite(wssr) || !isfinite(sum_log_w) || wssr < 0.0)
        return;
    const double N = (double)n, q = (double)k + 1.0; /* + sigma */
    double msr = wssr / N;
    if (msr < DBL_MIN)
        msr = DBL_MIN;
    m->loglik = -0.5 * N * (log(2.0 * M_PI * msr) + 1.0) + 0.5 * sum_log_w;
    m->aic = -2.0 * m->loglik + 2.0 * q;
    m->aicc = N - q - 1.0 > 0.0 ? m->aic + 2.0 * q * (q + 1.0) / (N - q - 1.0) : NAN;
    m->bic = -2.0 * m->loglik + q * log(N);
}
