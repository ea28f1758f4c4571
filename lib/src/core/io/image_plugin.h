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
 * written by the library (bf_outfile), not by the module. 3: one encoder for 1, 3 or 4
 * channels of 8-bit, 16-bit or float pixels (bf_oiio_encode, replacing
 * bf_oiio_encode_rgb), and bf_oiio_info and bf_oiio_read_rows. 4: bf_image and
 * bf_image_spec carry their size first (the module fills the library's own). */
#define BF_IMAGE_PLUGIN_ABI 4

/* "bf_oiio_abi": returns BF_IMAGE_PLUGIN_ABI as the module was built. */
typedef int (*bf_oiio_abi_fn)(void);

/* The pixel types bf_oiio_encode takes. */
enum { BF_OIIO_UINT8 = 1, BF_OIIO_UINT16 = 2, BF_OIIO_FLOAT = 3 };

/* "bf_oiio_encode": encodes width*height pixels of channels (1, 3 or 4) interleaved
 * values of the given type (BF_OIIO_*) as the file format fmt (bf_image_format_of)
 * names, which the caller has checked along with the size:
 * - fmt 1 (PNG): pixels are codes (UINT8 or UINT16), written as they are; srgb 1 marks
 *   them as sRGB-encoded in the file, 0 leaves the colour space unsaid (data codes).
 *   A fourth channel is unassociated alpha: the codes are not divided by it.
 * - fmt 2 (EXR): pixels are linear FLOATs, written as they are, channels Y, RGB or RGBA.
 * The file's bytes go to *data (malloc'd, the caller frees) and *size; no file is
 * touched, so that the library alone writes files, with every write checked. name is
 * for messages. */
typedef bf_status (*bf_oiio_encode_fn)(const char *name, int fmt, int width, int height, int channels, int type,
                                       int srgb, const void *pixels, unsigned char **data, size_t *size, bf_error *err);

/* "bf_oiio_read": bf_image_read's contract (img->pixels from malloc). Files with alpha
 * are read as stored, colour not premultiplied by alpha (codes, as image.h says). */
typedef bf_status (*bf_oiio_read_fn)(const char *path, bf_image *img, bf_error *err);

/* "bf_oiio_read_rows": bf_image_read_rows's contract; the caller has checked
 * 0 <= y0 < y1, the module checks y1 against the file's height. Thread-safe. */
typedef bf_status (*bf_oiio_read_rows_fn)(const char *path, int y0, int y1, bf_image *img, bf_error *err);

/* "bf_oiio_info": bf_image_info's contract (the file's header only). */
typedef bf_status (*bf_oiio_info_fn)(const char *path, bf_image_spec *out, bf_error *err);

/* *out: the loaded module's entry points, or NULL with err set (BF_ERR_IO, one line)
 * when it cannot be loaded. Thread-safe; the first call loads, later calls reuse the outcome. */
typedef struct bf_image_plugin {
    bf_oiio_encode_fn encode;
    bf_oiio_read_fn read;
    bf_oiio_read_rows_fn read_rows;
    bf_oiio_info_fn info;
} bf_image_plugin;

bf_status bf_image_plugin_get(const bf_image_plugin **out, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
