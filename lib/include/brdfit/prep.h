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

/* The seeded stratified subsample (the option subsample) as a mask: keep[i] = 1 for the
 * N samples chosen (N < s->n), 0 for the others; s is not changed. */
BF_API bf_status bf_samples_subsample_mask(const bf_samples *s, size_t N, uint64_t seed, unsigned char *keep,
                                           bf_error *err);

/* Seeded folds for K-fold cross-validation (2 <= K <= 255), stratified as the
 * subsample is (theta_h x theta_d strata): each stratum's samples, in order, are dealt
 * to the folds in rounds of K, each round in a fresh random order, so every fold holds
 * a K-th of every stratum (give or take one). fold[i] in [0, K). */
BF_API bf_status bf_samples_folds(const bf_samples *s, int K, uint64_t seed, unsigned char *fold, bf_error *err);

/* ---- What a data set holds (brdfit info) --------------------------------------- */
/* Frozen (docs/api.md): a small value. */
typedef struct bf_range {
    double lo, hi;
} bf_range;

/* What a data set holds. The caller sets it up with bf_samples_info_init (its size:
 * docs/api.md), bf_samples_describe fills it, bf_samples_info_clear frees its arrays. */
typedef struct bf_samples_info {
    size_t size; /* sizeof, set by bf_samples_info_init */
    size_t n;
    int channels;
    bf_range theta_i, theta_o, theta_h, theta_d; /* degrees, over samples above the horizon */
    size_t below_horizon, nonfinite, negative, zero;
    bf_range *value; /* per channel, over finite values (malloc'd, C entries) */
    double *mean;    /* per channel mean of finite values (malloc'd) */
    int weighted;
} bf_samples_info;

BF_API bf_status bf_samples_describe(bf_samples *s, bf_samples_info *info, bf_error *err);
BF_API void bf_samples_info_clear(bf_samples_info *info);
BF_API void bf_samples_info_init_size(bf_samples_info *info, size_t size);
static inline void bf_samples_info_init(bf_samples_info *info)
{
    bf_samples_info_init_size(info, sizeof *info);
}

#ifdef __cplusplus
}
#endif
#endif
