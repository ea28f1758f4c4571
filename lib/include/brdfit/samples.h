/* Sample sets: measured or synthetic reflectance at direction pairs, with C channels,
 * optional weights, and the geometry model evaluation uses (computed once, on demand). */
#ifndef BRDFIT_SAMPLES_H
#define BRDFIT_SAMPLES_H

#include <stddef.h>
#include <stdint.h>

#include "brdfit/error.h"
#include "brdfit/geometry.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Where a sample set read from a MERL table came from, so that writing it back gives
 * the same bytes: the raw table (3 planes of BF_MERL_CELLS doubles, scale factors not
 * applied, invalid cells included) and, per sample, its cell index. */
#define BF_MERL_TH 90
#define BF_MERL_TD 90
#define BF_MERL_PD 180
#define BF_MERL_CELLS (BF_MERL_TH * BF_MERL_TD * BF_MERL_PD)
typedef struct bf_merl_origin {
    double *raw;     /* 3 * BF_MERL_CELLS, planes R, G, B */
    int32_t *cell;   /* per sample: index phi_d + theta_d*180 + theta_h*180*90 */
} bf_merl_origin;

typedef struct bf_samples {
    size_t n;               /* samples */
    int channels;           /* C >= 1 */
    char **channel_names;   /* C names: "r","g","b", "value", "550" (nm), CSV headers... */
    double *wavelength;     /* NULL, or C wavelengths in nm for spectral data */
    /* Degrees, n each: the unit users write, kept exactly as read so that a CSV written
     * back has the same text. The geometry converts once. */
    double *theta_i, *phi_i, *theta_o, *phi_o;
    double *value;          /* n * C, value[i*C + c]: BRDF in 1/sr */
    double *weight;         /* NULL (all 1), or n weights: the data's own */
    double *scene_weight;   /* NULL (all 1), or n weights a scene gave (bf_scene_apply):
                               the fit multiplies them with the data's own weights (used
                               or not), and a scene's metrics are weighted by them alone */
    bf_merl_origin *merl;   /* NULL unless read from a MERL table and not reshaped since */
    bf_geometry *geom;      /* NULL until bf_samples_geometry */
} bf_samples;

/* n samples, C channels; names "value" (C = 1), "r,g,b" (C = 3) or "c0".. otherwise.
 * Arrays are allocated (angles and values zeroed); no weights, wavelengths or origin. */
bf_samples *bf_samples_new(size_t n, int channels, bf_error *err);
void bf_samples_free(bf_samples *s);
/* Replaces channel c's name (copied). */
int bf_samples_set_channel_name(bf_samples *s, int c, const char *name, bf_error *err);
void bf_samples_drop_origin(bf_samples *s);
/* Adds a weight array, all 1. */
int bf_samples_add_weights(bf_samples *s, bf_error *err);

/* The geometry for the current directions (computed on first use, kept until the
 * samples change through bf_samples_keep). NULL only on allocation failure. */
const bf_geometry *bf_samples_geometry(bf_samples *s, bf_error *err);

/* Keeps the samples whose keep[i] is non-zero, in order. Drops the geometry; marks the
 * cells of dropped samples invalid (-1) in the MERL origin, so a table written back has
 * exactly the kept samples. Any change of channels (selection, spectral to RGB) must
 * free the origin instead (bf_samples_drop_origin): it no longer describes the data. */
int bf_samples_keep(bf_samples *s, const unsigned char *keep, bf_error *err);

/* A new sample set with the samples of s whose keep[i] is non-zero (keep NULL: all),
 * in order: directions, values, weights, channel names and wavelengths; no MERL origin
 * (a copy describes no table) and no geometry yet. */
bf_samples *bf_samples_copy(const bf_samples *s, const unsigned char *keep, bf_error *err);

/* ---- Reading and writing ------------------------------------------------------- */

typedef enum bf_format {
    BF_FORMAT_AUTO = 0, /* by extension, then by content */
    BF_FORMAT_CSV,
    BF_FORMAT_MERL,     /* .binary */
    BF_FORMAT_CORNELL,  /* Cornell spectral gonioreflectometer text (.brdf) */
    BF_FORMAT_ALTA,     /* ALTA text data (#DIM / #PARAM_IN / #PARAM_OUT header) */
} bf_format;

/* How a CSV maps onto samples. Zeroed = the defaults of DESIGN.md. */
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
int bf_samples_read_merl(const char *path, bf_samples **out, bf_error *err);
int bf_samples_read_cornell(const char *path, bf_samples **out, bf_error *err);
int bf_samples_read_alta(const char *path, bf_samples **out, bf_error *err);

/* Writers: the whole file appears only when complete (bf_outfile). CSV: the four angle
 * columns in degrees, one column per channel (its name), then weight if present; values
 * with round-trip precision. MERL: needs 3 channels; every sample must sit at a cell
 * centre (else BF_ERR_ARG naming the first that does not); cells without a sample are
 * written from the origin's raw table, or as invalid (-1) without one. */
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
