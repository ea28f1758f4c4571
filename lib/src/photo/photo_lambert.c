/* The Lambertian least-squares baseline and the robust start of the model's fit
 * (photo_impl.h). Grey values g_k = mean_c v_kc / E_kc; b = rho n solves
 * min sum (g_k - b . l_k)^2; the albedo per channel is then the least-squares scale of
 * E_kc max(0, n . l_k). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "photo_impl.h"

/* Solves the 3x3 system A b = r (A symmetric); 0 when singular. */
static int solve3(const double A[9], const double r[3], double b[3])
{
    double c0 = A[4] * A[8] - A[5] * A[7], c1 = A[5] * A[6] - A[3] * A[8], c2 = A[3] * A[7] - A[4] * A[6];
    double det = A[0] * c0 + A[1] * c1 + A[2] * c2;
    double scale = fabs(A[0]) + fabs(A[4]) + fabs(A[8]);
    if (!(fabs(det) > 1e-12 * scale * scale * scale))
        return 0;
    double inv[9] = {c0, A[2] * A[7] - A[1] * A[8], A[1] * A[5] - A[2] * A[4],
                     c1, A[0] * A[8] - A[2] * A[6], A[2] * A[3] - A[0] * A[5],
                     c2, A[1] * A[6] - A[0] * A[7], A[0] * A[4] - A[1] * A[3]};
    for (int i = 0; i < 3; i++)
        b[i] = (inv[3 * i] * r[0] + inv[3 * i + 1] * r[1] + inv[3 * i + 2] * r[2]) / det;
    return 1;
}

static double grey(const float *v, const photo_lights *pl, int k, int C)
{
    double g = 0.0;
    for (int c = 0; c < C; c++)
        g += v[k * C + c] / pl->e[k * C + c];
    return g / C;
}

/* Least squares over the samples with use[k]; n and |b| out. */
static int ls_normal(const float *v, const photo_lights *pl, int K, int C, const unsigned char *use, double n[3])
{
    double A[9] = {0}, r[3] = {0};
    for (int k = 0; k < K; k++) {
        if (!use[k])
            continue;
        const double *l = pl->l + 3 * k;
        double g = grey(v, pl, k, C);
        for (int i = 0; i < 3; i++) {
            r[i] += l[i] * g;
            for (int j = 0; j < 3; j++)
                A[3 * i + j] += l[i] * l[j];
        }
    }
    double b[3];
    if (!solve3(A, r, b))
        return 0;
    double len = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    if (!(len > 0.0))
        return 0;
    for (int i = 0; i < 3; i++)
        n[i] = b[i] / len;
    return 1;
}

static void albedo_at(const float *v, const photo_lights *pl, int K, int C, const unsigned char *use, const double n[3],
                      double *albedo)
{
    for (int c = 0; c < C; c++) {
        double sv = 0.0, ss = 0.0;
        for (int k = 0; k < K; k++) {
            if (!use[k])
                continue;
            const double *l = pl->l + 3 * k;
            double s = pl->e[k * C + c] * fmax(0.0, n[0] * l[0] + n[1] * l[1] + n[2] * l[2]);
            sv += s * v[k * C + c];
            ss += s * s;
        }
        albedo[c] = ss > 0.0 ? M_PI * sv / ss : 0.0;
    }
}

int photo_lambert(const float *v, const photo_lights *pl, int K, int C, double n[3], double *albedo)
{
    unsigned char use[K];
    for (int k = 0; k < K; k++)
        use[k] = !isnan(v[k * C]);
    n[0] = n[1] = 0.0;
    n[2] = 1.0;
    int ok = ls_normal(v, pl, K, C, use, n);
    albedo_at(v, pl, K, C, use, n, albedo);
    return ok;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int photo_lambert_robust(const float *v, const photo_lights *pl, int K, int C, double n[3], double *albedo)
{
    unsigned char use[K];
    double res[K], sorted[K];
    int ok = photo_lambert(v, pl, K, C, n, albedo);
    if (!ok)
        return 0;
    /* Twice: leave out samples in shadow at the current normal, and those far above the
     * Lambertian fit (highlights) by more than 3 robust standard deviations. */
    for (int round = 0; round < 3; round++) {
        double a = 0.0;
        for (int c = 0; c < C; c++)
            a += albedo[c] / C;
        int m = 0;
        for (int k = 0; k < K; k++) {
            const double *l = pl->l + 3 * k;
            double nl = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
            res[k] = NAN;
            if (isnan(v[k * C]) || nl <= 0.05)
                continue;
            res[k] = grey(v, pl, k, C) - a / M_PI * nl;
            sorted[m++] = fabs(res[k]);
        }
        if (m < 4)
            return 1;
        qsort(sorted, (size_t)m, sizeof *sorted, cmp_double);
        double limit = fmax(3.0 * 1.4826 * sorted[m / 2], 0.02 * a / M_PI);
        int used = 0;
        for (int k = 0; k < K; k++) {
            use[k] = !isnan(res[k]) && res[k] <= limit && res[k] >= -4.0 * limit;
            used += use[k];
        }
        double nn[3];
        if (used < 4 || !ls_normal(v, pl, K, C, use, nn))
            return 1;
        memcpy(n, nn, sizeof nn);
        albedo_at(v, pl, K, C, use, n, albedo);
    }
    return 1;
}
