/* What a sample set holds, for `brdfit info`: coverage in angles, invalid samples,
 * value ranges.
 *
 * Angle ranges are over the samples above the horizon (as the geometry decides it);
 * theta_h and theta_d come from the geometry, which stays cached on s for the fit.
 * Counts are of samples (not values): below the horizon; with a NaN or Inf value; with
 * a negative value; with a zero value (any channel). Value ranges and means are per
 * channel over every finite value, above the horizon or not. A range or mean with
 * nothing to cover is NaN. */
#include "brdfit/prep.h"
#include "base/sized.h"

#include <math.h>
#include <stdlib.h>

static void widen(bf_range *r, double v)
{
    if (v < r->lo || isnan(r->lo))
        r->lo = v;
    if (v > r->hi || isnan(r->hi))
        r->hi = v;
}

/* The angle between L and H from |L x H| and L.H: acos(L.H) would read 1e-6 degrees
 * for L = V (a retro-reflection slice), where the answer is 0. */
static double theta_d(const bf_geometry *g, size_t i)
{
    double cx = g->ly[i] * g->hz[i] - g->lz[i] * g->hy[i];
    double cy = g->lz[i] * g->hx[i] - g->lx[i] * g->hz[i];
    double cz = g->lx[i] * g->hy[i] - g->ly[i] * g->hx[i];
    return atan2(sqrt(cx * cx + cy * cy + cz * cz), g->vh[i]);
}

static bf_status describe(bf_samples *s, bf_samples_info *info, bf_error *err)
{
    const bf_range none = {NAN, NAN};
    const size_t C = (size_t)s->channels;
    *info = (bf_samples_info){.size = info->size}; /* the caller's size stays */
    info->n = s->n;
    info->channels = s->channels;
    info->theta_i = info->theta_o = info->theta_h = info->theta_d = none;
    info->weighted = s->weight != NULL || s->scene_weight != NULL; /* own or a scene's */
    info->value = malloc(C * sizeof *info->value);
    info->mean = malloc(C * sizeof *info->mean);
    size_t *nfinite = calloc(C, sizeof *nfinite);
    /* Compensated (Neumaier) sums: a million similar values lose no digits. */
    double *sum = calloc(2 * C, sizeof *sum), *comp = sum ? sum + C : NULL;
    const bf_geometry *g = NULL;
    bf_status rc = s->n ? bf_samples_geometry(s, &g, err) : BF_OK;
    if (rc == BF_OK && (!info->value || !info->mean || !nfinite || !sum))
        rc = bf_fail(err, BF_ERR_NOMEM, "out of memory describing %zu samples", s->n);
    if (rc != BF_OK) {
        free(nfinite);
        free(sum);
        bf_samples_info_clear(info);
        return rc;
    }
    for (size_t c = 0; c < C; c++)
        info->value[c] = none;
    const double deg = 180.0 / M_PI;
    bf_geometry_block gb;
    double abuf[4 * BF_GEOMETRY_BLOCK];
    for (size_t b0 = 0; b0 < s->n; b0 += BF_GEOMETRY_BLOCK) {
        size_t cnt = s->n - b0 < BF_GEOMETRY_BLOCK ? s->n - b0 : BF_GEOMETRY_BLOCK;
        const bf_geometry *gv = bf_geometry_view(g, b0, cnt, &gb);
        const double *dir[4];
        bf_samples_angle_block(s, b0, cnt, abuf, dir);
        for (size_t j = 0; j < cnt; j++) {
            const double *v = s->value + (b0 + j) * C;
            int nonfinite = 0, negative = 0, zero = 0;
            for (size_t c = 0; c < C; c++) {
                if (!isfinite(v[c])) {
                    nonfinite = 1;
                    continue;
                }
                negative |= v[c] < 0.0;
                zero |= v[c] == 0.0;
                widen(&info->value[c], v[c]);
                nfinite[c]++;
                double t = sum[c] + v[c];
                comp[c] += fabs(sum[c]) >= fabs(v[c]) ? (sum[c] - t) + v[c] : (v[c] - t) + sum[c];
                sum[c] = t;
            }
            info->nonfinite += nonfinite;
            info->negative += negative;
            info->zero += zero;
            if (!bf_geometry_valid(gv, j)) {
                info->below_horizon++;
                continue;
            }
            widen(&info->theta_i, dir[0][j]);
            widen(&info->theta_o, dir[2][j]);
            widen(&info->theta_h, atan2(sqrt(gv->sin2h[j]), gv->hz[j]) * deg);
            widen(&info->theta_d, theta_d(gv, j) * deg);
        }
    }
    for (size_t c = 0; c < C; c++)
        info->mean[c] = nfinite[c] ? (sum[c] + comp[c]) / (double)nfinite[c] : NAN;
    free(nfinite);
    free(sum);
    return BF_OK;
}

bf_status bf_samples_describe(bf_samples *s, bf_samples_info *info, bf_error *err)
{
    if (bf_sized_check(info, sizeof *info, "bf_samples_info", err) != BF_OK)
        return BF_ERR_ARG;
    /* Every member of this version lies within the first version's size. */
    return describe(s, info, err);
}

BF_SIZED_INIT_ZERO(bf_samples_info)

void bf_samples_info_clear(bf_samples_info *info)
{
    if (!info)
        return;
    free(info->value);
    free(info->mean);
    info->value = NULL;
    info->mean = NULL;
}
