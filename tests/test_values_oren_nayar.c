/* Values of oren_nayar: sigma = 0 is Lambert, hand-computed geometries, and a plain
 * re-implementation of the docs/models.md formula from the angles (alpha, beta, phi). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>

#include <cmocka.h>

#include "support.h"

/* docs/models.md literally, from the angles in degrees. */
static double on_ref(double rd, double sigma, double ti, double pi_, double to, double po)
{
    double a = ti * DEG, b = pi_ * DEG, c = to * DEG, d = po * DEG;
    if (cos(a) <= 0.0 || cos(c) <= 0.0)
        return 0.0;
    double s2 = sigma * sigma;
    double A = 1.0 - s2 / (2.0 * (s2 + 0.33)), B = 0.45 * s2 / (s2 + 0.09);
    double alpha = fmax(a, c), beta = fmin(a, c);
    return rd / M_PI * (A + B * fmax(0.0, cos(b - d)) * sin(alpha) * tan(beta));
}

static void test_table(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("oren_nayar", 3, &m, NULL);
    assert_non_null(m);
    assert_int_equal(bf_model_nparams(m), 2);
    assert_int_equal(bf_model_nvalues(m), 4);
    assert_string_equal(bf_model_param(m, 0)->name, "rho_d");
    assert_string_equal(bf_model_param(m, 1)->name, "sigma");
    assert_true(bf_model_param(m, 1)->lo == 0.0 && bf_model_param(m, 1)->hi == M_PI / 2.0);
    bf_model_free(m);
}

/* sigma = 0: A = 1, B = 0, the model is lambert. */
static void test_lambert(void **state)
{
    (void)state;
    bf_model *m = ts_model("oren_nayar", 3), *l = ts_model("lambert", 3);
    double x[4] = {0.1, 0.5, 0.9, 0.0};
    ts_rng r = {42};
    for (int k = 0; k < 50; k++) {
        double ti = 89.0 * ts_uniform(&r), pi_ = 360.0 * ts_uniform(&r);
        double to = 89.0 * ts_uniform(&r), po = 360.0 * ts_uniform(&r);
        for (int c = 0; c < 3; c++) {
            double v = ts_eval1(m, x, ti, pi_, to, po, c);
            ts_assert_rel(v, ts_eval1(l, x, ti, pi_, to, po, c), 1e-15, "sigma 0 vs lambert");
            ts_assert_rel(v, x[c] / M_PI, 1e-15, "sigma 0");
        }
    }
    bf_model_free(m);
    bf_model_free(l);
}

/* By hand, sigma = 0.5: A = 1 - 0.25/1.16, B = 0.1125/0.34.
 * (60, 0) -> (30, 0): cos dphi = 1, sin 60 tan 30 = 1/2, f = rho_d/pi (A + B/2).
 * (30, 10) -> (60, 70): cos dphi = 1/2, f = rho_d/pi (A + B/4).
 * (40, 0) -> (50, 135): cos dphi < 0, f = rho_d/pi A.
 * (0, 0) -> (70, 0): theta_i = 0, sin(beta) = 0, f = rho_d/pi A. */
static void test_hand(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("oren_nayar", 1, &m, NULL);
    double x[2] = {0.8, 0.5};
    const double A = 1.0 - 0.25 / 1.16, B = 0.1125 / 0.34;
    ts_assert_rel(ts_eval1(m, x, 60.0, 0.0, 30.0, 0.0, 0), 0.8 / M_PI * (A + B / 2.0), 1e-14, "hand 1");
    ts_assert_rel(ts_eval1(m, x, 30.0, 0.0, 60.0, 0.0, 0), 0.8 / M_PI * (A + B / 2.0), 1e-14, "hand 1r");
    ts_assert_rel(ts_eval1(m, x, 30.0, 10.0, 60.0, 70.0, 0), 0.8 / M_PI * (A + B / 4.0), 1e-14, "hand 2");
    ts_assert_rel(ts_eval1(m, x, 40.0, 0.0, 50.0, 135.0, 0), 0.8 / M_PI * A, 1e-15, "hand 3");
    ts_assert_rel(ts_eval1(m, x, 0.0, 0.0, 70.0, 0.0, 0), 0.8 / M_PI * A, 1e-15, "hand 4");
    ts_assert_rel(ts_eval1(m, x, 0.0, 0.0, 0.0, 0.0, 0), 0.8 / M_PI * A, 1e-15, "hand 5");
    /* The digits: 0.8/pi (0.78448275862068966 + 0.16544117647058824) = 0.24189614372973056. */
    ts_assert_rel(ts_eval1(m, x, 60.0, 0.0, 30.0, 0.0, 0), 0.24189614372973056, 1e-14, "digits");
    bf_model_free(m);
}

/* Both at 89.999 degrees, same azimuth: sin(alpha) tan(beta) = sin^2/cos ~ 5.7e4, large
 * but finite; exactly on the horizon f = 0. */
static void test_grazing(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("oren_nayar", 1, &m, NULL);
    double x[2] = {1.0, M_PI / 2.0};
    double t = 89.999 * DEG;
    double s2 = x[1] * x[1];
    double A = 1.0 - s2 / (2.0 * (s2 + 0.33)), B = 0.45 * s2 / (s2 + 0.09);
    double want = (A + B * sin(t) * sin(t) / cos(t)) / M_PI;
    ts_assert_rel(ts_eval1(m, x, 89.999, 30.0, 89.999, 30.0, 0), want, 1e-10, "grazing");
    assert_true(ts_eval1(m, x, 90.0, 30.0, 90.0, 30.0, 0) == 0.0);
    bf_model_free(m);
}

static void test_random(void **state)
{
    (void)state;
    ts_rng r = {0xC0FFEE1234ULL};
    bf_model *m = NULL;
    bf_model_new("oren_nayar", 3, &m, NULL);
    double x[4];
    for (int k = 0; k < 400; k++) {
        for (int c = 0; c < 3; c++)
            x[c] = ts_uniform(&r);
        x[3] = 0.5 * M_PI * ts_uniform(&r);
        double ti = 89.0 * ts_uniform(&r), pi_ = 360.0 * ts_uniform(&r);
        double to = 89.0 * ts_uniform(&r), po = 360.0 * ts_uniform(&r);
        for (int c = 0; c < 3; c++)
            ts_assert_rel(ts_eval1(m, x, ti, pi_, to, po, c), on_ref(x[c], x[3], ti, pi_, to, po), 1e-12,
                          "oren_nayar random");
    }
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table),   cmocka_unit_test(test_lambert), cmocka_unit_test(test_hand),
        cmocka_unit_test(test_grazing), cmocka_unit_test(test_random),
    };
    return cmocka_run_group_tests_name("values_oren_nayar", tests, NULL, NULL);
}
