/* Data files: reading any supported format into samples (by --format, extension or
 * content) and writing CSV or MERL tables. The container is samples.h.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_FORMATS_H
#define BRDFIT_FORMATS_H

#include "brdfit/error.h"
#include "brdfit/options.h"
#include "brdfit/samples.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum bf_format {
    BF_FORMAT_AUTO = 0, /* by extension, then by content */
    BF_FORMAT_CSV,
    BF_FORMAT_MERL,    /* .binary */
    BF_FORMAT_CORNELL, /* Cornell spectral gonioreflectometer text (.brdf) */
    BF_FORMAT_ALTA,    /* ALTA text data (#DIM / #PARAM_IN / #PARAM_OUT header) */
    BF_FORMAT_RGL,     /* RGL-EPFL measured material (.bsdf, Mitsuba tensor file) */
    BF_FORMAT_MBSDF,   /* NVIDIA MDL measured BSDF (.mbsdf) */
} bf_format;

/* Reads any supported format with the reading options of o (brdfit/options.h: format,
 * grid, angles, radians, values, weight; NULL: the defaults), as it is: no sample dropped
 * or changed (bf_samples_load also prepares them). Errors name the file, the line or byte
 * offset, and the problem. Negative values are kept (they are data); NaN or Inf is an
 * error. o's cancel flag stops it as it stops bf_samples_load (brdfit/load.h). */
BF_API bf_status bf_samples_read(const char *path, const bf_options *o, bf_samples **out, bf_error *err);
/* "csv", "merl", "cornell", "alta", "rgl", "mbsdf" ("auto": BF_FORMAT_AUTO) into *out;
 * BF_ERR_ARG with a message listing them for any other name. */
BF_API bf_status bf_format_parse(const char *name, bf_format *out, bf_error *err);
/* The same, -1 for an unknown name (bf_format_parse replaces it). */
BF_API BF_DEPRECATED("use bf_format_parse") int bf_format_from_name(const char *name);
BF_API const char *bf_format_name(bf_format f);
/* The format a path's extension names for reading (.csv, .binary, .brdf, .alta, .bsdf,
 * .mbsdf, any case); BF_FORMAT_AUTO if none (bf_samples_read then looks at the content). */
BF_API bf_format bf_format_by_extension(const char *path);
/* The format a path's extension names for writing (csv, binary); BF_FORMAT_AUTO if none. */
BF_API bf_format bf_format_for_writing(const char *path);

/* Per-format readers (bf_samples_read dispatches to them). */
/* MERL: samples addressed by cells; keep_raw keeps the raw table (bf_merl_origin). */
BF_API bf_status bf_samples_read_merl(const char *path, int keep_raw, bf_samples **out, bf_error *err);
BF_API bf_status bf_samples_read_cornell(const char *path, bf_samples **out, bf_error *err);
BF_API bf_status bf_samples_read_alta(const char *path, bf_samples **out, bf_error *err);
/* RGL-EPFL .bsdf (isotropic; RGB: channels r, g, b; spectral: one per wavelength, named
 * by it in nm, s->wavelength set): the BRDF at the measured points (grid NULL) or
 * evaluated at a direction grid (the option grid). Anisotropic files are refused. */
BF_API bf_status bf_samples_read_rgl(const char *path, const char *grid, bf_samples **out, bf_error *err);
/* NVIDIA .mbsdf: the reflection table at its cell centres (grid NULL; channels r, g, b
 * or value), or interpolated on a direction grid. A transmission part is checked and
 * left out. */
BF_API bf_status bf_samples_read_mbsdf(const char *path, const char *grid, bf_samples **out, bf_error *err);

/* Writers: the whole file appears only when complete (bf_outfile). CSV: the four angle
 * columns in degrees, one column per channel (its name), then weight if present; values
 * with round-trip precision. MERL: needs 3 channels; every sample must sit at a cell
 * centre (else BF_ERR_ARG naming the first that does not); cells without a sample are
 * written from the raw table when the samples keep one, or as invalid (-1). */
BF_API bf_status bf_samples_write_csv(const bf_samples *s, const char *path, bf_error *err);
BF_API bf_status bf_samples_write_merl(const bf_samples *s, const char *path, bf_error *err);
BF_API bf_status bf_samples_write(const bf_samples *s, const char *path, bf_format f, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
