/* Image files through OpenImageIO. The format follows the extension: .png (8-bit sRGB)
 * or .exr (linear 32-bit float). Reading and writing files goes through a separately
 * loaded module, libbrdfit-oiio.so, loaded on the first call that needs it (so programs
 * that use no images never load OpenImageIO); it is looked for in $BRDFIT_PLUGIN_DIR if
 * set, else beside the executable as installed, the build tree, the install directory.
 * If it cannot be loaded, those calls fail with BF_ERR_IO ("image support ... could not
 * be loaded: ..."). bf_image_format_of, bf_srgb_encode, bf_srgb_decode, the init
 * functions and bf_image_clear need no module.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_IMAGE_H
#define BRDFIT_IMAGE_H

#include <stddef.h>

#include "brdfit/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* An image in memory: width * height pixels, row-major from the top row, channels
 * interleaved (pixels[(y*width + x)*channels + c]). Callers set it up with
 * bf_image_init; the readers fill what lies within its size (docs/api.md). */
typedef struct bf_image {
    size_t size; /* sizeof, set by bf_image_init */
    int width, height, channels;
    float *pixels;
} bf_image;

/* An empty image (no pixels) with its size set. */
BF_API void bf_image_init_size(bf_image *img, size_t size);
static inline void bf_image_init(bf_image *img)
{
    bf_image_init_size(img, sizeof *img);
}

/* 1 for a .png name, 2 for .exr (case-insensitive), 0 otherwise (BF_IMAGE_*). */
enum { BF_IMAGE_BY_NAME = 0, BF_IMAGE_PNG = 1, BF_IMAGE_EXR = 2 };
BF_API int bf_image_format_of(const char *path);

/* Writes an RGB float image (width*height*3 values).
 * - .exr: the values as they are (linear, scene-referred), 32-bit float.
 * - .png: the values are display-referred (tone-mapped by the caller, see render.h's
 *   bf_tonemap): clamped to [0, 1] (NaN -> 0), sRGB-encoded, rounded to 8 bits.
 * Encoded in memory, then written as bf_outfile writes (io.h): a temporary beside the
 * target renamed into place, so a failed write leaves no file and the old one whole. Errors: BF_ERR_ARG (unknown extension, bad size),
 * BF_ERR_IO naming the file. */
BF_API bf_status bf_image_write_rgb(const char *path, int width, int height, const float *rgb, bf_error *err);
/* The same in a given format (BF_IMAGE_PNG, BF_IMAGE_EXR; BF_IMAGE_BY_NAME: by the
 * extension), for names without one such as "-" (standard output). */
BF_API bf_status bf_image_write_rgb_as(const char *path, int format, int width, int height, const float *rgb,
                                       bf_error *err);

/* Reads any image OpenImageIO reads, every channel as float: EXR values as stored, PNG
 * values as stored codes / 255 (still sRGB-encoded: no colour conversion), into img (set
 * up by bf_image_init; empty on failure). On success img->pixels is malloc'd; free with
 * bf_image_clear. */
BF_API bf_status bf_image_read(const char *path, bf_image *img, bf_error *err);
/* Frees the pixels (NULL after; twice is harmless). img stays set up for another read. */
BF_API void bf_image_clear(bf_image *img);

/* What a file holds, without reading its pixels: size, channels, and how its values are
 * stored (bits 8 or 16 for integer formats, 16 or 32 with is_float for half and float).
 * Callers set it up with bf_image_spec_init; bf_image_info fills what lies within its
 * size (docs/api.md). */
typedef struct bf_image_spec {
    size_t size; /* sizeof, set by bf_image_spec_init */
    int width, height, channels;
    int bits;
    int is_float;
} bf_image_spec;
/* Zeroes *sp and sets its size. */
BF_API void bf_image_spec_init_size(bf_image_spec *sp, size_t size);
static inline void bf_image_spec_init(bf_image_spec *sp)
{
    bf_image_spec_init_size(sp, sizeof *sp);
} /* the program's size */
BF_API bf_status bf_image_info(const char *path, bf_image_spec *out, bf_error *err);

/* Reads rows [y0, y1) of any image OpenImageIO reads (0 <= y0 < y1 <= height), every
 * channel as float, as bf_image_read does (integer formats as code / max code, e.g. a
 * 16-bit PNG's codes / 65535, no colour conversion): img->height is y1 - y0. Reading
 * bands of a large image keeps memory to the band. */
BF_API bf_status bf_image_read_rows(const char *path, int y0, int y1, bf_image *img, bf_error *err);

/* Writing flags for bf_image_write. */
enum {
    BF_IMAGE_CODES = 1u << 0, /* PNG: values are codes in [0, 1], written without the sRGB
                                 encoding (normal maps, data textures) */
    BF_IMAGE_16BIT = 1u << 1, /* PNG: 16-bit codes instead of 8 */
};
/* Writes width * height pixels of 1, 3 or 4 channels (EXR channels Y, RGB or RGBA), as
 * bf_image_write_rgb_as does for RGB: .exr linear float; .png clamped to [0, 1], sRGB-
 * encoded unless BF_IMAGE_CODES, rounded to 8 or (BF_IMAGE_16BIT) 16 bits. */
BF_API bf_status bf_image_write(const char *path, int format, int width, int height, int channels, const float *pixels,
                                unsigned flags, bf_error *err);

/* The sRGB transfer function (linear [0, 1] -> encoded [0, 1]) the PNG writer applies. */
BF_API float bf_srgb_encode(float linear);
/* Its inverse (encoded [0, 1] -> linear), for 8-bit photographs. */
BF_API float bf_srgb_decode(float encoded);

#ifdef __cplusplus
}
#endif
#endif
