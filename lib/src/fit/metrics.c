/* Fit error as users compare it (definitions in metrics.h).
 *
 * Only samples above the horizon count (n = those samples times C): the model is 0 below
 * it by definition, so a measurement there says nothing about the fit. The log form
 * floors 1 + m c at 1e-12 as the objective does (a negative measurement stays finite).
 * rmse_rel is NaN when every measured value is 0 (no relative error is defined). AIC
 * and BIC use SSR / n floored at DBL_MIN, so an exact fit gives a very negative finite
 * value rather than -Inf. Weighted, every sum carries the sample's weight and is divided
 * by the sum of the weights instead of the count (metrics.h). The pass runs over fixed chunks on `threads` threads and
 * adds the chunks' sums in order: the result does not depend on the thread count. */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/metrics.h"
#include "objective_impl.h"
#include "parallel.h"

/* Sums over one chunk of samples, combined in chunk order afterwards. */
typedef struct partial {
    double ssr, scos, slog, srel, maxe;
    double wsum, wrel; /* sums of the weights behind ssr.. and srel */
    size_t n, nrel;
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

enum { CHUNK = 8192 }; /* samples: a value buffer that stays in cache */

static void chunk_sums(void *ctx, size_t c)
{
    job *j = ctx;
    partial *p = &j->part[c];
    size_t i0 = c * CHUNK, i1 = i0 + CHUNK < j->n ? i0 + CHUNK : j->n;
    const int C = j->C;
    double *f = malloc((i1 - i0) * (size_t)C * sizeof *f);
    if (!f) {
        p->failed = 1;
        return;
    }
    bf_model_eval_range(j->m, j->x, j->g, i0, i1, f, NULL);
    for (size_t i = i0; i < i1; i++) {
        if (!bf_geometry_valid(j->g, i))
            continue;
        /* w * x with w = 1 is x exactly: unweighted results are unchanged. */
        double w = j->weight ? (j->weight[i] > 0.0 ? j->weight[i] : 0.0) : 1.0;
        if (!(w > 0.0))
            continue;
        double cs = j->g->lz[i];
        for (int ch = 0; ch < C; ch++) {
            size_t r = i * (size_t)C + (size_t)ch;
            double fv = f[(i - i0) * (size_t)C + (size_t)ch], mv = j->value[r], d = fv - mv;
            p->ssr += w * (d * d);
            p->scos += w * ((d * cs) * (d * cs));
            double dl = bf_obj_log1p(fv * cs) - bf_obj_log1p(mv * cs);
            p->slog += w * (dl * dl);
            p->wsum += w;
            if (mv != 0.0) {
                double q = d / fabs(mv);
                p->srel += w * (q * q);
                p->wrel += w;
                p->nrel++;
            }
            if (fabs(d) > p->maxe)
                p->maxe = fabs(d);
            p->n++;
        }
    }
    free(f);
}

int bf_metrics_compute(const bf_model *m, const double *x, bf_samples *s, int k, int threads,
                       bf_metrics *out, bf_error *err)
{
    return bf_metrics_compute_weighted(m, x, s, k, threads, 0, out, err);
}

int bf_metrics_compute_weighted(const bf_model *m, const double *x, bf_samples *s, int k, int threads,
                                int weighted, bf_metrics *out, bf_error *err)
{
    memset(out, 0, sizeof *out);
    const int C = s->channels;
    if (bf_model_channels(m) != C)
        return bf_fail(err, BF_ERR_ARG, "metrics: model %s has %d channels but the samples have %d",
                       bf_model_name(m), bf_model_channels(m), C);
    const bf_geometry *g = bf_samples_geometry(s, err);
    if (!g)
        return err ? (int)err->code : BF_ERR_NOMEM;
    size_t nchunks = (s->n + CHUNK - 1) / CHUNK;
    job j = {m, x, g, s->value, weighted ? s->scene_weight : NULL, s->n, C, calloc(nchunks + 1, sizeof(partial))};
    if (!j.part)
        return bf_fail(err, BF_ERR_NOMEM, "metrics: out of memory");
    bf_parallel_for(nchunks, threads, chunk_sums, &j);
    partial t = {0};
    for (size_t c = 0; c < nchunks; c++) {
        const partial *p = &j.part[c];
        t.failed |= p->failed;
        t.ssr += p->ssr;
        t.scos += p->scos;
        t.slog += p->slog;
        t.srel += p->srel;
        t.wsum += p->wsum;
        t.wrel += p->wrel;
        t.maxe = p->maxe > t.maxe ? p->maxe : t.maxe;
        t.n += p->n;
        t.nrel += p->nrel;
    }
    free(j.part);
    if (t.failed)
        return bf_fail(err, BF_ERR_NOMEM, "metrics: out of memory for %zu values", s->n * (size_t)C);
    if (t.n == 0)
        return bf_fail(err, BF_ERR_ARG, "metrics: no samples above the horizon%s",
                       j.weight ? " with a positive weight" : "");
    /* Unweighted, wsum counts the values exactly (sums of 1.0), so dn is n. */
    double dn = (double)t.n, wn = t.wsum, msr = t.ssr / wn;
    if (msr < DBL_MIN)
        msr = DBL_MIN;
    out->n = t.n;
    out->k = k;
    out->weighted = j.weight != NULL;
    out->rmse = sqrt(t.ssr / wn);
    out->rmse_cos = sqrt(t.scos / wn);
    out->rmse_log = sqrt(t.slog / wn);
    out->rmse_rel = t.nrel ? sqrt(t.srel / t.wrel) : NAN;
    out->max_err = t.maxe;
    out->aic = dn * log(msr) + 2.0 * k;
    out->bic = dn * log(msr) + k * log(dn);
    return BF_OK;
}
