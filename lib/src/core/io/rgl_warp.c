/* Bilinear interpolants and their marginal-conditional warps (rgl_warp.h). */
#include "rgl_warp.h"

#include "base/big_alloc.h"

#include <math.h>
#include <stdlib.h>

static double clamp01(double x)
{
    return x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x;
}

int bf_rgl_warp_init(bf_rgl_warp *w, size_t nx, size_t ny, size_t slices, double *data, int with_cdf, size_t *bad_slice)
{
    w->nx = nx;
    w->ny = ny;
    w->slices = slices;
    w->data = data;
    w->cond = w->marg = NULL;
    *bad_slice = (size_t)-1;
    if (!with_cdf)
        return 0;
    const size_t size = nx * ny;
    w->cond = bf_big_malloc(slices * size * sizeof *w->cond);
    w->marg = bf_big_malloc(slices * ny * sizeof *w->marg);
    if (!w->cond || !w->marg)
        return -1;
    for (size_t s = 0; s < slices; s++) {
        double *d = data + s * size, *cond = w->cond + s * size, *marg = w->marg + s * ny;
        for (size_t i = 0; i < size; i++)
            if (!(d[i] >= 0.0)) {
                *bad_slice = s;
                return -1;
            }
        /* Trapezoids: the exact integral of the linear interpolant along each row, and
         * of the rows' integrals (linear in y along a patch) down the rows. */
        for (size_t y = 0; y < ny; y++) {
            const double *r = d + y * nx;
            double *c = cond + y * nx;
            c[0] = 0.0;
            for (size_t x = 0; x + 1 < nx; x++)
                c[x + 1] = c[x] + 0.5 * (r[x] + r[x + 1]);
        }
        marg[0] = 0.0;
        for (size_t y = 0; y + 1 < ny; y++)
            marg[y + 1] = marg[y] + 0.5 * (cond[y * nx + nx - 1] + cond[(y + 1) * nx + nx - 1]);
        const double total = marg[ny - 1];
        if (!(total > 0.0) || !isfinite(total)) {
            *bad_slice = s;
            return -1;
        }
        for (size_t i = 0; i < size; i++) {
            cond[i] /= total;
            d[i] /= total;
        }
        for (size_t y = 0; y < ny; y++)
            marg[y] /= total;
    }
    return 0;
}

void bf_rgl_warp_clear(bf_rgl_warp *w)
{
    free(w->data);
    free(w->cond);
    free(w->marg);
    w->data = w->cond = w->marg = NULL;
}

/* Value i of one slice-sized array (data or cond), mixed over the slices. */
static double mixed(const double *a, size_t slice_size, const bf_rgl_mix *m, size_t i)
{
    double v = 0.0;
    for (int k = 0; k < m->n; k++)
        v += m->w[k] * a[m->slice[k] * slice_size + i];
    return v;
}

/* The patch holding coordinate u (in [0,1]) of an axis with n nodes, and the position
 * inside it. */
static size_t patch_of(double u, size_t n, double *t)
{
    const double p = clamp01(u) * (double)(n - 1);
    size_t i = (size_t)p;
    if (i > n - 2)
        i = n - 2;
    *t = p - (double)i;
    return i;
}

double bf_rgl_warp_eval(const bf_rgl_warp *w, const bf_rgl_mix *m, const double u[2])
{
    double tx, ty;
    const size_t x = patch_of(u[0], w->nx, &tx), y = patch_of(u[1], w->ny, &ty);
    const size_t size = w->nx * w->ny, i = y * w->nx + x;
    const double v00 = mixed(w->data, size, m, i), v10 = mixed(w->data, size, m, i + 1),
                 v01 = mixed(w->data, size, m, i + w->nx), v11 = mixed(w->data, size, m, i + w->nx + 1);
    return (1.0 - ty) * ((1.0 - tx) * v00 + tx * v10) + ty * ((1.0 - tx) * v01 + tx * v11);
}

/* The t in [0,1] with t (a + t (b - a) / 2) = s: where the integral of the linear
 * density from a to b over a unit patch reaches s. The form without a difference of
 * square roots is exact for a == b and stable when a and b nearly agree; a zero density
 * (a = b = 0) has nothing to invert and gives 0. */
static double invert_linear(double a, double b, double s)
{
    const double disc = a * a + 2.0 * s * (b - a);
    const double den = a + sqrt(disc > 0.0 ? disc : 0.0);
    const double t = den > 0.0 ? 2.0 * s / den : 0.0;
    return t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
}

/* The last index i in [0, n - 2] with f(i) < x (0 when none): the patch whose CDF range
 * holds x. The CDFs never decrease, so a bisection finds it. */
typedef double (*cdf_at)(const bf_rgl_warp *w, const bf_rgl_mix *m, size_t row, double ty, size_t i);

static double marg_at(const bf_rgl_warp *w, const bf_rgl_mix *m, size_t row, double ty, size_t i)
{
    (void)row;
    (void)ty;
    return mixed(w->marg, w->ny, m, i);
}

static double cond_at(const bf_rgl_warp *w, const bf_rgl_mix *m, size_t row, double ty, size_t i)
{
    const size_t size = w->nx * w->ny;
    return (1.0 - ty) * mixed(w->cond, size, m, row * w->nx + i) + ty * mixed(w->cond, size, m, (row + 1) * w->nx + i);
}

static size_t find_patch(const bf_rgl_warp *w, const bf_rgl_mix *m, size_t n, cdf_at f, size_t row, double ty, double x)
{
    size_t lo = 0, hi = n - 2; /* the answer is in [lo, hi] */
    while (lo < hi) {
        const size_t mid = lo + (hi - lo + 1) / 2;
        if (f(w, m, row, ty, mid) < x)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

void bf_rgl_warp_sample(const bf_rgl_warp *w, const bf_rgl_mix *m, const double s_in[2], double u[2])
{
    const size_t size = w->nx * w->ny;
    double sx = clamp01(s_in[0]), sy = clamp01(s_in[1]);
    /* The row: the marginal CDF, then the position inside the patch, where the rows'
     * integral is linear from r0 to r1. */
    const size_t row = find_patch(w, m, w->ny, marg_at, 0, 0.0, sy);
    sy -= mixed(w->marg, w->ny, m, row);
    const double r0 = mixed(w->cond, size, m, row * w->nx + w->nx - 1),
                 r1 = mixed(w->cond, size, m, (row + 1) * w->nx + w->nx - 1);
    const double ty = invert_linear(r0, r1, sy);
    /* The column: the conditional CDF of the row interpolated at ty. */
    sx *= (1.0 - ty) * r0 + ty * r1;
    const size_t col = find_patch(w, m, w->nx, cond_at, row, ty, sx);
    sx -= cond_at(w, m, row, ty, col);
    const size_t i = row * w->nx + col;
    const double c0 = (1.0 - ty) * mixed(w->data, size, m, i) + ty * mixed(w->data, size, m, i + w->nx),
                 c1 = (1.0 - ty) * mixed(w->data, size, m, i + 1) + ty * mixed(w->data, size, m, i + w->nx + 1);
    const double tx = invert_linear(c0, c1, sx);
    u[0] = ((double)col + tx) / (double)(w->nx - 1);
    u[1] = ((double)row + ty) / (double)(w->ny - 1);
}

void bf_rgl_warp_invert(const bf_rgl_warp *w, const bf_rgl_mix *m, const double u[2], double s[2])
{
    const size_t size = w->nx * w->ny;
    double tx, ty;
    const size_t col = patch_of(u[0], w->nx, &tx), row = patch_of(u[1], w->ny, &ty);
    const size_t i = row * w->nx + col;
    const double c0 = (1.0 - ty) * mixed(w->data, size, m, i) + ty * mixed(w->data, size, m, i + w->nx),
                 c1 = (1.0 - ty) * mixed(w->data, size, m, i + 1) + ty * mixed(w->data, size, m, i + w->nx + 1);
    const double r0 = mixed(w->cond, size, m, row * w->nx + w->nx - 1),
                 r1 = mixed(w->cond, size, m, (row + 1) * w->nx + w->nx - 1);
    const double row_total = (1.0 - ty) * r0 + ty * r1;
    const double x = cond_at(w, m, row, ty, col) + tx * (c0 + 0.5 * tx * (c1 - c0));
    s[0] = row_total > 0.0 ? clamp01(x / row_total) : 0.0;
    s[1] = clamp01(mixed(w->marg, w->ny, m, row) + ty * (r0 + 0.5 * ty * (r1 - r0)));
}

void bf_rgl_param_weights(const double *v, size_t n, double x, size_t i[2], double wt[2])
{
    if (n < 2) {
        i[0] = i[1] = 0;
        wt[0] = 1.0;
        wt[1] = 0.0;
        return;
    }
    size_t lo = 0, hi = n - 2; /* the last interval whose start is <= x */
    while (lo < hi) {
        const size_t mid = lo + (hi - lo + 1) / 2;
        if (v[mid] <= x)
            lo = mid;
        else
            hi = mid - 1;
    }
    double t = (x - v[lo]) / (v[lo + 1] - v[lo]);
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    i[0] = lo;
    i[1] = lo + 1;
    wt[0] = 1.0 - t;
    wt[1] = t;
}
