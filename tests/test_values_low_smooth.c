/* Values of the low_smooth model (Löw et al. 2012's smooth-surface model) against closed
 * forms at special geometry, against a plain re-implementation of the docs/models.md
 * formula from the angles for every fresnel option, and at a published fit. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "support.h"

#define REL 1e-12
#define assert_close(got, want, rel) ts_assert_rel((got), (want), (rel), #got)

static double eval1(const char *spec, const double *x, double ti, double pi_, double to, double po)
{
    bf_model *m = ts_model(spec, 1);
    assert_int_equal(bf_model_check(m, x, NULL), BF_OK);
    double v = ts_eval1(m, x, ti, pi_, to, po, 0);
    bf_model_free(m);
    return v;
}

/* Unpolarised Fresnel reflectance from the Snell-law s and p amplitudes: an independent
 * route to the Cook-Torrance expression the model uses. */
static double fresnel_physical(double cos_i, double n)
{
    double sin_t = sqrt(1.0 - cos_i * cos_i) / n, cos_t = sqrt(1.0 - sin_t * sin_t);
    double rs = (cos_i - n * cos_t) / (cos_i + n * cos_t);
    double rp = (cos_t - n * cos_i) / (cos_t + n * cos_i);
    return 0.5 * (rs * rs + rp * rp);
}

/* ---- closed forms ---------------------------------------------------------------- */

/* Normal incidence and view: Dp = 0 so S = 1, and cos theta_d = 1 so F = f0,
 * ((n-1)/(n+1))^2 or 1. No 1/pi and no 1/(NL NV) on the lobe. */
static void test_normal_incidence(void **state)
{
    (void)state;
    const double rd = 0.25, rs = 3.0;
    double x[5] = {rd, rs, 1e4, 2.5, 0.04};
    assert_close(eval1("low_smooth", x, 0, 0, 0, 0), rd / M_PI + rs * 0.04, REL);
    x[4] = 2.0; /* ((2-1)/(2+1))^2 = 1/9 */
    assert_close(eval1("low_smooth:fresnel=dielectric", x, 0, 0, 0, 0), rd / M_PI + rs / 9.0, REL);
    assert_close(eval1("low_smooth:fresnel=none", x, 0, 0, 0, 0), rd / M_PI + rs, REL);
}

/* Mirror direction at 60 deg: Dp = 0 so S = 1 whatever b and c; |L_xy - V_xy| =
 * 2 sin 60 so cos theta_d = sqrt(1 - 3/4) = 1/2 = L.H exactly. */
static void test_mirror_60(void **state)
{
    (void)state;
    const double rs = 2.0;
    const double Fs = 0.04 + 0.96 / 32.0, Fd = fresnel_physical(0.5, 1.5);
    assert_close(Fd, 0.089186712802213, 1e-12);
    double x[5] = {0.0, rs, 3e5, 1.7, 0.04};
    assert_close(eval1("low_smooth", x, 60, 0, 60, 180), rs * Fs, REL);
    x[4] = 1.5;
    assert_close(eval1("low_smooth:fresnel=dielectric", x, 60, 0, 60, 180), rs * Fd, REL);
    assert_close(eval1("low_smooth:fresnel=none", x, 60, 0, 60, 180), rs, REL);
}

/* Retro-reflection at 45 deg (L = V): |Dp|^2 = (2 sin 45)^2 = 2, L_xy - V_xy = 0 so
 * F = f0: the lobe is rho_s f0 / (1 + 2 b)^c. b = 0 or c = 0: S = 1. */
static void test_retro_45(void **state)
{
    (void)state;
    const double rs = 5.0, f0 = 0.5;
    double x[5] = {0.0, rs, 10.0, 2.0, f0};
    assert_close(eval1("low_smooth", x, 45, 100, 45, 100), rs * f0 / 441.0, 1e-11);
    x[2] = 0.0;
    assert_close(eval1("low_smooth", x, 45, 100, 45, 100), rs * f0, 1e-11);
    x[2] = 1e7;
    x[3] = 0.0;
    assert_close(eval1("low_smooth", x, 45, 100, 45, 100), rs * f0, 1e-11);
}

/* Off the mirror plane cos theta_d is not L.H (eq. 14 uses the projected vectors
 * only): L = (30 deg, phi 0), V = (60 deg, phi 90). |L_xy - V_xy|^2 = 1/4 + 3/4 = 1, so
 * cos theta_d = sqrt(3)/2, while L.H = sqrt((1 + L.V)/2) with L.V = sqrt(3)/4;
 * |Dp|^2 = 1 too. With fresnel=none the lobe is rho_s / (1 + b)^c. */
static void test_projected_fresnel_angle(void **state)
{
    (void)state;
    const double rs = 4.0, n = 1.7;
    double x[5] = {0.0, rs, 3.0, 1.5, n};
    double S = 1.0 / pow(4.0, 1.5);
    double got = eval1("low_smooth:fresnel=dielectric", x, 30, 0, 60, 90);
    assert_close(got, rs * S * fresnel_physical(sqrt(3.0) / 2.0, n), REL);
    double lh = sqrt((1.0 + sqrt(3.0) / 4.0) / 2.0);
    assert_true(fabs(got - rs * S * fresnel_physical(lh, n)) > 1e-3 * got);
    assert_close(eval1("low_smooth:fresnel=none", x, 30, 0, 60, 90), rs * S, REL);
}

/* ---- plain re-implementation ------------------------------------------------------- */

/* x laid out as the model's table: rho_d[C], rho_s[C], b, c, then the Fresnel
 * parameter (absent for none). kind: 0 schlick, 1 dielectric, 2 none. */
static double plain(int kind, int C, const double *x, int c, double ti, double pi_, double to, double po)
{
    double L[3] = {sin(ti * DEG) * cos(pi_ * DEG), sin(ti * DEG) * sin(pi_ * DEG), cos(ti * DEG)};
    double V[3] = {sin(to * DEG) * cos(po * DEG), sin(to * DEG) * sin(po * DEG), cos(to * DEG)};
    if (L[2] <= 0.0 || V[2] <= 0.0)
        return 0.0;
    double b = x[2 * C], cc = x[2 * C + 1], fp = kind == 2 ? 0.0 : x[2 * C + 2];
    /* V against the mirror of L, (-Lx, -Ly, Lz), in the projected disc. */
    double dp2 = pow(V[0] - (-L[0]), 2) + pow(V[1] - (-L[1]), 2);
    double cd = sqrt(1.0 - (pow(L[0] - V[0], 2) + pow(L[1] - V[1], 2)) / 4.0);
    double S = pow(1.0 + b * dp2, -cc);
    double F = 1.0;
    if (kind == 0)
        F = fp + (1.0 - fp) * pow(1.0 - cd, 5.0);
    else if (kind == 1)
        F = fresnel_physical(cd, fp);
    return x[c] / M_PI + x[C + c] * S * F;
}

static void check_random(int kind, int C)
{
    static const char *const kinds[] = {"schlick", "dielectric", "none"};
    char spec[64];
    snprintf(spec, sizeof spec, "low_smooth:fresnel=%s", kinds[kind]);
    bf_model *m = ts_model(spec, C);
    int P = 2 * C + 2 + (kind != 2);
    assert_int_equal(bf_model_nvalues(m), P);
    ts_rng rng = {0x2545F4914F6CDD1DULL + (uint64_t)(kind * 7 + C)};
    double x[16];
    for (int t = 0; t < 24; t++) {
        for (int c = 0; c < C; c++) {
            x[c] = c == 0 ? 0.0 : ts_uniform(&rng); /* channel 0: the lobe alone */
            x[C + c] = 100.0 * ts_uniform(&rng);
        }
        x[2 * C] = expm1(ts_uniform(&rng) * log1p(1e6)); /* b */
        x[2 * C + 1] = 10.0 * ts_uniform(&rng);          /* c */
        if (kind == 0)
            x[2 * C + 2] = ts_uniform(&rng);
        else if (kind == 1)
            x[2 * C + 2] = 1.0 + 9.0 * ts_uniform(&rng); /* the published fits reach 9 */
        assert_int_equal(bf_model_check(m, x, NULL), BF_OK);
        for (int d = 0; d < 10; d++) {
            double ti, pi_, to, po;
            ts_random_pair_deg(&rng, d % 3 == 0, &ti, &pi_, &to, &po);
            for (int c = 0; c < C; c++)
                assert_close(ts_eval1(m, x, ti, pi_, to, po, c), plain(kind, C, x, c, ti, pi_, to, po), 1e-11);
        }
    }
    bf_model_free(m);
}

static void test_random(void **state)
{
    (void)state;
    for (int kind = 0; kind < 3; kind++) {
        check_random(kind, 1);
        check_random(kind, 3);
    }
}

/* ---- table ------------------------------------------------------------------------- */

static void check_names(const char *spec, const char *const *names, int n)
{
    bf_model *m = ts_model(spec, 3);
    assert_int_equal(bf_model_nparams(m), n);
    for (int i = 0; i < n; i++)
        assert_string_equal(bf_model_param(m, i)->name, names[i]);
    assert_false(bf_model_energy_conserving(m));
    assert_true(bf_model_reciprocal(m));
    bf_model_free(m);
}

static void test_table(void **state)
{
    (void)state;
    static const char *const ls[] = {"rho_d", "rho_s", "b", "c", "f0"};
    static const char *const ld[] = {"rho_d", "rho_s", "b", "c", "ior"};
    check_names("low_smooth", ls, 5);
    check_names("low_smooth:fresnel=dielectric", ld, 5);
    check_names("low_smooth:fresnel=none", ls, 4);
    bf_model *m = ts_model("low_smooth", 1);
    assert_string_equal(bf_model_spec(m), "low_smooth:fresnel=schlick");
    const bf_param_info *p = bf_model_param(m, 1);
    assert_true(p->lo == 0.0 && p->hi == 1e5 && p->scale == BF_SCALE_LOG1P && p->role == BF_ROLE_WEIGHT);
    p = bf_model_param(m, 2);
    assert_true(p->lo == 0.0 && p->hi == 1e7 && p->scale == BF_SCALE_LOG1P && p->role == BF_ROLE_FALLOFF);
    p = bf_model_param(m, 3);
    assert_true(p->lo == 0.0 && p->hi == 10.0 && p->scale == BF_SCALE_LOG1P && p->role == BF_ROLE_SHAPE);
    bf_model_free(m);
}

/* Published fit (Löw et al. 2012's smooth model, aluminium, green channel, as published
 * in bsdfbenchmark/bbm fits/low_lowsmooth_E2.fit): A = 750.01196, B = 75544.810541,
 * C = 1.045481, eta = 6.59476, kd = 0.0001, all inside the bounds. At normal incidence
 * f = kd/pi + A ((eta-1)/(eta+1))^2; at the mirror direction at 60 deg the lobe is
 * A F(1/2). */
static void test_published_fit(void **state)
{
    (void)state;
    bf_model *m = ts_model("low_smooth:fresnel=dielectric", 1);
    double x[5] = {0.0001, 750.01196, 75544.810541, 1.045481, 6.59476};
    assert_int_equal(bf_model_check(m, x, NULL), BF_OK);
    double r = 5.59476 / 7.59476;
    assert_close(ts_eval1(m, x, 0, 0, 0, 0, 0), 0.0001 / M_PI + 750.01196 * r * r, REL);
    assert_close(ts_eval1(m, x, 60, 0, 60, 180, 0), 0.0001 / M_PI + 750.01196 * fresnel_physical(0.5, 6.59476), REL);
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_normal_incidence), cmocka_unit_test(test_mirror_60),
        cmocka_unit_test(test_retro_45),         cmocka_unit_test(test_projected_fresnel_angle),
        cmocka_unit_test(test_random),           cmocka_unit_test(test_table),
        cmocka_unit_test(test_published_fit),
    };
    return cmocka_run_group_tests_name("values_low_smooth", tests, NULL, NULL);
}
