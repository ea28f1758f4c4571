/* Internal: what the plot files (lib/src/report/plot/) share: the plot object's fields and the
 * helpers used across files. plot.c: the object and its setters; plot_ticks.c: ranges
 * and ticks; plot_text.c: markup text; plot_layout.c: where everything goes;
 * plot_draw.c: drawing a laid-out plot; plot_output.c: the file formats. The decisions
 * that apply to them all are in plot.h. */
#ifndef BRDFIT_PLOT_IMPL_H
#define BRDFIT_PLOT_IMPL_H

#include <cairo.h>
#include <stddef.h>

#include "plot/plot.h"

#define PLOT_FONT_FACE "DejaVu Sans"

typedef struct axis_spec {
    char *title;
    int log, integer, fixed;
    double step, lo, hi;
    plot_ticks *custom; /* ticks given by the caller (plot_axis_ticks), or NULL */
} axis_spec;

/* A colour bar right of the plot area: what the colours of a raster mean. */
typedef struct color_bar {
    char *title;
    double lo, hi;
    int log;
    unsigned char lut[PLOT_LUT][3];
} color_bar;

typedef struct guide {
    int axis;
    double v, rgb[3];
} guide;

struct plot {
    char *title;
    axis_spec axis[2];
    plot_series **s;
    int ns;
    guide *g;
    int ng;
    char **notes;
    int nnotes;
    unsigned char *raster; /* rw x rh RGB bytes over the plot area, or NULL */
    int rw, rh;
    color_bar *bar; /* or NULL */
};

/* ---- Text (plot_text.c) ----------------------------------------------------------- */

typedef struct plot_text_size {
    double width, ascent, descent;
} plot_text_size;

/* Draws (draw 1) or measures markup text with its left end of the baseline at (x, y). */
plot_text_size plot_text_run(cairo_t *cr, const char *s, double size, double x, double y, int draw);
/* Text anchored at (x, y): ax 0 left, 0.5 centre, 1 right; ay 0 top, 0.5 middle, 1
 * baseline. */
plot_text_size plot_text_at(cairo_t *cr, const char *s, double size, double x, double y, double ax, double ay);
/* Text centred at x (top at y), moved and if need be made smaller to stay within
 * [pad, width - pad]. */
void plot_text_centred(cairo_t *cr, const char *s, double size, double x, double y, double width, double pad);

/* ---- Layout (plot_layout.c) ------------------------------------------------------- */

/* Value v of an axis (data units) as a device coordinate in the plot area. */
double plot_map(const plot_layout *l, int axis, double v);
/* Whether the point (x, y) can be shown: finite, and > 0 on a log axis. */
int plot_drawable(const plot_layout *l, double x, double y);
/* The length of a legend entry's sample line. */
double plot_legend_sample_width(double font);
/* The layout, with text measured on cr (it sets the font face on cr). */
void plot_layout_with(const plot *p, cairo_t *cr, int width, int height, plot_layout *l);

/* ---- Drawing (plot_draw.c) -------------------------------------------------------- */

/* The whole plot, laid out as l, on cr. */
void plot_draw(cairo_t *cr, const plot *p, const plot_layout *l);

#endif
