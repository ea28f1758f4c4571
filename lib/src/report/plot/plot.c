/* 2D plots with Cairo (see plot.h): the plot object and its setters (series, axes,
 * guides, notes, a raster, a colour bar) and the palette. What a setter is given is
 * copied; text is made printable on the way in. Ticks, text, layout, drawing and output
 * are in the other plot_*.c files (plot_impl.h). */
#include "plot/plot_impl.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/error.h"

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
    free(s->colors);
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

int plot_color_bar(plot *p, const char *title, double lo, double hi, int log, const unsigned char lut[PLOT_LUT][3])
{
    color_bar *b = p->bar ? p->bar : calloc(1, sizeof *b);
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

int plot_point_colors(plot_series *s, const unsigned char *rgb)
{
    unsigned char *c = malloc(3 * (s->n ? s->n : 1));
    if (!c)
        return -1;
    memcpy(c, rgb, 3 * s->n);
    free(s->colors);
    s->colors = c;
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
