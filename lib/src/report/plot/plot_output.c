/* A plot as PNG, SVG or PDF bytes, Cairo writing to memory; a file written from them
 * through bf_outfile (no partial file on failure); and the format names. A PDF carries
 * no creation date, so the same plot gives the same bytes in every format. */
#include "plot/plot_impl.h"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "brdfit/error.h"
#include "brdfit/io.h"

typedef struct membuf {
    unsigned char *data;
    size_t len, cap;
    int failed;
} membuf;

static cairo_status_t mem_write(void *closure, const unsigned char *data, unsigned int length)
{
    membuf *m = closure;
    if (m->len + length > m->cap) {
        size_t cap = m->cap ? m->cap : 65536;
        while (cap < m->len + length)
            cap *= 2;
        unsigned char *d = realloc(m->data, cap);
        if (!d) {
            m->failed = 1;
            return CAIRO_STATUS_WRITE_ERROR;
        }
        m->data = d;
        m->cap = cap;
    }
    memcpy(m->data + m->len, data, length);
    m->len += length;
    return CAIRO_STATUS_SUCCESS;
}

bf_status plot_encode(const plot *p, bf_plot_format fmt, int width, int height, unsigned char **data, size_t *len,
                      bf_error *err)
{
    *data = NULL;
    *len = 0;
    if (width < 40 || height < 40 || width > 16384 || height > 16384)
        return bf_fail(err, BF_ERR_ARG, "plot size %dx%d: each side must be 40 to 16384", width, height);
    if (fmt != BF_PLOT_PNG && fmt != BF_PLOT_SVG && fmt != BF_PLOT_PDF)
        return bf_fail(err, BF_ERR_ARG, "plot: unknown format");
    membuf m = {NULL, 0, 0, 0};
    cairo_surface_t *s;
    if (fmt == BF_PLOT_PNG)
        s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
    else if (fmt == BF_PLOT_SVG)
        s = cairo_svg_surface_create_for_stream(mem_write, &m, width, height);
    else {
        s = cairo_pdf_surface_create_for_stream(mem_write, &m, width, height);
        /* No creation date: the same plot gives the same bytes. */
        cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_CREATOR, "brdfit");
        cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_CREATE_DATE, "");
        if (p->title) {
            char plain[512];
            plot_plain_text(p->title, plain, sizeof plain);
            cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_TITLE, plain);
        }
    }
    cairo_t *cr = cairo_create(s);
    plot_layout l;
    bf_status rc = BF_OK;
    if (cairo_status(cr) != CAIRO_STATUS_SUCCESS) {
        rc = bf_fail(err, BF_ERR_NOMEM, "plot: cannot draw: %s", cairo_status_to_string(cairo_status(cr)));
    } else {
        plot_layout_with(p, cr, width, height, &l);
        plot_draw(cr, p, &l);
        if (cairo_status(cr) != CAIRO_STATUS_SUCCESS)
            rc = bf_fail(err, BF_ERR_NOMEM, "plot: cannot draw: %s", cairo_status_to_string(cairo_status(cr)));
    }
    cairo_destroy(cr);
    if (rc == BF_OK && fmt == BF_PLOT_PNG) {
        cairo_surface_flush(s);
        if (cairo_surface_write_to_png_stream(s, mem_write, &m) != CAIRO_STATUS_SUCCESS)
            rc = bf_fail(err, BF_ERR_NOMEM, "plot: cannot encode the PNG");
    }
    cairo_surface_finish(s);
    if (rc == BF_OK && (m.failed || cairo_surface_status(s) != CAIRO_STATUS_SUCCESS))
        rc = bf_fail(err, BF_ERR_NOMEM, "plot: cannot encode: %s", cairo_status_to_string(cairo_surface_status(s)));
    cairo_surface_destroy(s);
    if (rc != BF_OK) {
        free(m.data);
        return rc;
    }
    *data = m.data;
    *len = m.len;
    return BF_OK;
}

bf_status plot_write(const plot *p, const char *path, bf_plot_format fmt, int width, int height, bf_error *err)
{
    unsigned char *data;
    size_t len;
    bf_status rc = plot_encode(p, fmt, width, height, &data, &len, err);
    if (rc != BF_OK) {
        if (path && err && !strstr(err->msg, path)) {
            char msg[sizeof err->msg];
            snprintf(msg, sizeof msg, "%s", err->msg);
            bf_fail(err, rc, "%s: %s", path, msg);
        }
        return rc;
    }
    bf_outfile f;
    if ((rc = bf_outfile_open(&f, path, err)) == BF_OK) {
        fwrite(data, 1, len, f.fp);
        rc = bf_outfile_commit(&f, err); /* checks the write */
    }
    free(data);
    return rc;
}

/* ---- Public: formats ----------------------------------------------------------------- */

int bf_plot_format_of(const char *path)
{
    const char *dot = path ? strrchr(path, '.') : NULL;
    if (!dot || strchr(dot, '/'))
        return 0;
    return !strcasecmp(dot, ".png")   ? BF_PLOT_PNG
           : !strcasecmp(dot, ".svg") ? BF_PLOT_SVG
           : !strcasecmp(dot, ".pdf") ? BF_PLOT_PDF
                                      : 0;
}

bf_status bf_plot_format_parse(const char *name, bf_plot_format *out, bf_error *err)
{
    bf_plot_format f = !name                  ? BF_PLOT_BY_NAME
                       : !strcmp(name, "png") ? BF_PLOT_PNG
                       : !strcmp(name, "svg") ? BF_PLOT_SVG
                       : !strcmp(name, "pdf") ? BF_PLOT_PDF
                                              : BF_PLOT_BY_NAME;
    if (f == BF_PLOT_BY_NAME)
        return bf_fail(err, BF_ERR_ARG, "unknown plot format '%s' (png, svg, pdf)", name ? name : "");
    *out = f;
    return BF_OK;
}
