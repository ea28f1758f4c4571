/* Fit error as users compare it (definitions in metrics.h).
 *
 * Only samples above the horizon count (n = those samples times C): the model is 0 below
 * it by definition, so a measurement there says nothing about the fit. The log form
 * floors 1 + m c at 1e-12 as the objective does (a negative measurement stays finite).
 * rmse_rel is NaN when every measured value is 0 (no relative error is defined). AIC
 * and BIC use SSR / n floored at DBL_MIN, so an exact fit gives a very negative finite
 * value rather than -Inf. */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/metrics.h"
#include "objective_impl.h"

int bf_metrics_compute(const bf_model *m, const double *x, bf_samples *s, int k, bf_metrics *out,
                       bf_error *err)
{
    memset(out, 0, sizeof *out);
    const int C = s->channels;
    if (bf_model_channels(m) != C)
        return bf_fail(err, BF_ERR_ARG, "metrics: model %s has %d channels but the samples have %d",
                       bf_model_name(m), bf_model_channels(m), C);
    const bf_geometry *g = bf_samples_geometry(s, err);
    if (!g)
        return err ? (int)err->code : BF_ERR_NOMEM;
    double *f = malloc((s->n * (size_t)C + 1) * sizeof *f);
    if (!f)
        return bf_fail(err, BF_ERR_NOMEM, "metrics: out of memory for %zu values", s->n * (size_t)C);
    bf_model_eval(m, x, g, f, NULL);
    double ssr = 0.0, scos = 0.0, slog = 0.0, srel = 0.0, maxe = 0.0;
    size_t n = 0, nrel = 0;
    for (size_t i = 0; i < s->n; i++) {
        if (!bf_geometry_valid(g, i))
            continue;
        double c = g->lz[i];
        for (int ch = 0; ch < C; ch++) {
            size_t r = i * (size_t)C + (size_t)ch;
            double fv = f[r], mv = s->value[r], d = fv - mv;
            ssr += d * d;
            scos += (d * c) * (d * c);
            double dl = bf_obj_log1p(fv * c) - bf_obj_log1p(mv * c);
            slog += dl * dl;
            if (mv != 0.0) {
                double q = d / fabs(mv);
                srel += q * q;
                nrel++;
            }
            if (fabs(d) > maxe)
                maxe = fabs(d);
            n++;
        }
    }
    free(f);
    if (n == 0)
        return bf_fail(err, BF_ERR_ARG, "metrics: no samples above the horizon");
    double dn = (double)n, msr = ssr / dn;
    if (msr < DBL_MIN)
        msr = DBL_MIN;
    out->n = n;
    out->k = k;
    out->rmse = sqrt(ssr / dn);
    out->rmse_cos = sqrt(scos / dn);
    out->rmse_log = sqrt(slog / dn);
    out->rmse_rel = nrel ? sqrt(srel / (double)nrel) : NAN;
    out->max_err = maxe;
    out->aic = dn * log(msr) + 2.0 * k;
    out->bic = dn * log(msr) + k * log(dn);
    return BF_OK;
}
