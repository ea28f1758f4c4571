/* The start of the per-pixel fits and the shared parameters (photo_impl.h's driver):
 *  - a subsample of the masked pixels (evenly spread, at most START_PIXELS);
 *  - their robust Lambertian normals and albedos, and from them the automatic scale and
 *    the material clusters (k-means on the albedo, seeded k-means++);
 *  - per cluster, the model fitted by bf_fit to the subsample's pixels pooled as BRDF
 *    samples at their normals: the start of every pixel of the cluster;
 *  - with shared entries, their joint solve with the subsample's pixels (photo_joint.c,
 *    called from photo_fit.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/parallel.h"
#include "base/rng.h"
#include "brdfit/fit.h"
#include "fit_impl.h"
#include "photo_run.h"

#define POOL_PIXELS 512 /* a cluster's pixels pooled for its start, at most */

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

size_t photo_subsample(const unsigned char *mask, int y0, int y1, int width, size_t max, int32_t **out)
{
    size_t n = 0, from = (size_t)y0 * (size_t)width, to = (size_t)y1 * (size_t)width;
    for (size_t i = from; i < to; i++)
        n += mask[i] != 0;
    size_t stride = n > max ? (n + max - 1) / max : 1, m = 0, seen = 0;
    *out = malloc(((n + stride - 1) / stride + 1) * sizeof **out);
    if (!*out)
        return (size_t)-1;
    for (size_t i = from; i < to; i++)
        if (mask[i] && seen++ % stride == 0)
            (*out)[m++] = (int32_t)i;
    return m;
}

/* Robust Lambertian normal and albedo of every subsample pixel. */
void photo_start_lambert(photo_run *run, const photo_band *b, double *normal, double *albedo)
{
    const bf_stack *s = run->s;
    int K = s->nimages, C = s->channels;
    photo_lights pl = {run->lbuf, run->ebuf, {0}};
    for (size_t p = 0; p < b->npix; p++) {
        int x = b->pixel[p] % s->width, y = b->pixel[p] / s->width;
        photo_lights_at(s, x, y, &pl);
        double *n = normal + 3 * p;
        if (!photo_lambert_robust(b->v + p * (size_t)K * (size_t)C, &pl, K, C, n, albedo + p * (size_t)C)) {
            n[0] = n[1] = 0.0;
            n[2] = 1.0;
        }
        photo_given_normal(run, x, y, n);
    }
}

double photo_auto_scale(const double *albedo, size_t n, int C)
{
    double *a = malloc((n ? n : 1) * sizeof *a);
    if (!a || !n) {
        free(a);
        return 1.0;
    }
    for (size_t p = 0; p < n; p++) {
        double m = 0.0;
        for (int c = 0; c < C; c++)
            m = fmax(m, albedo[p * (size_t)C + c]);
        a[p] = m;
    }
    qsort(a, n, sizeof *a, cmp_double);
    double q = a[(size_t)floor(0.99 * (double)(n - 1))];
    free(a);
    return q > 0.0 ? 0.8 / q : 1.0;
}

static double dist2(const double *a, const double *b, int C)
{
    double d = 0.0;
    for (int c = 0; c < C; c++)
        d += (a[c] - b[c]) * (a[c] - b[c]);
    return d;
}

int photo_nearest(const double *centroids, int k, const double *a, int C)
{
    int best = 0;
    double bd = INFINITY;
    for (int j = 0; j < k; j++) {
        double d = dist2(centroids + (size_t)j * (size_t)C, a, C);
        if (d < bd) {
            bd = d;
            best = j;
        }
    }
    return best;
}

/* k-means++ seeding (seeded) and Lloyd iterations on the albedos: k centroids. */
void photo_kmeans(const double *albedo, size_t n, int C, int k, uint64_t seed, double *centroids, int *label)
{
    uint64_t st = seed ^ 0x6b6d65616e73ull;
    double *d = malloc((n ? n : 1) * sizeof *d);
    size_t first = n ? (size_t)(bf_uniform01(&st) * (double)n) : 0;
    memcpy(centroids, albedo + first * (size_t)C, (size_t)C * sizeof *centroids);
    for (int j = 1; j < k; j++) {
        double total = 0.0;
        for (size_t p = 0; p < n; p++) {
            d[p] = dist2(albedo + p * (size_t)C,
                         centroids + (size_t)photo_nearest(centroids, j, albedo + p * (size_t)C, C) * (size_t)C, C);
            total += d[p];
        }
        double u = bf_uniform01(&st) * total, acc = 0.0;
        size_t pick = n - 1;
        for (size_t p = 0; p < n; p++)
            if ((acc += d[p]) > u) {
                pick = p;
                break;
            }
        memcpy(centroids + (size_t)j * (size_t)C, albedo + pick * (size_t)C, (size_t)C * sizeof *centroids);
    }
    free(d);
    double *sum = calloc((size_t)k * (size_t)C, sizeof *sum);
    size_t *cnt = calloc((size_t)k, sizeof *cnt);
    for (int it = 0; it < 50 && sum && cnt; it++) {
        int changed = 0;
        for (size_t p = 0; p < n; p++) {
            int l = photo_nearest(centroids, k, albedo + p * (size_t)C, C);
            changed += l != label[p];
            label[p] = l;
        }
        memset(sum, 0, (size_t)k * (size_t)C * sizeof *sum);
        memset(cnt, 0, (size_t)k * sizeof *cnt);
        for (size_t p = 0; p < n; p++) {
            cnt[label[p]]++;
            for (int c = 0; c < C; c++)
                sum[(size_t)label[p] * (size_t)C + (size_t)c] += albedo[p * (size_t)C + c];
        }
        for (int j = 0; j < k; j++)
            if (cnt[j])
                for (int c = 0; c < C; c++)
                    centroids[(size_t)j * (size_t)C + (size_t)c] =
                        sum[(size_t)j * (size_t)C + (size_t)c] / (double)cnt[j];
        if (!changed && it > 0)
            break;
    }
    free(sum);
    free(cnt);
}

/* The cluster's pixels pooled as BRDF samples at their normals (value / (E n.l), for
 * n.l > 0.1 and v.n > 0), fitted by bf_fit: the cluster's start. */
bf_status photo_cluster_start(photo_run *run, const photo_band *b, const double *normal, const int *label, int cl,
                              double *x, bf_error *err)
{
    const bf_stack *s = run->s;
    int K = s->nimages, C = s->channels;
    /* Two passes: the count, then the samples (a sample set is allocated to its size:
     * its angle arrays are one block). */
    bf_samples *smp = NULL;
    photo_lights pl = {run->lbuf, run->ebuf, {0}};
    size_t members = 0, m = 0;
    for (size_t p = 0; p < b->npix; p++)
        members += label[p] == cl;
    size_t stride = members > POOL_PIXELS ? (members + POOL_PIXELS - 1) / POOL_PIXELS : 1;
    bf_status rc = BF_OK;
    for (int pass = 0; pass < 2 && rc == BF_OK; pass++) {
        if (pass == 1 && (rc = bf_samples_new(m, C, &smp, err)) != BF_OK)
            break;
        m = 0;
        for (size_t p = 0, seen = 0; p < b->npix; p++) {
            if (label[p] != cl || seen++ % stride)
                continue;
            photo_lights_at(s, b->pixel[p] % s->width, b->pixel[p] / s->width, &pl);
            const float *v = b->v + p * (size_t)K * (size_t)C;
            for (int k = 0; k < K; k++) {
                double ang[4];
                if (isnan(v[k * C]) || !photo_local_angles(normal + 3 * p, pl.l + 3 * k, pl.v, ang))
                    continue;
                double nl = cos(ang[0] * M_PI / 180.0);
                if (nl < 0.1)
                    continue;
                if (pass == 1) {
                    smp->theta_i[m] = ang[0];
                    smp->phi_i[m] = ang[1];
                    smp->theta_o[m] = ang[2];
                    smp->phi_o[m] = ang[3];
                    for (int c = 0; c < C; c++)
                        smp->value[m * (size_t)C + (size_t)c] = fmax(v[k * C + c], 0.0) / (pl.e[k * C + c] * nl);
                }
                m++;
            }
        }
    }
    if (rc != BF_OK)
        return rc;
    bf_model_defaults(run->model, x);
    if (m < 16) { /* too few samples: the defaults */
        bf_samples_free(smp);
        return BF_OK;
    }
    bf_fit_options fo;
    bf_fit_options_init(&fo);
    fo.objective.residual = BF_RESIDUAL_COSINE;
    fo.solver.threads = run->threads;
    fo.seed = run->o->seed;
    bf_fit_result fr;
    rc = bf_fit_with(smp, run->spec, &fo, &fr, err);
    if (rc == BF_OK) {
        if (fr.ok)
            memcpy(x, fr.x, (size_t)run->P * sizeof *x);
        bf_fit_result_clear(&fr);
    }
    bf_samples_free(smp);
    return rc;
}
