/* 2D plots with Cairo: see plot.h. */
#include "plot/plot.h"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#include <ctype.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "brdfit/error.h"
#include "brdfit/io.h"

#define FONT_FACE "DejaVu Sans"

typedef struct axis_spec {
    char *title;
    int log, integer, fixed;
    double step, lo, hi;
    plot_ticks *custom; /* ticks given by the caller (plot_axis_ticks), or NULL */
} axis_spec;

/* A colour bar right of the plot area: what the colours of a raster mean. */
typedef struct colour_bar {
    char *title;
    double lo, hi;
    int log;
    unsigned char lut[PLOT_LUT][3];
} colour_bar;

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
    colour_bar *bar;       /* or NULL */
};

/* Text as Cairo can take it: from file names and the command line it may hold invalid
 * UTF-8 or control characters, which are escaped as a terminal shows them. */
static char *text_dup(const char *s)
{
    return bf_printable_dup(s);
}

static char *dup_or_null(const char *s)
{
    return s ? text_dup(s) : NULL;
}

plot *plot_new(const char *title)
{
    plot *p = calloc(1, sizeof *p);
    if (p && title && !(p->title = text_dup(title))) {
        free(p);
        return NULL;
    }
    return p;
}

static void series_free(plot_series *s)
{
    if (!s)
        return;
    if (s->labels)
        for (size_t i = 0; i < s->n; i++)
            free(s->labels[i]);
    free(s->labels);
    free(s->name);
    free(s->x);
    free(s);
}

void plot_free(plot *p)
{
    if (!p)
        return;
    for (int i = 0; i < p->ns; i++)
        series_free(p->s[i]);
    for (int i = 0; i < p->nnotes; i++)
        free(p->notes[i]);
    free(p->notes);
    free(p->s);
    free(p->g);
    free(p->axis[0].title);
    free(p->axis[1].title);
    free(p->axis[0].custom);
    free(p->axis[1].custom);
    free(p->raster);
    if (p->bar)
        free(p->bar->title);
    free(p->bar);
    free(p->title);
    free(p);
}

int plot_axis(plot *p, int axis, const char *title, int log)
{
    axis_spec *a = &p->axis[axis];
    free(a->title);
    a->title = dup_or_null(title);
    a->log = log;
    return !title || a->title ? 0 : -1;
}

void plot_axis_integer(plot *p, int axis)
{
    p->axis[axis].integer = 1;
}

void plot_axis_step(plot *p, int axis, double step)
{
    p->axis[axis].step = step;
}

void plot_axis_range(plot *p, int axis, double lo, double hi)
{
    axis_spec *a = &p->axis[axis];
    a->fixed = lo < hi && (!a->log || lo > 0.0);
    a->lo = lo;
    a->hi = hi;
}

int plot_axis_ticks(plot *p, int axis, int n, const double *values, const char *const *labels)
{
    axis_spec *a = &p->axis[axis];
    if (!a->custom && !(a->custom = calloc(1, sizeof *a->custom)))
        return -1;
    memset(a->custom, 0, sizeof *a->custom);
    for (int i = 0; i < n && i < PLOT_MAX_TICKS; i++) {
        a->custom->value[i] = values[i];
        snprintf(a->custom->label[i], PLOT_LABEL_LEN, "%s", labels[i]);
        a->custom->n++;
    }
    return 0;
}

int plot_raster(plot *p, int width, int height, const unsigned char *rgb)
{
    unsigned char *r = malloc((size_t)width * (size_t)height * 3);
    if (!r)
        return -1;
    memcpy(r, rgb, (size_t)width * (size_t)height * 3);
    free(p->raster);
    p->raster = r;
    p->rw = width;
    p->rh = height;
    return 0;
}

int plot_colour_bar(plot *p, const char *title, double lo, double hi, int log, const unsigned char lut[PLOT_LUT][3])
{
    colour_bar *b = p->bar ? p->bar : calloc(1, sizeof *b);
    if (!b)
        return -1;
    p->bar = b;
    free(b->title);
    if (!(b->title = dup_or_null(title)) && title)
        return -1;
    b->lo = lo;
    b->hi = hi;
    b->log = log;
    memcpy(b->lut, lut, sizeof b->lut);
    return 0;
}

plot_series *plot_add(plot *p, const char *name, plot_style style, size_t n, const double *x, const double *y)
{
    plot_series *s = calloc(1, sizeof *s), **grown = realloc(p->s, (size_t)(p->ns + 1) * sizeof *grown);
    if (grown)
        p->s = grown;
    if (!s || !grown || !(s->x = malloc(2 * (n ? n : 1) * sizeof *s->x)) || (name && !(s->name = text_dup(name)))) {
        series_free(s);
        return NULL;
    }
    s->y = s->x + n;
    if (n) {
        memcpy(s->x, x, n * sizeof *x);
        memcpy(s->y, y, n * sizeof *y);
    }
    s->n = n;
    s->style = style;
    s->alpha = 1.0;
    s->line_width = 1.0;
    s->marker_size = 1.0;
    p->s[p->ns++] = s;
    return s;
}

int plot_point_labels(plot_series *s, const char *const *labels)
{
    if (!(s->labels = calloc(s->n ? s->n : 1, sizeof *s->labels)))
        return -1;
    for (size_t i = 0; i < s->n; i++)
        if (labels[i] && !(s->labels[i] = text_dup(labels[i])))
            return -1;
    return 0;
}

int plot_guide(plot *p, int axis, double v, const double rgb[3])
{
    guide *g = realloc(p->g, (size_t)(p->ng + 1) * sizeof *g);
    if (!g)
        return -1;
    p->g = g;
    g[p->ng].axis = axis;
    g[p->ng].v = v;
    memcpy(g[p->ng].rgb, rgb, sizeof g[p->ng].rgb);
    p->ng++;
    return 0;
}

int plot_note(plot *p, const char *text)
{
    char **n = realloc(p->notes, (size_t)(p->nnotes + 1) * sizeof *n);
    if (!n)
        return -1;
    p->notes = n;
    if (!(n[p->nnotes] = text_dup(text)))
        return -1;
    p->nnotes++;
    return 0;
}

int plot_nseries(const plot *p)
{
    return p->ns;
}

const plot_series *plot_series_at(const plot *p, int i)
{
    return p->s[i];
}

void plot_palette(int k, double rgb[3])
{
    static const double c[8][3] = {
        {0.000, 0.447, 0.698}, /* blue */
        {0.835, 0.369, 0.000}, /* vermillion */
        {0.000, 0.620, 0.451}, /* bluish green */
        {0.800, 0.475, 0.655}, /* reddish purple */
        {0.902, 0.624, 0.000}, /* orange */
        {0.337, 0.706, 0.914}, /* sky blue */
        {0.000, 0.000, 0.000}, /* black */
        {0.600, 0.600, 0.600}, /* grey */
    };
    memcpy(rgb, c[(k % 8 + 8) % 8], 3 * sizeof *rgb);
}

/* ---- Ranges and ticks ------------------------------------------------------------- */

int plot_extent(size_t n, const double *v, int log, double *lo, double *hi)
{
    double a = INFINITY, b = -INFINITY;
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(v[i]) || (log && !(v[i] > 0.0)))
            continue;
        a = fmin(a, v[i]);
        b = fmax(b, v[i]);
    }
    if (!(a <= b))
        return 0;
    *lo = a;
    *hi = b;
    return 1;
}

void plot_pad(double lo, double hi, int have, int log, double *out_lo, double *out_hi)
{
    if (!have) {
        lo = log ? 0.1 : 0.0;
        hi = log ? 10.0 : 1.0;
    }
    double a = log ? log10(lo) : lo, b = log ? log10(hi) : hi;
    double mag = fmax(fabs(a), fabs(b));
    double min_span = log ? 0.1 : (mag > 0.0 ? 0.1 * mag : 1.0);
    if (b - a < min_span) {
        double mid = 0.5 * (a + b);
        a = mid - 0.5 * min_span;
        b = mid + 0.5 * min_span;
    }
    double pad = 0.05 * (b - a);
    a -= pad;
    b += pad;
    *out_lo = log ? pow(10.0, a) : a;
    *out_hi = log ? pow(10.0, b) : b;
}

/* ASCII '-' as the typographic minus sign. */
static void minus_sign(char *s, size_t size)
{
    if (s[0] != '-' || strlen(s) + 3 > size)
        return;
    memmove(s + 3, s + 1, strlen(s));
    memcpy(s, "\xe2\x88\x92", 3);
}

/* A tick value with `decimals` digits after the point, or as m x 10^{e} when
 * scientific (e: the exponent shared by the axis). */
static void fmt_tick(double v, int decimals, int sci, int e, char *out, size_t size)
{
    if (sci) {
        double m = v / pow(10.0, e);
        if (fabs(m) < 1e-9)
            snprintf(out, size, "0");
        else {
            char mb[32];
            snprintf(mb, sizeof mb, "%.*f", decimals, m);
            minus_sign(mb, sizeof mb);
            snprintf(out, size, "%s\xc3\x97" "10^{%d}", mb, e);
        }
    } else {
        snprintf(out, size, "%.*f", decimals, fabs(v) < 1e-12 ? 0.0 : v);
    }
    if (out[0] == '-') {
        char tmp[PLOT_LABEL_LEN];
        snprintf(tmp, sizeof tmp, "%s", out);
        minus_sign(tmp, sizeof tmp);
        snprintf(out, size, "%s", tmp);
    }
    /* "m x 10^{e}" exponents keep the ASCII '-'; draw_text shows it as a minus. */
}

/* Labels for ticks[0..n) at a common step: fixed decimals, or scientific with the
 * exponent of the largest magnitude when values are very large or very small. */
static void label_linear(plot_ticks *t, double step)
{
    double mag = 0.0;
    for (int i = 0; i < t->n; i++)
        mag = fmax(mag, fabs(t->value[i]));
    int e = mag > 0.0 ? (int)floor(log10(mag) + 1e-9) : 0;
    int sci = mag > 0.0 && (e >= 5 || e <= -4);
    double s = sci ? step / pow(10.0, e) : step;
    int decimals = s >= 1.0 - 1e-9 ? 0 : (int)ceil(-log10(s) - 1e-9);
    if (decimals > 12)
        decimals = 12;
    for (int i = 0; i < t->n; i++)
        fmt_tick(t->value[i], decimals, sci, e, t->label[i], PLOT_LABEL_LEN);
}

/* Shortest label that reads back as v (to 1e-9): m x 10^{e} when sci, else plain. */
static void label_as(double v, int sci, char *out, size_t size)
{
    double a = fabs(v);
    if (a > 0.0 && sci) {
        int e = (int)floor(log10(a) + 1e-9);
        double m = v / pow(10.0, e);
        char mb[32];
        int d = 0;
        while (d < 6 && fabs(strtod((snprintf(mb, sizeof mb, "%.*f", d, m), mb), NULL) - m) > 1e-9 * fabs(m))
            d++;
        minus_sign(mb, sizeof mb);
        if (!strcmp(mb, "1"))
            snprintf(out, size, "10^{%d}", e);
        else
            snprintf(out, size, "%s\xc3\x97" "10^{%d}", mb, e);
        return;
    }
    int d = 0;
    while (d < 12 && fabs(strtod((snprintf(out, size, "%.*f", d, v), out), NULL) - v) > 1e-9 * fmax(a, 1e-300))
        d++;
    minus_sign(out, size);
}

/* As label_as, scientific outside [1e-3, 1e5). */
static void label_value(double v, char *out, size_t size)
{
    double a = fabs(v);
    label_as(v, a > 0.0 && (a < 1e-3 || a >= 1e5), out, size);
}

static void linear_ticks(double lo, double hi, int target, int integer, double step, plot_ticks *t)
{
    if (!(step > 0.0)) {
        /* The 1-2-5 step whose tick count comes nearest the target (ties: fewer). */
        double raw = (hi - lo) / (target > 1 ? target : 1), e = floor(log10(raw));
        int best = -1;
        for (int j = 2; j >= -1; j--)
            for (int k = 2; k >= 0; k--) {
                static const double m[3] = {1.0, 2.0, 5.0};
                double c = m[k] * pow(10.0, e + j);
                int count = (int)(floor(hi / c + 1e-9) - ceil(lo / c - 1e-9)) + 1;
                if (best < 0 || abs(count - target) < best) {
                    best = abs(count - target);
                    step = c;
                }
            }
    }
    if (integer && step < 1.0)
        step = 1.0;
    t->n = 0;
    double first = ceil(lo / step - 1e-9);
    for (double k = first; t->n < PLOT_MAX_TICKS; k += 1.0) {
        double v = k * step;
        if (v > hi + 1e-9 * step)
            break;
        t->value[t->n++] = fabs(v) < 1e-12 * step ? 0.0 : v;
    }
    label_linear(t, step);
}

/* The labelled 1-2-5 values in [lo, hi] on a log axis: 1 when there are 3 to most. */
static int log_125(double lo, double hi, int most, plot_ticks *t)
{
    static const double m125[3] = {1.0, 2.0, 5.0};
    memset(t, 0, sizeof *t);
    int d0 = (int)floor(log10(lo)), d1 = (int)floor(log10(hi));
    for (int k = d0; k <= d1; k++)
        for (int j = 0; j < 3; j++) {
            double v = m125[j] * pow(10.0, k);
            if (v >= lo * (1 - 1e-12) && v <= hi * (1 + 1e-12) && t->n < PLOT_MAX_TICKS)
                t->value[t->n++] = v;
        }
    if (t->n < 3 || t->n > most)
        return 0;
    /* One notation for the whole axis: 10^{-4} beside 0.001 reads as a mistake. */
    int sci = t->value[0] < 1e-3 || t->value[t->n - 1] >= 1e5;
    for (int i = 0; i < t->n; i++)
        label_as(t->value[i], sci, t->label[i], PLOT_LABEL_LEN);
    /* Minor ticks at the other whole multiples (3, 4, 6 ... x 10^k). */
    for (int k = d0; k <= d1; k++)
        for (int m = 3; m <= 9 && t->nminor < 4 * PLOT_MAX_TICKS; m++) {
            double v = m * pow(10.0, k);
            if (m != 5 && v >= lo && v <= hi)
                t->minor[t->nminor++] = v;
        }
    return 1;
}

void plot_make_ticks(double lo, double hi, int log, int target, int integer, double step, plot_ticks *t)
{
    memset(t, 0, sizeof *t);
    if (target < 2)
        target = 2;
    if (!log) {
        linear_ticks(lo, hi, target, integer, step, t);
        return;
    }
    double a = log10(lo), b = log10(hi);
    int d0 = (int)ceil(a - 1e-9), d1 = (int)floor(b + 1e-9), ndec = d1 - d0 + 1;
    /* Under three decades two or three decade ticks say too little: the labelled 1-2-5
     * values instead, when they are not too many. */
    if (ndec >= 2 && b - a < 3.0 && log_125(lo, hi, target + 3, t))
        return;
    memset(t, 0, sizeof *t);
    if (ndec >= 2) {
        /* Whole decades, every stride-th (a 1-2-5 stride) when there are many. */
        int stride = 1;
        while (ndec / stride + 1 > target + 1)
            stride = stride == 1 ? 2 : stride == 2 ? 5 : stride * 2;
        int start = (int)ceil((double)d0 / stride) * stride;
        for (int k = start; k <= d1 && t->n < PLOT_MAX_TICKS; k += stride) {
            t->value[t->n] = pow(10.0, k);
            snprintf(t->label[t->n], PLOT_LABEL_LEN, "10^{%d}", k);
            t->n++;
        }
        /* Minor ticks at 2..9 x 10^k when each decade has a tick and there is room. */
        if (stride == 1 && ndec <= 8)
            for (int k = d0 - 1; k <= d1; k++)
                for (int m = 2; m <= 9 && t->nminor < 4 * PLOT_MAX_TICKS; m++) {
                    double v = m * pow(10.0, k);
                    if (v >= lo && v <= hi)
                        t->minor[t->nminor++] = v;
                }
        return;
    }
    /* Less than two decades: the 1-2-5 values inside, if there are enough of them. */
    if (log_125(lo, hi, PLOT_MAX_TICKS, t))
        return;
    /* A narrow range: linear 1-2-5 ticks of the values. */
    memset(t, 0, sizeof *t);
    linear_ticks(lo, hi, target < 4 ? target : 4, integer, step, t);
    if (t->n < 2) { /* never fewer than the two ends */
        t->n = 2;
        t->value[0] = lo;
        t->value[1] = hi;
        label_value(lo, t->label[0], PLOT_LABEL_LEN);
        label_value(hi, t->label[1], PLOT_LABEL_LEN);
    }
}

/* ---- Text ------------------------------------------------------------------------- */

typedef struct text_size {
    double width, ascent, descent;
} text_size;

/* Draws (draw 1) or measures markup text with its left end of the baseline at (x, y). */
static text_size text_run(cairo_t *cr, const char *s, double size, double x, double y, int draw)
{
    text_size ts = {0.0, 0.0, 0.0};
    cairo_font_extents_t fe;
    cairo_set_font_size(cr, size);
    cairo_font_extents(cr, &fe);
    ts.ascent = fe.ascent;
    ts.descent = fe.descent;
    char buf[512];
    size_t nb = 0;
    int level = 0; /* 0 base, 1 raised, -1 lowered */
    for (const char *q = s;; q++) {
        int special = *q == '\0' || ((*q == '^' || *q == '_') && q[1] == '{') || (*q == '}' && level != 0);
        if (!special && nb + 5 < sizeof buf) {
            if (*q == '-' && level != 0) { /* a minus sign in exponents */
                memcpy(buf + nb, "\xe2\x88\x92", 3);
                nb += 3;
            } else
                buf[nb++] = *q;
            continue;
        }
        if (special || nb + 5 >= sizeof buf) {
            buf[nb] = '\0';
            if (nb) {
                double fs = level ? 0.72 * size : size;
                double rise = level > 0 ? -0.42 * size : level < 0 ? 0.22 * size : 0.0;
                cairo_set_font_size(cr, fs);
                cairo_text_extents_t te;
                cairo_text_extents(cr, buf, &te);
                if (draw) {
                    cairo_move_to(cr, x + ts.width, y + rise);
                    cairo_show_text(cr, buf);
                }
                ts.width += te.x_advance;
                if (level > 0)
                    ts.ascent = fmax(ts.ascent, 0.42 * size + 0.75 * fs);
                if (level < 0)
                    ts.descent = fmax(ts.descent, 0.22 * size + 0.25 * fs);
            }
            nb = 0;
        }
        if (*q == '\0')
            break;
        if (*q == '}')
            level = 0;
        else if (special) {
            level = *q == '^' ? 1 : -1;
            q++; /* the brace */
        } else
            buf[nb++] = *q; /* the buffer was full */
    }
    cairo_set_font_size(cr, size);
    return ts;
}

void plot_plain_text(const char *markup, char *out, size_t size)
{
    size_t n = 0;
    for (const char *q = markup; *q && n + 1 < size; q++) {
        if ((*q == '^' || *q == '_') && q[1] == '{') {
            q++;
            continue;
        }
        if (*q == '}')
            continue;
        out[n++] = *q;
    }
    out[n] = '\0';
}

/* Text anchored at (x, y): ax 0 left, 0.5 centre, 1 right; ay 0 top, 0.5 middle, 1
 * baseline. */
static text_size text_at(cairo_t *cr, const char *s, double size, double x, double y, double ax, double ay)
{
    text_size ts = text_run(cr, s, size, 0, 0, 0);
    double by = ay >= 1.0 ? y : ay > 0.0 ? y + 0.36 * size : y + ts.ascent;
    text_run(cr, s, size, x - ax * ts.width, by, 1);
    return ts;
}

/* Text centred at x (top at y), moved and if need be made smaller to stay within
 * [pad, width - pad]. */
static void centred(cairo_t *cr, const char *s, double size, double x, double y, double width, double pad)
{
    double w = text_run(cr, s, size, 0, 0, 0).width, room = width - 2.0 * pad;
    if (w > room && w > 0.0) {
        size *= room / w;
        w = room;
    }
    double left = x - 0.5 * w;
    left = left < pad ? pad : left + w > width - pad ? width - pad - w : left;
    text_at(cr, s, size, left, y, 0.0, 0.0);
}

/* ---- Layout ----------------------------------------------------------------------- */

static double map(const plot_layout *l, int axis, double v)
{
    const plot_axis_layout *a = &l->axis[axis];
    double t = a->log ? (log10(v) - log10(a->lo)) / (log10(a->hi) - log10(a->lo)) : (v - a->lo) / (a->hi - a->lo);
    return axis == PLOT_X ? l->x0 + t * (l->x1 - l->x0) : l->y1 - t * (l->y1 - l->y0);
}

static void axis_range(const plot *p, int axis, plot_axis_layout *a)
{
    const axis_spec *s = &p->axis[axis];
    a->log = s->log;
    if (s->fixed) {
        a->lo = s->lo;
        a->hi = s->hi;
        return;
    }
    double lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < p->ns; i++) {
        double a0, a1;
        if (plot_extent(p->s[i]->n, axis == PLOT_X ? p->s[i]->x : p->s[i]->y, s->log, &a0, &a1)) {
            lo = fmin(lo, a0);
            hi = fmax(hi, a1);
        }
    }
    plot_pad(lo, hi, lo <= hi, s->log, &a->lo, &a->hi);
}

static double legend_sample_width(double font)
{
    return 2.4 * font;
}

static double max_label_width(cairo_t *cr, const plot_ticks *t, double size)
{
    double w = 0.0;
    for (int i = 0; i < t->n; i++)
        w = fmax(w, text_run(cr, t->label[i], size, 0, 0, 0).width);
    return w;
}

static int clampi(int v, int lo, int hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

static int drawable(const plot_layout *l, double x, double y);

/* The corner of the plot area whose legend box covers the fewest points; a labelled
 * point counts with the room its label takes beside it (its name must stay readable). */
static void legend_corner(const plot *p, plot_layout *l)
{
    double inset = 0.5 * l->font, best_x = l->x1 - inset - l->legend_w, best_y = l->y0 + inset;
    size_t best = (size_t)-1;
    for (int c = 0; c < 4; c++) {
        double x = c % 2 == 0 ? l->x1 - inset - l->legend_w : l->x0 + inset;
        double y = c < 2 ? l->y0 + inset : l->y1 - inset - l->legend_h;
        size_t covered = 0;
        for (int i = 0; i < p->ns; i++)
            for (size_t k = 0; k < p->s[i]->n; k++) {
                const plot_series *s = p->s[i];
                if (!drawable(l, s->x[k], s->y[k]))
                    continue;
                double X = map(l, PLOT_X, s->x[k]), Y = map(l, PLOT_Y, s->y[k]);
                const double mx = s->labels && s->labels[k] ? 6.0 * l->font : 0.0,
                             my = s->labels && s->labels[k] ? 1.5 * l->font : 0.0;
                covered += X >= x - mx && X <= x + l->legend_w + mx && Y >= y - my && Y <= y + l->legend_h + my;
            }
        if (covered < best) {
            best = covered;
            best_x = x;
            best_y = y;
        }
    }
    l->legend_x = best_x;
    l->legend_y = best_y;
}

static void layout_with(const plot *p, cairo_t *cr, int width, int height, plot_layout *l)
{
    memset(l, 0, sizeof *l);
    l->width = width;
    l->height = height;
    double font = fmin(width, height) / 34.0;
    l->font = font = font < 9.0 ? 9.0 : font > 22.0 ? 22.0 : font;
    double tick_font = 0.9 * font, pad = 0.6 * font, tick = 0.4 * font;
    cairo_select_font_face(cr, FONT_FACE, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    for (int a = 0; a < 2; a++)
        axis_range(p, a, &l->axis[a]);

    /* Legend: the widest entry. */
    double lw = 0.0;
    for (int i = 0; i < p->ns; i++)
        if (p->s[i]->name) {
            l->nlegend++;
            lw = fmax(lw, text_run(cr, p->s[i]->name, tick_font, 0, 0, 0).width);
        }
    l->legend_w = l->nlegend ? legend_sample_width(font) + 0.5 * font + lw + 1.2 * font : 0.0;
    l->legend_h = l->nlegend ? l->nlegend * 1.45 * tick_font + 0.8 * font : 0.0;
    /* A wide legend would squeeze the plot: it goes inside, in the emptiest corner. */
    l->legend_inside = l->nlegend && l->legend_w > 0.3 * width;

    double top = pad + (p->title ? 1.25 * font + pad : 0.0);
    double bottom = pad + tick + 1.3 * tick_font + (p->axis[0].title ? 1.35 * font : 0.0) + p->nnotes * 1.3 * tick_font;
    double right = (l->nlegend && !l->legend_inside ? l->legend_w + 1.2 * font : 0.0) + 1.5 * font;
    if (p->bar) {
        /* The bar, its tick labels and its title (turned, reading upwards). */
        l->colour_bar = 1;
        plot_make_ticks(p->bar->lo, p->bar->hi, p->bar->log, 5, 0, 0.0, &l->bar_ticks);
        l->bar_w = 0.9 * font;
        right += l->bar_w + tick + 0.3 * font + max_label_width(cr, &l->bar_ticks, tick_font) +
                 (p->bar->title ? 1.3 * font + pad : 0.0);
    }
    /* Two passes: the y ticks (and so the left margin) depend on the plot height. */
    double left = 4.0 * font;
    for (int pass = 0; pass < 2; pass++) {
        l->x0 = left;
        l->x1 = width - right;
        l->y0 = top;
        l->y1 = height - bottom;
        if (l->x1 < l->x0 + 20)
            l->x1 = l->x0 + 20;
        if (l->y1 < l->y0 + 20)
            l->y1 = l->y0 + 20;
        int ty = clampi((int)((l->y1 - l->y0) / (2.8 * font)), 2, 10);
        int tx = clampi((int)((l->x1 - l->x0) / (6.0 * font)), 2, 10);
        plot_make_ticks(l->axis[1].lo, l->axis[1].hi, l->axis[1].log, ty, p->axis[1].integer, p->axis[1].step,
                        &l->axis[1].ticks);
        plot_make_ticks(l->axis[0].lo, l->axis[0].hi, l->axis[0].log, tx, p->axis[0].integer, p->axis[0].step,
                        &l->axis[0].ticks);
        for (int a = 0; a < 2; a++)
            if (p->axis[a].custom)
                l->axis[a].ticks = *p->axis[a].custom;
        /* Fewer x ticks when their labels would touch. */
        double xw = max_label_width(cr, &l->axis[0].ticks, tick_font);
        while (l->axis[0].ticks.n > 2 && tx > 2 && xw * l->axis[0].ticks.n * 1.3 > l->x1 - l->x0 &&
               !(p->axis[0].step > 0.0) && !p->axis[0].custom) {
            tx--;
            plot_make_ticks(l->axis[0].lo, l->axis[0].hi, l->axis[0].log, tx, p->axis[0].integer, 0.0,
                            &l->axis[0].ticks);
            xw = max_label_width(cr, &l->axis[0].ticks, tick_font);
        }
        left = pad + (p->axis[1].title ? 1.3 * font + pad : 0.0) + max_label_width(cr, &l->axis[1].ticks, tick_font) +
               tick + 0.4 * font;
    }
    l->legend_x = l->x1 + 1.2 * font;
    l->legend_y = l->y0;
    l->bar_x = l->x1 + 1.2 * font + (l->nlegend && !l->legend_inside ? l->legend_w + 1.2 * font : 0.0);
    if (l->legend_inside)
        legend_corner(p, l);
}

/* A measuring context: a 1x1 image surface. */
int plot_layout_compute(const plot *p, int width, int height, plot_layout *l)
{
    cairo_surface_t *s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, 1, 1);
    cairo_t *cr = cairo_create(s);
    int ok = cairo_status(cr) == CAIRO_STATUS_SUCCESS;
    if (ok)
        layout_with(p, cr, width, height, l);
    cairo_destroy(cr);
    cairo_surface_destroy(s);
    return ok ? 0 : -1;
}

/* ---- Drawing ---------------------------------------------------------------------- */

static void set_dash(cairo_t *cr, plot_dash d, double lw)
{
    double dashed[2] = {4.0 * lw, 2.5 * lw}, dotted[2] = {1.0 * lw, 2.0 * lw};
    if (d == PLOT_DASHED)
        cairo_set_dash(cr, dashed, 2, 0.0);
    else if (d == PLOT_DOTTED)
        cairo_set_dash(cr, dotted, 2, 0.0);
    else
        cairo_set_dash(cr, NULL, 0, 0.0);
}

static void marker(cairo_t *cr, plot_marker m, double x, double y, double r, double lw)
{
    cairo_new_path(cr);
    switch (m) {
    case PLOT_SQUARE:
        cairo_rectangle(cr, x - 0.85 * r, y - 0.85 * r, 1.7 * r, 1.7 * r);
        cairo_fill(cr);
        break;
    case PLOT_DIAMOND:
        cairo_move_to(cr, x, y - 1.2 * r);
        cairo_line_to(cr, x + 1.2 * r, y);
        cairo_line_to(cr, x, y + 1.2 * r);
        cairo_line_to(cr, x - 1.2 * r, y);
        cairo_close_path(cr);
        cairo_fill(cr);
        break;
    case PLOT_TRIANGLE:
        cairo_move_to(cr, x, y - 1.2 * r);
        cairo_line_to(cr, x + 1.05 * r, y + 0.65 * r);
        cairo_line_to(cr, x - 1.05 * r, y + 0.65 * r);
        cairo_close_path(cr);
        cairo_fill(cr);
        break;
    case PLOT_RING:
        cairo_set_dash(cr, NULL, 0, 0.0);
        cairo_set_line_width(cr, 1.5 * lw);
        cairo_arc(cr, x, y, 1.6 * r, 0, 2 * M_PI);
        cairo_stroke(cr);
        break;
    default:
        cairo_arc(cr, x, y, r, 0, 2 * M_PI);
        cairo_fill(cr);
    }
}

static int drawable(const plot_layout *l, double x, double y)
{
    return isfinite(x) && isfinite(y) && !(l->axis[0].log && !(x > 0.0)) && !(l->axis[1].log && !(y > 0.0));
}

static void draw_series(cairo_t *cr, const plot_layout *l, const plot_series *s, double lw)
{
    cairo_set_source_rgba(cr, s->rgb[0], s->rgb[1], s->rgb[2], s->alpha);
    if (s->style & PLOT_LINE) {
        cairo_set_line_width(cr, 1.6 * lw * s->line_width);
        set_dash(cr, s->dash, 1.6 * lw * s->line_width);
        cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
        cairo_new_path(cr);
        int open = 0;
        for (size_t i = 0; i < s->n; i++) {
            if (!drawable(l, s->x[i], s->y[i])) {
                open = 0; /* the line breaks at values it cannot show */
                continue;
            }
            double X = map(l, PLOT_X, s->x[i]), Y = map(l, PLOT_Y, s->y[i]);
            if (open)
                cairo_line_to(cr, X, Y);
            else
                cairo_move_to(cr, X, Y);
            open = 1;
        }
        cairo_stroke(cr);
        set_dash(cr, PLOT_SOLID, 1.0);
    }
    if (s->style & PLOT_MARKERS)
        for (size_t i = 0; i < s->n; i++)
            if (drawable(l, s->x[i], s->y[i]))
                marker(cr, s->marker, map(l, PLOT_X, s->x[i]), map(l, PLOT_Y, s->y[i]), 0.28 * l->font * s->marker_size,
                       lw);
}

typedef struct rect {
    double x0, y0, x1, y1;
} rect;

static int overlaps(rect a, rect b)
{
    return a.x0 < b.x1 && b.x0 < a.x1 && a.y0 < b.y1 && b.y0 < a.y1;
}

/* Point labels: each at the first of eight places around its point that stays inside
 * the plot area and clear of the labels and points placed so far. */
static void draw_labels(cairo_t *cr, const plot *p, const plot_layout *l, double size)
{
    int cap = 0, n = 0;
    for (int i = 0; i < p->ns; i++)
        cap += p->s[i]->labels ? (int)p->s[i]->n * 2 : 0;
    rect *placed = cap ? malloc((size_t)cap * sizeof *placed) : NULL;
    if (cap && !placed)
        return;
    double r = 0.45 * l->font;
    for (int i = 0; i < p->ns; i++) /* the labelled points themselves */
        for (size_t k = 0; p->s[i]->labels && k < p->s[i]->n; k++)
            if (drawable(l, p->s[i]->x[k], p->s[i]->y[k]) && p->s[i]->labels[k]) {
                double X = map(l, PLOT_X, p->s[i]->x[k]), Y = map(l, PLOT_Y, p->s[i]->y[k]);
                placed[n++] = (rect){X - r, Y - r, X + r, Y + r};
            }
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    for (int i = 0; i < p->ns; i++)
        for (size_t k = 0; p->s[i]->labels && k < p->s[i]->n; k++) {
            const char *text = p->s[i]->labels[k];
            if (!text || !drawable(l, p->s[i]->x[k], p->s[i]->y[k]))
                continue;
            double X = map(l, PLOT_X, p->s[i]->x[k]), Y = map(l, PLOT_Y, p->s[i]->y[k]);
            text_size ts = text_run(cr, text, size, 0, 0, 0);
            double w = ts.width, h = ts.ascent + ts.descent, d = 0.5 * l->font;
            const double dx[8] = {d, d, -d - w, -d - w, -0.5 * w, -0.5 * w, d, -d - w};
            const double dy[8] = {-d - h, d, -d - h, d, -d - h - 0.2 * d, d + 0.2 * d, -0.5 * h, -0.5 * h};
            int best = 0;
            for (int c = 0; c < 8; c++) {
                rect b = {X + dx[c], Y + dy[c], X + dx[c] + w, Y + dy[c] + h};
                int ok = b.x0 >= l->x0 && b.x1 <= l->x1 && b.y0 >= l->y0 && b.y1 <= l->y1;
                for (int q = 0; ok && q < n; q++)
                    ok = !overlaps(b, placed[q]) || (fabs(placed[q].x0 + r - X) < 1e-9 && fabs(placed[q].y0 + r - Y) < 1e-9);
                if (ok) {
                    best = c;
                    break;
                }
            }
            rect b = {X + dx[best], Y + dy[best], X + dx[best] + w, Y + dy[best] + h};
            if (n < cap)
                placed[n++] = b;
            text_run(cr, text, size, b.x0, b.y0 + ts.ascent, 1);
        }
    free(placed);
}

/* A line across the plot area at position v (device units) along axis. */
static void span_line(cairo_t *cr, const plot_layout *l, int axis, double v)
{
    if (axis == PLOT_X) {
        cairo_move_to(cr, v, l->y0);
        cairo_line_to(cr, v, l->y1);
    } else {
        cairo_move_to(cr, l->x0, v);
        cairo_line_to(cr, l->x1, v);
    }
}

/* w x h RGB bytes stretched over a rectangle, each cell a sharp block (no smoothing
 * between cells: a table's cells stay cells). */
static void draw_raster(cairo_t *cr, const unsigned char *rgb, int w, int h, double x, double y, double dw,
                        double dh)
{
    cairo_surface_t *img = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
    if (cairo_surface_status(img) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(img);
        return;
    }
    cairo_surface_flush(img);
    unsigned char *d = cairo_image_surface_get_data(img);
    int stride = cairo_image_surface_get_stride(img);
    for (int j = 0; j < h; j++)
        for (int i = 0; i < w; i++) {
            const unsigned char *c = rgb + 3 * ((size_t)j * (size_t)w + (size_t)i);
            uint32_t px = (uint32_t)c[0] << 16 | (uint32_t)c[1] << 8 | (uint32_t)c[2];
            memcpy(d + (size_t)j * (size_t)stride + 4 * (size_t)i, &px, 4);
        }
    cairo_surface_mark_dirty(img);
    cairo_save(cr);
    cairo_translate(cr, x, y);
    cairo_scale(cr, dw / w, dh / h);
    cairo_set_source_surface(cr, img, 0, 0);
    cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
    cairo_rectangle(cr, 0, 0, w, h);
    cairo_fill(cr);
    cairo_restore(cr);
    cairo_surface_destroy(img);
}

static double bar_map(const colour_bar *b, const plot_layout *l, double v)
{
    double t = b->log ? (log10(v) - log10(b->lo)) / (log10(b->hi) - log10(b->lo)) : (v - b->lo) / (b->hi - b->lo);
    return l->y1 - t * (l->y1 - l->y0);
}

/* The colour bar: the table's colours bottom (lo) to top (hi), framed, ticked on the
 * right, titled beside its labels. */
static void draw_colour_bar(cairo_t *cr, const colour_bar *b, const plot_layout *l, double lw)
{
    double font = l->font, tick_font = 0.9 * font, tick = 0.4 * font, x = l->bar_x, w = l->bar_w;
    unsigned char strip[PLOT_LUT * 3];
    for (int k = 0; k < PLOT_LUT; k++)
        memcpy(strip + 3 * k, b->lut[PLOT_LUT - 1 - k], 3);
    draw_raster(cr, strip, 1, PLOT_LUT, x, l->y0, w, l->y1 - l->y0);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, lw);
    cairo_rectangle(cr, x, l->y0, w, l->y1 - l->y0);
    cairo_stroke(cr);
    double widest = 0.0;
    for (int i = 0; i < l->bar_ticks.n; i++) {
        double v = bar_map(b, l, l->bar_ticks.value[i]);
        if (v < l->y0 - 0.5 || v > l->y1 + 0.5)
            continue;
        cairo_move_to(cr, x + w, v);
        cairo_line_to(cr, x + w + tick, v);
        cairo_stroke(cr);
        text_size ts = text_at(cr, l->bar_ticks.label[i], tick_font, x + w + tick + 0.3 * font, v, 0.0, 0.5);
        widest = fmax(widest, ts.width);
    }
    if (b->title) {
        cairo_save(cr);
        cairo_translate(cr, x + w + tick + 0.3 * font + widest + 0.4 * font, 0.5 * (l->y0 + l->y1));
        cairo_rotate(cr, -M_PI / 2);
        text_at(cr, b->title, font, 0.0, 0.0, 0.5, 0.0);
        cairo_restore(cr);
    }
}

static void draw_plot(cairo_t *cr, const plot *p, const plot_layout *l)
{
    double font = l->font, tick_font = 0.9 * font, tick = 0.4 * font, lw = fmax(1.0, font / 13.0);
    cairo_select_font_face(cr, FONT_FACE, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);

    /* A raster, or a grid at the major ticks; guides, then the series, inside the plot
     * area. */
    cairo_save(cr);
    cairo_rectangle(cr, l->x0, l->y0, l->x1 - l->x0, l->y1 - l->y0);
    cairo_clip(cr);
    if (p->raster)
        draw_raster(cr, p->raster, p->rw, p->rh, l->x0, l->y0, l->x1 - l->x0, l->y1 - l->y0);
    cairo_set_line_width(cr, 0.6 * lw);
    cairo_set_source_rgb(cr, 0.89, 0.89, 0.89);
    for (int a = 0; a < 2 && !p->raster; a++)
        for (int i = 0; i < l->axis[a].ticks.n; i++) {
            double v = map(l, a, l->axis[a].ticks.value[i]);
            span_line(cr, l, a, v);
        }
    cairo_stroke(cr);
    for (int i = 0; i < p->ng; i++) {
        const guide *g = &p->g[i];
        if (!drawable(l, g->axis == PLOT_X ? g->v : 1.0, g->axis == PLOT_Y ? g->v : 1.0))
            continue;
        double v = map(l, g->axis, g->v);
        cairo_set_source_rgb(cr, g->rgb[0], g->rgb[1], g->rgb[2]);
        cairo_set_line_width(cr, lw);
        set_dash(cr, PLOT_DOTTED, 1.5 * lw);
        span_line(cr, l, g->axis, v);
        cairo_stroke(cr);
        set_dash(cr, PLOT_SOLID, 1.0);
    }
    for (int i = 0; i < p->ns; i++)
        draw_series(cr, l, p->s[i], lw);
    cairo_restore(cr);

    /* Frame, ticks and their labels. */
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, lw);
    cairo_rectangle(cr, l->x0, l->y0, l->x1 - l->x0, l->y1 - l->y0);
    cairo_stroke(cr);
    for (int a = 0; a < 2; a++) {
        const plot_ticks *t = &l->axis[a].ticks;
        for (int i = 0; i < t->n + t->nminor; i++) {
            int major = i < t->n;
            double v = map(l, a, major ? t->value[i] : t->minor[i - t->n]), len = major ? tick : 0.55 * tick;
            if (a == PLOT_X) {
                cairo_move_to(cr, v, l->y1);
                cairo_line_to(cr, v, l->y1 + len);
            } else {
                cairo_move_to(cr, l->x0, v);
                cairo_line_to(cr, l->x0 - len, v);
            }
        }
        cairo_stroke(cr);
        for (int i = 0; i < t->n; i++) {
            double v = map(l, a, t->value[i]);
            if (a == PLOT_X)
                text_at(cr, t->label[i], tick_font, v, l->y1 + tick + 0.25 * font, 0.5, 0.0);
            else
                text_at(cr, t->label[i], tick_font, l->x0 - tick - 0.3 * font, v, 1.0, 0.5);
        }
    }
    double pad = 0.6 * font;
    if (p->axis[0].title)
        centred(cr, p->axis[0].title, font, 0.5 * (l->x0 + l->x1), l->y1 + tick + 1.3 * tick_font + 0.35 * font,
                l->width, pad);
    if (p->axis[1].title) {
        cairo_save(cr);
        cairo_translate(cr, pad, 0.5 * (l->y0 + l->y1));
        cairo_rotate(cr, -M_PI / 2);
        text_at(cr, p->axis[1].title, font, 0.0, 0.0, 0.5, 0.0);
        cairo_restore(cr);
    }
    if (p->title) {
        cairo_select_font_face(cr, FONT_FACE, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
        centred(cr, p->title, 1.1 * font, 0.5 * (l->x0 + l->x1), pad, l->width, pad);
        cairo_select_font_face(cr, FONT_FACE, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    }
    double ny = l->y1 + tick + 1.3 * tick_font + (p->axis[0].title ? 1.35 * font : 0.0) + 0.3 * font;
    for (int i = 0; i < p->nnotes; i++, ny += 1.3 * tick_font)
        text_at(cr, p->notes[i], tick_font, l->x0, ny, 0.0, 0.0);

    /* Legend: a framed box right of the plot area. */
    if (l->nlegend) {
        if (l->legend_inside) {
            cairo_set_source_rgba(cr, 1, 1, 1, 0.88);
            cairo_rectangle(cr, l->legend_x, l->legend_y, l->legend_w, l->legend_h);
            cairo_fill(cr);
        }
        cairo_set_source_rgb(cr, 0.55, 0.55, 0.55);
        cairo_set_line_width(cr, 0.7 * lw);
        cairo_rectangle(cr, l->legend_x, l->legend_y, l->legend_w, l->legend_h);
        cairo_stroke(cr);
        double y = l->legend_y + 0.4 * font + 0.72 * tick_font, sx = l->legend_x + 0.6 * font;
        for (int i = 0; i < p->ns; i++) {
            const plot_series *s = p->s[i];
            if (!s->name)
                continue;
            /* On a pixel row's centre: a line between two rows would be smeared over
             * both and look thicker than its neighbours in a PNG. */
            double cy = floor(y - 0.33 * tick_font) + 0.5, sw = legend_sample_width(font);
            cairo_set_source_rgba(cr, s->rgb[0], s->rgb[1], s->rgb[2], s->alpha < 0.6 ? 0.6 : s->alpha);
            if (s->style & PLOT_LINE) {
                cairo_set_line_width(cr, 1.6 * lw * s->line_width);
                set_dash(cr, s->dash, 1.6 * lw * s->line_width);
                cairo_move_to(cr, sx, cy);
                cairo_line_to(cr, sx + sw, cy);
                cairo_stroke(cr);
                set_dash(cr, PLOT_SOLID, 1.0);
            }
            if (s->style & PLOT_MARKERS)
                marker(cr, s->marker, sx + 0.5 * sw, cy, 0.28 * font * fmax(s->marker_size, 0.8), lw);
            cairo_set_source_rgb(cr, 0, 0, 0);
            text_run(cr, s->name, tick_font, sx + sw + 0.5 * font, y, 1);
            y += 1.45 * tick_font;
        }
    }
    if (l->colour_bar)
        draw_colour_bar(cr, p->bar, l, lw);
    draw_labels(cr, p, l, 0.85 * font);
}

/* ---- Output ----------------------------------------------------------------------- */

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
    int rc = BF_OK;
    if (cairo_status(cr) != CAIRO_STATUS_SUCCESS) {
        rc = bf_fail(err, BF_ERR_NOMEM, "plot: cannot draw: %s", cairo_status_to_string(cairo_status(cr)));
    } else {
        layout_with(p, cr, width, height, &l);
        draw_plot(cr, p, &l);
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
    int rc = plot_encode(p, fmt, width, height, &data, &len, err);
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
    return !strcasecmp(dot, ".png") ? BF_PLOT_PNG : !strcasecmp(dot, ".svg") ? BF_PLOT_SVG
           : !strcasecmp(dot, ".pdf") ? BF_PLOT_PDF : 0;
}

int bf_plot_format_parse(const char *name)
{
    return !name ? 0 : !strcmp(name, "png") ? BF_PLOT_PNG : !strcmp(name, "svg") ? BF_PLOT_SVG
                                           : !strcmp(name, "pdf") ? BF_PLOT_PDF : 0;
}
