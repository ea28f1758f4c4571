/* Colorimetry of spectral data: a reflectance spectrum to CIE XYZ (CIE 1931 2 degree
 * observer, a chosen illuminant) and on to linear sRGB or ACEScg. docs/color.md.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_COLOR_H
#define BRDFIT_COLOR_H

#include "brdfit/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum bf_color {
    BF_COLOR_NONE = 0, /* no conversion */
    BF_COLOR_SRGB,     /* linear sRGB (IEC 61966-2-1 primaries, D65 white) */
    BF_COLOR_ACESCG,   /* ACEScg (ACES AP1 primaries, ACES white, linear) */
    BF_COLOR_XYZ       /* CIE XYZ under the illuminant, no adaptation */
} bf_color;

typedef enum bf_illuminant {
    BF_ILLUMINANT_D65 = 0, /* CIE standard illuminant D65 (the default) */
    BF_ILLUMINANT_E,       /* equal energy */
    BF_ILLUMINANT_A,       /* CIE standard illuminant A (Planck, 2856 K) */
    BF_ILLUMINANT_D50      /* CIE daylight D50 (ICC, graphic arts) */
} bf_illuminant;

/* "srgb", "acescg", "xyz" ("none" for BF_COLOR_NONE); "d65", "e", "a", "d50". */
BF_API const char *bf_color_name(bf_color c);
BF_API const char *bf_illuminant_name(bf_illuminant i);
/* The enum value of a name (case-insensitive) into *out; BF_ERR_ARG with a message
 * listing the names for an unknown one. */
BF_API bf_status bf_color_parse(const char *name, bf_color *out, bf_error *err);
BF_API bf_status bf_illuminant_parse(const char *name, bf_illuminant *out, bf_error *err);
/* The same, -1 for an unknown name (the parsers above replace them). */
BF_API BF_DEPRECATED("use bf_color_parse") int bf_color_from_name(const char *name);
BF_API BF_DEPRECATED("use bf_illuminant_parse") int bf_illuminant_from_name(const char *name);

/* The linear map from a reflectance spectrum sampled at n wavelengths (nm, any order,
 * distinct, n >= 2, at least one inside 360-830 nm) to the three outputs of space c:
 * out[k] = sum_i w[k * n + i] v[i]. The spectrum is interpolated between the given
 * wavelengths (cubic Lagrange on the four nearest) and held at its end values outside them, over the CIE table's 360-
 * 830 nm every 5 nm. Normalised as reflectance: a flat spectrum of 1 gives Y = 1 (the
 * illuminant's white) in XYZ and, after Bradford adaptation from the illuminant's
 * white to the space's white, (1, 1, 1) in sRGB and ACEScg. Errors: bad wavelengths,
 * BF_COLOR_NONE. */
BF_API bf_status bf_color_weights(const double *wavelength, int n, bf_color c, bf_illuminant ill, double *w,
                                  bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
