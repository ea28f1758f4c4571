/* image.h: what needs no OpenImageIO is done here, in C (the format from the name, the
 * argument checks, the sRGB encoding of PNG pixels), so that bad arguments fail without
 * loading anything. The image module (loaded on first use, image_plugin.c) encodes
 * images into memory and reads files; the library writes the bytes (bf_outfile), so a
 * failed write is always seen and never replaces a good file. */
#include "brdfit/image.h"

#include "brdfit/io.h"
#include "render/image_plugin.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

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
    int fmt = format == BF_IMAGE_PNG || format == BF_IMAGE_EXR ? format : bf_image_format_of(path);
    if (!fmt)
        return bf_fail(err, BF_ERR_ARG, "%s: unknown image format (use .png or .exr)", path ? path : "(null)");
    if (width <= 0 || height <= 0 || !rgb)
        return bf_fail(err, BF_ERR_ARG, "%s: bad image size %dx%d", path, width, height);
    const bf_image_plugin *plugin;
    bf_status rc = bf_image_plugin_get(&plugin, err);
    if (rc != BF_OK)
        return rc;
    unsigned char *px = NULL, *data = NULL;
    size_t size = 0;
    if (fmt == 2) {
        rc = plugin->encode_rgb(path, fmt, width, height, rgb, &data, &size, err);
    } else {
        size_t n = (size_t)width * (size_t)height * 3;
        if (!(px = malloc(n)))
            return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory for %zu pixels", path, n / 3);
        for (size_t i = 0; i < n; i++)
            px[i] = (unsigned char)lroundf(bf_srgb_encode(rgb[i]) * 255.0f);
        rc = plugin->encode_rgb(path, fmt, width, height, px, &data, &size, err);
        free(px);
    }
    if (rc == BF_OK)
        rc = write_bytes(path, data, size, err);
    free(data);
    return rc;
}

bf_status bf_image_read(const char *path, bf_image *img, bf_error *err)
{
    memset(img, 0, sizeof *img);
    const bf_image_plugin *plugin;
    bf_status rc = bf_image_plugin_get(&plugin, err);
    return rc != BF_OK ? rc : plugin->read(path, img, err);
}

void bf_image_clear(bf_image *img)
{
    if (img) {
        free(img->pixels);
        img->pixels = NULL;
    }
}
