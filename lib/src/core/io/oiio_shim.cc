// The image module, libbrdfit-oiio.so: the one place that speaks OpenImageIO (a C++
// library), loaded by the library on first use (image_plugin.c) so that commands without
// images don't load OpenImageIO's ~270 shared libraries. Its entry points (image_plugin.h)
// have C linkage and catch every exception so nothing crosses into C. It uses no brdfit
// symbol (it is linked with --no-undefined): errors are written into the bf_error here.
#include "io/image_plugin.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#define BF_OIIO_EXPORT extern "C" __attribute__((visibility("default")))

using OIIO::ImageInput;
using OIIO::ImageOutput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

namespace
{

// bf_fail's contract, without needing the library's copy.
__attribute__((format(printf, 3, 4))) bf_status fail(bf_error *err, bf_status code, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        std::vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
        err->code = code;
    }
    return code;
}

// OpenImageIO messages may span lines; ours are one line.
std::string one_line(std::string s)
{
    for (char &c : s)
        if (c == '\n' || c == '\r')
            c = ' ';
    while (!s.empty() && s.back() == ' ')
        s.pop_back();
    return s.empty() ? std::string("unknown OpenImageIO error") : s;
}

} // namespace

BF_OIIO_EXPORT int bf_oiio_abi(void)
{
    return BF_IMAGE_PLUGIN_ABI;
}

// Flat C arguments: the entry point is found by name (dlsym) across the module boundary.
BF_OIIO_EXPORT bf_status bf_oiio_encode(const char *name, int fmt, int width, int height, int channels, int type,
                                        int srgb, const void *pixels, unsigned char **data, size_t *size, bf_error *err)
{
    // The library has checked the name and size and turned PNG values into codes (image.c).
    *data = nullptr;
    *size = 0;
    const bool types_ok = fmt == 1 ? (type == BF_OIIO_UINT8 || type == BF_OIIO_UINT16) : type == BF_OIIO_FLOAT;
    if (!name || (fmt != 1 && fmt != 2) || !types_ok || (channels != 1 && channels != 3 && channels != 4) ||
        width <= 0 || height <= 0 || !pixels)
        return fail(err, BF_ERR_ARG, "%s: bad image arguments", name ? name : "(null)");
    try {
        // Encoded into memory through an IOProxy: OpenImageIO's PNG writer does not report
        // a failed write (a full disk gave a truncated file and success), so the library
        // writes the bytes itself, checking each write.
        auto out = ImageOutput::create(fmt == 1 ? "png" : "exr");
        if (!out)
            return fail(err, BF_ERR_IO, "%s: %s", name, one_line(OIIO::geterror()).c_str());
        if (!out->supports("ioproxy"))
            return fail(err, BF_ERR_IO, "%s: this OpenImageIO cannot encode %s into memory", name,
                        fmt == 1 ? "PNG" : "EXR");
        std::vector<unsigned char> bytes;
        OIIO::Filesystem::IOVecOutput vec(bytes);
        void *proxy = &vec;
        const TypeDesc td = type == BF_OIIO_UINT8    ? TypeDesc::UINT8
                            : type == BF_OIIO_UINT16 ? TypeDesc::UINT16
                                                     : TypeDesc::FLOAT;
        ImageSpec spec(width, height, channels, td);
        if (channels == 1) // OpenImageIO's default too; said here as image.h promises it
            spec.channelnames.assign(1, "Y");
        spec.attribute("oiio:ioproxy", TypeDesc::PTR, &proxy);
        if (fmt == 1) {
            if (srgb)
                spec.attribute("oiio:ColorSpace", "sRGB");
            if (channels == 4) // the codes as given, not divided by alpha
                spec.attribute("oiio:UnassociatedAlpha", 1);
        } else {
            spec.attribute("oiio:ColorSpace", "Linear");
            spec.attribute("compression", "zip");
        }
        if (!(out->open(name, spec) && out->write_image(td, pixels) && out->close()))
            return fail(err, BF_ERR_IO, "%s: %s", name, one_line(out->geterror()).c_str());
        // malloc, not new: the library frees it, with the same C library.
        unsigned char *copy = static_cast<unsigned char *>(std::malloc(bytes.size() ? bytes.size() : 1));
        if (!copy)
            return fail(err, BF_ERR_NOMEM, "%s: out of memory for %zu bytes", name, bytes.size());
        std::memcpy(copy, bytes.data(), bytes.size());
        *data = copy;
        *size = bytes.size();
    } catch (const std::exception &e) {
        return fail(err, BF_ERR_NOMEM, "%s: %s", name, e.what());
    }
    return BF_OK;
}

namespace
{

// Opens path for reading, or fails with BF_ERR_IO naming it. Images with alpha are read
// as stored (no premultiplication), as image.h promises: codes, not colours. Each call has
// its own ImageInput, so different files may be read from several threads at once.
bf_status open_input(const char *path, std::unique_ptr<ImageInput> &in, bf_error *err)
{
    if (!path)
        return fail(err, BF_ERR_ARG, "(null): no image file name");
    ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    in = ImageInput::open(path, &config);
    if (!in)
        return fail(err, BF_ERR_IO, "%s: %s", path, one_line(OIIO::geterror()).c_str());
    return BF_OK;
}

// Room for n floats from malloc (the library frees it, with the same C library).
float *alloc_floats(size_t n)
{
    return static_cast<float *>(std::malloc((n ? n : 1) * sizeof(float)));
}

} // namespace

BF_OIIO_EXPORT bf_status bf_oiio_read(const char *path, bf_image *img, bf_error *err)
{
    std::memset(img, 0, sizeof *img);
    try {
        std::unique_ptr<ImageInput> in;
        bf_status rc = open_input(path, in, err);
        if (rc != BF_OK)
            return rc;
        const ImageSpec &spec = in->spec();
        size_t n =
            static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height) * static_cast<size_t>(spec.nchannels);
        float *px = alloc_floats(n);
        if (!px)
            return fail(err, BF_ERR_NOMEM, "%s: out of memory for %zu values", path, n);
        if (!in->read_image(0, 0, 0, spec.nchannels, TypeDesc::FLOAT, px)) {
            std::free(px);
            return fail(err, BF_ERR_PARSE, "%s: %s", path, one_line(in->geterror()).c_str());
        }
        img->width = spec.width;
        img->height = spec.height;
        img->channels = spec.nchannels;
        img->pixels = px;
    } catch (const std::exception &e) {
        return fail(err, BF_ERR_NOMEM, "%s: %s", path, e.what());
    }
    return BF_OK;
}

BF_OIIO_EXPORT bf_status bf_oiio_read_rows(const char *path, int y0, int y1, bf_image *img, bf_error *err)
{
    std::memset(img, 0, sizeof *img);
    try {
        std::unique_ptr<ImageInput> in;
        bf_status rc = open_input(path, in, err);
        if (rc != BF_OK)
            return rc;
        const ImageSpec &spec = in->spec();
        if (y0 < 0 || y1 <= y0 || y1 > spec.height)
            return fail(err, BF_ERR_ARG, "%s: rows %d to %d are not within the image's %d rows", path, y0, y1,
                        spec.height);
        const size_t nch = static_cast<size_t>(spec.nchannels), w = static_cast<size_t>(spec.width);
        const size_t row = w * nch, n = row * static_cast<size_t>(y1 - y0);
        float *px = alloc_floats(n);
        if (!px)
            return fail(err, BF_ERR_NOMEM, "%s: out of memory for %zu values", path, n);
        bool ok;
        if (spec.tile_width <= 0) {
            // Rows are counted from the top of the data window (as read_image returns it).
            ok = in->read_scanlines(0, 0, spec.y + y0, spec.y + y1, spec.z, 0, spec.nchannels, TypeDesc::FLOAT, px);
        } else {
            // A tiled file: the rows of whole tiles around the band, then the band.
            const int th = spec.tile_height > 0 ? spec.tile_height : 1;
            const int t0 = y0 / th * th, t1 = std::min((y1 + th - 1) / th * th, spec.height);
            std::vector<float> tiles(row * static_cast<size_t>(t1 - t0));
            ok = in->read_tiles(0, 0, spec.x, spec.x + spec.width, spec.y + t0, spec.y + t1, spec.z,
                                spec.z + std::max(1, spec.depth), 0, spec.nchannels, TypeDesc::FLOAT, tiles.data());
            if (ok)
                std::memcpy(px, tiles.data() + row * static_cast<size_t>(y0 - t0), n * sizeof(float));
        }
        if (!ok) {
            std::free(px);
            return fail(err, BF_ERR_PARSE, "%s: %s", path, one_line(in->geterror()).c_str());
        }
        img->width = spec.width;
        img->height = y1 - y0;
        img->channels = spec.nchannels;
        img->pixels = px;
    } catch (const std::exception &e) {
        return fail(err, BF_ERR_NOMEM, "%s: %s", path, e.what());
    }
    return BF_OK;
}

BF_OIIO_EXPORT bf_status bf_oiio_info(const char *path, bf_image_spec *out, bf_error *err)
{
    std::memset(out, 0, sizeof *out);
    try {
        std::unique_ptr<ImageInput> in;
        bf_status rc = open_input(path, in, err);
        if (rc != BF_OK)
            return rc;
        const ImageSpec &spec = in->spec();
        const TypeDesc::BASETYPE b = static_cast<TypeDesc::BASETYPE>(spec.format.basetype);
        out->width = spec.width;
        out->height = spec.height;
        out->channels = spec.nchannels;
        out->bits = static_cast<int>(spec.format.basesize() * 8);
        out->is_float = b == TypeDesc::HALF || b == TypeDesc::FLOAT || b == TypeDesc::DOUBLE;
    } catch (const std::exception &e) {
        return fail(err, BF_ERR_NOMEM, "%s: %s", path, e.what());
    }
    return BF_OK;
}
