/* Internal: the 2D interpolants and warps of Dupuy and Jakob 2018 ("An adaptive
 * parameterization for efficient material acquisition and rendering"), on which
 * RGL-EPFL .bsdf materials are stored. A function on [0,1]^2 is given at nx x ny grid
 * nodes (x fastest) and interpolated bilinearly; a stack of such slices is indexed by
 * parameters (the incident angles), between which it is interpolated linearly.
 *
 * A warp is the marginal-conditional inversion of that bilinear density: the sample
 * space point (sx, sy) in [0,1]^2 is (conditional CDF of x given y, marginal CDF of y)
 * of the density at u, each CDF integrated exactly over the bilinear patches (so the
 * map is continuous and invertible, the paper's "continuous" variant). The material's
 * measurements sit at the grid nodes of the sample space of the VNDF warp, so
 * evaluating at a direction needs the warp's inverse (u -> s), and the measured points
 * are the forward warp (s -> u) of those nodes. Computed in double precision. */
#ifndef BF_RGL_WARP_H
#define BF_RGL_WARP_H

#include <stddef.h>

/* The slices a parameter value mixes: up to four (two parameters, two neighbours each),
 * slice index and weight. */
typedef struct bf_rgl_mix {
    int n;
    size_t slice[4];
    double w[4];
} bf_rgl_mix;

typedef struct bf_rgl_warp {
    size_t nx, ny, slices;
    double *data; /* slices * nx * ny; normalised (integral 1 per slice) when cdfs exist */
    double *cond; /* NULL, or the conditional CDF of each row, per slice (unnormalised per row) */
    double *marg; /* NULL, or the marginal CDF of the rows, per slice (ends at 1) */
} bf_rgl_warp;

/* Takes data (slices * nx * ny, owned from then on). with_cdf: normalise each slice and
 * build its CDFs (for sampling and inversion); every slice must then have a positive
 * integral and no negative value. Returns 0, or -1 when a slice cannot be normalised
 * (*bad_slice = its index) or memory is short (*bad_slice = (size_t)-1). */
int bf_rgl_warp_init(bf_rgl_warp *w, size_t nx, size_t ny, size_t slices, double *data, int with_cdf,
                     size_t *bad_slice);
void bf_rgl_warp_clear(bf_rgl_warp *w);

/* Bilinear value at u in [0,1]^2 (clamped), mixed over the slices of m. */
double bf_rgl_warp_eval(const bf_rgl_warp *w, const bf_rgl_mix *m, const double u[2]);
/* Sample space -> domain: s in [0,1]^2 to the position u whose CDFs are s. */
void bf_rgl_warp_sample(const bf_rgl_warp *w, const bf_rgl_mix *m, const double s[2], double u[2]);
/* Domain -> sample space: the inverse of bf_rgl_warp_sample. */
void bf_rgl_warp_invert(const bf_rgl_warp *w, const bf_rgl_mix *m, const double u[2], double s[2]);

/* The mix for value x of a parameter given at n increasing values v[] (n >= 1): the two
 * neighbours and their linear weights, x clamped to the range. Writes index and weight
 * pairs to i[2], wt[2]. */
void bf_rgl_param_weights(const double *v, size_t n, double x, size_t i[2], double wt[2]);

#endif
