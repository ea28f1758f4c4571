/* Per-sample geometry, computed once per data set and reused by every model
 * evaluation. Structure of arrays so the model loops vectorise. */
#ifndef BRDFIT_GEOMETRY_H
#define BRDFIT_GEOMETRY_H

#include <stddef.h>
#include "brdfit/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Local frame: N = +z, X = +x, Y = +y. L towards the light, V towards the viewer,
 * H = normalize(L + V). A sample is valid (above the horizon) when lz > 0 and vz > 0;
 * models return 0 for the others. */
typedef struct bf_geometry {
    size_t n;
    double *lx, *ly, *lz;   /* L; lz = N.L */
    double *vx, *vy, *vz;   /* V; vz = N.V */
    double *hx, *hy, *hz;   /* H; hz = N.H */
    double *vh;             /* V.H = L.H */
    double *sin2h;          /* hx^2 + hy^2: sin^2(theta_h) without cancellation */
} bf_geometry;

/* Angles in radians. A cosine within 1e-15 of zero is taken as exactly zero, so a
 * direction given as exactly 90 degrees lies on the horizon (f = 0) rather than at
 * cos = 6e-17, where 1/(NL NV) factors would dominate a fit. */
bf_geometry *bf_geometry_from_angles(size_t n, const double *theta_i, const double *phi_i,
                                     const double *theta_o, const double *phi_o,
                                     bf_error *err);

/* L and V as n vectors each, xyz interleaved (3n doubles). They are normalised, and a
 * z within 1e-15 of zero is set to zero (on the horizon), as for angles. */
bf_geometry *bf_geometry_from_vectors(size_t n, const double *L, const double *V,
                                      bf_error *err);

void bf_geometry_free(bf_geometry *g);

static inline int bf_geometry_valid(const bf_geometry *g, size_t i)
{
    return g->lz[i] > 0.0 && g->vz[i] > 0.0;
}

#ifdef __cplusplus
}
#endif
#endif
