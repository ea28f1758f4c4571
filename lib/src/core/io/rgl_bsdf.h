/* Internal: RGL-EPFL measured materials (.bsdf, Dupuy and Jakob 2018), evaluated at any
 * pair of directions as the paper's parameterization defines them, and the directions
 * of their measured points. The reader (bf_samples_read_rgl) is built on this; tests
 * check the evaluation against the stored values.
 *
 * Directions are unit vectors in the local frame (z = normal). wi is the direction the
 * material's tables are conditioned on (the paper's incident direction: the tables are
 * indexed by its elevation), wo the other one. */
#ifndef BF_RGL_BSDF_H
#define BF_RGL_BSDF_H

#include <stddef.h>

#include "brdfit/error.h"
#include "rgl_warp.h"

typedef struct bf_rgl_bsdf {
    size_t n_theta;         /* incident elevations measured */
    double *theta_i;        /* n_theta, radians, increasing */
    double phi_i;           /* the one incident azimuth (isotropic), radians */
    int channels;           /* 3 (rgb) or the wavelengths (spectra) */
    double *wavelength;     /* NULL (rgb), or channels wavelengths in nm */
    int jacobian;           /* the stored values are divided by the sampling density */
    bf_rgl_warp ndf, sigma; /* D(theta_m) and projected area sigma(theta_i): plain interpolants */
    bf_rgl_warp vndf;       /* the visible-normal warp, one slice per incident elevation */
    bf_rgl_warp values;     /* the measurements: one slice per (elevation, channel) */
} bf_rgl_bsdf;

/* Reads and checks a file ("PATH: problem" errors; anisotropic files are refused). */
bf_status bf_rgl_bsdf_read(const char *path, bf_rgl_bsdf *b, bf_error *err);
void bf_rgl_bsdf_clear(bf_rgl_bsdf *b);

/* The BRDF (1/sr) per channel at wi, wo; 0 where either is not above the horizon.
 * stored (may be NULL): the interpolated table values themselves, before the factor
 * D / (4 sigma cos theta_o) that makes them a BRDF. */
void bf_rgl_bsdf_eval(const bf_rgl_bsdf *b, const double wi[3], const double wo[3], double *f, double *stored);

/* The directions of measured point (k, x, y): incident elevation k, node (x, y) of the
 * nx x ny sample-space grid (b->values.nx, .ny), and (f not NULL) the BRDF from the
 * values stored at the node. Returns 0 when wo is above the horizon, -1 when the point
 * lies below it or within 1e-6 of it in cosine (not a sample: the BRDF there is the
 * stored value divided by cos(theta_o) = 0; f is then not set). */
int bf_rgl_bsdf_point(const bf_rgl_bsdf *b, size_t k, size_t x, size_t y, double wi[3], double wo[3], double *f);

#endif
