/* Per-sample geometry, computed once per data set and reused by every model
 * evaluation. Structure of arrays so the model loops vectorise.
 *
 * A geometry is either stored (every array holds n values) or generated: for a sample
 * set addressed by MERL table cells the vectors of a cell centre cost a few multiplies
 * from a small table, so they are made a block at a time when needed instead of being
 * kept (88 bytes per sample, 97 MB for a full table). Code that reads the arrays takes
 * a block view first (bf_geometry_view); bf_model_eval_range does so itself.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_GEOMETRY_H
#define BRDFIT_GEOMETRY_H

#include <stddef.h>
#include <stdint.h>

#include "brdfit/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Local frame: N = +z, X = +x, Y = +y. L towards the light, V towards the viewer,
 * H = normalize(L + V). A sample is valid (above the horizon) when lz > 0 and vz > 0;
 * models return 0 for the others. */
typedef struct bf_geometry {
    size_t n;
    double *lx, *ly, *lz; /* L; lz = N.L */
    double *vx, *vy, *vz; /* V; vz = N.V */
    double *hx, *hy, *hz; /* H; hz = N.H */
    double *vh;           /* V.H = L.H */
    double *sin2h;        /* hx^2 + hy^2: sin^2(theta_h) without cancellation */
    /* Generated geometry: the arrays are NULL and each sample is a MERL cell (not owned:
     * it must outlive the geometry). NULL for a stored geometry. */
    const int32_t *cell;
} bf_geometry;

/* Angles in radians. A cosine within 1e-15 of zero is taken as exactly zero, so a
 * direction given as exactly 90 degrees lies on the horizon (f = 0) rather than at
 * cos = 6e-17, where 1/(NL NV) factors would dominate a fit. */
BF_API bf_status bf_geometry_from_angles(size_t n, const double *theta_i, const double *phi_i, const double *theta_o,
                                         const double *phi_o, bf_geometry **out, bf_error *err);

/* L and V as n vectors each, xyz interleaved (3n doubles). They are normalised, and a
 * z within 1e-15 of zero is set to zero (on the horizon), as for angles. */
BF_API bf_status bf_geometry_from_vectors(size_t n, const double *L, const double *V, bf_geometry **out, bf_error *err);

/* The geometry of n MERL cell centres (merl.h's convention), generated on demand from
 * cell[] (not copied: it must outlive the geometry). Every cell must be in range. */
BF_API bf_status bf_geometry_from_merl_cells(size_t n, const int32_t *cell, bf_geometry **out, bf_error *err);

BF_API void bf_geometry_free(bf_geometry *g);

/* 1 when the arrays are stored (they may be read directly), 0 when generated. */
static inline int bf_geometry_stored(const bf_geometry *g)
{
    return g->cell == NULL;
}

/* A block view: samples [i0, i0 + cnt) of g as a stored geometry of cnt samples (its
 * sample 0 is sample i0 of g). For a stored g the view points into g and cnt may be
 * anything up to n - i0; for a generated one the block's vectors are computed into
 * b->buf and cnt must be at most BF_GEOMETRY_BLOCK. Returns &b->view. */
#define BF_GEOMETRY_BLOCK 256
/* Frozen (docs/api.md): a view filled by bf_geometry_view in inner loops. */
typedef struct bf_geometry_block {
    bf_geometry view;
    double buf[11 * BF_GEOMETRY_BLOCK];
} bf_geometry_block;
BF_API const bf_geometry *bf_geometry_view(const bf_geometry *g, size_t i0, size_t cnt, bf_geometry_block *b);

/* Valid (above the horizon) for any geometry, one sample at a time; loops over many
 * samples are faster on views with bf_geometry_valid. */
BF_API int bf_geometry_valid_at(const bf_geometry *g, size_t i);

/* Valid (above the horizon) on a stored geometry or a view. */
static inline int bf_geometry_valid(const bf_geometry *g, size_t i)
{
    return g->lz[i] > 0.0 && g->vz[i] > 0.0;
}

#ifdef __cplusplus
}
#endif
#endif
