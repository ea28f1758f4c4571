/* A laid-out plot drawn with Cairo: a white background, the raster or the grid, guides
 * and series clipped to the plot area; then frame, ticks, titles, notes, legend, colour
 * bar and point labels. Legend lines sit on pixel-row centres and raster cells stay
 * sharp (plot.h). */
#include "plot/plot_impl.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

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
    default: cairo_arc(cr, x, y, r, 0, 2 * M_PI); cairo_fill(cr);
    }
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
            if (!plot_drawable(l, s->x[i], s->y[i])) {
                open = 0; /* the line breaks at values it cannot show */
                continue;
            }
            double X = plot_map(l, PLOT_X, s->x[i]), Y = plot_map(l, PLOT_Y, s->y[i]);
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
            if (plot_drawable(l, s->x[i], s->y[i])) {
                if (s->colors) {
                    const unsigned char *c = s->colors + 3 * i;
                    cairo_set_source_rgba(cr, c[0] / 255.0, c[1] / 255.0, c[2] / 255.0, s->alpha);
                }
                marker(cr, s->marker, plot_map(l, PLOT_X, s->x[i]), plot_map(l, PLOT_Y, s->y[i]),
                       0.28 * l->font * s->marker_size, lw);
            }
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
            if (plot_drawable(l, p->s[i]->x[k], p->s[i]->y[k]) && p->s[i]->labels[k]) {
                double X = plot_map(l, PLOT_X, p->s[i]->x[k]), Y = plot_map(l, PLOT_Y, p->s[i]->y[k]);
                placed[n++] = (rect){X - r, Y - r, X + r, Y + r};
            }
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    for (int i = 0; i < p->ns; i++)
        for (size_t k = 0; p->s[i]->labels && k < p->s[i]->n; k++) {
            const char *text = p->s[i]->labels[k];
            if (!text || !plot_drawable(l, p->s[i]->x[k], p->s[i]->y[k]))
                continue;
            double X = plot_map(l, PLOT_X, p->s[i]->x[k]), Y = plot_map(l, PLOT_Y, p->s[i]->y[k]);
            plot_text_size ts = plot_text_run(cr, text, size, 0, 0, 0);
            double w = ts.width, h = ts.ascent + ts.descent, d = 0.5 * l->font;
            const double dx[8] = {d, d, -d - w, -d - w, -0.5 * w, -0.5 * w, d, -d - w};
            const double dy[8] = {-d - h, d, -d - h, d, -d - h - 0.2 * d, d + 0.2 * d, -0.5 * h, -0.5 * h};
            int best = 0;
            for (int c = 0; c < 8; c++) {
                rect b = {X + dx[c], Y + dy[c], X + dx[c] + w, Y + dy[c] + h};
                int ok = b.x0 >= l->x0 && b.x1 <= l->x1 && b.y0 >= l->y0 && b.y1 <= l->y1;
                for (int q = 0; ok && q < n; q++)
                    ok = !overlaps(b, placed[q]) ||
                         (fabs(placed[q].x0 + r - X) < 1e-9 && fabs(placed[q].y0 + r - Y) < 1e-9);
                if (ok) {
                    best = c;
                    break;
                }
            }
            rect b = {X + dx[best], Y + dy[best], X + dx[best] + w, Y + dy[best] + h};
            if (n < cap)
                placed[n++] = b;
            plot_text_run(cr, text, size, b.x0, b.y0 + ts.ascent, 1);
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

/* A rectangle on the page: its top left corner and its size. */
typedef struct plot_rect {
    double x, y, w, h;
} plot_rect;

/* w x h RGB bytes stretched over a rectangle, each cell a sharp block (no smoothing
 * between cells: a table's cells stay cells). */
static void draw_raster(cairo_t *cr, const unsigned char *rgb, int w, int h, plot_rect at)
{
    const double x = at.x, y = at.y, dw = at.w, dh = at.h;
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

static double bar_map(const color_bar *b, const plot_layout *l, double v)
{
    double t = b->log ? (log10(v) - log10(b->lo)) / (log10(b->hi) - log10(b->lo)) : (v - b->lo) / (b->hi - b->lo);
    return l->y1 - t * (l->y1 - l->y0);
}

/* The colour bar: the table's colours bottom (lo) to top (hi), framed, ticked on the
 * right, titled beside its labels. */
static void draw_color_bar(cairo_t *cr, const color_bar *b, const plot_layout *l, double lw)
{
    double font = l->font, tick_font = 0.9 * font, tick = 0.4 * font, x = l->bar_x, w = l->bar_w;
    unsigned char strip[PLOT_LUT * 3];
    for (int k = 0; k < PLOT_LUT; k++)
        memcpy(strip + 3 * k, b->lut[PLOT_LUT - 1 - k], 3);
    draw_raster(cr, strip, 1, PLOT_LUT, (plot_rect){x, l->y0, w, l->y1 - l->y0});
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
        plot_text_size ts = plot_text_at(cr, l->bar_ticks.label[i], tick_font, x + w + tick + 0.3 * font, v, 0.0, 0.5);
        widest = fmax(widest, ts.width);
    }
    if (b->title) {
        cairo_save(cr);
        cairo_translate(cr, x + w + tick + 0.3 * font + widest + 0.4 * font, 0.5 * (l->y0 + l->y1));
        cairo_rotate(cr, -M_PI / 2);
        plot_text_at(cr, b->title, font, 0.0, 0.0, 0.5, 0.0);
        cairo_restore(cr);
    }
}

/* The sizes every phase of plot_draw derives from the layout's font. */
typedef struct pen {
    double font, tick_font, tick, lw;
} pen;

static pen pen_of(const plot_layout *l)
{
    return (pen){l->font, 0.9 * l->font, 0.4 * l->font, fmax(1.0, l->font / 13.0)};
}

/* Inside the plot area (clipped): a raster, or a grid at the major ticks; the guides,
 * then the series. */
static void draw_area(cairo_t *cr, const plot *p, const plot_layout *l, pen k)
{
    const double lw = k.lw;
    cairo_save(cr);
    cairo_rectangle(cr, l->x0, l->y0, l->x1 - l->x0, l->y1 - l->y0);
    cairo_clip(cr);
    if (p->raster)
        draw_raster(cr, p->raster, p->rw, p->rh, (plot_rect){l->x0, l->y0, l->x1 - l->x0, l->y1 - l->y0});
    cairo_set_line_width(cr, 0.6 * lw);
    cairo_set_source_rgb(cr, 0.89, 0.89, 0.89);
    for (int a = 0; a < 2 && !p->raster; a++)
        for (int i = 0; i < l->axis[a].ticks.n; i++) {
            double v = plot_map(l, a, l->axis[a].ticks.value[i]);
            span_line(cr, l, a, v);
        }
    cairo_stroke(cr);
    for (int i = 0; i < p->ng; i++) {
        const guide *g = &p->g[i];
        if (!plot_drawable(l, g->axis == PLOT_X ? g->v : 1.0, g->axis == PLOT_Y ? g->v : 1.0))
            continue;
        double v = plot_map(l, g->axis, g->v);
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
}

/* The frame, the ticks and their labels. */
static void draw_frame(cairo_t *cr, const plot_layout *l, pen k)
{
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, k.lw);
    cairo_rectangle(cr, l->x0, l->y0, l->x1 - l->x0, l->y1 - l->y0);
    cairo_stroke(cr);
    for (int a = 0; a < 2; a++) {
        const plot_ticks *t = &l->axis[a].ticks;
        for (int i = 0; i < t->n + t->nminor; i++) {
            int major = i < t->n;
            double v = plot_map(l, a, major ? t->value[i] : t->minor[i - t->n]), len = major ? k.tick : 0.55 * k.tick;
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
            double v = plot_map(l, a, t->value[i]);
            if (a == PLOT_X)
                plot_text_at(cr, t->label[i], k.tick_font, v, l->y1 + k.tick + 0.25 * k.font, 0.5, 0.0);
            else
                plot_text_at(cr, t->label[i], k.tick_font, l->x0 - k.tick - 0.3 * k.font, v, 1.0, 0.5);
        }
    }
}

/* The axis titles, the plot's title and the notes under the x axis. */
static void draw_titles(cairo_t *cr, const plot *p, const plot_layout *l, pen k)
{
    const double font = k.font, tick_font = k.tick_font, tick = k.tick, pad = 0.6 * font;
    if (p->axis[0].title)
        plot_text_centred(cr, p->axis[0].title, font, 0.5 * (l->x0 + l->x1),
                          l->y1 + tick + 1.3 * tick_font + 0.35 * font, l->width, pad);
    if (p->axis[1].title) {
        cairo_save(cr);
        cairo_translate(cr, pad, 0.5 * (l->y0 + l->y1));
        cairo_rotate(cr, -M_PI / 2);
        plot_text_at(cr, p->axis[1].title, font, 0.0, 0.0, 0.5, 0.0);
        cairo_restore(cr);
    }
    if (p->title) {
        cairo_select_font_face(cr, PLOT_FONT_FACE, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
        plot_text_centred(cr, p->title, 1.1 * font, 0.5 * (l->x0 + l->x1), pad, l->width, pad);
        cairo_select_font_face(cr, PLOT_FONT_FACE, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    }
    double ny = l->y1 + tick + 1.3 * tick_font + (p->axis[0].title ? 1.35 * font : 0.0) + 0.3 * font;
    for (int i = 0; i < p->nnotes; i++, ny += 1.3 * tick_font)
        plot_text_at(cr, p->notes[i], tick_font, l->x0, ny, 0.0, 0.0);
}

/* The legend: a framed box right of the plot area, or inside it (a wide one, in the
 * emptiest corner: plot_layout.c) on a translucent white ground. */
static void draw_legend(cairo_t *cr, const plot *p, const plot_layout *l, pen k)
{
    const double font = k.font, tick_font = k.tick_font, lw = k.lw;
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
        double cy = floor(y - 0.33 * tick_font) + 0.5, sw = plot_legend_sample_width(font);
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
        plot_text_run(cr, s->name, tick_font, sx + sw + 0.5 * font, y, 1);
        y += 1.45 * tick_font;
    }
}

void plot_draw(cairo_t *cr, const plot *p, const plot_layout *l)
{
    const pen k = pen_of(l);
    cairo_select_font_face(cr, PLOT_FONT_FACE, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    draw_area(cr, p, l, k);
    draw_frame(cr, l, k);
    draw_titles(cr, p, l, k);
    if (l->nlegend)
        draw_legend(cr, p, l, k);
    if (l->color_bar)
        draw_color_bar(cr, p->bar, l, k.lw);
    draw_labels(cr, p, l, 0.85 * k.font);
}
