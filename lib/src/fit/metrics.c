/* Fit error as users compare it (definitions in metrics.h).
 *
 * Only samples above the horizon count (n = those samples times C): the model is 0 below
 * it by definition, so a measurement there says nothing about the fit. The log form
 * floors 1 + m c at 1e-12 as the objective does (a negative measurement stays finite).
 * rmse_rel is NaN when every measured value is 0 (no relative error is defined). AIC
 * and BIC use SSR / n floored at DBL_MIN, so an exact fit gives a very negative finite
 * value rather than -Inf. The pass runs over fixed chunks on `threads` threads and
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
    size_t n, nrel;
    int failed; /* out of memory */
} partial;

typedef struct job {
    const bf_model *m;
    const double *x;
    const bf_geometry *g;
    const double *value;
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
        double cs = j->g->lz[i];
        for (int ch = 0; ch < C; ch++) {
            size_t r = i * (size_t)C + (size_t)ch;
            double fv = f[(i - i0) * (size_t)C + (size_t)ch], mv = j->value[r], d = fv - mv;
            p->ssr += d * d;
            p->scos += (d * cs) * (d * cs);
            double dl = bf_obj_log1p(fv * cs) - bf_obj_log1p(mv * cs);
            p->slog += dl * dl;
            if (mv != 0.0) {
                double q = d / fabs(mv);
                p->srel += q * q;
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
    memset(out, 0, sizeof *out);
    const int C = s->channels;
    if (bf_model_channels(m) != C)
        return bf_fail(err, BF_ERR_ARG, "metrics: model %s has %d channels but the samples have %d",
                       bf_model_name(m), bf_model_channels(m), C);
    const bf_geometry *g = bf_samples_geometry(s, err);
    if (!g)
        return err ? (int)err->code : BF_ERR_NOMEM;
    size_t nchunks = (s->n + CHUNK - 1) / CHUNK;
    job j = {m, x, g, s->value, s->n, C, calloc(nchunks + 1, sizeof(partial))};
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
        t.maxe = p->maxe > t.maxe ? p->maxe : t.maxe;
        t.n += p->n;
        t.nrel += p->nrel;
    }
    free(j.part);
    if (t.failed)
        return bf_fail(err, BF_ERR_NOMEM, "metrics: out of memory for %zu values", s->n * (size_t)C);
    if (t.n == 0)
        return bf_fail(err, BF_ERR_ARG, "metrics: no samples above the horizon");
    double dn = (double)t.n, msr = t.ssr / dn;
    if (msr < DBL_MIN)
        msr = DBL_MIN;
    out->n = t.n;
    out->k = k;
    out->rmse = sqrt(t.ssr / dn);
    out->rmse_cos = sqrt(t.scos / dn);
    out->rmse_log = sqrt(t.slog / dn);
    out->rmse_rel = t.nrel ? sqrt(t.srel / (double)t.nrel) : NAN;
    out->max_err = t.maxe;
    out->aic = dn * log(msr) + 2.0 * k;
    out->bic = dn * log(msr) + k * log(dn);
    return BF_OK;
}
