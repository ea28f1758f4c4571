/* The boundary between the library and the image module (libbrdfit-oiio.so, built from
 * oiio_shim.cc), which the library loads on first use (image_plugin.c) so that only
 * commands that write or read images load OpenImageIO and its ~270 shared libraries.
 *
 * The module exports the entry points below under their own names (not image.h's, so
 * nothing in the module can bind to the library's symbols or the other way round). It
 * needs no brdfit symbol: it fills a bf_error itself. */
#ifndef BRDFIT_IMAGE_PLUGIN_H
#define BRDFIT_IMAGE_PLUGIN_H

#include <stddef.h>

#include "brdfit/error.h"
#include "brdfit/image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Bumped whenever an entry point's meaning or signature changes, so a stale installed
 * module is refused instead of called wrongly. 2: images are encoded into memory and
 * written by the library (bf_outfile), not by the module. */
#define BF_IMAGE_PLUGIN_ABI 2

/* "bf_oiio_abi": returns BF_IMAGE_PLUGIN_ABI as the module was built. */
typedef int (*bf_oiio_abi_fn)(void);

/* "bf_oiio_encode_rgb": encodes width*height RGB pixels as the file format fmt
 * (bf_image_format_of) names, which the caller has checked along with the size:
 * - fmt 1 (PNG): pixels are unsigned char codes, already sRGB-encoded;
 * - fmt 2 (EXR): pixels are linear floats, written as they are.
 * The file's bytes go to *data (malloc'd, the caller frees) and *size; no file is
 * touched, so that the library alone writes files, with every write checked. name is
 * for messages. */
typedef bf_status (*bf_oiio_encode_rgb_fn)(const char *name, int fmt, int width, int height, const void *pixels,
                                           unsigned char **data, size_t *size, bf_error *err);

/* "bf_oiio_read": bf_image_read's contract (img->pixels from malloc). */
typedef bf_status (*bf_oiio_read_fn)(const char *path, bf_image *img, bf_error *err);

/* *out: the loaded module's entry points, or NULL with err set (BF_ERR_IO, one line)
 * when it cannot be loaded. Thread-safe; the first call loads, later calls reuse the outcome. */
typedef struct bf_image_plugin {
    bf_oiio_encode_rgb_fn encode_rgb;
    bf_oiio_read_fn read;
} bf_image_plugin;

bf_status bf_image_plugin_get(const bf_image_plugin **out, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
