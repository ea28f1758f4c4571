/* The synthetic data generator: a model sampled at a chosen direction pattern, with
 * optional noise, into a bf_samples that the ordinary writers save (CSV or MERL).
 * Everything random comes from one seeded generator, so the same seed gives the same
 * bytes (on one platform: the patterns go through the C library's acos, log, ...). */
#ifndef BRDFIT_SYNTH_H
#define BRDFIT_SYNTH_H

#include <stddef.h>
#include <stdint.h>

#include "brdfit/error.h"
#include "brdfit/model.h"
#include "brdfit/samples.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- Random numbers (rng.c) --------------------------------------------------------
 * xoshiro256** (Blackman and Vigna, 2018), its state filled by splitmix64 from the
 * seed; normals by the Marsaglia polar method; Poisson counts by Knuth's product method
 * below a mean of 10, by PTRS (Hoermann 1993, transformed rejection with squeeze)
 * up to 1e9, and above that by round(mean + sqrt(mean) N(0,1)), whose skewness
 * (1/sqrt(mean) < 3e-5) no fit can see. */
typedef struct bf_synth_rng {
    uint64_t s[4];
    double spare; /* the polar method makes normals in pairs */
    int has_spare;
} bf_synth_rng;

void bf_synth_rng_seed(bf_synth_rng *r, uint64_t seed);
/* Advances by 2^128 draws: a second stream that never overlaps the first. */
void bf_synth_rng_jump(bf_synth_rng *r);
uint64_t bf_synth_next(bf_synth_rng *r);
double bf_synth_uniform(bf_synth_rng *r);              /* [0, 1), 53 bits */
uint64_t bf_synth_below(bf_synth_rng *r, uint64_t n);  /* uniform in [0, n), unbiased; n >= 1 */
double bf_synth_normal(bf_synth_rng *r);               /* N(0, 1) */
double bf_synth_poisson(bf_synth_rng *r, double mean); /* a count, as a double; mean <= 0: 0 */

/* ---- Direction patterns (patterns.c) ----------------------------------------------- */
typedef enum bf_synth_pattern {
    BF_SYNTH_UNIFORM = 0, /* uniform in solid angle over each hemisphere */
    BF_SYNTH_COSINE,      /* cosine-weighted (pdf cos(theta)/pi) for each direction */
    BF_SYNTH_STRATIFIED,  /* jittered strata in (cos theta, phi) for each direction */
    BF_SYNTH_RANDOM,      /* uniform in the angles theta in [0, 90), phi in [0, 360) */
    BF_SYNTH_GONIO,       /* in-plane and out-of-plane sweeps per incidence angle */
    BF_SYNTH_MERL,        /* MERL cell centres above the horizon */
} bf_synth_pattern;

/* "uniform", "cosine", ...: a bf_synth_pattern, or -1. */
int bf_synth_pattern_from_name(const char *name);
const char *bf_synth_pattern_name(bf_synth_pattern p);
/* Patterns whose sample count is fixed by their own settings (gonio, merl). */
int bf_synth_pattern_fixed_count(bf_synth_pattern p);

/* Gonio settings: incidence angles in [0, 90) degrees, step in (0, 90] degrees.
 * For each incidence theta_i (phi_i = 0), in this order:
 *  - in-plane: the detector crosses the plane of incidence from the back-scatter
 *    horizon to the forward one: signed angles t = -K step, ..., 0, ..., K step
 *    (K step < 90), theta_o = |t|, phi_o = 0 for t <= 0 and 180 for t > 0 (the mirror
 *    direction is at phi_o = 180);
 *  - out-of-plane (theta_i > 0 only): the detector circles the normal on the cone
 *    through the mirror direction, theta_o = theta_i, phi_o = j step for j = 0, 1, ...
 *    while j step < 360, leaving out phi_o = 0 and 180 when theta_i is itself an in-plane
 *    angle (K' step == theta_i), so that no direction pair is listed twice. */
typedef struct bf_synth_gonio {
    const double *incidence;
    int n_incidence;
    double step;
} bf_synth_gonio;

/* Samples the gonio pattern makes, or 0 for invalid settings. */
size_t bf_synth_gonio_count(const bf_synth_gonio *g);

/* How the stratified pattern splits N: N = dims[0] * dims[1] * dims[2] * dims[3] strata
 * (one sample each) over cos theta_i, phi_i, cos theta_o, phi_o. N's prime factors are
 * dealt out, largest first, to the dimension with the fewest strata so far, and the two
 * largest counts go to the azimuths (which span 2 pi against 1 for cos theta). So
 * N = m^4 gives m strata in each dimension, 1000 gives 5 x 8 x 5 x 5, and a prime N
 * stratifies phi_i alone: choose N with small factors. */
void bf_synth_strata(size_t n, size_t dims[4]);

/* The pattern's direction pairs (degrees) in a new sample set of `channels` channels,
 * values zero. count: for uniform, cosine, stratified and random (>= 1); ignored for
 * gonio and merl. gonio: for BF_SYNTH_GONIO. Every pair is above the horizon. */
bf_status bf_synth_directions(bf_synth_pattern p, size_t count, const bf_synth_gonio *gonio, bf_synth_rng *r,
                              int channels, bf_samples **out, bf_error *err);

/* ---- Noise (noise.c) ---------------------------------------------------------------
 * Applied per value v, in this order:
 *  1. the noise model: relative v (1 + s N(0,1)); additive v + s N(0,1);
 *     photon Poisson(k max(v, 0)) / k (variance v / k: relative noise 1 / sqrt(k v));
 *  2. outliers: exactly round(fraction n) samples, chosen uniformly without replacement
 *     (Floyd's algorithm), have every channel replaced: by v * factor when factor > 0,
 *     else by u * vmax with u uniform in [0, 1) drawn per channel and vmax the largest
 *     value of that channel after step 1 (glints and dropouts of any size);
 *  3. clamping: negative values set to 0 when clamp is set. */
typedef enum bf_synth_noise_model {
    BF_NOISE_NONE = 0,
    BF_NOISE_RELATIVE,
    BF_NOISE_ADDITIVE,
    BF_NOISE_PHOTON,
} bf_synth_noise_model;

typedef struct bf_synth_noise {
    bf_synth_noise_model model;
    double level;            /* s, for relative and additive (>= 0) */
    double counts;           /* k, counts per unit value, for photon (> 0) */
    double outlier_fraction; /* in [0, 1] */
    double outlier_factor;   /* > 0: multiply; 0: random */
    int clamp;
} bf_synth_noise;

int bf_synth_noise_model_from_name(const char *name); /* "none", "relative", ...; -1 if unknown */
const char *bf_synth_noise_model_name(bf_synth_noise_model m);

/* BF_ERR_ARG naming the setting when one is out of range. */
bf_status bf_synth_noise_check(const bf_synth_noise *nz, bf_error *err);
/* BF_ERR_RANGE if a value comes out NaN or Inf (a level or factor near DBL_MAX); photon
 * counts whose mean k v overflows leave v as it is (the limit of infinite counts). */
bf_status bf_synth_noise_apply(bf_samples *s, const bf_synth_noise *nz, bf_synth_rng *r, bf_error *err);

/* ---- The whole job (synth.c) -------------------------------------------------------- */
typedef struct bf_synth_options {
    bf_synth_pattern pattern;
    size_t count; /* see bf_synth_directions */
    bf_synth_gonio gonio;
    uint64_t seed;
    bf_synth_noise noise; /* zeroed: no noise */
} bf_synth_options;

/* Directions from the generator seeded with o->seed; values by bf_model_eval; noise from
 * a second stream (the seed's stream jumped), so the same seed gives the same directions
 * with or without noise. For merl: the model must have 3 channels, and clamping is
 * always on, since a negative value marks a cell invalid in a MERL table. */
bf_status bf_synth_generate(const bf_model *m, const double *x, const bf_synth_options *o, bf_samples **out,
                            bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
