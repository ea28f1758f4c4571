/* What the report's writers share (report.h): HTML text, an image or a figure written
 * into the folder and embedded, names and fits to show. Apart from the page
 * (report_html.c), which calls the pictures and the viewer that call these. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/image.h"
#include "brdfit/io.h"
#include "html/report.h"

/* Text from the data and the command line as HTML: markup escaped, and control
 * characters and invalid UTF-8, which HTML cannot show, as a terminal shows them
 * (bf_printable_dup; out of memory: dropped). */
void report_esc(FILE *fp, const char *text)
{
    char *safe = bf_printable_dup(text);
    for (const char *s = safe ? safe : ""; *s; s++)
        switch (*s) {
        case '&': fputs("&amp;", fp); break;
        case '<': fputs("&lt;", fp); break;
        case '>': fputs("&gt;", fp); break;
        case '"': fputs("&quot;", fp); break;
        case '\'': fputs("&#39;", fp); break;
        default: fputc(*s, fp);
        }
    free(safe);
}

bf_status report_image(report_page *r, const char *name, int w, int h, const float *rgb, const char *alt)
{
    char path[4096];
    if (snprintf(path, sizeof path, "%s/%s", r->tmp, name) >= (int)sizeof path)
        return bf_fail(r->err, BF_ERR_ARG, "%s: path too long", r->tmp);
    if (bf_image_write_rgb(path, w, h, rgb, r->err) != BF_OK)
        return r->err->code;
    fprintf(r->fp, "<img src=\"%s\" width=\"%d\" height=\"%d\" alt=\"", name, w, h);
    report_esc(r->fp, alt);
    fputs("\">", r->fp);
    return BF_OK;
}

bf_status report_figure(report_page *r, const char *name, const plot *p, int w, int h, const char *alt)
{
    /* SVG stays sharp when zoomed; PNG is what any viewer shows; the PDF is for papers,
     * written only when asked for (format PDF): a PDF of every figure about doubles a
     * report's size. */
    const char *shown = r->o->format == BF_PLOT_SVG ? "svg" : "png";
    const bf_plot_format fmt[2] = {r->o->format == BF_PLOT_SVG ? BF_PLOT_SVG : BF_PLOT_PNG, BF_PLOT_PDF};
    const int with_pdf = r->o->format == BF_PLOT_PDF;
    char path[4096];
    for (int f = 0; f < 1 + with_pdf; f++) {
        if (snprintf(path, sizeof path, "%s/%s.%s", r->tmp, name, f ? "pdf" : shown) >= (int)sizeof path)
            return bf_fail(r->err, BF_ERR_ARG, "%s: path too long", r->tmp);
        bf_status rc = plot_write(p, path, fmt[f], w, h, r->err);
        if (rc != BF_OK)
            return rc;
    }
    fprintf(r->fp, "<img src=\"%s.%s\" width=\"%d\" height=\"%d\" alt=\"", name, shown, w, h);
    report_esc(r->fp, alt);
    fputs("\">", r->fp);
    if (with_pdf)
        fprintf(r->fp, "<br><a class=\"pdf\" href=\"%s.pdf\">PDF</a>", name);
    return BF_OK;
}

/* The data file's name without its folders, for plot titles. */
const char *report_base_name(const char *path)
{
    const char *b = strrchr(path, '/');
    return b && b[1] ? b + 1 : path;
}

const bf_fit_result *report_fitted(const bf_compare_fit *f)
{
    return f->state == BF_CMP_OK && f->result && f->result->model ? f->result : NULL;
}
