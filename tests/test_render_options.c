/* brdfit render's defaults, limits and checks as the library gives them (render.h): the
 * inits' values, the checks' ranges and messages, the tone map's names and its mapping
 * through bf_tonemap_apply, and the memory check under BRDFIT_MEMORY. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/render.h"
#include "support.h"

static void assert_fails(bf_status rc, bf_status want, const bf_error *err, const char *msg)
{
    assert_int_equal(rc, want);
    assert_string_equal(err->msg, msg);
}

static void test_defaults(void **state)
{
    (void)state;
    bf_tonemap_options tm;
    bf_tonemap_options_init(&tm);
    assert_int_equal(tm.size, sizeof tm);
    assert_int_equal(tm.mode, BF_TONEMAP_CLAMP);
    assert_true(tm.exposure == 1.0 && tm.decades == 4.0);
    bf_halfdiff_options hd;
    bf_halfdiff_options_init(&hd);
    assert_int_equal(hd.size, sizeof hd);
    assert_true(hd.width == 256 && hd.height == 256 && hd.phi_d == 90.0);
    assert_int_equal(hd.tonemap, BF_TONEMAP_LOG);
    assert_true(hd.plot_width == 480 && hd.plot_height == 400);
    bf_sphere_options so;
    bf_sphere_options_init(&so);
    assert_int_equal(hd.width, so.resolution); /* the sphere's size */
    bf_error err;
    assert_int_equal(bf_tonemap_options_check(&tm, &err), BF_OK);
    assert_int_equal(bf_halfdiff_options_check(&hd, &err), BF_OK);
    assert_int_equal(bf_sphere_options_check(&so, &err), BF_OK);
}

static void test_tonemap_names_and_checks(void **state)
{
    (void)state;
    bf_tonemap_mode m = BF_TONEMAP_CLAMP;
    bf_error err;
    assert_int_equal(bf_tonemap_parse("reinhard", &m, &err), BF_OK);
    assert_int_equal(m, BF_TONEMAP_REINHARD);
    assert_int_equal(bf_tonemap_parse("log", &m, &err), BF_OK);
    assert_int_equal(m, BF_TONEMAP_LOG);
    assert_fails(bf_tonemap_parse("Log", &m, &err), BF_ERR_ARG, &err,
                 "unknown tone map 'Log' (clamp, reinhard or log)");
    assert_int_equal(m, BF_TONEMAP_LOG); /* left as it was */
    assert_string_equal(bf_tonemap_name(BF_TONEMAP_CLAMP), "clamp");
    assert_string_equal(bf_tonemap_name(BF_TONEMAP_LOG), "log");
    assert_null(bf_tonemap_name((bf_tonemap_mode)7));

    bf_tonemap_options tm;
    bf_tonemap_options_init(&tm);
    tm.exposure = 0.0;
    assert_fails(bf_tonemap_options_check(&tm, &err), BF_ERR_ARG, &err,
                 "tone map: exposure must be a finite number above 0, got 0");
    tm.exposure = NAN;
    assert_int_equal(bf_tonemap_options_check(&tm, &err), BF_ERR_ARG);
    tm.exposure = 2.0;
    tm.decades = -1.0;
    assert_fails(bf_tonemap_options_check(&tm, &err), BF_ERR_ARG, &err,
                 "tone map: decades must be a finite number above 0, got -1");
    tm.decades = INFINITY;
    assert_int_equal(bf_tonemap_options_check(&tm, &err), BF_ERR_ARG);
    tm.decades = 3.0;
    tm.mode = (bf_tonemap_mode)3;
    assert_fails(bf_tonemap_options_check(&tm, &err), BF_ERR_ARG, &err, "tone map: unknown mode 3");
    tm.size = 0;
    assert_int_equal(bf_tonemap_options_check(&tm, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "bf_tonemap_options: size 0"));
}

static void test_tonemap_apply_is_bf_tonemap(void **state)
{
    (void)state;
    const float v[6] = {0.0f, 0.25f, 1.0f, 4.0f, -1.0f, 100.0f};
    for (int mode = 0; mode < 3; mode++) {
        bf_tonemap_options tm;
        bf_tonemap_options_init(&tm);
        tm.mode = (bf_tonemap_mode)mode;
        tm.exposure = 0.5;
        tm.decades = 2.0;
        float a[6], b[6];
        memcpy(a, v, sizeof v);
        memcpy(b, v, sizeof v);
        assert_int_equal(bf_tonemap_apply(a, 6, &tm, NULL), BF_OK);
        bf_tonemap(b, 6, tm.mode, 0.5, 2.0);
        assert_memory_equal(a, b, sizeof a);
    }
    /* Values known by hand: clamp multiplies, reinhard e/(1+e), log over two decades
     * below the maximum (50 after the exposure): 0.5 -> 0, 50 -> 1. */
    bf_tonemap_options tm;
    bf_tonemap_options_init(&tm);
    tm.exposure = 0.5;
    float c[2] = {4.0f, 1.0f};
    assert_int_equal(bf_tonemap_apply(c, 2, &tm, NULL), BF_OK);
    assert_true(c[0] == 2.0f && c[1] == 0.5f);
    tm.mode = BF_TONEMAP_REINHARD;
    float r[1] = {2.0f};
    assert_int_equal(bf_tonemap_apply(r, 1, &tm, NULL), BF_OK);
    assert_true(r[0] == 0.5f);
    tm.mode = BF_TONEMAP_LOG;
    tm.decades = 2.0;
    float l[3] = {100.0f, 1.0f, 10.0f};
    assert_int_equal(bf_tonemap_apply(l, 3, &tm, NULL), BF_OK);
    ts_assert_near(l[0], 1.0, 1e-6, 1e-6, "log: the maximum");
    ts_assert_near(l[1], 0.0, 1e-6, 1e-6, "log: two decades down");
    ts_assert_near(l[2], 0.5, 1e-6, 1e-6, "log: one decade down");
    /* A bad exposure changes nothing. */
    tm.exposure = -1.0;
    float keep[1] = {3.0f};
    bf_error err;
    assert_int_equal(bf_tonemap_apply(keep, 1, &tm, &err), BF_ERR_ARG);
    assert_true(keep[0] == 3.0f);
}

static void test_sphere_check(void **state)
{
    (void)state;
    bf_dir lights[BF_RENDER_MAX_LIGHTS + 1];
    for (int k = 0; k <= BF_RENDER_MAX_LIGHTS; k++)
        lights[k] = (bf_dir){3.0 * k, 20.0 * k};
    bf_sphere_options so;
    bf_sphere_options_init(&so);
    so.lights = lights;
    so.nlights = BF_RENDER_MAX_LIGHTS;
    bf_error err;
    assert_int_equal(bf_sphere_options_check(&so, &err), BF_OK);
    so.nlights = BF_RENDER_MAX_LIGHTS + 1;
    assert_fails(bf_sphere_options_check(&so, &err), BF_ERR_ARG, &err, "at most 16 lights");
    so.nlights = 0;
    assert_fails(bf_sphere_options_check(&so, &err), BF_ERR_ARG, &err,
                 "sphere render: need a size >= 1 and at least one light");
    so.nlights = 2;
    so.resolution = BF_RENDER_MAX_SIDE + 1;
    assert_fails(bf_sphere_options_check(&so, &err), BF_ERR_ARG, &err,
                 "sphere render: size 16385 is above 16384 pixels");
    so.resolution = 0;
    assert_int_equal(bf_sphere_options_check(&so, &err), BF_ERR_ARG);
    so.resolution = 8;
    lights[1].phi = NAN;
    assert_fails(bf_sphere_options_check(&so, &err), BF_ERR_ARG, &err,
                 "sphere render: light 2 (3, nan) is not a finite direction");
    lights[1].phi = 20.0;
    so.view.theta = INFINITY;
    assert_int_equal(bf_sphere_options_check(&so, &err), BF_ERR_ARG);
    /* The render refuses what the check refuses, before drawing. */
    bf_model *m = ts_model("lambert", 1);
    double x = 0.5;
    float rgb[8 * 8 * 3];
    assert_int_equal(bf_render_sphere(m, &x, &so, rgb, &err), BF_ERR_ARG);
    assert_string_equal(err.msg, "sphere render: the view (inf, 0) is not a finite direction");
    so.view.theta = 0.0;
    assert_int_equal(bf_render_sphere(m, &x, &so, rgb, &err), BF_OK);
    bf_model_free(m);
}

static void test_halfdiff_check(void **state)
{
    (void)state;
    bf_halfdiff_options hd;
    bf_halfdiff_options_init(&hd);
    bf_error err;
    hd.width = 0;
    hd.height = 5;
    assert_fails(bf_halfdiff_options_check(&hd, &err), BF_ERR_ARG, &err,
                 "half/difference image: bad size 0x5 (each side 1 to 16384)");
    hd.width = 16385;
    assert_int_equal(bf_halfdiff_options_check(&hd, &err), BF_ERR_ARG);
    hd.width = 10;
    hd.phi_d = NAN;
    assert_fails(bf_halfdiff_options_check(&hd, &err), BF_ERR_ARG, &err, "half/difference image: phi_d is not finite");
    hd.phi_d = 400.0; /* any finite angle */
    assert_int_equal(bf_halfdiff_options_check(&hd, &err), BF_OK);
    hd.plot_width = 39;
    assert_fails(bf_halfdiff_options_check(&hd, &err), BF_ERR_ARG, &err, "a half-diff plot must be at least 40x40");
    hd.plot_width = 40;
    hd.plot_height = 16385;
    assert_fails(bf_halfdiff_options_check(&hd, &err), BF_ERR_ARG, &err,
                 "a half-diff plot must be at most 16384x16384");
    hd.plot_height = 40;
    hd.tonemap = (bf_tonemap_mode)-1;
    assert_int_equal(bf_halfdiff_options_check(&hd, &err), BF_ERR_ARG);
    /* The drawing functions take the same sizes. */
    bf_model *m = ts_model("lambert", 1);
    double x = 0.5;
    assert_fails(bf_render_halfdiff_model(m, &x, 0, 5, 90.0, NULL, &err), BF_ERR_ARG, &err,
                 "half/difference image: bad size 0x5 (each side 1 to 16384)");
    assert_int_equal(bf_render_halfdiff_plot(m, &x, NULL, 90.0, 4.0, 39, 100, ts_tmp_path("hd.svg"), 0, &err),
                     BF_ERR_ARG);
    assert_string_equal(err.msg, "half/difference plot: bad size 39x100 (each side 40 to 16384)");
    bf_model_free(m);
}

static void test_memory_check(void **state)
{
    (void)state;
    bf_error err;
    setenv("BRDFIT_MEMORY", "1M", 1);
    assert_int_equal(bf_render_memory_check(256, 256, &err), BF_OK); /* exactly 1 MiB */
    /* 16 bytes a pixel: 1.37 MiB. */
    assert_fails(bf_render_memory_check(300, 300, &err), BF_ERR_NOMEM, &err,
                 "a 300x300 image needs about 1.37 MiB, 1 MiB available (BRDFIT_MEMORY)");
    unsetenv("BRDFIT_MEMORY");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_tonemap_names_and_checks),
        cmocka_unit_test(test_tonemap_apply_is_bf_tonemap),
        cmocka_unit_test(test_sphere_check),
        cmocka_unit_test(test_halfdiff_check),
        cmocka_unit_test(test_memory_check),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
