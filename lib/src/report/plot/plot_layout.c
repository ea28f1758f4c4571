/* Where everything goes (plot_layout, plot.h): axis ranges, ticks for the room there is,
 * margins for the titles, tick labels, notes, legend and colour bar, and the legend's
 * corner when it goes inside. Text is measured with Cairo, on the surface that is drawn
 * on (plot_output.c) or on a 1x1 image (plot_layout_compute). The decisions on ranges,
 * ticks and the legend are plot.h's. */
#include "plot/plot_impl.h"

#include <math.h>
#include <string.h>

double plot_map(const plot_layout *l, int axis, double v)
{
    const plot_axis_layout *a = &l->axis[axis];
    double t = a->log ? (log10(v) - log10(a->lo)) / (log10(a->hi) - log10(a->lo)) : (v - a->lo) / (a->hi - a->lo);
    return axis == PLOT_X ? l->x0 + t * (l->x1 - l->x0) : l->y1 - t * (l->y1 - l->y0);
}

int plot_drawable(const plot_layout *l, double x, double y)
{
    return isfinite(x) && isfinite(y) && !(l->axis[0].log && !(x > 0.0)) && !(l->axis[1].log && !(y > 0.0));
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

double plot_legend_sample_width(double font)
{
    return 2.4 * font;
}

static double max_label_width(cairo_t *cr, const plot_ticks *t, double size)
{
    double w = 0.0;
    for (int i = 0; i < t->n; i++)
        w = fmax(w, plot_text_run(cr, t->label[i], size, 0, 0, 0).width);
    return w;
}

static int clampi(int v, int lo, int hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

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
                if (!plot_drawable(l, s->x[k], s->y[k]))
                    continue;
                double X = plot_map(l, PLOT_X, s->x[k]), Y = plot_map(l, PLOT_Y, s->y[k]);
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

void plot_layout_with(const plot *p, cairo_t *cr, int width, int height, plot_layout *l)
{
    memset(l, 0, sizeof *l);
    l->width = width;
    l->height = height;
    double font = fmin(width, height) / 34.0;
    l->font = font = font < 9.0 ? 9.0 : font > 22.0 ? 22.0 : font;
    double tick_font = 0.9 * font, pad = 0.6 * font, tick = 0.4 * font;
    cairo_select_font_face(cr, PLOT_FONT_FACE, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    for (int a = 0; a < 2; a++)
        axis_range(p, a, &l->axis[a]);

    /* Legend: the widest entry. */
    double lw = 0.0;
    for (int i = 0; i < p->ns; i++)
        if (p->s[i]->name) {
            l->nlegend++;
            lw = fmax(lw, plot_text_run(cr, p->s[i]->name, tick_font, 0, 0, 0).width);
        }
    l->legend_w = l->nlegend ? plot_legend_sample_width(font) + 0.5 * font + lw + 1.2 * font : 0.0;
    l->legend_h = l->nlegend ? l->nlegend * 1.45 * tick_font + 0.8 * font : 0.0;
    /* A wide legend would squeeze the plot: it goes inside, in the emptiest corner. */
    l->legend_inside = l->nlegend && l->legend_w > 0.3 * width;

    double top = pad + (p->title ? 1.25 * font + pad : 0.0);
    double bottom = pad + tick + 1.3 * tick_font + (p->axis[0].title ? 1.35 * font : 0.0) + p->nnotes * 1.3 * tick_font;
    double right = (l->nlegend && !l->legend_inside ? l->legend_w + 1.2 * font : 0.0) + 1.5 * font;
    if (p->bar) {
        /* The bar, its tick labels and its title (turned, reading upwards). */
        l->color_bar = 1;
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
        plot_layout_with(p, cr, width, height, l);
    cairo_destroy(cr);
    cairo_surface_destroy(s);
    return ok ? 0 : -1;
}
