#include "brdfit/geometry.h"

#include <math.h>
#include <stdlib.h>

#include "big_alloc.h"
#include "io/merl_cells.h"

enum { NFIELDS = 11 };

static bf_status alloc_geometry(size_t n, bf_geometry **out, bf_error *err)
{
    bf_geometry *g = calloc(1, sizeof *g);
    /* One block for all fields; +1 so n = 0 still gets a valid pointer. */
    double *block = g ? bf_big_malloc((NFIELDS * n + 1) * sizeof *block) : NULL;
    if (!g || !block) {
        free(g);
        free(block);
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for the geometry of %zu samples", n);
    }
    double **fields[NFIELDS] = {&g->lx, &g->ly, &g->lz, &g->vx, &g->vy,   &g->vz,
                                &g->hx, &g->hy, &g->hz, &g->vh, &g->sin2h};
    for (int f = 0; f < NFIELDS; f++)
        *fields[f] = block + (size_t)f * n;
    g->n = n;
    *out = g;
    return BF_OK;
}

/* Fills H, V.H and sin^2(theta_h) for sample i from L and V already stored. */
static void half_vector(bf_geometry *g, size_t i)
{
    double x = g->lx[i] + g->vx[i], y = g->ly[i] + g->vy[i], z = g->lz[i] + g->vz[i];
    double len = sqrt(x * x + y * y + z * z);
    if (len > 0.0) {
        x /= len;
        y /= len;
        z /= len;
    } else { /* L = -V: only possible on the horizon, where every model returns 0 */
        x = y = 0.0;
        z = 1.0;
    }
    g->hx[i] = x;
    g->hy[i] = y;
    g->hz[i] = z;
    /* V.H = |L + V| / 2 for unit L and V. The dot product V.normalize(L + V) loses
     * digits when L is nearly -V in x, y (grazing mirror pairs: 1e-7 relative at 89.999
     * degrees), where the leftovers of Lx + Vx meet |V| = 1. */
    g->vh[i] = 0.5 * len;
    g->sin2h[i] = x * x + y * y;
}

/* A cosine within 1e-15 of zero is the horizon (see geometry.h). */
static double horizon(double c)
{
    return fabs(c) < 1e-15 ? 0.0 : c;
}

bf_status bf_geometry_from_angles(size_t n, const double *theta_i, const double *phi_i, const double *theta_o,
                                  const double *phi_o, bf_geometry **out, bf_error *err)
{
    *out = NULL;
    bf_geometry *g;
    bf_status rc = alloc_geometry(n, &g, err);
    if (rc != BF_OK)
        return rc;
    for (size_t i = 0; i < n; i++) {
        double si = sin(theta_i[i]), so = sin(theta_o[i]);
        g->lx[i] = si * cos(phi_i[i]);
        g->ly[i] = si * sin(phi_i[i]);
        g->lz[i] = horizon(cos(theta_i[i]));
        g->vx[i] = so * cos(phi_o[i]);
        g->vy[i] = so * sin(phi_o[i]);
        g->vz[i] = horizon(cos(theta_o[i]));
        half_vector(g, i);
    }
    *out = g;
    return BF_OK;
}

bf_status bf_geometry_from_vectors(size_t n, const double *L, const double *V, bf_geometry **out, bf_error *err)
{
    *out = NULL;
    for (size_t i = 0; i < n; i++) {
        double ll = L[3 * i] * L[3 * i] + L[3 * i + 1] * L[3 * i + 1] + L[3 * i + 2] * L[3 * i + 2];
        double vv = V[3 * i] * V[3 * i] + V[3 * i + 1] * V[3 * i + 1] + V[3 * i + 2] * V[3 * i + 2];
        if (!(ll > 0.0) || !(vv > 0.0) || !isfinite(ll) || !isfinite(vv))
            return bf_fail(err, BF_ERR_RANGE, "sample %zu: direction is zero, NaN or Inf", i);
    }
    bf_geometry *g;
    bf_status rc = alloc_geometry(n, &g, err);
    if (rc != BF_OK)
        return rc;
    for (size_t i = 0; i < n; i++) {
        double il = 1.0 / sqrt(L[3 * i] * L[3 * i] + L[3 * i + 1] * L[3 * i + 1] + L[3 * i + 2] * L[3 * i + 2]);
        double iv = 1.0 / sqrt(V[3 * i] * V[3 * i] + V[3 * i + 1] * V[3 * i + 1] + V[3 * i + 2] * V[3 * i + 2]);
        g->lx[i] = L[3 * i] * il;
        g->ly[i] = L[3 * i + 1] * il;
        g->lz[i] = horizon(L[3 * i + 2] * il);
        g->vx[i] = V[3 * i] * iv;
        g->vy[i] = V[3 * i + 1] * iv;
        g->vz[i] = horizon(V[3 * i + 2] * iv);
        half_vector(g, i);
    }
    *out = g;
    return BF_OK;
}

bf_status bf_geometry_from_merl_cells(size_t n, const int32_t *cell, bf_geometry **out, bf_error *err)
{
    *out = NULL;
    for (size_t i = 0; i < n; i++)
        if (cell[i] < 0 || cell[i] >= BF_MERL_CELLS)
            return bf_fail(err, BF_ERR_RANGE, "sample %zu: MERL cell %ld is out of range", i, (long)cell[i]);
    bf_geometry *g = calloc(1, sizeof *g);
    if (!g)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for a geometry");
    g->n = n;
    g->cell = cell;
    *out = g;
    return BF_OK;
}

void bf_geometry_free(bf_geometry *g)
{
    if (g) {
        free(g->lx);
        free(g);
    }
}

/* Points v's 11 arrays at field[f] + i0, in the struct's order. */
static void point_fields(bf_geometry *v, double *const field[11], size_t i0)
{
    double **dst[11] = {&v->lx, &v->ly, &v->lz, &v->vx, &v->vy, &v->vz, &v->hx, &v->hy, &v->hz, &v->vh, &v->sin2h};
    for (int f = 0; f < 11; f++)
        *dst[f] = field[f] + i0;
}

const bf_geometry *bf_geometry_view(const bf_geometry *g, size_t i0, size_t cnt, bf_geometry_block *b)
{
    bf_geometry *v = &b->view;
    v->n = cnt;
    v->cell = NULL;
    if (bf_geometry_stored(g)) {
        double *const field[11] = {g->lx, g->ly, g->lz, g->vx, g->vy, g->vz, g->hx, g->hy, g->hz, g->vh, g->sin2h};
        point_fields(v, field, i0);
        return v;
    }
    double *field[11];
    for (int f = 0; f < 11; f++)
        field[f] = b->buf + (size_t)f * BF_GEOMETRY_BLOCK;
    point_fields(v, field, 0);
    /* bf_merl_cell_vectors, with the (theta_h, theta_d) row's sines and cosines kept:
     * the samples of a table run through phi_d within a row. */
    const bf_merl_trig *t = bf_merl_trig_get();
    int32_t row = -1;
    double sth = 0.0, cth = 1.0, std_ = 0.0, ctd = 1.0;
    for (size_t j = 0; j < cnt; j++) {
        const int32_t cell = g->cell[i0 + j], r = cell / BF_MERL_PD, k = cell - r * BF_MERL_PD;
        if (r != row) {
            const int jd = r % BF_MERL_TD, ih = r / BF_MERL_TD;
            sth = t->sth[ih], cth = t->cth[ih], std_ = t->std_[jd], ctd = t->ctd[jd];
            row = r;
        }
        double L[3], V[3];
        bf_merl_centre_lv(sth, cth, std_, ctd, t->spd[k], t->cpd[k], L, V);
        v->lx[j] = L[0], v->ly[j] = L[1], v->lz[j] = L[2];
        v->vx[j] = V[0], v->vy[j] = V[1], v->vz[j] = V[2];
        v->hx[j] = sth, v->hy[j] = 0.0, v->hz[j] = cth;
        v->vh[j] = ctd;
        v->sin2h[j] = sth * sth;
    }
    return v;
}

int bf_geometry_valid_at(const bf_geometry *g, size_t i)
{
    if (bf_geometry_stored(g))
        return bf_geometry_valid(g, i);
    double L[3], V[3], H[3], vh, sin2h;
    bf_merl_cell_vectors(bf_merl_trig_get(), g->cell[i], L, V, H, &vh, &sin2h);
    return L[2] > 0.0 && V[2] > 0.0;
}
