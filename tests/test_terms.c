/* Shared terms (terms.h) at the edges of their conditioning. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>

#include <cmocka.h>

#include "models/terms.h"
#include "support.h"

/* Unpolarised Fresnel reflectance from Snell's law, an independent route. */
static double fresnel_snell(double ci, double n)
{
    double si = sqrt(1.0 - ci * ci), st = si / n, ct = sqrt(1.0 - st * st);
    double rs = (ci - n * ct) / (ci + n * ct), rp = (ct - n * ci) / (ct + n * ci);
    return 0.5 * (rs * rs + rp * rp);
}

static void test_dielectric_values(void **state)
{
    (void)state;
    ts_assert_rel(bf_dielectric(1.0, 1.5, NULL), 0.04, 1e-15, "ior 1.5 at normal incidence");
    const double cs[] = {0.05, 0.2, 0.5, 0.8, 0.99};
    const double ns[] = {1.01, 1.33, 1.5, 2.4, 3.0};
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 5; j++)
            ts_assert_rel(bf_dielectric(cs[i], ns[j], NULL), fresnel_snell(cs[i], ns[j]), 1e-12, "dielectric vs Snell");
}

/* At ior = 1 nothing reflects: F is exactly 0 at every angle, grazing included (the
 * literal g - c lost this to rounding when c^2 is below the ulp of 1). */
static void test_dielectric_ior_one(void **state)
{
    (void)state;
    const double cs[] = {1e-12, 1e-8, 1.7e-5, 1e-3, 0.5, 1.0};
    for (int i = 0; i < 6; i++) {
        double dF;
        assert_true(bf_dielectric(cs[i], 1.0, &dF) == 0.0);
        assert_true(dF == 0.0);
    }
    /* End to end: a sharp dielectric lobe at ior = 1, grazing mirror pair, adds nothing. */
    bf_model *m = ts_model("walter:fresnel=dielectric", 1);
    double x[4] = {0.3, 1.0, 1e-4, 1.0};
    ts_assert_rel(ts_eval1(m, x, 89.999, 0.0, 89.999, 180.0, 0), 0.3 / M_PI, 1e-15, "grazing, ior 1");
    bf_model_free(m);
}

/* Up to the bound BF_IOR_MAX = 100 (the effective index of a metal fitted with a
 * dielectric Fresnel; Löw et al.'s published fits reach 99.9996): F against Snell's law
 * and dF/dior against central differences, from grazing to normal incidence, all finite. */
static void test_dielectric_high_ior(void **state)
{
    (void)state;
    assert_true(BF_IOR_MAX == 100.0);
    ts_assert_rel(bf_dielectric(1.0, 100.0, NULL), (99.0 / 101.0) * (99.0 / 101.0), 1e-14, "F0 at ior 100");
    const double cs[] = {1e-9, 1e-3, 0.05, 0.3, 0.7, 1.0};
    const double ns[] = {3.0, 6.59476, 10.08556, 38.0, 99.99961, 100.0};
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < 6; j++) {
            double c = cs[i], n = ns[j], dF;
            double F = bf_dielectric(c, n, &dF);
            assert_true(isfinite(F) && isfinite(dF) && F > 0.0 && F <= 1.0); /* dF < 0 near grazing */
            ts_assert_rel(F, fresnel_snell(c, n), 1e-12, "dielectric vs Snell, high ior");
            double h = 1e-3 * n; /* F is near 1 at grazing: a wide step keeps rounding out */
            double fd = (bf_dielectric(c, n + h, NULL) - bf_dielectric(c, n - h, NULL)) / (2.0 * h);
            ts_assert_near(dF, fd, 1e-5, 1e-13, "dF/dior, high ior");
        }
}

/* Conductor Fresnel for a complex index by the real-arithmetic form (Born & Wolf; as in
 * Lazanyi & Szirmay-Kalos 2005), independent of the complex-number code under test. */
static double conductor_ref(double c, double n, double k)
{
    double s2 = 1.0 - c * c, t = n * n - k * k - s2;
    double ab = sqrt(t * t + 4.0 * n * n * k * k); /* a^2 + b^2 */
    double a = sqrt(0.5 * (ab + t));
    double Rs = (ab - 2.0 * a * c + c * c) / (ab + 2.0 * a * c + c * c);
    double st = s2 / c; /* sin tan */
    double Rp = Rs * (ab - 2.0 * a * st + st * st) / (ab + 2.0 * a * st + st * st);
    return 0.5 * (Rs + Rp);
}

static void test_conductor(void **state)
{
    (void)state;
    /* Gold-like reflectivity and edge tint per channel (illustrative values). */
    const double r[3] = {0.944, 0.776, 0.373}, g[3] = {0.998, 0.981, 0.751};
    for (int ch = 0; ch < 3; ch++) {
        double n, k;
        bf_conductor_nk(r[ch], g[ch], &n, &k, NULL);
        /* The mapping keeps the normal reflectance at r. */
        ts_assert_near(((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k), r[ch], 1e-13, 0.0, "F(0) of n, k");
        ts_assert_near(bf_conductor(1.0, r[ch], g[ch], NULL, NULL), r[ch], 1e-13, 0.0, "F at normal incidence");
        for (double c = 0.05; c < 1.0; c += 0.1)
            ts_assert_near(bf_conductor(c, r[ch], g[ch], NULL, NULL), conductor_ref(c, n, k), 1e-12, 0.0,
                           "complex vs real form");
        ts_assert_near(bf_conductor(0.0, r[ch], g[ch], NULL, NULL), 1.0, 0.0, 1e-15, "grazing");
    }
    /* g = 1: n = (1 - r)/(1 + r) and k = 2 sqrt(r)/(1 + r); g -> 0: k -> 0, n -> the
     * dielectric index (1 + sqrt r)/(1 - sqrt r). */
    double n, k;
    bf_conductor_nk(0.64, 1.0, &n, &k, NULL);
    ts_assert_near(n, 0.36 / 1.64, 1e-14, 0.0, "n at g = 1");
    ts_assert_near(k, 1.6 / 1.64, 1e-14, 0.0, "k at g = 1");
    bf_conductor_nk(0.64, 1e-3, &n, &k, NULL);
    ts_assert_near(n, 1e-3 * 0.36 / 1.64 + 0.999 * 9.0, 1e-14, 0.0, "n near g = 0");
    assert_true(k > 0.0 && k < 0.4);
    /* The derivatives of the mapping against central differences. */
    double d[4];
    bf_conductor_nk(0.7, 0.6, &n, &k, d);
    const double h = 1e-6;
    double np, kp, nm, km;
    bf_conductor_nk(0.7 + h, 0.6, &np, &kp, NULL);
    bf_conductor_nk(0.7 - h, 0.6, &nm, &km, NULL);
    ts_assert_near(d[0], (np - nm) / (2 * h), 1e-7, 0.0, "dn/dr");
    ts_assert_near(d[2], (kp - km) / (2 * h), 1e-7, 0.0, "dk/dr");
    bf_conductor_nk(0.7, 0.6 + h, &np, &kp, NULL);
    bf_conductor_nk(0.7, 0.6 - h, &nm, &km, NULL);
    ts_assert_near(d[1], (np - nm) / (2 * h), 1e-7, 0.0, "dn/dg");
    ts_assert_near(d[3], (kp - km) / (2 * h), 1e-7, 0.0, "dk/dg");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dielectric_values),
        cmocka_unit_test(test_dielectric_ior_one),
        cmocka_unit_test(test_dielectric_high_ior),
        cmocka_unit_test(test_conductor),
    };
    return cmocka_run_group_tests_name("terms", tests, NULL, NULL);
}
