/* How files are read, inside the library: the reading part of the run options
 * (brdfit/options.h) as the readers take it, and the reader dispatch and the CSV reader
 * that take it. */
#ifndef BRDFIT_READ_OPTIONS_H
#define BRDFIT_READ_OPTIONS_H

#include "brdfit/formats.h"

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
} bf_read_options;

/* bf_samples_read with the reading options as a struct (NULL: the defaults). */
bf_status bf_samples_read_with(const char *path, const bf_read_options *opt, bf_samples **out, bf_error *err);
/* The CSV reader (bf_samples_read_with dispatches to it). */
bf_status bf_samples_read_csv(const char *path, const bf_csv_map *map, bf_samples **out, bf_error *err);

#endif
