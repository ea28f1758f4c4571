/* Sample sets: measured or synthetic reflectance at direction pairs, with C channels,
 * optional weights, and the geometry model evaluation uses (computed once, on demand). */
#ifndef BRDFIT_SAMPLES_H
#define BRDFIT_SAMPLES_H

#include <stddef.h>
#include <stdint.h>

#include "brdfit/error.h"
#include "brdfit/geometry.h"
#include "brdfit/limits.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A sample set addressed by MERL table cells: each sample stands for the direction pair
 * at the centre of its cell (cell = phi_d + theta_d*180 + theta_h*180*90), so the
 * directions need no arrays of their own. raw is the table as read (3 planes of
 * BF_MERL_CELLS doubles, scale factors not applied, invalid cells included), kept only
 * when asked for (bf_read_options.keep_origin): with it, writing the samples back as a
 * MERL table gives the same bytes. */
#define BF_MERL_TH 90
#define BF_MERL_TD 90
#define BF_MERL_PD 180
#define BF_MERL_CELLS (BF_MERL_TH * BF_MERL_TD * BF_MERL_PD)
typedef struct bf_merl_origin {
    double *raw;     /* NULL, or 3 * BF_MERL_CELLS, planes R, G, B */
    int32_t *cell;   /* per sample */
} bf_merl_origin;

typedef struct bf_samples {
    size_t n;               /* samples */
    int channels;           /* C >= 1 */
    char **channel_names;   /* C names: "r","g","b", "value", "550" (nm), CSV headers... */
    double *wavelength;     /* NULL, or C wavelengths in nm for spectral data */
    /* Degrees, n each: the unit users write, kept exactly as read so that a CSV written
     * back has the same text. The geometry converts once. NULL for a set addressed by
     * MERL cells (merl != NULL): read directions with bf_samples_angle_block or
     * bf_samples_direction, which work for both. */
    double *theta_i, *phi_i, *theta_o, *phi_o;
    double *value;          /* n * C, value[i*C + c]: BRDF in 1/sr */
    double *weight;         /* NULL (all 1), or n weights: the data's own */
    double *scene_weight;   /* NULL (all 1), or n weights a scene gave (bf_scene_apply):
                               the fit multiplies them with the data's own weights (used
                               or not), and a scene's metrics are weighted by them alone */
    bf_merl_origin *merl;   /* NULL unless the samples are MERL table cells */
    bf_geometry *geom;      /* NULL until bf_samples_geometry */
} bf_samples;

/* n samples, C channels; names "value" (C = 1), "r,g,b" (C = 3) or "c0".. otherwise.
 * Arrays are allocated (angles and values zeroed); no weights, wavelengths or origin. */
bf_samples *bf_samples_new(size_t n, int channels, bf_error *err);
/* The same, addressed by MERL cells: s->merl->cell (n, zeroed) instead of angle arrays;
 * no raw table. */
bf_samples *bf_samples_new_cells(size_t n, int channels, bf_error *err);
void bf_samples_free(bf_samples *s);
/* Replaces channel c's name (copied). */
int bf_samples_set_channel_name(bf_samples *s, int c, const char *name, bf_error *err);
/* Forgets the raw MERL table (the values no longer are that table's); the cells stay,
 * they are the samples' directions. */
void bf_samples_drop_origin(bf_samples *s);

/* Directions in degrees of samples [i0, i0 + cnt): dir[0..3] point at theta_i, phi_i,
 * theta_o, phi_o of sample i0. With angle arrays they point into them; for MERL cells
 * they are computed into buf (4 * cnt doubles). */
void bf_samples_angle_block(const bf_samples *s, size_t i0, size_t cnt, double *buf, const double *dir[4]);
/* One sample's directions in degrees: theta_i, phi_i, theta_o, phi_o. */
void bf_samples_direction(const bf_samples *s, size_t i, double dir[4]);
/* Adds a weight array, all 1. */
int bf_samples_add_weights(bf_samples *s, bf_error *err);

/* The geometry for the current directions (computed on first use, kept until the
 * samples change through bf_samples_keep): stored for angle arrays, generated for MERL
 * cells (geometry.h). NULL only on allocation failure. */
const bf_geometry *bf_samples_geometry(bf_samples *s, bf_error *err);

/* Keeps the samples whose keep[i] is non-zero, in order. Drops the geometry; marks the
 * cells of dropped samples invalid (-1) in the raw MERL table, so a table written back
 * has exactly the kept samples. Any change of channels (selection, spectral to RGB) must
 * forget the raw table instead (bf_samples_drop_origin): it no longer describes the data. */
int bf_samples_keep(bf_samples *s, const unsigned char *keep, bf_error *err);

/* A new sample set with the samples of s whose keep[i] is non-zero (keep NULL: all),
 * in order: directions (MERL cells stay cells), values, weights, channel names and
 * wavelengths; no raw MERL table (a copy describes no file) and no geometry yet. */
bf_samples *bf_samples_copy(const bf_samples *s, const unsigned char *keep, bf_error *err);

/* ---- Reading and writing ------------------------------------------------------- */

typedef enum bf_format {
    BF_FORMAT_AUTO = 0, /* by extension, then by content */
    BF_FORMAT_CSV,
    BF_FORMAT_MERL,     /* .binary */
    BF_FORMAT_CORNELL,  /* Cornell spectral gonioreflectometer text (.brdf) */
    BF_FORMAT_ALTA,     /* ALTA text data (#DIM / #PARAM_IN / #PARAM_OUT header) */
} bf_format;

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
    int keep_origin; /* keep what writing the file back byte for byte needs (MERL: the raw
                        table, 35 MB); only a command that writes the format back asks */
} bf_read_options;

/* Reads any supported format. Errors name the file, the line or byte offset, and the
 * problem. Negative values are kept (they are data); NaN or Inf is an error. */
int bf_samples_read(const char *path, const bf_read_options *opt, bf_samples **out, bf_error *err);
int bf_format_from_name(const char *name); /* "csv", "merl", "cornell", "alta": a bf_format; -1 if unknown */
const char *bf_format_name(bf_format f);
/* The format a path's extension names for writing (csv, binary); BF_FORMAT_AUTO if none. */
bf_format bf_format_for_writing(const char *path);

/* Per-format readers (bf_samples_read dispatches to them). */
int bf_samples_read_csv(const char *path, const bf_csv_map *map, bf_samples **out, bf_error *err);
/* MERL: samples addressed by cells; keep_raw keeps the raw table (bf_merl_origin). */
int bf_samples_read_merl(const char *path, int keep_raw, bf_samples **out, bf_error *err);
int bf_samples_read_cornell(const char *path, bf_samples **out, bf_error *err);
int bf_samples_read_alta(const char *path, bf_samples **out, bf_error *err);

/* Writers: the whole file appears only when complete (bf_outfile). CSV: the four angle
 * columns in degrees, one column per channel (its name), then weight if present; values
 * with round-trip precision. MERL: needs 3 channels; every sample must sit at a cell
 * centre (else BF_ERR_ARG naming the first that does not); cells without a sample are
 * written from the raw table when the samples keep one, or as invalid (-1). */
int bf_samples_write_csv(const bf_samples *s, const char *path, bf_error *err);
int bf_samples_write_merl(const bf_samples *s, const char *path, bf_error *err);
int bf_samples_write(const bf_samples *s, const char *path, bf_format f, bf_error *err);

/* MERL cell centre <-> directions in degrees (Rusinkiewicz half/difference angles,
 * phi_h = 0). */
void bf_merl_cell_directions(int32_t cell, double *theta_i, double *phi_i, double *theta_o,
                             double *phi_o);
/* The cell whose centre these directions are (within 1e-9 rad in theta_h and theta_d;
 * phi_d within 1e-9 rad plus its own rounding, which grows as H nears N), or -1. */
int32_t bf_merl_cell_of(double theta_i, double phi_i, double theta_o, double phi_o);

#ifdef __cplusplus
}
#endif
#endif
