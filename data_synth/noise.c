/* Noise models: what measurement does to the model's values (see synth.h for the
 * order: noise model, outliers, clamping). */
#include "synth.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *const noise_names[] = {"none", "relative", "additive", "photon"};
#define NNOISE (int)(sizeof noise_names / sizeof noise_names[0])

int bf_synth_noise_model_from_name(const char *name)
{
    for (int m = 0; m < NNOISE; m++)
        if (strcmp(name, noise_names[m]) == 0)
            return m;
    return -1;
}

const char *bf_synth_noise_model_name(bf_synth_noise_model m)
{
    return (int)m >= 0 && (int)m < NNOISE ? noise_names[m] : "unknown";
}

bf_status bf_synth_noise_check(const bf_synth_noise *nz, bf_error *err)
{
    if ((int)nz->model < 0 || (int)nz->model >= NNOISE)
        return bf_fail(err, BF_ERR_ARG, "unknown noise model %d", (int)nz->model);
    if ((nz->model == BF_NOISE_RELATIVE || nz->model == BF_NOISE_ADDITIVE) &&
        !(nz->level >= 0.0 && isfinite(nz->level)))
        return bf_fail(err, BF_ERR_ARG, "noise level %g must be finite and >= 0", nz->level);
    if (nz->model == BF_NOISE_PHOTON && !(nz->counts > 0.0 && isfinite(nz->counts)))
        return bf_fail(err, BF_ERR_ARG, "photon counts per unit value %g must be finite and > 0", nz->counts);
    if (!(nz->outlier_fraction >= 0.0 && nz->outlier_fraction <= 1.0))
        return bf_fail(err, BF_ERR_ARG, "outlier fraction %g must be in [0, 1]", nz->outlier_fraction);
    if (!(nz->outlier_factor >= 0.0 && isfinite(nz->outlier_factor)))
        return bf_fail(err, BF_ERR_ARG, "outlier factor %g must be finite and > 0 (0: random)", nz->outlier_factor);
    return BF_OK;
}

static double noisy(const bf_synth_noise *nz, bf_synth_rng *r, double v)
{
    switch (nz->model) {
    case BF_NOISE_RELATIVE: return v * (1.0 + nz->level * bf_synth_normal(r));
    case BF_NOISE_ADDITIVE: return v + nz->level * bf_synth_normal(r);
    case BF_NOISE_PHOTON: {
        const double mean = nz->counts * (v > 0.0 ? v : 0.0);
        /* Past the largest double the counts are the limit of no noise at all. */
        return isfinite(mean) ? bf_synth_poisson(r, mean) / nz->counts : v;
    }
    default: return v;
    }
}

/* Floyd's sampling: k of n indices, each k-subset equally likely, in O(k) draws. */
static void choose(size_t n, size_t k, unsigned char *mark, bf_synth_rng *r)
{
    for (size_t j = n - k; j < n; j++) {
        size_t t = (size_t)bf_synth_below(r, (uint64_t)j + 1);
        mark[mark[t] ? j : t] = 1;
    }
}

static bf_status outliers(bf_samples *s, const bf_synth_noise *nz, bf_synth_rng *r, bf_error *err)
{
    const size_t C = (size_t)s->channels, n = s->n;
    const size_t k = (size_t)llround(nz->outlier_fraction * (double)n);
    if (k == 0)
        return BF_OK;
    unsigned char *mark = calloc(n, 1);
    double *vmax = calloc(C, sizeof *vmax);
    if (!mark || !vmax) {
        free(mark);
        free(vmax);
        return bf_fail(err, BF_ERR_NOMEM, "out of memory choosing %zu outliers", k);
    }
    for (size_t i = 0; i < n; i++)
        for (size_t c = 0; c < C; c++)
            if (s->value[i * C + c] > vmax[c])
                vmax[c] = s->value[i * C + c];
    choose(n, k, mark, r);
    for (size_t i = 0; i < n; i++) {
        if (!mark[i])
            continue;
        for (size_t c = 0; c < C; c++) {
            double *v = &s->value[i * C + c];
            *v = nz->outlier_factor > 0.0 ? *v * nz->outlier_factor : bf_synth_uniform(r) * vmax[c];
        }
    }
    free(mark);
    free(vmax);
    return BF_OK;
}

bf_status bf_synth_noise_apply(bf_samples *s, const bf_synth_noise *nz, bf_synth_rng *r, bf_error *err)
{
    int rc = bf_synth_noise_check(nz, err);
    if (rc != BF_OK)
        return rc;
    const size_t nv = s->n * (size_t)s->channels;
    if (nz->model != BF_NOISE_NONE)
        for (size_t i = 0; i < nv; i++)
            s->value[i] = noisy(nz, r, s->value[i]);
    if ((rc = outliers(s, nz, r, err)) != BF_OK)
        return rc;
    for (size_t i = 0; i < nv; i++) {
        if (nz->clamp && s->value[i] < 0.0)
            s->value[i] = 0.0;
        /* A huge level or factor can overflow; no NaN or Inf goes out as data. */
        if (!isfinite(s->value[i]))
            return bf_fail(
                err, BF_ERR_RANGE,
                "sample %zu, channel %d: the noise made the value %g (noise level or outlier factor too large)",
                i / (size_t)s->channels + 1, (int)(i % (size_t)s->channels), s->value[i]);
    }
    return BF_OK;
}
