/* Image files through OpenImageIO. The format follows the extension: .png (8-bit sRGB)
 * or .exr (linear 32-bit float). Reading and writing files goes through a separately
 * loaded module, libbrdfit-oiio.so, loaded on the first call that needs it (so programs
 * that use no images never load OpenImageIO); it is looked for in $BRDFIT_PLUGIN_DIR if
 * set, else beside the executable as installed, the build tree, the install directory.
 * If it cannot be loaded, those calls fail with BF_ERR_IO ("image support ... could not
 * be loaded: ..."). bf_image_format_of, bf_srgb_encode and bf_image_clear need no module.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_IMAGE_H
#define BRDFIT_IMAGE_H

#include "brdfit/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* An image in memory: width * height pixels, row-major from the top row, channels
 * interleaved (pixels[(y*width + x)*channels + c]). */
typedef struct bf_image {
    int width, height, channels;
    float *pixels;
} bf_image;

/* 1 for a .png name, 2 for .exr (case-insensitive), 0 otherwise (BF_IMAGE_*). */
enum { BF_IMAGE_BY_NAME = 0, BF_IMAGE_PNG = 1, BF_IMAGE_EXR = 2 };
int bf_image_format_of(const char *path);

/* Writes an RGB float image (width*height*3 values).
 * - .exr: the values as they are (linear, scene-referred), 32-bit float.
 * - .png: the values are display-referred (tone-mapped by the caller, see render.h's
 *   bf_tonemap): clamped to [0, 1] (NaN -> 0), sRGB-encoded, rounded to 8 bits.
 * Encoded in memory, then written as bf_outfile writes (io.h): a temporary beside the
 * target renamed into place, so a failed write leaves no file and the old one whole. Errors: BF_ERR_ARG (unknown extension, bad size),
 * BF_ERR_IO naming the file. */
bf_status bf_image_write_rgb(const char *path, int width, int height, const float *rgb, bf_error *err);
/* The same in a given format (BF_IMAGE_PNG, BF_IMAGE_EXR; BF_IMAGE_BY_NAME: by the
 * extension), for names without one such as "-" (standard output). */
bf_status bf_image_write_rgb_as(const char *path, int format, int width, int height, const float *rgb, bf_error *err);

/* Reads any image OpenImageIO reads, every channel as float: EXR values as stored, PNG
 * values as stored codes / 255 (still sRGB-encoded: no colour conversion). On success
 * img->pixels is malloc'd; free with bf_image_clear. */
bf_status bf_image_read(const char *path, bf_image *img, bf_error *err);
void bf_image_clear(bf_image *img);

/* The sRGB transfer function (linear [0, 1] -> encoded [0, 1]) the PNG writer applies. */
float bf_srgb_encode(float linear);

#ifdef __cplusplus
}
#endif
#endif
