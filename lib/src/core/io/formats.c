/* Format names and file extensions, shared by the reader and writer dispatch. */
#include "brdfit/formats.h"

#include <string.h>
#include <strings.h>

static const char *const format_names[] = {"auto", "csv", "merl", "cornell", "alta", "rgl", "mbsdf"};

bf_status bf_format_parse(const char *name, bf_format *out, bf_error *err)
{
    for (int f = 0; name && f < (int)(sizeof format_names / sizeof format_names[0]); f++)
        if (strcmp(name, format_names[f]) == 0) {
            *out = (bf_format)f;
            return BF_OK;
        }
    return bf_fail(err, BF_ERR_ARG, "unknown format '%s' (csv, merl, cornell, alta, rgl, mbsdf)", name ? name : "");
}

int bf_format_from_name(const char *name)
{
    bf_format f;
    return bf_format_parse(name, &f, NULL) == BF_OK ? (int)f : -1;
}

const char *bf_format_name(bf_format f)
{
    return (unsigned)f < sizeof format_names / sizeof format_names[0] ? format_names[f] : "unknown";
}

bf_format bf_format_by_extension(const char *path)
{
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    const char *ext = dot && (!slash || dot > slash) ? dot + 1 : "";
    if (!strcasecmp(ext, "csv"))
        return BF_FORMAT_CSV;
    if (!strcasecmp(ext, "binary"))
        return BF_FORMAT_MERL;
    if (!strcasecmp(ext, "brdf"))
        return BF_FORMAT_CORNELL;
    if (!strcasecmp(ext, "alta"))
        return BF_FORMAT_ALTA;
    if (!strcasecmp(ext, "bsdf"))
        return BF_FORMAT_RGL;
    if (!strcasecmp(ext, "mbsdf"))
        return BF_FORMAT_MBSDF;
    return BF_FORMAT_AUTO;
}

bf_format bf_format_for_writing(const char *path)
{
    bf_format f = bf_format_by_extension(path);
    return f == BF_FORMAT_CSV || f == BF_FORMAT_MERL ? f : BF_FORMAT_AUTO;
}
