/* Half/difference figures (lib/src/report/render/halfdiff_figure.c) and the data-chosen
 * exposure: a model against itself differs by exactly 0 everywhere and shows exactly
 * the scale's white centre; the signed difference says which side is brighter; the
 * shared log scale comes from the measurement; a sphere's exposure is its percentile. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/render.h"
#include "render/halfdiff_figure.h"
#include "support.h"

enum { W = 90, H = 60 };

/* A model's image, as the report makes it: the mean of the channels per pixel. */
static double *model_image(const char *spec)
{
    bf_model *m = ts_model(spec, 3);
    double x[16];
    assert_true(bf_model_nvalues(m) <= 16);
    bf_model_defaults(m, x);
    float *rgb = malloc((size_t)W * H * 3 * sizeof *rgb);
    double *v = malloc((size_t)W * H * sizeof *v);
    bf_error err;
    assert_int_equal(bf_render_halfdiff_model(m, x, W, H, 90.0, rgb, &err), BF_OK);
    halfdiff_mean(rgb, (size_t)W * H, v);
    free(rgb);
    bf_model_free(m);
    return v;
}

static void test_self_difference_is_centre(void **state)
{
    (void)state;
    double *v = model_image("walter"), *r = malloc((size_t)W * H * sizeof *r);
    halfdiff_log2_ratio(v, v, (size_t)W * H, r);
    unsigned char *px = malloc((size_t)W * H * 3);
    halfdiff_ratio_raster(r, W, H, 2.0, px);
    size_t valid = 0;
    for (size_t p = 0; p < (size_t)W * H; p++) {
        if (!(v[p] > 0.0)) { /* nothing to compare: the "no value" grey, never white */
            assert_true(isnan(r[p]));
            assert_int_equal(px[3 * p], HALFDIFF_NONE);
            continue;
        }
        valid++;
        assert_true(r[p] == 0.0);
        assert_int_equal(px[3 * p], 255);
        assert_int_equal(px[3 * p + 1], 255);
        assert_int_equal(px[3 * p + 2], 255);
    }
    assert_true(valid > (size_t)W * H / 2);
    /* The figure: a raster with a colour bar from -2 to 2, titled. */
    plot *p = halfdiff_ratio_figure(r, W, H, "walter vs walter", 2.0);
    assert_non_null(p);
    plot_layout l;
    assert_int_equal(plot_layout_compute(p, 340, 280, &l), 0);
    assert_int_equal(l.color_bar, 1);
    assert_true(l.bar_ticks.n >= 3);
    assert_true(l.bar_ticks.value[0] >= -2.0 && l.bar_ticks.value[l.bar_ticks.n - 1] <= 2.0);
    /* theta_h ticks in degrees on the sqrt axis: 45 degrees sits at sqrt(1/2). */
    int at45 = 0;
    for (int i = 0; i < l.axis[PLOT_X].ticks.n; i++)
        if (!strcmp(l.axis[PLOT_X].ticks.label[i], "45\xc2\xb0"))
            at45 = fabs(l.axis[PLOT_X].ticks.value[i] - sqrt(0.5)) < 1e-12;
    assert_true(at45);
    plot_free(p);
    free(px);
    free(r);
    free(v);
}

/* Signed: a brighter model is red (more red than blue), a darker one blue, and the
 * colour saturates beyond the span. */
static void test_signed_difference(void **state)
{
    (void)state;
    const double model[4] = {2.0, 0.5, 64.0, 0.0}, meas[4] = {1.0, 1.0, 1.0, 1.0};
    double r[4];
    halfdiff_log2_ratio(model, meas, 4, r);
    assert_true(r[0] == 1.0 && r[1] == -1.0 && r[2] == 6.0 && isinf(r[3]) && r[3] < 0);
    unsigned char c[3], d[3];
    halfdiff_diverging(r[0] / 2.0, c);
    assert_true(c[0] > c[2]);
    halfdiff_diverging(r[1] / 2.0, c);
    assert_true(c[2] > c[0]);
    halfdiff_diverging(r[2] / 2.0, c);
    halfdiff_diverging(1.0, d);
    assert_memory_equal(c, d, 3);
    halfdiff_diverging(-INFINITY, c);
    halfdiff_diverging(-1.0, d);
    assert_memory_equal(c, d, 3);
}

/* The shared log scale: from the measurement's percentile, 4 decades down; models drawn
 * with it keep it (the same numbers on every panel's colour bar). */
static void test_shared_scale(void **state)
{
    (void)state;
    double v[1000];
    for (int i = 0; i < 1000; i++)
        v[i] = i < 10 ? 0.0 : (double)i; /* zeros: no value */
    double lo, hi;
    assert_int_equal(halfdiff_log_range(v, 1000, 100.0, 4.0, &lo, &hi), 0);
    assert_true(hi == log10(999.0) && lo == hi - 4.0);
    assert_int_equal(halfdiff_log_range(v, 1000, 50.0, 4.0, &lo, &hi), 0);
    assert_true(fabs(hi - log10(505.0)) < 0.01);
    double zero[3] = {0, 0, 0};
    assert_int_equal(halfdiff_log_range(zero, 3, 99.0, 4.0, &lo, &hi), -1);
    double *a = model_image("walter"), *b = model_image("lambert");
    assert_int_equal(halfdiff_log_range(a, (size_t)W * H, 99.0, 4.0, &lo, &hi), 0);
    plot *pa = halfdiff_value_figure(a, W, H, "a", lo, hi), *pb = halfdiff_value_figure(b, W, H, "b", lo, hi);
    plot_layout la, lb;
    assert_int_equal(plot_layout_compute(pa, 340, 280, &la), 0);
    assert_int_equal(plot_layout_compute(pb, 340, 280, &lb), 0);
    assert_int_equal(la.bar_ticks.n, lb.bar_ticks.n);
    for (int i = 0; i < la.bar_ticks.n; i++)
        assert_string_equal(la.bar_ticks.label[i], lb.bar_ticks.label[i]);
    plot_free(pa);
    plot_free(pb);
    free(a);
    free(b);
}

/* Half/difference angles of direction pairs: the mirror direction has theta_h 0 and
 * theta_d the incidence; the retro direction (L = V) theta_d 0 and theta_h the
 * incidence; phi does not matter for either. */
static void test_angles(void **state)
{
    (void)state;
    double th, td;
    const double mirror[4] = {30.0, 10.0, 30.0, 190.0}, retro[4] = {40.0, 75.0, 40.0, 75.0};
    halfdiff_angles(mirror, &th, &td);
    ts_assert_near(th, 0.0, 0.0, 1e-9, "mirror theta_h");
    ts_assert_near(td, 30.0, 1e-12, 1e-9, "mirror theta_d");
    halfdiff_angles(retro, &th, &td);
    ts_assert_near(th, 40.0, 1e-12, 1e-9, "retro theta_h");
    ts_assert_near(td, 0.0, 0.0, 1e-6, "retro theta_d");
    /* Normal incidence, viewed at 60 degrees: H halfway, 30 degrees from each. */
    const double tilt[4] = {0.0, 0.0, 60.0, 0.0};
    halfdiff_angles(tilt, &th, &td);
    ts_assert_near(th, 30.0, 1e-12, 1e-9, "tilt theta_h");
    ts_assert_near(td, 30.0, 1e-12, 1e-9, "tilt theta_d");
}

/* The drawing order: NaN keys left out, ascending, equal keys by index. */
static void test_point_order(void **state)
{
    (void)state;
    const double key[6] = {3.0, NAN, 1.0, 3.0, 2.0, 1.0};
    size_t idx[6];
    assert_int_equal(halfdiff_point_order(6, key, idx), 5);
    const size_t want[5] = {2, 5, 4, 0, 3};
    for (int i = 0; i < 5; i++)
        assert_int_equal(idx[i], want[i]);
    assert_int_equal(halfdiff_point_order(0, key, idx), 0);
}

/* Scattered samples as points: the table figures' axes and colour bar, one marker per
 * sample with a value, brightest last (on top), each in the colour the scale gives; the
 * differences with the worst misfit last and an exact match white. No samples: an empty
 * figure, not a crash. */
static void test_points(void **state)
{
    (void)state;
    const double th[5] = {0.0, 10.0, 45.0, 80.0, 20.0}, td[5] = {0.0, 30.0, 60.0, 90.0, 5.0};
    const double v[5] = {1.0, 0.01, 0.0, 0.1, 1e-9}; /* 0: no value, left out */
    plot *p = halfdiff_value_points(5, th, td, v, "points", -4.0, 0.0);
    assert_non_null(p);
    assert_int_equal(plot_nseries(p), 1);
    const plot_series *s = plot_series_at(p, 0);
    assert_int_equal(s->n, 4);
    assert_non_null(s->colors);
    /* Ascending values: 1e-9 (below the scale: its bottom colour), 0.01, 0.1, 1. */
    const double want_x[4] = {sqrt(20.0 / 90.0), sqrt(10.0 / 90.0), sqrt(80.0 / 90.0), 0.0};
    const double want_y[4] = {5.0, 30.0, 90.0, 0.0}, want_t[4] = {0.0, 0.5, 0.75, 1.0};
    for (int i = 0; i < 4; i++) {
        ts_assert_near(s->x[i], want_x[i], 1e-12, 1e-12, "point x");
        ts_assert_near(s->y[i], want_y[i], 1e-12, 1e-12, "point y");
        unsigned char c[3];
        halfdiff_sequential(want_t[i], c);
        assert_memory_equal(s->colors + 3 * i, c, 3);
    }
    plot_layout l;
    assert_int_equal(plot_layout_compute(p, 340, 280, &l), 0);
    assert_int_equal(l.color_bar, 1);
    /* The axes cover 0..90 with a margin, so points on an edge show whole. */
    assert_true(l.axis[PLOT_Y].lo < 0.0 && l.axis[PLOT_Y].hi > 90.0);
    assert_true(l.axis[PLOT_X].lo < 0.0 && l.axis[PLOT_X].hi > 1.0);
    unsigned char *png;
    size_t len;
    bf_error err;
    assert_int_equal(plot_encode(p, BF_PLOT_PNG, 340, 280, &png, &len, &err), BF_OK);
    assert_true(len > 1000);
    free(png);
    plot_free(p);

    const double r[5] = {0.5, -3.0, NAN, 0.0, -0.25};
    p = halfdiff_ratio_points(5, th, td, r, "ratios", 2.0);
    assert_non_null(p);
    s = plot_series_at(p, 0);
    assert_int_equal(s->n, 4);
    ts_assert_near(s->y[0], 90.0, 0, 1e-12, "exact match first"); /* |r| 0 */
    ts_assert_near(s->y[3], 30.0, 0, 1e-12, "worst misfit last"); /* |r| 3 */
    assert_int_equal(s->colors[0], 255);
    assert_int_equal(s->colors[1], 255);
    assert_int_equal(s->colors[2], 255);
    unsigned char c[3];
    halfdiff_diverging(-1.0, c); /* saturated blue: the model far too dark */
    assert_memory_equal(s->colors + 9, c, 3);
    plot_free(p);

    p = halfdiff_value_points(0, th, td, v, "none", -4.0, 0.0);
    assert_non_null(p);
    assert_int_equal(plot_series_at(p, 0)->n, 0);
    assert_int_equal(plot_encode(p, BF_PLOT_PNG, 340, 280, &png, &len, &err), BF_OK);
    free(png);
    plot_free(p);
}

/* The exposure: 1 / the percentile of the brightest channel of the lit pixels. */
static void test_exposure(void **state)
{
    (void)state;
    float rgb[3 * 101];
    for (int p = 0; p < 101; p++) {
        rgb[3 * p] = p == 0 ? 0.0f : 0.01f * (float)p; /* 0: background, left out */
        rgb[3 * p + 1] = 0.0f;
        rgb[3 * p + 2] = 0.5f * rgb[3 * p];
    }
    /* 100 lit pixels 0.01 .. 1.00: the 50th percentile is 0.505. */
    ts_assert_near(bf_exposure_percentile(rgb, 101, 50.0), 1.0 / 0.505, 1e-5, 0, "median exposure");
    ts_assert_near(bf_exposure_percentile(rgb, 101, 100.0), 1.0, 1e-6, 0, "max exposure");
    float dark[6] = {0};
    assert_true(bf_exposure_percentile(dark, 2, 99.0) == 1.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_self_difference_is_centre),
        cmocka_unit_test(test_signed_difference),
        cmocka_unit_test(test_shared_scale),
        cmocka_unit_test(test_exposure),
        cmocka_unit_test(test_angles),
        cmocka_unit_test(test_point_order),
        cmocka_unit_test(test_points),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
