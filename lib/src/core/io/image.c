/* image.h: what needs no OpenImageIO is done here, in C (the format from the name, the
 * argument checks, the sRGB encoding and rounding of PNG pixels to 8- or 16-bit codes),
 * so that bad arguments fail without loading anything. The image module (loaded on
 * first use, image_plugin.c) encodes images into memory and reads files; the library
 * writes the bytes (bf_outfile), so a failed write is always seen and never replaces a
 * good file. */
#include "brdfit/image.h"

#include "base/sized.h"
#include "brdfit/io.h"
#include "io/image_plugin.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* The module writes its messages itself, quoting OpenImageIO's and the file's name as
 * they are: passed through bf_fail, they become one safe line like every other message. */
static bf_status printable(bf_status rc, bf_error *err)
{
    if (rc != BF_OK && err) {
        char msg[sizeof err->msg];
        snprintf(msg, sizeof msg, "%s", err->msg);
        return bf_fail(err, rc, "%s", msg);
    }
    return rc;
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcasecmp(s + n - m, suffix) == 0;
}

int bf_image_format_of(const char *path)
{
    if (!path)
        return 0;
    if (ends_with(path, ".png"))
        return 1;
    if (ends_with(path, ".exr"))
        return 2;
    return 0;
}

/* Single-precision throughout (powf), as the C++ shim's std::pow(float, float) was, so
 * PNG codes do not change. */
float bf_srgb_encode(float v)
{
    if (!(v > 0.0f)) /* NaN too */
        return 0.0f;
    if (v >= 1.0f)
        return 1.0f;
    return v <= 0.0031308f ? 12.92f * v : 1.055f * powf(v, 1.0f / 2.4f) - 0.055f;
}

/* bf_srgb_encode's formula turned round, in single precision too: the linear segment up
 * to where encode's ends (12.92 * 0.0031308), the power above, [0, 1] clamped as there. */
float bf_srgb_decode(float e)
{
    if (!(e > 0.0f)) /* NaN too */
        return 0.0f;
    if (e >= 1.0f)
        return 1.0f;
    return e <= 12.92f * 0.0031308f ? e / 12.92f : powf((e + 0.055f) / 1.055f, 2.4f);
}

/* The encoded bytes into path through bf_outfile: a temporary renamed into place with
 * every write checked, or written through to a device. */
static bf_status write_bytes(const char *path, const unsigned char *data, size_t size, bf_error *err)
{
    bf_outfile o;
    bf_status rc = bf_outfile_open(&o, path, err);
    if (rc != BF_OK)
        return rc;
    fwrite(data, 1, size, o.fp);
    return bf_outfile_commit(&o, err); /* checks every write */
}

bf_status bf_image_write_rgb(const char *path, int width, int height, const float *rgb, bf_error *err)
{
    return bf_image_write_rgb_as(path, BF_IMAGE_BY_NAME, width, height, rgb, err);
}

bf_status bf_image_write_rgb_as(const char *path, int format, int width, int height, const float *rgb, bf_error *err)
{
    return bf_image_write(path, format, width, height, 3, rgb, 0, err);
}

/* A PNG value as a code in [0, 1]: clamped (NaN -> 0), sRGB-encoded unless codes. */
static float png_code(float v, int codes)
{
    if (!codes)
        return bf_srgb_encode(v);
    return !(v > 0.0f) ? 0.0f : v >= 1.0f ? 1.0f : v;
}

/* Positional, as bf_image_write_rgb_as: the file, its format, the pixels' shape and data,
 * and the flags. */
bf_status bf_image_write(const char *path, int format, int width, int height, int channels, const float *pixels,
                         unsigned flags, bf_error *err)
{
    int fmt = format == BF_IMAGE_PNG || format == BF_IMAGE_EXR ? format : bf_image_format_of(path);
    if (!fmt)
        return bf_fail(err, BF_ERR_ARG, "%s: unknown image format (use .png or .exr)", path ? path : "(null)");
    if (width <= 0 || height <= 0 || !pixels)
        return bf_fail(err, BF_ERR_ARG, "%s: bad image size %dx%d", path, width, height);
    if (channels != 1 && channels != 3 && channels != 4)
        return bf_fail(err, BF_ERR_ARG, "%s: %d channels (images have 1, 3 or 4)", path, channels);
    if (flags & ~(unsigned)(BF_IMAGE_CODES | BF_IMAGE_16BIT))
        return bf_fail(err, BF_ERR_ARG, "%s: unknown image flags 0x%x", path, flags);
    const bf_image_plugin *plugin;
    bf_status rc = bf_image_plugin_get(&plugin, err);
    if (rc != BF_OK)
        return rc;
    unsigned char *data = NULL;
    size_t size = 0;
    if (fmt == BF_IMAGE_EXR) {
        rc = printable(plugin->encode(path, fmt, width, height, channels, BF_OIIO_FLOAT, 0, pixels, &data, &size, err),
                       err);
    } else {
        const int codes = (flags & BF_IMAGE_CODES) != 0, wide = (flags & BF_IMAGE_16BIT) != 0;
        size_t n = (size_t)width * (size_t)height * (size_t)channels;
        void *px = malloc(n * (wide ? 2 : 1));
        if (!px)
            return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory for %zu pixels", path, n / (size_t)channels);
        if (wide) {
            unsigned short *q = px;
            for (size_t i = 0; i < n; i++)
                q[i] = (unsigned short)lroundf(png_code(pixels[i], codes) * 65535.0f);
        } else {
            unsigned char *q = px;
            for (size_t i = 0; i < n; i++)
                q[i] = (unsigned char)lroundf(png_code(pixels[i], codes) * 255.0f);
        }
        rc = printable(plugin->encode(path, fmt, width, height, channels, wide ? BF_OIIO_UINT16 : BF_OIIO_UINT8, !codes,
                                      px, &data, &size, err),
                       err);
        free(px);
    }
    if (rc == BF_OK)
        rc = write_bytes(path, data, size, err);
    free(data);
    return rc;
}

BF_SIZED_INIT_ZERO(bf_image)

BF_SIZED_INIT_ZERO(bf_image_spec)

/* The module fills the library's own struct, copied out as far as the caller's size
 * reaches (docs/api.md), so it never writes past a caller's older, smaller one. The
 * caller's is emptied first: empty on every failure. */
bf_status bf_image_read(const char *path, bf_image *img, bf_error *err)
{
    if (bf_sized_check(img, sizeof *img, "bf_image", err) != BF_OK)
        return BF_ERR_ARG;
    bf_image mine;
    bf_image_init(&mine);
    bf_sized_copy(img, &mine, sizeof mine);
    const bf_image_plugin *plugin;
    bf_status rc = bf_image_plugin_get(&plugin, err);
    if (rc != BF_OK)
        return rc;
    rc = printable(plugin->read(path, &mine, err), err);
    bf_sized_copy(img, &mine, sizeof mine);
    return rc;
}

bf_status bf_image_read_rows(const char *path, int y0, int y1, bf_image *img, bf_error *err)
{
    if (bf_sized_check(img, sizeof *img, "bf_image", err) != BF_OK)
        return BF_ERR_ARG;
    bf_image mine;
    bf_image_init(&mine);
    bf_sized_copy(img, &mine, sizeof mine);
    if (!path)
        return bf_fail(err, BF_ERR_ARG, "(null): no image file name");
    /* What the file's height does not decide is checked without the module. */
    if (y0 < 0 || y1 <= y0)
        return bf_fail(err, BF_ERR_ARG, "%s: bad rows %d to %d (want 0 <= first < end)", path, y0, y1);
    const bf_image_plugin *plugin;
    bf_status rc = bf_image_plugin_get(&plugin, err);
    if (rc != BF_OK)
        return rc;
    rc = printable(plugin->read_rows(path, y0, y1, &mine, err), err);
    bf_sized_copy(img, &mine, sizeof mine);
    return rc;
}

bf_status bf_image_info(const char *path, bf_image_spec *out, bf_error *err)
{
    if (bf_sized_check(out, sizeof *out, "bf_image_spec", err) != BF_OK)
        return BF_ERR_ARG;
    bf_image_spec mine;
    bf_image_spec_init(&mine);
    bf_sized_copy(out, &mine, sizeof mine);
    if (!path)
        return bf_fail(err, BF_ERR_ARG, "(null): no image file name");
    const bf_image_plugin *plugin;
    bf_status rc = bf_image_plugin_get(&plugin, err);
    if (rc != BF_OK)
        return rc;
    rc = printable(plugin->info(path, &mine, err), err);
    bf_sized_copy(out, &mine, sizeof mine);
    return rc;
}

/* Frees pixels only where img's size reaches it: a zeroed struct (size 0) holds none. */
void bf_image_clear(bf_image *img)
{
    if (img && img->size >= offsetof(bf_image, pixels) + sizeof img->pixels) {
        free(img->pixels);
        img->pixels = NULL;
    }
}
