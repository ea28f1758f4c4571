/* Values of ward and ward_iso against closed forms at the specular peak and against a
 * plain re-implementation of the docs/models.md formula from the angles. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "support.h"

/* docs/models.md, written out from the angles (degrees), nothing shared with the library. */
static double ward_ref(double rd, double rs, double ax, double ay, double ti, double pi_, double to, double po)
{
    double a = ti * DEG, b = pi_ * DEG, c = to * DEG, d = po * DEG;
    double L[3] = {sin(a) * cos(b), sin(a) * sin(b), cos(a)};
    double V[3] = {sin(c) * cos(d), sin(c) * sin(d), cos(c)};
    if (L[2] <= 0.0 || V[2] <= 0.0)
        return 0.0;
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double len = sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
    H[0] /= len;
    H[1] /= len;
    H[2] /= len;
    double ex = H[0] / ax, ey = H[1] / ay;
    return rd / M_PI + rs * exp(-(ex * ex + ey * ey) / (H[2] * H[2])) / (4.0 * M_PI * ax * ay * sqrt(L[2] * V[2]));
}

static void test_table(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("ward", 3, &m, NULL);
    assert_non_null(m);
    assert_int_equal(bf_model_nparams(m), 4);
    assert_int_equal(bf_model_nvalues(m), 3 + 3 + 2);
    const char *names[] = {"rho_d", "rho_s", "alpha_x", "alpha_y"};
    for (int i = 0; i < 4; i++)
        assert_string_equal(bf_model_param(m, i)->name, names[i]);
    assert_true(bf_model_param(m, 2)->lo == 1e-3 && bf_model_param(m, 2)->hi == 1.0);
    assert_true(bf_model_param(m, 3)->lo == 1e-3 && bf_model_param(m, 3)->hi == 1.0);
    assert_int_equal(bf_model_energy_conserving(m), 0);
    bf_model_free(m);
    bf_model_new("ward_iso", 1, &m, NULL);
    assert_non_null(m);
    assert_int_equal(bf_model_nparams(m), 3);
    assert_string_equal(bf_model_param(m, 2)->name, "alpha");
    bf_model_free(m);
}

/* Normal incidence, normal viewing: H = N, so f = rho_d/pi + rho_s/(4 pi ax ay). */
static void test_peak_normal(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("ward", 3, &m, NULL);
    double x[8] = {0.1, 0.2, 0.3, 0.7, 0.5, 0.25, 0.05, 0.3};
    for (int c = 0; c < 3; c++) {
        double want = x[c] / M_PI + x[3 + c] / (4.0 * M_PI * 0.05 * 0.3);
        ts_assert_rel(ts_eval1(m, x, 0.0, 0.0, 0.0, 0.0, c), want, 1e-14, "ward peak");
    }
    bf_model_free(m);
}

/* Mirror direction at theta: H = N, NL = NV = cos(theta). */
static void test_mirror(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("ward", 1, &m, NULL);
    double x[4] = {0.3, 0.6, 0.2, 0.08};
    double th[] = {10.0, 45.0, 75.0, 89.0};
    for (int k = 0; k < 4; k++) {
        double want = 0.3 / M_PI + 0.6 / (4.0 * M_PI * 0.2 * 0.08 * cos(th[k] * DEG));
        ts_assert_rel(ts_eval1(m, x, th[k], 33.0, th[k], 213.0, 0), want, 1e-12, "ward mirror");
    }
    bf_model_free(m);
}

/* H in the XZ plane (both directions at phi = 0/180): only alpha_x shapes the lobe, the
 * value is rho_s exp(-tan^2(theta_h)/ax^2) / (4 pi ax ay sqrt(NL NV)) with
 * theta_h = (theta_o - theta_i)/2 for L at phi 180 and V at phi 0. */
static void test_axis(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("ward", 1, &m, NULL);
    double x[4] = {0.0, 1.0, 0.3, 0.05};
    double ti = 20.0, to = 26.0, th = (to - ti) / 2.0 * DEG;
    double t = tan(th) / 0.3;
    double want = exp(-t * t) / (4.0 * M_PI * 0.3 * 0.05 * sqrt(cos(ti * DEG) * cos(to * DEG)));
    ts_assert_rel(ts_eval1(m, x, ti, 180.0, to, 0.0, 0), want, 1e-12, "ward along X");
    /* The same geometry turned by 90 degrees: now alpha_y = 0.05 shapes it. */
    t = tan(th) / 0.05;
    want = exp(-t * t) / (4.0 * M_PI * 0.3 * 0.05 * sqrt(cos(ti * DEG) * cos(to * DEG)));
    ts_assert_rel(ts_eval1(m, x, ti, 270.0, to, 90.0, 0), want, 1e-12, "ward along Y");
    bf_model_free(m);
}

static void test_random(void **state)
{
    (void)state;
    ts_rng r = {0x1234567887654321ULL};
    bf_model *m = ts_model("ward", 3), *mi = ts_model("ward_iso", 3);
    double x[8], xi[7];
    for (int k = 0; k < 300; k++) {
        for (int c = 0; c < 3; c++) {
            x[c] = ts_uniform(&r);
            x[3 + c] = ts_uniform(&r);
        }
        x[6] = 1e-3 * pow(1e3, ts_uniform(&r));
        x[7] = 1e-3 * pow(1e3, ts_uniform(&r));
        double ti = 88.0 * ts_uniform(&r), pi_ = 360.0 * ts_uniform(&r);
        double to = 88.0 * ts_uniform(&r), po = 360.0 * ts_uniform(&r);
        if (k % 2) { /* near the mirror direction, where narrow lobes are not ~0 */
            to = fmin(88.0, ti + 4.0 * (ts_uniform(&r) - 0.5) * sqrt(x[6]));
            to = fabs(to);
            po = pi_ + 180.0 + 8.0 * (ts_uniform(&r) - 0.5) * sqrt(x[7]);
        }
        for (int c = 0; c < 3; c++) {
            double want = ward_ref(x[c], x[3 + c], x[6], x[7], ti, pi_, to, po);
            ts_assert_rel(ts_eval1(m, x, ti, pi_, to, po, c), want, 1e-12, "ward random");
        }
        /* ward_iso = ward with alpha_x = alpha_y. */
        memcpy(xi, x, 6 * sizeof *x);
        xi[6] = x[6];
        double xa[8];
        memcpy(xa, x, sizeof xa);
        xa[7] = x[6];
        for (int c = 0; c < 3; c++) {
            double want = ward_ref(x[c], x[3 + c], x[6], x[6], ti, pi_, to, po);
            double iso = ts_eval1(mi, xi, ti, pi_, to, po, c);
            ts_assert_rel(iso, want, 1e-12, "ward_iso random");
            ts_assert_rel(iso, ts_eval1(m, xa, ti, pi_, to, po, c), 1e-13, "ward_iso vs ward");
        }
    }
    bf_model_free(m);
    bf_model_free(mi);
}

/* Below the horizon f = 0, and a huge exponent underflows to the diffuse term alone. */
static void test_limits(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("ward_iso", 1, &m, NULL);
    double x[3] = {0.4, 0.6, 1e-3};
    assert_true(ts_eval1(m, x, 95.0, 0.0, 30.0, 180.0, 0) == 0.0);
    ts_assert_rel(ts_eval1(m, x, 30.0, 0.0, 60.0, 90.0, 0), 0.4 / M_PI, 1e-15, "ward underflow");
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table), cmocka_unit_test(test_peak_normal), cmocka_unit_test(test_mirror),
        cmocka_unit_test(test_axis),  cmocka_unit_test(test_random),      cmocka_unit_test(test_limits),
    };
    return cmocka_run_group_tests_name("values_ward", tests, NULL, NULL);
}
