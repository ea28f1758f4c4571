/* Which reader or writer a file gets: by the --format option, else by extension, else
 * by content. */
#include "io/read_options.h"
#include "base/cancel.h"
#include "brdfit/formats.h"
#include "brdfit/io.h"

#include <ctype.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Binary formats by their first bytes (MERL's dimensions, the RGL tensor file's and the
 * mbsdf's magic); text formats by their first meaningful line: ALTA starts with '#' header keys
 * (#DIM ...), Cornell with a lone wavelength count, CSV with a header row. */
static bf_status by_content(const char *path, bf_format *format, bf_error *err)
{
    FILE *fp = bf_input_open(path);
    if (!fp)
        return bf_fail(err, BF_ERR_IO, "%s: cannot open: %s", path, bf_input_error(errno));
    /* MERL tables open with their dimensions, three int32: 90 90 180. */
    unsigned char head[20];
    static const unsigned char merl_dims[12] = {90, 0, 0, 0, 90, 0, 0, 0, 180, 0, 0, 0};
    const size_t got = fread(head, 1, sizeof head, fp);
    bf_format binary = got >= 12 && !memcmp(head, merl_dims, 12)            ? BF_FORMAT_MERL
                       : got >= 12 && !memcmp(head, "tensor_file", 12)      ? BF_FORMAT_RGL
                       : got >= 20 && !memcmp(head, "NVIDIA ARC MBSDF", 16) ? BF_FORMAT_MBSDF
                                                                            : BF_FORMAT_AUTO;
    if (binary != BF_FORMAT_AUTO) {
        fclose(fp);
        *format = binary;
        return BF_OK;
    }
    rewind(fp);
    char line[512];
    bf_format f = BF_FORMAT_CSV;
    while (fgets(line, sizeof line, fp)) {
        if (!strncmp(line, "#DIM", 4) || !strncmp(line, "#PARAM_IN", 9)) {
            f = BF_FORMAT_ALTA;
            break;
        }
        char *p = line;
        while (isspace((unsigned char)*p))
            p++;
        if (*p == '#' || *p == '\0')
            continue;
        char *end;
        strtol(p, &end, 10);
        while (isspace((unsigned char)*end))
            end++;
        if (end != p && *end == '\0') /* a lone integer: Cornell's wavelength count */
            f = BF_FORMAT_CORNELL;
        break;
    }
    fclose(fp);
    *format = f;
    return BF_OK;
}

bf_status bf_samples_read_with(const char *path, const bf_read_options *opt, bf_samples **out, bf_error *err)
{
    bf_format f = opt ? opt->format : BF_FORMAT_AUTO;
    if (f == BF_FORMAT_AUTO)
        f = bf_format_by_extension(path);
    bf_status rc;
    if (f == BF_FORMAT_AUTO && (rc = by_content(path, &f, err)) != BF_OK)
        return rc;
    const char *grid = opt ? opt->grid : NULL;
    if (grid && f != BF_FORMAT_RGL && f != BF_FORMAT_MBSDF) {
        *out = NULL;
        return bf_fail(err, BF_ERR_ARG,
                       "%s: a direction grid (%s) needs a format that can be evaluated anywhere (rgl, mbsdf), not %s",
                       path, grid, bf_format_name(f));
    }
    const bf_cancel_flag *cancel = opt ? opt->cancel : NULL;
    if (bf_cancel_is_set(cancel)) {
        *out = NULL;
        return bf_read_cancelled(path, err);
    }
    switch (f) {
    case BF_FORMAT_RGL: return bf_samples_read_rgl(path, grid, out, err);
    case BF_FORMAT_MBSDF: return bf_samples_read_mbsdf(path, grid, out, err);
    case BF_FORMAT_MERL: return bf_samples_read_merl_cancellable(path, opt ? opt->keep_origin : 0, cancel, out, err);
    case BF_FORMAT_CORNELL: return bf_samples_read_cornell_cancellable(path, cancel, out, err);
    case BF_FORMAT_ALTA: return bf_samples_read_alta_cancellable(path, cancel, out, err);
    default: return bf_samples_read_csv_cancellable(path, opt ? &opt->csv : NULL, cancel, out, err);
    }
}
