/* What every data-reading command can do to a sample set before using it, and what
 * `brdfit info` reports about one.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_PREP_H
#define BRDFIT_PREP_H

#include <stddef.h>
#include <stdint.h>

#include "brdfit/color.h"
#include "brdfit/error.h"
#include "brdfit/samples.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum bf_negative { BF_NEGATIVE_KEEP = 0, BF_NEGATIVE_DROP, BF_NEGATIVE_CLAMP } bf_negative;

/* Zeroed = change nothing but drop what cannot be used (below the horizon, NaN/Inf). */
typedef struct bf_prep {
    const char *channels;  /* keep these channels, in this order: comma-separated names or
                              0-based indices; NULL keeps all */
    int to_bands;          /* spectral -> three band means r, g, b: 600-700, 500-600,
                              400-500 nm (not colorimetric: see color) */
    bf_color color;        /* spectral -> a colour space (brdfit/color.h); NONE: no */
    bf_illuminant illuminant; /* of the colour conversion, or of to_luminance on spectra;
                                 D65 (0) by default */
    int to_luminance;      /* -> one channel: CIE Y of spectra with wavelengths, Rec. 709 of
                              r, g, b, else the mean */
    double max_theta;      /* degrees; > 0 drops samples with theta_i or theta_o above it */
    bf_negative negative;  /* negative values are data by default (KEEP) */
    size_t subsample;      /* > 0: seeded stratified subsample to this many samples */
    uint64_t seed;
} bf_prep;

typedef struct bf_prep_report {
    size_t read;            /* samples before */
    size_t below_horizon;   /* theta_i or theta_o >= 90 degrees: dropped */
    size_t nonfinite;       /* a NaN or Inf value: dropped */
    size_t negative;        /* with a negative value: dropped, clamped or kept per option */
    size_t above_max_theta; /* dropped by max_theta */
    size_t subsampled_out;  /* dropped by subsampling */
    size_t kept;            /* samples after */
} bf_prep_report;

/* Applies p to s in place: channel selection, then to_bands or color, then
 * to_luminance, then the drops, then subsampling. A dropped sample is counted once, under the first of:
 * non-finite, below the horizon, above max_theta, negative (so the negative count
 * describes samples otherwise used). Changing channels
 * drops the MERL origin. report may be NULL. Errors: unknown channel, to_bands without
 * spectral data, color without a wavelength per channel, to_bands with color, an
 * illuminant without color (or to_luminance on spectra), no sample left. */
BF_API bf_status bf_samples_prep(bf_samples *s, const bf_prep *p, bf_prep_report *report, bf_error *err);

/* The seeded stratified subsample of bf_prep.subsample as a mask: keep[i] = 1 for the
 * N samples chosen (N < s->n), 0 for the others; s is not changed. */
BF_API bf_status bf_samples_subsample_mask(const bf_samples *s, size_t N, uint64_t seed, unsigned char *keep, bf_error *err);

/* Seeded folds for K-fold cross-validation (2 <= K <= 255), stratified as the
 * subsample is (theta_h x theta_d strata): each stratum's samples, in order, are dealt
 * to the folds in rounds of K, each round in a fresh random order, so every fold holds
 * a K-th of every stratum (give or take one). fold[i] in [0, K). */
BF_API bf_status bf_samples_folds(const bf_samples *s, int K, uint64_t seed, unsigned char *fold, bf_error *err);

/* ---- What a data set holds (brdfit info) --------------------------------------- */
typedef struct bf_range { double lo, hi; } bf_range;

typedef struct bf_samples_info {
    size_t n;
    int channels;
    bf_range theta_i, theta_o, theta_h, theta_d; /* degrees, over samples above the horizon */
    size_t below_horizon, nonfinite, negative, zero;
    bf_range *value;   /* per channel, over finite values (malloc'd, C entries) */
    double *mean;      /* per channel mean of finite values (malloc'd) */
    int weighted;
} bf_samples_info;

BF_API bf_status bf_samples_describe(bf_samples *s, bf_samples_info *info, bf_error *err);
BF_API void bf_samples_info_clear(bf_samples_info *info);

#ifdef __cplusplus
}
#endif
#endif
