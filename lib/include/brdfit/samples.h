/* Sample sets: measured or synthetic reflectance at direction pairs, with C channels,
 * optional weights, and the geometry model evaluation uses (computed once, on demand).
 * The container only: reading and writing files is formats.h, MERL cells merl.h.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_SAMPLES_H
#define BRDFIT_SAMPLES_H

#include <stddef.h>
#include <stdint.h>

#include "brdfit/error.h"
#include "brdfit/geometry.h"
#include "brdfit/limits.h"
#include "brdfit/merl.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct bf_samples {
    size_t n;             /* samples */
    int channels;         /* C >= 1 */
    char **channel_names; /* C names: "r","g","b", "value", "550" (nm), CSV headers... */
    double *wavelength;   /* NULL, or C wavelengths in nm for spectral data */
    /* Degrees, n each: the unit users write, kept exactly as read so that a CSV written
     * back has the same text. The geometry converts once. NULL for a set addressed by
     * MERL cells (merl != NULL): read directions with bf_samples_angle_block or
     * bf_samples_direction, which work for both. */
    double *theta_i, *phi_i, *theta_o, *phi_o;
    double *value;        /* n * C, value[i*C + c]: BRDF in 1/sr */
    double *weight;       /* NULL (all 1), or n weights: the data's own */
    double *scene_weight; /* NULL (all 1), or n weights a scene gave (bf_scene_apply):
                               the fit multiplies them with the data's own weights (used
                               or not), and a scene's metrics are weighted by them alone */
    bf_merl_origin *merl; /* NULL unless the samples are MERL table cells */
    bf_geometry *geom;    /* NULL until bf_samples_geometry */
} bf_samples;

/* n samples, C channels; names "value" (C = 1), "r,g,b" (C = 3) or "c0".. otherwise.
 * Arrays are allocated (angles and values zeroed); no weights, wavelengths or origin. */
BF_API bf_status bf_samples_new(size_t n, int channels, bf_samples **out, bf_error *err);
/* The same, addressed by MERL cells: s->merl->cell (n, zeroed) instead of angle arrays;
 * no raw table. */
BF_API bf_status bf_samples_new_cells(size_t n, int channels, bf_samples **out, bf_error *err);
BF_API void bf_samples_free(bf_samples *s);
/* Replaces channel c's name (copied). */
BF_API bf_status bf_samples_set_channel_name(bf_samples *s, int c, const char *name, bf_error *err);
/* Forgets the raw MERL table (the values no longer are that table's); the cells stay,
 * they are the samples' directions. */
BF_API void bf_samples_drop_origin(bf_samples *s);

/* Directions in degrees of samples [i0, i0 + cnt): dir[0..3] point at theta_i, phi_i,
 * theta_o, phi_o of sample i0. With angle arrays they point into them; for MERL cells
 * they are computed into buf (4 * cnt doubles). */
BF_API void bf_samples_angle_block(const bf_samples *s, size_t i0, size_t cnt, double *buf, const double *dir[4]);
/* One sample's directions in degrees: theta_i, phi_i, theta_o, phi_o. */
BF_API void bf_samples_direction(const bf_samples *s, size_t i, double dir[4]);
/* Adds a weight array, all 1. */
BF_API bf_status bf_samples_add_weights(bf_samples *s, bf_error *err);

/* The geometry for the current directions (computed on first use, kept until the
 * samples change through bf_samples_keep): stored for angle arrays, generated for MERL
 * cells (geometry.h). *out is NULL only on failure (out of memory, a cell out of range). */
BF_API bf_status bf_samples_geometry(bf_samples *s, const bf_geometry **out, bf_error *err);

/* Keeps the samples whose keep[i] is non-zero, in order. Drops the geometry; marks the
 * cells of dropped samples invalid (-1) in the raw MERL table, so a table written back
 * has exactly the kept samples. Any change of channels (selection, spectral to RGB) must
 * forget the raw table instead (bf_samples_drop_origin): it no longer describes the data. */
BF_API bf_status bf_samples_keep(bf_samples *s, const unsigned char *keep, bf_error *err);

/* A new sample set with the samples of s whose keep[i] is non-zero (keep NULL: all),
 * in order: directions (MERL cells stay cells), values, weights, channel names and
 * wavelengths; no raw MERL table (a copy describes no file) and no geometry yet. */
BF_API bf_status bf_samples_copy(const bf_samples *s, const unsigned char *keep, bf_samples **out, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
