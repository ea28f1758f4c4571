// The image module, libbrdfit-oiio.so: the one place that speaks OpenImageIO (a C++
// library), loaded by the library on first use (image_plugin.c) so that commands without
// images don't load OpenImageIO's ~270 shared libraries. Its entry points (image_plugin.h)
// have C linkage and catch every exception so nothing crosses into C. It uses no brdfit
// symbol (it is linked with --no-undefined): errors are written into the bf_error here.
#include "render/image_plugin.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

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

namespace {

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

BF_OIIO_EXPORT bf_status bf_oiio_encode_rgb(const char *name, int fmt, int width, int height, const void *pixels,
                                      unsigned char **data, size_t *size, bf_error *err)
{
    // The library has checked the name and size and sRGB-encoded PNG pixels (image.c).
    *data = nullptr;
    *size = 0;
    if (!name || (fmt != 1 && fmt != 2) || width <= 0 || height <= 0 || !pixels)
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
        const TypeDesc type = fmt == 1 ? TypeDesc::UINT8 : TypeDesc::FLOAT;
        ImageSpec spec(width, height, 3, type);
        spec.attribute("oiio:ioproxy", TypeDesc::PTR, &proxy);
        if (fmt == 1) {
            spec.attribute("oiio:ColorSpace", "sRGB");
        } else {
            spec.attribute("oiio:ColorSpace", "Linear");
            spec.attribute("compression", "zip");
        }
        if (!(out->open(name, spec) && out->write_image(type, pixels) && out->close()))
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

BF_OIIO_EXPORT bf_status bf_oiio_read(const char *path, bf_image *img, bf_error *err)
{
    std::memset(img, 0, sizeof *img);
    try {
        auto in = ImageInput::open(path);
        if (!in)
            return fail(err, BF_ERR_IO, "%s: %s", path, one_line(OIIO::geterror()).c_str());
        const ImageSpec &spec = in->spec();
        size_t n = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height) *
                   static_cast<size_t>(spec.nchannels);
        // malloc, not new: the library frees it (bf_image_clear), with the same C library.
        float *px = static_cast<float *>(std::malloc(n * sizeof(float)));
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
