/* The HTML report's parts (internal): report_html.c writes the page, its tables and the
 * folder; report_pictures.c the slices, spheres and half/difference images;
 * report_viewer.c the interactive viewer; report_util.c what they share. */
#ifndef BRDFIT_COMPARE_REPORT_H
#define BRDFIT_COMPARE_REPORT_H

#include <stdio.h>

#include "brdfit/compare.h"
#include "plot/plot.h"

typedef struct report_page {
    const bf_compare *c;
    const bf_report_options *o;
    const char *tmp; /* the folder being written */
    FILE *fp;        /* index.html */
    bf_error *err;
} report_page;

/* Text as HTML: markup escaped, unprintable bytes shown as a terminal shows them. */
void report_esc(FILE *fp, const char *text);
/* A display-referred RGB buffer written as NAME (PNG) in the folder and embedded. */
bf_status report_image(report_page *r, const char *name, int w, int h, const float *rgb, const char *alt);
/* A plot written as NAME.svg or NAME.png (embedded, by the report's format), and
 * NAME.pdf (linked) when the format is PDF. */
bf_status report_figure(report_page *r, const char *name, const plot *p, int w, int h, const char *alt);
/* The data file's name without its folders, for titles. */
const char *report_base_name(const char *path);
/* The fit of a ranked model, or NULL. */
const bf_fit_result *report_fitted(const bf_compare_fit *f);
/* The measurement of material i to draw pictures of (a whole MERL table, or MERL cells
 * an RGL or MDL file was evaluated at), or NULL with *why saying why there is none. */
const bf_samples *report_measured_table(const report_page *r, int i, const char **why);
/* Material i's pictures: slices, spheres, half/difference images. */
bf_status report_pictures(report_page *r, int i, const bf_compare_material *m);
/* Material i's interactive viewer: its data file (mN-viewer.js) and its place in the
 * page; table and why as report_measured_table gives them. */
bf_status report_viewer(report_page *r, int i, const bf_compare_material *m, const bf_samples *table, const char *why);
/* The viewer's code, viewer.js, written once into the folder. */
bf_status report_viewer_code(report_page *r);

#endif
