/* Preparing samples, inside the library: the preprocessing part of the run options
 * (brdfit/options.h) as bf_samples_prep takes it, and what it reports (bf_samples_load
 * and bf_samples_prepare are the public way in). */
#ifndef BRDFIT_PREP_OPTIONS_H
#define BRDFIT_PREP_OPTIONS_H

#include "brdfit/prep.h"

/* Zeroed = change nothing but drop what cannot be used (below the horizon, NaN/Inf). */
typedef struct bf_prep {
    const char *channels;     /* keep these channels, in this order: comma-separated names or
                              0-based indices; NULL keeps all */
    int to_bands;             /* spectral -> three band means r, g, b: 600-700, 500-600,
                              400-500 nm (not colorimetric: see color) */
    bf_color color;           /* spectral -> a colour space (brdfit/color.h); NONE: no */
    bf_illuminant illuminant; /* of the colour conversion, or of to_luminance on spectra;
                                 D65 (0) by default */
    int to_luminance;         /* -> one channel: CIE Y of spectra with wavelengths, Rec. 709 of
                              r, g, b, else the mean */
    double max_theta;         /* degrees; > 0 drops samples with theta_i or theta_o above it */
    bf_negative negative;     /* negative values are data by default (KEEP) */
    size_t subsample;         /* > 0: seeded stratified subsample to this many samples */
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
bf_status bf_samples_prep(bf_samples *s, const bf_prep *p, bf_prep_report *report, bf_error *err);

#endif
