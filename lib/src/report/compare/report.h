/* The HTML report's parts (internal): report_html.c writes the page, its tables and the
 * folder; report_pictures.c the slices, spheres and half/difference images. */
#ifndef BRDFIT_COMPARE_REPORT_H
#define BRDFIT_COMPARE_REPORT_H

#include <stdio.h>

#include "brdfit/compare.h"
#include "plot/plot.h"

typedef struct report {
    const bf_compare *c;
    const bf_report_options *o;
    const char *tmp; /* the folder being written */
    FILE *fp;        /* index.html */
    bf_error *err;
} report;

/* Text as HTML: markup escaped, unprintable bytes shown as a terminal shows them. */
void report_esc(FILE *fp, const char *text);
/* A display-referred RGB buffer written as NAME (PNG) in the folder and embedded. */
bf_status report_image(report *r, const char *name, int w, int h, const float *rgb, const char *alt);
/* A plot written as NAME.svg or NAME.png (embedded, by the report's format) and NAME.pdf
 * (linked). */
bf_status report_figure(report *r, const char *name, const plot *p, int w, int h, const char *alt);
/* The data file's name without its folders, for titles. */
const char *report_base_name(const char *path);
/* The fit of a ranked model, or NULL. */
const bf_fit_result *report_fitted(const bf_compare_fit *f);
/* Material i's pictures: slices, spheres, half/difference images. */
bf_status report_pictures(report *r, int i, const bf_compare_material *m);

#endif
