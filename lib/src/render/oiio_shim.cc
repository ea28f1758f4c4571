// The one place that speaks OpenImageIO (a C++ library): image.h's functions, exported
// with C linkage, catching every exception so nothing crosses into C.
#include "brdfit/image.h"

#include <OpenImageIO/imageio.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

using OIIO::ImageInput;
using OIIO::ImageOutput;
using OIIO::ImageSpec;
using OIIO::TypeDesc;

namespace {

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

bool ends_with(const char *s, const char *suffix)
{
    size_t n = std::strlen(s), m = std::strlen(suffix);
    return n >= m && strcasecmp(s + n - m, suffix) == 0;
}

unsigned char encode8(float v)
{
    float e = bf_srgb_encode(v);
    return static_cast<unsigned char>(std::lround(e * 255.0f));
}

} // namespace

extern "C" float bf_srgb_encode(float v)
{
    if (!(v > 0.0f)) // NaN too
        return 0.0f;
    if (v >= 1.0f)
        return 1.0f;
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

extern "C" int bf_image_format_of(const char *path)
{
    if (!path)
        return 0;
    if (ends_with(path, ".png"))
        return 1;
    if (ends_with(path, ".exr"))
        return 2;
    return 0;
}

extern "C" int bf_image_write_rgb(const char *path, int width, int height, const float *rgb, bf_error *err)
{
    int fmt = bf_image_format_of(path);
    if (!fmt)
        return bf_fail(err, BF_ERR_ARG, "%s: unknown image format (use .png or .exr)", path ? path : "(null)");
    if (width <= 0 || height <= 0 || !rgb)
        return bf_fail(err, BF_ERR_ARG, "%s: bad image size %dx%d", path, width, height);
    std::string tmp;
    try {
        // The plugin is chosen from the target's extension; the pixels go to a temporary
        // file beside it (same file system, so the rename is atomic).
        auto out = ImageOutput::create(path);
        if (!out)
            return bf_fail(err, BF_ERR_IO, "%s: %s", path, one_line(OIIO::geterror()).c_str());
        tmp = std::string(path) + ".tmpXXXXXX";
        int fd = mkstemp(&tmp[0]);
        if (fd < 0)
            return bf_fail(err, BF_ERR_IO, "%s: cannot create a temporary file beside it: %s", path,
                           std::strerror(errno));
        // mkstemp makes the file 0600; the image gets the mode a plain create would.
        mode_t mask = umask(0);
        umask(mask);
        fchmod(fd, 0666 & ~mask);
        close(fd);
        size_t n = static_cast<size_t>(width) * static_cast<size_t>(height) * 3;
        bool ok;
        if (fmt == 1) {
            std::vector<unsigned char> px(n);
            for (size_t i = 0; i < n; i++)
                px[i] = encode8(rgb[i]);
            ImageSpec spec(width, height, 3, TypeDesc::UINT8);
            spec.attribute("oiio:ColorSpace", "sRGB");
            ok = out->open(tmp, spec) && out->write_image(TypeDesc::UINT8, px.data()) && out->close();
        } else {
            ImageSpec spec(width, height, 3, TypeDesc::FLOAT);
            spec.attribute("oiio:ColorSpace", "Linear");
            spec.attribute("compression", "zip");
            ok = out->open(tmp, spec) && out->write_image(TypeDesc::FLOAT, rgb) && out->close();
        }
        if (!ok) {
            std::string msg = one_line(out->geterror());
            out.reset();
            std::remove(tmp.c_str());
            return bf_fail(err, BF_ERR_IO, "%s: %s", path, msg.c_str());
        }
        out.reset();
        if (std::rename(tmp.c_str(), path) != 0) {
            int e = errno;
            std::remove(tmp.c_str());
            return bf_fail(err, BF_ERR_IO, "%s: cannot rename into place: %s", path, std::strerror(e));
        }
    } catch (const std::exception &e) {
        if (!tmp.empty())
            std::remove(tmp.c_str());
        return bf_fail(err, BF_ERR_NOMEM, "%s: %s", path, e.what());
    }
    return BF_OK;
}

extern "C" int bf_image_read(const char *path, bf_image *img, bf_error *err)
{
    std::memset(img, 0, sizeof *img);
    try {
        auto in = ImageInput::open(path);
        if (!in)
            return bf_fail(err, BF_ERR_IO, "%s: %s", path, one_line(OIIO::geterror()).c_str());
        const ImageSpec &spec = in->spec();
        size_t n = static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height) *
                   static_cast<size_t>(spec.nchannels);
        float *px = static_cast<float *>(std::malloc(n * sizeof(float)));
        if (!px)
            return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory for %zu values", path, n);
        if (!in->read_image(0, 0, 0, spec.nchannels, TypeDesc::FLOAT, px)) {
            std::free(px);
            return bf_fail(err, BF_ERR_PARSE, "%s: %s", path, one_line(in->geterror()).c_str());
        }
        img->width = spec.width;
        img->height = spec.height;
        img->channels = spec.nchannels;
        img->pixels = px;
    } catch (const std::exception &e) {
        return bf_fail(err, BF_ERR_NOMEM, "%s: %s", path, e.what());
    }
    return BF_OK;
}

extern "C" void bf_image_free(bf_image *img)
{
    if (img) {
        std::free(img->pixels);
        img->pixels = nullptr;
    }
}
