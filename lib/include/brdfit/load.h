/* Reading a data file and preparing its samples in one call, as every command does:
 * read (the reading options), preprocess (channels, colour, drops), keep and weight the
 * samples a scene uses, then subsample, in that order, so that a subsample of N gives N
 * samples inside the scene (docs/api.md).
 * Status codes and ownership follow brdfit/error.h. */
#ifndef BRDFIT_LOAD_H
#define BRDFIT_LOAD_H

#include <stddef.h>

#include "brdfit/error.h"
#include "brdfit/options.h"
#include "brdfit/samples.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What loading left out, and why: what `brdfit info` prints. A sample dropped for
 * several reasons counts once, under the first of non-finite, below the horizon, above
 * max_theta, negative (so negative counts samples otherwise used). Callers set size
 * (bf_load_report_init); the library fills what fits in it (docs/api.md). */
typedef struct bf_load_report {
    size_t size;
    size_t read;            /* samples in the file */
    int channels_read;      /* channels in the file */
    size_t below_horizon;   /* theta_i or theta_o >= 90 degrees: dropped */
    size_t nonfinite;       /* a NaN or Inf value: dropped */
    size_t negative;        /* with a negative value: dropped, clamped or kept (option negative) */
    size_t above_max_theta; /* dropped by max_theta */
    int scene;              /* 1: a scene was applied */
    size_t scene_in;        /* samples the scene was given (after the drops) */
    size_t scene_kept;      /* of them, those its lights and views use */
    size_t subsampled_out;  /* dropped by subsampling */
    size_t kept;            /* samples loaded */
} bf_load_report;

BF_API void bf_load_report_init_size(bf_load_report *r, size_t size);
static inline void bf_load_report_init(bf_load_report *r)
{
    bf_load_report_init_size(r, sizeof *r);
}

/* Reads path (any format bf_samples_read takes; "-": standard input) with o's reading
 * options, and prepares the samples with its preprocessing options and scene, into *out
 * (freed with bf_samples_free). report may be NULL. Errors name the file (and line) or
 * the scene file, and the problem; nothing is printed.
 * Cancelling: o's cancel flag (bf_options_set_cancel) is read between the steps and, in
 * the readers of files that take long (CSV, MERL tables, Cornell, ALTA), at every line
 * or chunk; once it is set the load stops with BF_ERR_CANCELLED ("PATH: reading
 * cancelled", or "PATH: cancelled" between steps) and *out stays NULL. */
BF_API bf_status bf_samples_load(const char *path, const bf_options *o, bf_samples **out, bf_load_report *report,
                                 bf_error *err);

/* The same preparation applied to samples already in memory (a program's own, or a set
 * loaded before), in place: preprocessing, the scene, then the subsample. The reading
 * options play no part. Messages name the samples "samples". o's cancel flag is read
 * between the steps (BF_ERR_CANCELLED; s is then partly prepared, as after any error). */
BF_API bf_status bf_samples_prepare(bf_samples *s, const bf_options *o, bf_load_report *report, bf_error *err);

/* What `brdfit info` prints about samples loaded from path (the name the report gives
 * the file) with the options o (NULL: the defaults) and their load report: JSON (`brdfit
 * info --json`: the file, samples read and used, channels, wavelengths, weights, what
 * the preprocessing dropped and what the option negative did, the scene, angle coverage,
 * counts and value ranges per channel, as bf_samples_describe gives them) or the text
 * (the same in words: the wavelength range, the negatives "dropped", "clamped to 0" or
 * "kept", a subsample that kept every sample). Each ends with a newline; *out is freed
 * with bf_free. Errors name path. */
BF_API bf_status bf_samples_info_json(bf_samples *s, const bf_load_report *report, const bf_options *o,
                                      const char *path, char **out, bf_error *err);
BF_API bf_status bf_samples_info_text(bf_samples *s, const bf_load_report *report, const bf_options *o,
                                      const char *path, char **out, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
