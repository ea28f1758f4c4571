/* Markup text with Cairo (plot.h): "^{...}" raised and "_{...}" lowered, smaller; a '-'
 * in them is drawn as a minus sign. One routine measures and draws (plot_text_run), so
 * the layout's sizes are the drawn ones. */
#include "plot/plot_impl.h"

#include <math.h>
#include <string.h>

plot_text_size plot_text_run(cairo_t *cr, const char *s, double size, double x, double y, int draw)
{
    plot_text_size ts = {0.0, 0.0, 0.0};
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

plot_text_size plot_text_at(cairo_t *cr, const char *s, double size, double x, double y, double ax, double ay)
{
    plot_text_size ts = plot_text_run(cr, s, size, 0, 0, 0);
    double by = ay >= 1.0 ? y : ay > 0.0 ? y + 0.36 * size : y + ts.ascent;
    plot_text_run(cr, s, size, x - ax * ts.width, by, 1);
    return ts;
}

void plot_text_centred(cairo_t *cr, const char *s, double size, double x, double y, double width, double pad)
{
    double w = plot_text_run(cr, s, size, 0, 0, 0).width, room = width - 2.0 * pad;
    if (w > room && w > 0.0) {
        size *= room / w;
        w = room;
    }
    double left = x - 0.5 * w;
    left = left < pad ? pad : left + w > width - pad ? width - pad - w : left;
    plot_text_at(cr, s, size, left, y, 0.0, 0.0);
}
