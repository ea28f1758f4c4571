/* 2D plots drawn with Cairo (internal to the library): lines and markers on linear or
 * log axes, with a title, axis titles, "nice" ticks, a legend and labelled points;
 * written as PNG, SVG or PDF through bf_outfile (no partial file on failure).
 *
 * Text is UTF-8 with a small markup: "^{...}" raises and "_{...}" lowers the braced
 * text (10^{-3}, theta_{o}). Sizes are in pixels for PNG and points for SVG and PDF.
 *
 * Decisions:
 *  - Ranges come from the data (non-finite values, and values <= 0 on a log axis, are
 *    left out), widened to a minimum span so that they never collapse and so that a
 *    tiny spread does not fill the whole axis (linear: 10% of the larger magnitude, 1
 *    around 0; log: 0.1 decade), then padded by 5% of the span on each side. A range
 *    set with plot_axis_range is used as given (shared scales across plots).
 *  - Ticks: 1-2-5 steps on linear axes; on log axes whole decades labelled 10^{k} when
 *    the range spans three decades or more (every 2nd, 5th ... when crowded), else the
 *    labelled 1-2-5 values of the range (one notation for the axis) when there are 3 to
 *    a few more than asked for, else the decades, else linear 1-2-5 ticks of the values.
 *    Given ticks (plot_axis_ticks) replace them all.
 *  - Legend sample lines sit on pixel-row centres, so equal lines look equal in a PNG.
 *  - A raster (plot_raster) fills the plot area in place of the grid, cells kept sharp;
 *    a colour bar (plot_colour_bar) stands right of the plot area and the legend.
 *  - The legend sits right of the plot area, so it never covers data; a legend wider
 *    than 30% of the figure goes inside, in the corner that covers the fewest points.
 *    Point labels take the first free place around their point. */
#ifndef BRDFIT_PLOT_H
#define BRDFIT_PLOT_H

#include <stddef.h>

#include "brdfit/error.h"
#include "brdfit/render.h"

#define PLOT_MAX_TICKS 32
#define PLOT_LABEL_LEN 48
#define PLOT_LUT 256 /* entries of a colour bar's table */

enum { PLOT_X = 0, PLOT_Y = 1 };
typedef enum plot_style { PLOT_LINE = 1, PLOT_MARKERS = 2, PLOT_LINE_MARKERS = 3 } plot_style;
typedef enum plot_marker { PLOT_CIRCLE = 0, PLOT_SQUARE, PLOT_DIAMOND, PLOT_TRIANGLE, PLOT_RING } plot_marker;
typedef enum plot_dash { PLOT_SOLID = 0, PLOT_DASHED, PLOT_DOTTED } plot_dash;

typedef struct plot_series {
    char *name; /* legend entry (markup); NULL: not in the legend */
    plot_style style;
    plot_marker marker;
    plot_dash dash;
    double rgb[3], alpha;           /* alpha 1: opaque */
    double line_width, marker_size; /* in units of the base line width / font size */
    size_t n;
    double *x, *y;
    char **labels;         /* n point labels (NULL entries: none), or NULL */
    unsigned char *colors; /* n RGB byte triples, one per marker (plot_point_colors), or
                               NULL: rgb for every marker */
} plot_series;

typedef struct plot plot;

/* The ticks of one axis as laid out: positions in data units and their labels. */
typedef struct plot_ticks {
    int n;
    double value[PLOT_MAX_TICKS];
    char label[PLOT_MAX_TICKS][PLOT_LABEL_LEN];
    int nminor;
    double minor[4 * PLOT_MAX_TICKS];
} plot_ticks;

typedef struct plot_axis_layout {
    double lo, hi; /* the axis ends, data units */
    int log;
    plot_ticks ticks;
} plot_axis_layout;

/* Where everything goes, computed before drawing (and what the tests check). */
typedef struct plot_layout {
    double width, height, font; /* font: the base text size */
    double x0, y0, x1, y1;      /* plot area (top-left x0,y0) */
    plot_axis_layout axis[2];
    int nlegend; /* series with a name, in order */
    double legend_x, legend_y, legend_w, legend_h;
    int legend_inside; /* 1: in a corner of the plot area (a wide legend) */
    int color_bar;     /* 1: a colour bar right of the plot area (and legend) */
    double bar_x, bar_w;
    plot_ticks bar_ticks;
} plot_layout;

plot *plot_new(const char *title);
void plot_free(plot *p);
/* Axis title (markup), log scale, an integer axis (ticks at whole numbers only), and a
 * fixed tick step on a linear axis (0: automatic). */
int plot_axis(plot *p, int axis, const char *title, int log);
void plot_axis_integer(plot *p, int axis);
void plot_axis_step(plot *p, int axis, double step);
/* A fixed range (data units); lo < hi (on a log axis, 0 < lo). */
void plot_axis_range(plot *p, int axis, double lo, double hi);
/* Ticks at n given positions (data units) with the given labels (markup), in place of
 * the computed ones: an axis whose numbers are not its values (sqrt theta_h, labelled
 * in degrees). 0, or -1 when out of memory. */
int plot_axis_ticks(plot *p, int axis, int n, const double *values, const char *const *labels);
/* An image of width x height RGB bytes (top row first, copied) filling the plot area,
 * in place of the grid: set both axis ranges to what its edges stand for. Cells stay
 * sharp blocks when scaled. 0, or -1 when out of memory. */
int plot_raster(plot *p, int width, int height, const unsigned char *rgb);
/* A colour bar right of the plot area: lut[0] at lo up to lut[PLOT_LUT-1] at hi, on a
 * linear or log scale, ticked and titled (markup). 0, or -1 when out of memory. */
int plot_color_bar(plot *p, const char *title, double lo, double hi, int log, const unsigned char lut[PLOT_LUT][3]);
/* A series (x, y copied); NULL when out of memory. Colour, dash, marker and sizes are
 * set on the returned series; defaults: black, solid, circle, opaque, size 1. */
plot_series *plot_add(plot *p, const char *name, plot_style style, size_t n, const double *x, const double *y);
/* Point labels (copied; entries may be NULL): 0, or -1 when out of memory. */
int plot_point_labels(plot_series *s, const char *const *labels);
/* A colour per marker (3 * n RGB bytes, copied), in place of rgb: values shown as
 * coloured points against a colour bar. Markers are drawn in the series' order, the
 * last on top. 0, or -1 when out of memory. */
int plot_point_colors(plot_series *s, const unsigned char *rgb);
/* A faint guide line across the plot area at value v of the axis. */
int plot_guide(plot *p, int axis, double v, const double rgb[3]);
/* A line of text under the plot area (markup). */
int plot_note(plot *p, const char *text);
int plot_nseries(const plot *p);
const plot_series *plot_series_at(const plot *p, int i);

/* Colour k of the palette (Okabe-Ito, distinguishable by most colour-blind readers). */
void plot_palette(int k, double rgb[3]);

/* The data extent of values v (finite; > 0 on a log axis): 1, or 0 when none. */
int plot_extent(size_t n, const double *v, int log, double *lo, double *hi);
/* An axis range from a data extent (as the header says); have 0: no data. */
void plot_pad(double lo, double hi, int have, int log, double *out_lo, double *out_hi);
/* Ticks for [lo, hi] (data units); target: about how many; integer: whole numbers only;
 * step: a fixed linear step (0: automatic). */
void plot_make_ticks(double lo, double hi, int log, int target, int integer, double step, plot_ticks *t);

/* The layout at width x height: 0, or -1 when Cairo cannot measure text. */
int plot_layout_compute(const plot *p, int width, int height, plot_layout *l);

/* The plot as a file's bytes (malloc'd): BF_OK, or an error. */
bf_status plot_encode(const plot *p, bf_plot_format fmt, int width, int height, unsigned char **data, size_t *len,
                      bf_error *err);
/* Written to path ("-": standard output) through bf_outfile. */
bf_status plot_write(const plot *p, const char *path, bf_plot_format fmt, int width, int height, bf_error *err);

/* The markup's plain text (braces and ^ _ dropped), for tests and messages. */
void plot_plain_text(const char *markup, char *out, size_t size);

#endif
