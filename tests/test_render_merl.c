/* A sphere of a measured MERL table matches the sphere of the model the table was made
 * from: exactly for Lambert (a constant table) wherever the looked-up cell is valid, and
 * to within the table's discretisation for a glossy model. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>

#include <cmocka.h>

#include "brdfit/formats.h"
#include "brdfit/render.h"
#include "support.h"
#include "synth.h"

enum { SIZE = 64 };

/* The model's MERL table, written and read back so that it carries its origin. */
static bf_samples *merl_of(const bf_model *m, const double *x, const char *name)
{
    bf_synth_options so = {.pattern = BF_SYNTH_MERL};
    bf_samples *gen, *s;
    bf_error err;
    if (bf_synth_generate(m, x, &so, &gen, &err) != BF_OK)
        fail_msg("%s", err.msg);
    const char *path = ts_tmp_path(name);
    if (bf_samples_write_merl(gen, path, &err) != BF_OK || bf_samples_read_merl(path, 0, &s, &err) != BF_OK)
        fail_msg("%s", err.msg);
    bf_samples_free(gen);
    return s;
}

static void spheres(const bf_model *m, const double *x, const bf_samples *s, float *a, float *b)
{
    bf_dir light = {30.0, 0.0};
    bf_sphere_options o;
    bf_sphere_options_init(&o);
    o.resolution = SIZE;
    o.lights = &light;
    assert_int_equal(bf_render_sphere(m, x, &o, a, NULL), BF_OK);
    assert_int_equal(bf_render_sphere_merl(s, &o, b, NULL), BF_OK);
}

static void test_lambert_table(void **state)
{
    (void)state;
    bf_model *m = ts_model("lambert", 3);
    double x[3] = {0.6, 0.4, 0.2};
    bf_samples *s = merl_of(m, x, "lambert.binary");
    float *a = malloc(SIZE * SIZE * 3 * sizeof *a), *b = malloc(SIZE * SIZE * 3 * sizeof *b);
    spheres(m, x, s, a, b);
    int lit = 0, equal = 0;
    for (int q = 0; q < SIZE * SIZE * 3; q++) {
        if (a[q] == 0.0f) {
            assert_true(b[q] == 0.0f); /* dark (or background) in both */
            continue;
        }
        lit++;
        /* Same value, or 0 where the lookup hit a cell below the horizon (near the rim). */
        if (fabsf(a[q] - b[q]) <= 1e-6f * a[q])
            equal++;
        else
            assert_true(b[q] == 0.0f);
    }
    assert_true(lit > SIZE * SIZE); /* a lit disc */
    assert_true(equal > 0.9 * lit);
    free(a);
    free(b);
    bf_samples_free(s);
    bf_model_free(m);
}

static void test_glossy_table(void **state)
{
    (void)state;
    bf_model *m = ts_model("walter", 3);
    double x[8] = {0.5, 0.3, 0.1, 0.5, 0.5, 0.5, 0.3, 0.04};
    bf_samples *s = merl_of(m, x, "walter.binary");
    float *a = malloc(SIZE * SIZE * 3 * sizeof *a), *b = malloc(SIZE * SIZE * 3 * sizeof *b);
    spheres(m, x, s, a, b);
    double sa = 0.0, sb = 0.0, diff = 0.0;
    for (int q = 0; q < SIZE * SIZE * 3; q++) {
        sa += a[q];
        sb += b[q];
        diff += fabs((double)a[q] - b[q]);
    }
    assert_true(fabs(sb / sa - 1.0) < 0.05); /* same light overall */
    assert_true(diff / sa < 0.1);            /* and in the same places */
    free(a);
    free(b);
    bf_samples_free(s);
    bf_model_free(m);
}

static void test_needs_a_table(void **state)
{
    (void)state;
    bf_samples *s = NULL;
    bf_samples_new(3, 3, &s, NULL);
    bf_dir light = {0.0, 0.0};
    bf_sphere_options o;
    bf_sphere_options_init(&o);
    o.resolution = 8;
    o.lights = &light;
    float img[8 * 8 * 3];
    bf_error err;
    assert_int_equal(bf_render_sphere_merl(s, &o, img, &err), BF_ERR_ARG);
    bf_samples_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lambert_table),
        cmocka_unit_test(test_glossy_table),
        cmocka_unit_test(test_needs_a_table),
    };
    return cmocka_run_group_tests_name("render_merl", tests, NULL, NULL);
}
