// The image module, libbrdfit-oiio.so: the one place that speaks OpenImageIO (a C++
// library), loaded by the library on first use (image_plugin.c) so that commands without
// images don't load OpenImageIO's ~270 shared libraries. Its entry points (image_plugin.h)
// have C linkage and catch every exception so nothing crosses into C. It uses no brdfit
// symbol (it is linked with --no-undefined): errors are written into the bf_error here.
#include "render/image_plugin.h"

#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

#define BF_OIIO_EXPORT extern "C" __attribute__((visibility("default")))

using OIIO::ImageInput;
using OIIO::ImageOutput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

namespace {

// bf_fail's contract, without needing the library's copy.
__attribute__((format(printf, 3, 4))) int fail(bf_error *err, bf_status code, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        std::vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
        err->code = code;
    }
    return static_cast<int>(code);
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

BF_OIIO_EXPORT int bf_oiio_write_rgb(const char *path, int fmt, int width, int height, const void *pixels,
                                     bf_error *err)
{
    // The library has checked the name and size and sRGB-encoded PNG pixels (image.c).
    if (!path || (fmt != 1 && fmt != 2) || width <= 0 || height <= 0 || !pixels)
        return fail(err, BF_ERR_ARG, "%s: bad image arguments", path ? path : "(null)");
    std::string tmp;
    try {
        // The plugin is chosen from the target's extension; the pixels go to a temporary
        // file beside it (same file system, so the rename is atomic).
        auto out = ImageOutput::create(path);
        if (!out)
            return fail(err, BF_ERR_IO, "%s: %s", path, one_line(OIIO::geterror()).c_str());
        tmp = std::string(path) + ".tmpXXXXXX";
        int fd = mkstemp(&tmp[0]);
        if (fd < 0)
            return fail(err, BF_ERR_IO, "%s: cannot create a temporary file beside it: %s", path,
                        std::strerror(errno));
        // mkstemp makes the file 0600; the image gets the mode a plain create would.
        mode_t mask = umask(0);
        umask(mask);
        fchmod(fd, 0666 & ~mask);
        close(fd);
        bool ok;
        if (fmt == 1) {
            ImageSpec spec(width, height, 3, TypeDesc::UINT8);
            spec.attribute("oiio:ColorSpace", "sRGB");
            ok = out->open(tmp, spec) && out->write_image(TypeDesc::UINT8, pixels) && out->close();
        } else {
            ImageSpec spec(width, height, 3, TypeDesc::FLOAT);
            spec.attribute("oiio:ColorSpace", "Linear");
            spec.attribute("compression", "zip");
            ok = out->open(tmp, spec) && out->write_image(TypeDesc::FLOAT, pixels) && out->close();
        }
        if (!ok) {
            std::string msg = one_line(out->geterror());
            out.reset();
            std::remove(tmp.c_str());
            return fail(err, BF_ERR_IO, "%s: %s", path, msg.c_str());
        }
        out.reset();
        if (std::rename(tmp.c_str(), path) != 0) {
            int e = errno;
            std::remove(tmp.c_str());
            return fail(err, BF_ERR_IO, "%s: cannot rename into place: %s", path, std::strerror(e));
        }
    } catch (const std::exception &e) {
        if (!tmp.empty())
            std::remove(tmp.c_str());
        return fail(err, BF_ERR_NOMEM, "%s: %s", path, e.what());
    }
    return BF_OK;
}

BF_OIIO_EXPORT int bf_oiio_read(const char *path, bf_image *img, bf_error *err)
{
    std::memset(img, 0, sizeof *img);
    try {
        auto in = ImageInput::open(path);
        if (!in)
            return fail(err, BF_ERR_IO, "%s: %s", path, one_line(OIIO::geterror()).c_str());
        const ImageSpec &spec = in->spec();
        size_t n = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height) *
                   static_cast<size_t>(spec.nchannels);
        // malloc, not new: the library frees it (bf_image_free), with the same C library.
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
