/* Display mapping of linear values for 8-bit images (render.h). */
#include <math.h>
#include <stdlib.h>

#include "brdfit/render.h"

void bf_tonemap(float *v, size_t n, bf_tonemap_mode mode, double exposure, double decades)
{
    if (mode == BF_TONEMAP_LOG) {
        double hi = 0.0;
        for (size_t i = 0; i < n; i++)
            if (v[i] * exposure > hi)
                hi = v[i] * exposure;
        if (!(hi > 0.0) || !(decades > 0.0)) {
            for (size_t i = 0; i < n; i++)
                v[i] = 0.0f;
            return;
        }
        double top = log10(hi), bottom = top - decades;
        for (size_t i = 0; i < n; i++) {
            double e = v[i] * exposure;
            v[i] = e > 0.0 ? (float)fmax(0.0, (log10(e) - bottom) / decades) : 0.0f;
        }
        return;
    }
    for (size_t i = 0; i < n; i++) {
        double e = v[i] * exposure;
        v[i] = (float)(mode == BF_TONEMAP_REINHARD ? (e > 0.0 ? e / (1.0 + e) : 0.0) : e);
    }
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

double bf_exposure_percentile(const float *rgb, size_t npx, double percentile)
{
    float *v = malloc((npx ? npx : 1) * sizeof *v);
    if (!v)
        return NAN;
    size_t n = 0;
    for (size_t p = 0; p < npx; p++) {
        float m = fmaxf(rgb[3 * p], fmaxf(rgb[3 * p + 1], rgb[3 * p + 2]));
        if (m > 0.0f && isfinite(m))
            v[n++] = m;
    }
    double e = 1.0;
    if (n) {
        qsort(v, n, sizeof *v, cmp_float);
        double q = fmin(fmax(percentile, 0.0), 100.0) / 100.0 * (double)(n - 1);
        size_t k = (size_t)floor(q);
        double f = q - (double)k, at = k + 1 < n ? (1.0 - f) * v[k] + f * v[k + 1] : v[k];
        e = at > 0.0 ? 1.0 / at : 1.0;
    }
    free(v);
    return e;
}
