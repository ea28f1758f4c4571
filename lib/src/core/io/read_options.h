/* How files are read, inside the library: the reading part of the run options
 * (brdfit/options.h) as the readers take it, and the reader dispatch and the CSV reader
 * that take it. */
#ifndef BRDFIT_READ_OPTIONS_H
#define BRDFIT_READ_OPTIONS_H

#include "brdfit/error.h"
#include "brdfit/formats.h"
#include "brdfit/io.h"

/* How a CSV maps onto samples. Zeroed = the defaults (docs/formats.md, CSV). */
typedef struct bf_csv_map {
    const char *angle_cols[4]; /* theta_i, phi_i, theta_o, phi_o column names (NULL: those names) */
    int radians;               /* angles in radians instead of degrees */
    const char *channels;      /* comma-separated channel columns; NULL: every column but the
                                  angles and the weight */
    const char *weight_col;    /* NULL: "weight" if present */
} bf_csv_map;

typedef struct bf_read_options {
    bf_format format;
    bf_csv_map csv;
    int keep_origin;  /* keep what writing the file back byte for byte needs (MERL: the raw
                        table, 35 MB); only a command that writes the format back asks */
    const char *grid; /* NULL: the file's own measured points. Else the directions at which
                         to evaluate a format that can be evaluated anywhere (RGL, mbsdf):
                         "merl" (MERL cell centres above the horizon), "uniform:N" (N^3:
                         theta_i, theta_o, phi_o - phi_i at cell centres), or a CSV file of
                         theta_i,phi_i,theta_o,phi_o in degrees (docs/formats.md) */
    /* NULL, or the caller's cancel flag (bf_options_set_cancel): once set, the readers of
     * files that take long (CSV, MERL, Cornell, ALTA) stop at their next line or chunk
     * with BF_ERR_CANCELLED ("PATH: reading cancelled") and nothing read. */
    const bf_cancel_flag *cancel;
} bf_read_options;

/* bf_samples_read with the reading options as a struct (NULL: the defaults). */
bf_status bf_samples_read_with(const char *path, const bf_read_options *opt, bf_samples **out, bf_error *err);
/* The CSV reader (bf_samples_read_with dispatches to it). */
bf_status bf_samples_read_csv(const char *path, const bf_csv_map *map, bf_samples **out, bf_error *err);

/* The readers that watch a cancel flag (NULL: none; bf_read_options.cancel says how):
 * the public ones are these with none. */
bf_status bf_csv_read_cancellable(const char *path, const bf_cancel_flag *cancel, bf_csv **out, bf_error *err);
bf_status bf_samples_read_csv_cancellable(const char *path, const bf_csv_map *map, const bf_cancel_flag *cancel,
                                          bf_samples **out, bf_error *err);
bf_status bf_samples_read_merl_cancellable(const char *path, int keep_raw, const bf_cancel_flag *cancel,
                                           bf_samples **out, bf_error *err);
bf_status bf_samples_read_cornell_cancellable(const char *path, const bf_cancel_flag *cancel, bf_samples **out,
                                              bf_error *err);
bf_status bf_samples_read_alta_cancellable(const char *path, const bf_cancel_flag *cancel, bf_samples **out,
                                           bf_error *err);
/* The error of a read that saw its cancel flag set (inline: every reader and their
 * dispatch give it, so it belongs to none of them). */
static inline bf_status bf_read_cancelled(const char *path, bf_error *err)
{
    return bf_fail(err, BF_ERR_CANCELLED, "%s: reading cancelled", path);
}

#endif
