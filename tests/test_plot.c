/* The plot module (lib/src/report/plot): ranges that never collapse, 1-2-5 and decade ticks
 * with their labels, the layout (legend entries, ticks matching the data), the scatter
 * with its Pareto front and labels, and the encoded files (PNG size, SVG and PDF
 * headers, no file on failure). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "brdfit/image.h"
#include "plot/plot.h"
#include "plot/scatter.h"
#include "support.h"

static int has_label(const plot_ticks *t, const char *label)
{
    for (int i = 0; i < t->n; i++)
        if (!strcmp(t->label[i], label))
            return 1;
    return 0;
}

/* Padding: 5% each side; a zero-width range gets a span; a tiny spread does not fill
 * the axis; no data gives a default range. */
static void test_ranges(void **state)
{
    (void)state;
    double lo, hi;
    plot_pad(0.0, 10.0, 1, 0, &lo, &hi);
    ts_assert_near(lo, -0.5, 1e-12, 1e-12, "linear lo");
    ts_assert_near(hi, 10.5, 1e-12, 1e-12, "linear hi");
    plot_pad(5.0, 5.0, 1, 0, &lo, &hi); /* 10% of the magnitude, padded */
    assert_true(lo < 5.0 && hi > 5.0);
    ts_assert_near(hi - lo, 0.55, 1e-12, 1e-12, "collapsed linear");
    plot_pad(0.0, 0.0, 1, 0, &lo, &hi);
    assert_true(lo < 0.0 && hi > 0.0 && hi - lo >= 1.0);
    plot_pad(0.0, 0.0, 0, 0, &lo, &hi); /* no data */
    assert_true(lo < hi);
    /* Log: 0.2% spread -> at least 0.1 decade, so the points sit in the middle. */
    plot_pad(0.00645, 0.00646, 1, 1, &lo, &hi);
    assert_true(log10(hi / lo) >= 0.1);
    assert_true(lo < 0.00645 && hi > 0.00646);
    double frac = (log10(0.00646) - log10(0.00645)) / log10(hi / lo);
    assert_true(frac < 0.02);
    plot_pad(1e-3, 1e1, 1, 1, &lo, &hi);
    ts_assert_near(log10(lo), -3.2, 1e-12, 1e-12, "log lo");
    ts_assert_near(log10(hi), 1.2, 1e-12, 1e-12, "log hi");
    /* Extent: NaN and (log) non-positive values left out. */
    const double v[5] = {NAN, -1.0, 0.0, 2.0, 8.0};
    assert_int_equal(plot_extent(5, v, 1, &lo, &hi), 1);
    assert_true(lo == 2.0 && hi == 8.0);
    assert_int_equal(plot_extent(5, v, 0, &lo, &hi), 1);
    assert_true(lo == -1.0 && hi == 8.0);
    const double none[2] = {NAN, -3.0};
    assert_int_equal(plot_extent(2, none, 1, &lo, &hi), 0);
}

static void test_ticks_linear(void **state)
{
    (void)state;
    plot_ticks t;
    plot_make_ticks(-0.5, 10.5, 0, 5, 0, 0.0, &t);
    assert_int_equal(t.n, 6); /* 0 2 4 6 8 10 */
    assert_true(t.value[0] == 0.0 && t.value[5] == 10.0);
    assert_string_equal(t.label[0], "0");
    assert_string_equal(t.label[5], "10");
    plot_make_ticks(-0.93, 0.93, 0, 5, 0, 0.0, &t); /* step 0.5 */
    assert_int_equal(t.n, 3);
    assert_string_equal(t.label[0], "\xe2\x88\x92"
                                    "0.5"); /* a real minus sign */
    assert_string_equal(t.label[1], "0.0");
    assert_string_equal(t.label[2], "0.5");
    plot_make_ticks(-90, 90, 0, 4, 0, 30.0, &t); /* a fixed step */
    assert_int_equal(t.n, 7);
    assert_string_equal(t.label[3], "0");
    plot_make_ticks(0.6, 3.4, 0, 10, 1, 0.0, &t); /* integer axis: no 1.5 */
    assert_int_equal(t.n, 3);
    assert_string_equal(t.label[0], "1");
    /* Large values: a shared power of ten. */
    plot_make_ticks(0.0, 3e6, 0, 4, 0, 0.0, &t);
    assert_true(has_label(&t, "1\xc3\x97"
                              "10^{6}"));
    /* Ticks stay inside the range; the steps are 1, 2 or 5 times a power of ten. */
    for (double span = 0.013; span < 1e4; span *= 3.7) {
        plot_make_ticks(1.0, 1.0 + span, 0, 6, 0, 0.0, &t);
        assert_true(t.n >= 2);
        double step = t.value[1] - t.value[0], m = step / pow(10.0, floor(log10(step) + 1e-9));
        assert_true(fabs(m - 1.0) < 1e-6 || fabs(m - 2.0) < 1e-6 || fabs(m - 5.0) < 1e-6);
        assert_true(t.value[0] >= 1.0 - 1e-9 && t.value[t.n - 1] <= 1.0 + span + 1e-9);
    }
}

static void test_ticks_log(void **state)
{
    (void)state;
    plot_ticks t;
    plot_make_ticks(0.6e-3, 20.0, 1, 8, 0, 0.0, &t); /* decades 10^-3 .. 10^1 */
    assert_int_equal(t.n, 5);
    assert_string_equal(t.label[0], "10^{-3}");
    assert_string_equal(t.label[4], "10^{1}");
    assert_true(t.nminor > 0);
    plot_make_ticks(1e-12, 1e12, 1, 5, 0, 0.0, &t); /* crowded: every 5th or 10th decade */
    assert_true(t.n >= 3 && t.n <= 6);
    assert_true(has_label(&t, "10^{0}"));
    plot_make_ticks(0.012, 0.09, 1, 6, 0, 0.0, &t); /* under two decades: values */
    assert_true(t.n >= 2);
    for (int i = 0; i < t.n; i++)
        assert_true(t.value[i] >= 0.012 && t.value[i] <= 0.09);
    plot_make_ticks(0.15, 6.0, 1, 6, 0, 0.0, &t); /* 1-2-5 values: 0.2 0.5 1 2 5 */
    assert_int_equal(t.n, 5);
    assert_string_equal(t.label[0], "0.2");
    assert_string_equal(t.label[4], "5");
    /* 1.7 decades: two decade ticks would say little; the labelled 1-2-5 values. */
    plot_make_ticks(0.011, 0.55, 1, 6, 0, 0.0, &t);
    assert_int_equal(t.n, 5);
    const char *want[5] = {"0.02", "0.05", "0.1", "0.2", "0.5"};
    for (int i = 0; i < 5; i++)
        assert_string_equal(t.label[i], want[i]);
    assert_true(t.nminor > 0);
    plot_make_ticks(2e-5, 1e-3, 1, 6, 0, 0.0, &t); /* small values: m x 10^k */
    assert_true(has_label(&t, "5\xc3\x97"
                              "10^{-5}") &&
                has_label(&t, "10^{-4}") && has_label(&t, "10^{-3}"));
    /* Three decades and more: decades only. */
    plot_make_ticks(0.0011, 2.0, 1, 6, 0, 0.0, &t);
    assert_int_equal(t.n, 3); /* 10^-2, 10^-1, 10^0 */
    assert_string_equal(t.label[0], "10^{-2}");
    /* The tradeoff's 0.2% spread, padded: readable values, not one repeated label. */
    double lo, hi;
    plot_pad(0.00645, 0.00646, 1, 1, &lo, &hi);
    plot_make_ticks(lo, hi, 1, 6, 0, 0.0, &t);
    assert_true(t.n >= 2);
    for (int i = 1; i < t.n; i++)
        assert_string_not_equal(t.label[i], t.label[i - 1]);
    assert_true(has_label(&t, "6.5\xc3\x97"
                              "10^{-3}") ||
                has_label(&t, "0.0065"));
}

static void test_markup(void **state)
{
    (void)state;
    char out[64];
    plot_plain_text("\xce\xb8_{o} (sr^{-1})", out, sizeof out);
    assert_string_equal(out, "\xce\xb8o (sr-1)");
    plot_plain_text("a_b^c", out, sizeof out); /* no braces: as written */
    assert_string_equal(out, "a_b^c");
}

/* A plot's layout: the ranges cover the data, ticks label them, every named series is a
 * legend entry; the scatter's front is in x order and its points are labelled. */
static void test_layout_and_scatter(void **state)
{
    (void)state;
    const double x[4] = {2, 5, 3, 8}, y[4] = {0.2, 0.011, 0.05, 0.01};
    const int front[4] = {1, 1, 1, 1};
    const char *labels[4] = {"lambert", "walter", "ward", "cook_torrance"};
    plot_scatter_spec sp = {
        "error against k", "free parameters k", "rmse_log", 0, 1, 1, 4, x, y, front, labels, "models", NULL, 1,
        "simplest"};
    plot *p = plot_scatter(&sp);
    assert_non_null(p);
    assert_int_equal(plot_nseries(p), 3);
    const plot_series *f = plot_series_at(p, 1);
    assert_string_equal(f->name, "Pareto front");
    assert_int_equal(f->n, 4);
    for (size_t i = 1; i < f->n; i++)
        assert_true(f->x[i] >= f->x[i - 1]);
    const plot_series *pts = plot_series_at(p, 0);
    assert_non_null(pts->labels);
    assert_string_equal(pts->labels[3], "cook_torrance");
    plot_layout l;
    assert_int_equal(plot_layout_compute(p, 640, 400, &l), 0);
    assert_int_equal(l.nlegend, 3);
    assert_true(l.axis[PLOT_X].lo < 2.0 && l.axis[PLOT_X].hi > 8.0);
    assert_true(l.axis[PLOT_Y].lo < 0.01 && l.axis[PLOT_Y].hi > 0.2 && l.axis[PLOT_Y].log);
    assert_true(has_label(&l.axis[PLOT_X].ticks, "2") && has_label(&l.axis[PLOT_X].ticks, "8"));
    for (int i = 0; i < l.axis[PLOT_X].ticks.n; i++) /* integer axis */
        assert_true(l.axis[PLOT_X].ticks.value[i] == floor(l.axis[PLOT_X].ticks.value[i]));
    assert_true(has_label(&l.axis[PLOT_Y].ticks, "0.01") || has_label(&l.axis[PLOT_Y].ticks, "10^{-2}"));
    assert_true(l.x0 < l.x1 && l.y0 < l.y1 && l.x1 <= 640 && l.y1 <= 400);
    /* The legend is beside or inside the plot area, never off the figure. */
    assert_true(l.legend_x >= 0 && l.legend_x + l.legend_w <= 640 + 1e-9);

    /* Files: a PNG of the size asked for, SVG and PDF by their headers. */
    bf_error err;
    unsigned char *data;
    size_t len;
    assert_int_equal(plot_encode(p, BF_PLOT_SVG, 640, 400, &data, &len, &err), BF_OK);
    assert_non_null(strstr((const char *)data, "<svg"));
    assert_non_null(strstr((const char *)data, "width=\"640pt\""));
    free(data);
    assert_int_equal(plot_encode(p, BF_PLOT_PDF, 640, 400, &data, &len, &err), BF_OK);
    assert_memory_equal(data, "%PDF-", 5);
    free(data);
    const char *path = ts_tmp_path("scatter.png");
    assert_int_equal(plot_write(p, path, BF_PLOT_PNG, 300, 200, &err), BF_OK);
    bf_image img;
    bf_image_init(&img);
    assert_int_equal(bf_image_read(path, &img, &err), BF_OK);
    assert_int_equal(img.width, 300);
    assert_int_equal(img.height, 200);
    bf_image_clear(&img);
    /* Too small, or an unwritable place: an error naming the file, and no file. */
    assert_int_equal(plot_write(p, ts_tmp_path("tiny.png"), BF_PLOT_PNG, 10, 10, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "tiny.png"));
    assert_int_equal(access(ts_tmp_path("tiny.png"), F_OK), -1);
    assert_int_equal(plot_write(p, "/nonexistent-dir/p.pdf", BF_PLOT_PDF, 300, 200, &err), BF_ERR_IO);
    assert_non_null(strstr(err.msg, "/nonexistent-dir/p.pdf"));
    plot_free(p);
}

/* Rows of a PNG column that hold a colour (within 8 of each byte). */
static int rows_of(const bf_image *img, int x, const unsigned char c[3])
{
    int n = 0;
    for (int y = 0; y < img->height; y++) {
        const float *v = img->pixels + 3 * ((size_t)y * (size_t)img->width + (size_t)x);
        int hit = 1;
        for (int k = 0; k < 3; k++)
            hit &= fabs(v[k] * 255.0 - c[k]) <= 8.0;
        n += hit;
    }
    return n;
}

/* Legend lines of one width are as many pixel rows thick whatever their place in the
 * legend (a line between two rows would be smeared over both). */
static void test_legend_lines_equal(void **state)
{
    (void)state;
    plot *p = plot_new("legend");
    const double x[2] = {0, 1}, y[2] = {1, 2};
    for (int k = 0; k < 5; k++) {
        char name[32];
        snprintf(name, sizeof name, "entry %d", k);
        plot_series *s = plot_add(p, name, PLOT_LINE, 2, x, y);
        plot_palette(k, s->rgb);
    }
    plot_layout l;
    assert_int_equal(plot_layout_compute(p, 503, 377, &l), 0);
    bf_error err;
    const char *path = ts_tmp_path("legend.png");
    assert_int_equal(plot_write(p, path, BF_PLOT_PNG, 503, 377, &err), BF_OK);
    bf_image img;
    bf_image_init(&img);
    assert_int_equal(bf_image_read(path, &img, &err), BF_OK);
    int column = (int)(l.legend_x + 0.6 * l.font + 1.2 * l.font), rows = -1;
    for (int k = 0; k < 5; k++) {
        double rgb[3];
        plot_palette(k, rgb);
        /* The exact colour as the PNG stores it (no sRGB step in Cairo's PNG). */
        unsigned char c[3] = {(unsigned char)lround(rgb[0] * 255), (unsigned char)lround(rgb[1] * 255),
                              (unsigned char)lround(rgb[2] * 255)};
        int n = rows_of(&img, column, c);
        assert_true(n >= 1);
        if (rows < 0)
            rows = n;
        assert_int_equal(n, rows);
    }
    bf_image_clear(&img);
    plot_free(p);
}

/* A raster with a colour bar: the bar's ticks span its range, its title is in the SVG,
 * and the plot area is left of the bar. */
static void test_raster_color_bar(void **state)
{
    (void)state;
    plot *p = plot_new("raster");
    unsigned char px[4 * 3 * 3], lut[PLOT_LUT][3];
    for (int i = 0; i < 36; i++)
        px[i] = (unsigned char)(7 * i);
    for (int k = 0; k < PLOT_LUT; k++)
        lut[k][0] = lut[k][1] = lut[k][2] = (unsigned char)k;
    assert_int_equal(plot_raster(p, 4, 3, px), 0);
    plot_axis(p, PLOT_X, "x", 0);
    plot_axis_range(p, PLOT_X, 0.0, 3.0);
    plot_axis_range(p, PLOT_Y, 0.0, 90.0);
    const double tv[3] = {0.0, 1.0, 3.0};
    const char *tl[3] = {"0\xc2\xb0", "1\xc2\xb0", "9\xc2\xb0"};
    assert_int_equal(plot_axis_ticks(p, PLOT_X, 3, tv, tl), 0);
    assert_int_equal(plot_color_bar(p, "log_{2} ratio", -2.0, 2.0, 0, lut), 0);
    plot_layout l;
    assert_int_equal(plot_layout_compute(p, 400, 300, &l), 0);
    assert_int_equal(l.color_bar, 1);
    assert_true(l.bar_x > l.x1 && l.bar_x + l.bar_w < 400);
    assert_true(has_label(&l.bar_ticks, "\xe2\x88\x92"
                                        "2") &&
                has_label(&l.bar_ticks, "2"));
    assert_int_equal(l.axis[PLOT_X].ticks.n, 3);
    assert_string_equal(l.axis[PLOT_X].ticks.label[2], "9\xc2\xb0");
    bf_error err;
    unsigned char *data;
    size_t len;
    assert_int_equal(plot_encode(p, BF_PLOT_PDF, 400, 300, &data, &len, &err), BF_OK);
    free(data);
    assert_int_equal(plot_encode(p, BF_PLOT_SVG, 400, 300, &data, &len, &err), BF_OK);
    assert_non_null(strstr((const char *)data, "<image"));
    free(data);
    plot_free(p);
}

static void test_formats(void **state)
{
    (void)state;
    assert_int_equal(bf_plot_format_of("a.png"), BF_PLOT_PNG);
    assert_int_equal(bf_plot_format_of("dir.x/A.SVG"), BF_PLOT_SVG);
    assert_int_equal(bf_plot_format_of("a.pdf"), BF_PLOT_PDF);
    assert_int_equal(bf_plot_format_of("a.exr"), 0);
    assert_int_equal(bf_plot_format_of("dir.pdf/a"), 0);
    assert_int_equal(bf_plot_format_of("-"), 0);
    bf_plot_format f = BF_PLOT_BY_NAME;
    assert_int_equal(bf_plot_format_parse("svg", &f, NULL), BF_OK);
    assert_int_equal(f, BF_PLOT_SVG);
    assert_int_equal(bf_plot_format_parse("gif", &f, NULL), BF_ERR_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ranges),
        cmocka_unit_test(test_ticks_linear),
        cmocka_unit_test(test_ticks_log),
        cmocka_unit_test(test_markup),
        cmocka_unit_test(test_layout_and_scatter),
        cmocka_unit_test(test_formats),
        cmocka_unit_test(test_legend_lines_equal),
        cmocka_unit_test(test_raster_color_bar),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
