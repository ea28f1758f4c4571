/* Values of the nishino and abc models against closed forms at special geometry and
 * against plain re-implementations of the docs/models.md formulas from the angles, for every
 * fresnel option. */
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

/* Fresnel reflectance of unpolarised light from the Snell-law s and p amplitudes: an
 * independent route to the Cook-Torrance dielectric expression. */
static double fresnel_physical(double cos_i, double n)
{
    double sin_t = sqrt(1.0 - cos_i * cos_i) / n, cos_t = sqrt(1.0 - sin_t * sin_t);
    double rs = (cos_i - n * cos_t) / (cos_i + n * cos_t);
    double rp = (cos_t - n * cos_i) / (cos_t + n * cos_i);
    return 0.5 * (rs * rs + rp * rp);
}

/* ---- closed forms ---------------------------------------------------------------- */

/* Normal incidence: NH = VH = NL = NV = 1, G_ct = 1, F = f0 (schlick),
 * ((n-1)/(n+1))^2 (dielectric), 1 (none). nishino D = 1 - exp(-kappa); abc D = 1. */
static void test_normal_incidence(void **state)
{
    (void)state;
    const double rd = 0.25, rs = 3.0, kappa = 2.0, gamma = 80.0, f0 = 0.04, n = 1.5;
    const double Dn = 1.0 - exp(-2.0);
    {
        double x[5] = {rd, rs, kappa, gamma, f0};
        assert_close(eval1("nishino", x, 0, 0, 0, 0), rd / M_PI + rs * Dn * f0 / M_PI, REL);
        x[4] = n;
        assert_close(eval1("nishino:fresnel=dielectric", x, 0, 0, 0, 0), rd / M_PI + rs * Dn * 0.04 / M_PI, REL);
        assert_close(eval1("nishino:fresnel=none", x, 0, 0, 0, 0), rd / M_PI + rs * Dn / M_PI, REL);
    }
    {
        double x[5] = {rd, rs, 1e4, 2.5, f0};
        assert_close(eval1("abc", x, 0, 0, 0, 0), rd / M_PI + rs * f0 / M_PI, REL);
        x[4] = 2.0; /* ((2-1)/(2+1))^2 = 1/9 */
        assert_close(eval1("abc:fresnel=dielectric", x, 0, 0, 0, 0), rd / M_PI + rs / 9.0 / M_PI, REL);
        assert_close(eval1("abc:fresnel=none", x, 0, 0, 0, 0), rd / M_PI + rs / M_PI, REL);
    }
}

/* Mirror direction at 60 deg: NH = 1, NL = NV = VH = 1/2, G_ct = min(1, 2, 2) = 1, so
 * the lobe is rho_s D F / (pi / 4). Schlick f0 = 0.04 and dielectric n = 1.5 agree at
 * normal incidence but not here: 0.07 against 0.0891867... */
static void test_mirror_60_fresnel(void **state)
{
    (void)state;
    const double rs = 2.0, kappa = 0.7, gamma = 500.0;
    const double Dn = 1.0 - exp(-kappa);
    const double Fs = 0.04 + 0.96 / 32.0, Fd = fresnel_physical(0.5, 1.5);
    assert_close(Fs, 0.07, 1e-15);
    assert_close(Fd, 0.089186712802213, 1e-12);
    double x[5] = {0.0, rs, kappa, gamma, 0.04};
    double vs = eval1("nishino", x, 60, 0, 60, 180);
    assert_close(vs, rs * Dn * Fs * 4.0 / M_PI, REL);
    x[4] = 1.5;
    double vd = eval1("nishino:fresnel=dielectric", x, 60, 0, 60, 180);
    assert_close(vd, rs * Dn * Fd * 4.0 / M_PI, REL);
    assert_true(vd > 1.2 * vs);
    assert_close(eval1("nishino:fresnel=none", x, 60, 0, 60, 180), rs * Dn * 4.0 / M_PI, REL);

    double y[5] = {0.0, rs, 300.0, 1.3, 0.04};
    assert_close(eval1("abc", y, 60, 0, 60, 180), rs * Fs * 4.0 / M_PI, REL);
    y[4] = 1.5;
    assert_close(eval1("abc:fresnel=dielectric", y, 60, 0, 60, 180), rs * Fd * 4.0 / M_PI, REL);
    assert_close(eval1("abc:fresnel=none", y, 60, 0, 60, 180), rs * 4.0 / M_PI, REL);
}

/* Retro-reflection at 45 deg (L = V): H = L, NH = NL = NV = 1/sqrt(2), VH = 1,
 * G_ct = min(1, 2 NH NV / VH = 1) = 1, F = f0, so the lobe is rho_s D f0 / (pi / 2).
 * nishino D = 1 - exp(-kappa 2^(-gamma/2)); abc D = (1 + b (1 - 1/sqrt(2)))^-c. */
static void test_retro_45(void **state)
{
    (void)state;
    const double rs = 5.0, f0 = 0.5;
    double x[5] = {0.0, rs, 3.0, 2.0, f0}; /* NH^2 = 1/2: D = 1 - exp(-1.5) */
    assert_close(eval1("nishino", x, 45, 100, 45, 100), rs * (1.0 - exp(-1.5)) * f0 * 2.0 / M_PI, 1e-11);
    double y[5] = {0.0, rs, 10.0, 2.0, f0};
    double bx = 10.0 * (1.0 - sqrt(0.5));
    assert_close(eval1("abc", y, 45, 100, 45, 100), rs / ((1.0 + bx) * (1.0 + bx)) * f0 * 2.0 / M_PI, 1e-11);
    /* b = 0 or c = 0: D = 1. */
    y[2] = 0.0;
    assert_close(eval1("abc", y, 45, 100, 45, 100), rs * f0 * 2.0 / M_PI, 1e-11);
    y[2] = 1e7;
    y[3] = 0.0;
    assert_close(eval1("abc", y, 45, 100, 45, 100), rs * f0 * 2.0 / M_PI, 1e-11);
}

/* ---- plain re-implementations -------------------------------------------------------- */

enum { NISHINO, ABC };

/* x laid out as the model's table: rho_d[C], rho_s[C], then the two shape scalars and
 * the Fresnel parameter (absent for none). kind: 0 schlick, 1 dielectric, 2 none. */
static double plain(int model, int kind, int C, const double *x, int c, double ti, double pi_, double to, double po)
{
    double L[3] = {sin(ti * DEG) * cos(pi_ * DEG), sin(ti * DEG) * sin(pi_ * DEG), cos(ti * DEG)};
    double V[3] = {sin(to * DEG) * cos(po * DEG), sin(to * DEG) * sin(po * DEG), cos(to * DEG)};
    if (L[2] <= 0.0 || V[2] <= 0.0)
        return 0.0;
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double len = sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
    for (int k = 0; k < 3; k++)
        H[k] /= len;
    double nl = L[2], nv = V[2], nh = H[2], vh = V[0] * H[0] + V[1] * H[1] + V[2] * H[2];
    double p1 = x[2 * C], p2 = x[2 * C + 1], fp = kind == 2 ? 0.0 : x[2 * C + 2];
    double D;
    if (model == NISHINO) {
        D = -expm1(-p1 * pow(nh, p2)); /* 1 - exp(..) loses digits for small kappa NH^gamma */
    } else {
        double one_minus_nh = (H[0] * H[0] + H[1] * H[1]) / (1.0 + nh);
        D = 1.0 / pow(1.0 + p1 * one_minus_nh, p2);
    }
    double G = fmin(1.0, fmin(2.0 * nh * nv / vh, 2.0 * nh * nl / vh));
    double F = 1.0;
    if (kind == 0) {
        F = fp + (1.0 - fp) * pow(1.0 - vh, 5.0);
    } else if (kind == 1) {
        double g = sqrt(fp * fp + vh * vh - 1.0), a = g - vh, b = g + vh;
        double num = vh * b - 1.0, den = vh * a + 1.0;
        F = 0.5 * a * a / (b * b) * (1.0 + num * num / (den * den));
    }
    return x[c] / M_PI + x[C + c] * D * G * F / (M_PI * nl * nv);
}

static void check_random(int model, int kind, int C)
{
    static const char *const kinds[] = {"schlick", "dielectric", "none"};
    char spec[64];
    snprintf(spec, sizeof spec, "%s:fresnel=%s", model == NISHINO ? "nishino" : "abc", kinds[kind]);
    bf_model *m = ts_model(spec, C);
    int P = 2 * C + 2 + (kind != 2);
    assert_int_equal(bf_model_nvalues(m), P);
    ts_rng rng = {0x94D049BB133111EBULL + (uint64_t)(model * 31 + kind * 7 + C)};
    double x[16];
    for (int t = 0; t < 24; t++) {
        for (int c = 0; c < C; c++) {
            x[c] = c == 0 ? 0.0 : ts_uniform(&rng); /* channel 0: the lobe alone */
            x[C + c] = 100.0 * ts_uniform(&rng);
        }
        if (model == NISHINO) {
            x[2 * C] = 1e-3 * pow(1e6, ts_uniform(&rng));     /* kappa */
            x[2 * C + 1] = 1e-3 * pow(1e6, ts_uniform(&rng)); /* gamma up to 1e3 */
        } else {
            x[2 * C] = expm1(ts_uniform(&rng) * log1p(1e6)); /* b */
            x[2 * C + 1] = 10.0 * ts_uniform(&rng);          /* c */
        }
        if (kind == 0)
            x[2 * C + 2] = ts_uniform(&rng);
        else if (kind == 1)
            x[2 * C + 2] = 1.0 + 2.0 * ts_uniform(&rng);
        assert_int_equal(bf_model_check(m, x, NULL), BF_OK);
        for (int d = 0; d < 10; d++) {
            double ti, pi_, to, po;
            ts_random_pair_deg(&rng, d % 3 == 0, &ti, &pi_, &to, &po);
            for (int c = 0; c < C; c++)
                assert_close(ts_eval1(m, x, ti, pi_, to, po, c), plain(model, kind, C, x, c, ti, pi_, to, po), REL);
        }
    }
    bf_model_free(m);
}

static void test_random_nishino(void **state)
{
    (void)state;
    for (int kind = 0; kind < 3; kind++) {
        check_random(NISHINO, kind, 1);
        check_random(NISHINO, kind, 3);
    }
}

static void test_random_abc(void **state)
{
    (void)state;
    for (int kind = 0; kind < 3; kind++) {
        check_random(ABC, kind, 1);
        check_random(ABC, kind, 3);
    }
}

/* ---- tables ---------------------------------------------------------------------- */

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

static void test_tables(void **state)
{
    (void)state;
    static const char *const ns[] = {"rho_d", "rho_s", "kappa", "gamma", "f0"};
    static const char *const nd[] = {"rho_d", "rho_s", "kappa", "gamma", "ior"};
    static const char *const as[] = {"rho_d", "rho_s", "b", "c", "f0"};
    static const char *const ad[] = {"rho_d", "rho_s", "b", "c", "ior"};
    check_names("nishino", ns, 5);
    check_names("nishino:fresnel=dielectric", nd, 5);
    check_names("nishino:fresnel=none", ns, 4);
    check_names("abc", as, 5);
    check_names("abc:fresnel=dielectric", ad, 5);
    check_names("abc:fresnel=none", as, 4);

    bf_model *m = ts_model("nishino:fresnel=dielectric", 1);
    assert_string_equal(bf_model_spec(m), "nishino:fresnel=dielectric");
    const bf_param_info *p = bf_model_param(m, 2);
    assert_true(p->lo == 1e-3 && p->hi == 1e3);
    p = bf_model_param(m, 3);
    assert_true(p->lo == 1e-3 && p->hi == 1e4);
    p = bf_model_param(m, 4);
    assert_true(p->lo == 1.0 && p->hi == 100.0 && p->scale == BF_SCALE_LOG);
    bf_model_free(m);
    m = ts_model("abc", 1);
    assert_string_equal(bf_model_spec(m), "abc:fresnel=schlick");
    p = bf_model_param(m, 2);
    assert_true(p->lo == 0.0 && p->hi == 1e7);
    p = bf_model_param(m, 3);
    assert_true(p->lo == 0.0 && p->hi == 10.0);
    p = bf_model_param(m, 4);
    assert_true(p->lo == 0.0 && p->hi == 1.0);
    bf_model_free(m);
}

/* Published ABC fit (Low et al. 2012, alum-bronze, green channel, via dj_brdf): rho_s is
 * the paper's A = 37.93 and the fit reaches b = 1.05e4, so both must be in bounds. */
static void test_published_fit_in_bounds(void **state)
{
    (void)state;
    bf_model *m = ts_model("abc:fresnel=dielectric", 1);
    double x[5] = {0.022346, 37.932693, 10482.133789, 0.816737, 2.236525};
    assert_int_equal(bf_model_check(m, x, NULL), BF_OK);
    /* At the peak for normal incidence: kd/pi + A F(1) / pi. */
    double F = (1.236525 / 3.236525) * (1.236525 / 3.236525);
    assert_close(ts_eval1(m, x, 0, 0, 0, 0, 0), 0.022346 / M_PI + 37.932693 * F / M_PI, REL);
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_normal_incidence),
        cmocka_unit_test(test_mirror_60_fresnel),
        cmocka_unit_test(test_retro_45),
        cmocka_unit_test(test_random_nishino),
        cmocka_unit_test(test_random_abc),
        cmocka_unit_test(test_tables),
        cmocka_unit_test(test_published_fit_in_bounds),
    };
    return cmocka_run_group_tests_name("values_nishino_abc", tests, NULL, NULL);
}
