/* Values of lafortune and lafortune_aniso: the Phong special case, the normalisation by
 * max|c|^n, hand-worked angles, the conventions at cmax = 0 and n = 0, multiple lobes,
 * and a plain re-implementation of the docs/models.md formula from the angles. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "support.h"

/* Relative tolerance plus a tiny absolute one, for values that may be ~0. */
#define assert_close(got, want, tol, what) ts_assert_near((got), (want), (tol), 1e-15, (what))

/* docs/models.md written out plainly: lobes K, per lobe (rho_s, cx, cy, cz, n). For the
 * isotropic model cx = cy = cxy. Only for n small enough that cmax^n stays normal. */
typedef struct lobe_p {
    double rs, cx, cy, cz, n;
} lobe_p;

static double laf_ref(double rd, int K, const lobe_p *lp, double ti, double pi_, double to, double po)
{
    double L[3], V[3];
    ts_dirs_deg(ti, pi_, to, po, L, V);
    if (L[2] <= 0.0 || V[2] <= 0.0)
        return 0.0;
    double f = rd / M_PI;
    for (int k = 0; k < K; k++) {
        const lobe_p *p = &lp[k];
        double d = p->cx * L[0] * V[0] + p->cy * L[1] * V[1] + p->cz * L[2] * V[2];
        double cmax = fmax(fabs(p->cx), fmax(fabs(p->cy), fabs(p->cz)));
        f += p->rs * (p->n + 2.0) / (2.0 * M_PI * pow(cmax, p->n)) * pow(fmax(0.0, d), p->n);
    }
    return f;
}

static void test_tables(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("lafortune", 3, &m, NULL);
    assert_non_null(m);
    const char *n1[] = {"rho_d", "rho_s", "cxy", "cz", "n"};
    assert_int_equal(bf_model_nparams(m), 5);
    assert_int_equal(bf_model_nvalues(m), 3 + 3 + 3);
    for (int i = 0; i < 5; i++)
        assert_string_equal(bf_model_param(m, i)->name, n1[i]);
    double x[9];
    bf_model_defaults(m, x);
    assert_true(x[6] == -1.0 && x[7] == 1.0 && x[8] == 50.0); /* the Phong lobe */
    assert_true(bf_model_param(m, 2)->lo == -1.0 && bf_model_param(m, 2)->hi == 1.0);
    assert_true(bf_model_param(m, 4)->lo == 0.0 && bf_model_param(m, 4)->hi == 1e6);
    assert_int_equal(bf_model_energy_conserving(m), 1);
    assert_int_equal(bf_model_reciprocal(m), 1);
    bf_model_free(m);

    bf_model_new("lafortune:lobes=2", 1, &m, NULL);
    assert_non_null(m);
    const char *n2[] = {"rho_d", "rho_s_1", "cxy_1", "cz_1", "n_1", "rho_s_2", "cxy_2", "cz_2", "n_2"};
    assert_int_equal(bf_model_nparams(m), 9);
    for (int i = 0; i < 9; i++)
        assert_string_equal(bf_model_param(m, i)->name, n2[i]);
    assert_true(bf_model_param(m, 8)->def != bf_model_param(m, 4)->def);
    bf_model_free(m);

    bf_model_new("lafortune_aniso:lobes=1", 1, &m, NULL);
    assert_non_null(m);
    const char *n3[] = {"rho_d", "rho_s", "cx", "cy", "cz", "n"};
    assert_int_equal(bf_model_nparams(m), 6);
    for (int i = 0; i < 6; i++)
        assert_string_equal(bf_model_param(m, i)->name, n3[i]);
    assert_int_equal(bf_model_energy_conserving(m), 1);
    bf_model_free(m);
    for (int f = 0; f < bf_family_count(); f++) {
        const bf_family_info *fi = bf_family_get(f);
        if (strcmp(fi->name, "lafortune") == 0)
            assert_true(fi->lobes && !fi->anisotropic);
        if (strcmp(fi->name, "lafortune_aniso") == 0)
            assert_true(fi->lobes && fi->anisotropic);
    }
}

/* cxy = -1, cz = 1 is the normalised Phong lobe: the same values as phong to rounding. */
static void test_equals_phong(void **state)
{
    (void)state;
    bf_model *laf = NULL;
    bf_model_new("lafortune", 3, &laf, NULL);
    bf_model *ph = NULL;
    bf_model_new("phong", 3, &ph, NULL);
    ts_rng r = {0x42ULL};
    for (int t = 0; t < 300; t++) {
        double xp[7], xl[9];
        for (int c = 0; c < 6; c++)
            xp[c] = ts_uniform(&r);
        xp[6] = expm1(ts_uniform(&r) * log(1e4));
        memcpy(xl, xp, 6 * sizeof *xp);
        xl[6] = -1.0;
        xl[7] = 1.0;
        xl[8] = xp[6];
        double ti = 89.0 * ts_uniform(&r), pi_ = 360.0 * ts_uniform(&r);
        double to = 89.0 * ts_uniform(&r), po = 360.0 * ts_uniform(&r);
        if (t % 2 == 0) {
            to = fmin(89.0, ti + 2.0 * (ts_uniform(&r) - 0.5));
            po = pi_ + 180.0 + 2.0 * (ts_uniform(&r) - 0.5);
        }
        for (int c = 0; c < 3; c++)
            assert_close(ts_eval1(laf, xl, ti, pi_, to, po, c), ts_eval1(ph, xp, ti, pi_, to, po, c), 1e-13,
                         "lafortune vs phong");
    }
    bf_model_free(laf);
    bf_model_free(ph);
}

/* Scaling all c by s > 0 leaves the lobe unchanged (normalised by cmax^n), even where
 * cmax^n itself underflows (0.001^1e6). At the mirror direction the value is then
 * exactly the Phong peak (n+2)/(2 pi). */
static void test_normalisation(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("lafortune", 1, &m, NULL);
    const double sc[] = {1.0, 0.5, 1e-3};
    const double ns[] = {3.0, 80.0, 1e6};
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            double x[5] = {0.2, 0.7, -sc[a], sc[a], ns[b]};
            ts_assert_rel(ts_eval1(m, x, 50.0, 30.0, 50.0, 210.0, 0), 0.2 / M_PI + 0.7 * (ns[b] + 2.0) / (2.0 * M_PI),
                          1e-12, "scaled Phong lobe at the mirror direction");
            if (ns[b] < 100.0) {
                double y[5] = {0.2, 0.7, -1.0, 1.0, ns[b]};
                ts_assert_rel(ts_eval1(m, x, 20.0, 30.0, 45.0, 170.0, 0), ts_eval1(m, y, 20.0, 30.0, 45.0, 170.0, 0),
                              1e-13, "scale invariance");
            }
        }
    bf_model_free(m);
}

static void test_hand(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("lafortune", 1, &m, NULL);
    /* Retro-reflection lobe cxy = cz = 1 at the retro direction: d = |L|^2 = 1. */
    double x[5] = {0.1, 0.6, 1.0, 1.0, 7.0};
    ts_assert_rel(ts_eval1(m, x, 70.0, 40.0, 70.0, 40.0, 0), 0.1 / M_PI + 0.6 * 9.0 / (2.0 * M_PI), 1e-12,
                  "retro lobe");
    /* Off-specular lobe cxy = 0.5, cz = 1, n = 2: L at (30, 0), V at (60, 180):
     * LxVx + LyVy = -sin30 sin60, LzVz = cos30 cos60, both sqrt(3)/4 in size:
     * d = sqrt(3)/4 (1 - 0.5) = sqrt(3)/8, cmax = 1: f = rho_d/pi + rho_s (4/(2 pi)) 3/64. */
    double y[5] = {0.1, 0.6, 0.5, 1.0, 2.0};
    ts_assert_rel(ts_eval1(m, y, 30.0, 0.0, 60.0, 180.0, 0), 0.1 / M_PI + 0.6 * 2.0 / M_PI * 3.0 / 64.0, 1e-13,
                  "off-specular lobe");
    /* cz = -1 (lobe below the horizon for the z part), cxy = -0.5 at the mirror pair:
     * d = 0.5 sin^2 - cos^2 < 0 for theta = 30: the lobe vanishes. */
    double z[5] = {0.1, 0.6, -0.5, -1.0, 2.0};
    ts_assert_rel(ts_eval1(m, z, 30.0, 0.0, 30.0, 180.0, 0), 0.1 / M_PI, 1e-15, "d < 0");
    /* cxy = cz = 0: the lobe is 0 for n > 0 and 1/pi at n = 0; n = 0 gives 1/pi anywhere. */
    double w[5] = {0.1, 0.6, 0.0, 0.0, 2.0};
    ts_assert_rel(ts_eval1(m, w, 30.0, 0.0, 30.0, 180.0, 0), 0.1 / M_PI, 1e-15, "cmax = 0");
    w[4] = 0.0;
    ts_assert_rel(ts_eval1(m, w, 30.0, 0.0, 30.0, 180.0, 0), 0.7 / M_PI, 1e-15, "cmax = 0, n = 0");
    z[4] = 0.0;
    ts_assert_rel(ts_eval1(m, z, 30.0, 0.0, 30.0, 180.0, 0), 0.7 / M_PI, 1e-15, "n = 0, d < 0");
    bf_model_free(m);

    bf_model_new("lafortune_aniso", 1, &m, NULL);
    /* L at (45, 45), V at (45, 225): LxVx = LyVy = -1/4, LzVz = 1/2. cx = -1, cy = 0.5,
     * cz = 1, n = 3: d = 1/4 - 1/8 + 1/2 = 5/8, cmax = 1: f = rd/pi + rs (5/(2 pi)) (5/8)^3. */
    double a[6] = {0.1, 0.6, -1.0, 0.5, 1.0, 3.0};
    ts_assert_rel(ts_eval1(m, a, 45.0, 45.0, 45.0, 225.0, 0), 0.1 / M_PI + 0.6 * 5.0 / (2.0 * M_PI) * 125.0 / 512.0,
                  1e-13, "aniso hand");
    /* The same lobe scaled by 0.8 and normalised by max|c| = 0.8: unchanged. */
    double b[6] = {0.1, 0.6, -0.8, 0.4, 0.8, 3.0};
    ts_assert_rel(ts_eval1(m, b, 45.0, 45.0, 45.0, 225.0, 0), 0.1 / M_PI + 0.6 * 5.0 / (2.0 * M_PI) * 125.0 / 512.0,
                  1e-13, "aniso hand, scaled");
    /* cy largest: cx = 0.2, cy = -0.5, cz = 0.25: d = -0.05 + 0.125 + 0.125 = 0.2,
     * r = d / 0.5 = 0.4; n = 2: f = rd/pi + rs (4/(2 pi)) 0.16. */
    double c[6] = {0.1, 0.6, 0.2, -0.5, 0.25, 2.0};
    ts_assert_rel(ts_eval1(m, c, 45.0, 45.0, 45.0, 225.0, 0), 0.1 / M_PI + 0.6 * 2.0 / M_PI * 0.16, 1e-13,
                  "aniso, cy the largest");
    bf_model_free(m);
}

/* lafortune_aniso with cx = cy equals lafortune with cxy = cx. */
static void test_aniso_reduces(void **state)
{
    (void)state;
    bf_model *iso = NULL;
    bf_model_new("lafortune:lobes=2", 1, &iso, NULL);
    bf_model *an = NULL;
    bf_model_new("lafortune_aniso:lobes=2", 1, &an, NULL);
    ts_rng r = {0x99ULL};
    for (int t = 0; t < 200; t++) {
        double xi[9], xa[11];
        xi[0] = xa[0] = ts_uniform(&r);
        for (int k = 0; k < 2; k++) {
            double rs = ts_uniform(&r), cxy = 2.0 * ts_uniform(&r) - 1.0;
            double cz = 2.0 * ts_uniform(&r) - 1.0, n = expm1(ts_uniform(&r) * log(101.0));
            double *pi = xi + 1 + 4 * k, *pa = xa + 1 + 5 * k;
            pi[0] = rs, pi[1] = cxy, pi[2] = cz, pi[3] = n;
            pa[0] = rs, pa[1] = cxy, pa[2] = cxy, pa[3] = cz, pa[4] = n;
        }
        double ti = 89.0 * ts_uniform(&r), pi_ = 360.0 * ts_uniform(&r);
        double to = 89.0 * ts_uniform(&r), po = 360.0 * ts_uniform(&r);
        assert_close(ts_eval1(an, xa, ti, pi_, to, po, 0), ts_eval1(iso, xi, ti, pi_, to, po, 0), 1e-14,
                     "aniso with cx = cy vs iso");
    }
    bf_model_free(iso);
    bf_model_free(an);
}

/* Random parameters (coefficients at the bounds and tied sometimes) and geometry, K = 1
 * and 2 lobes, three channels, against the plain formula. */
static void random_case(const char *spec, int aniso, int K, uint64_t seed)
{
    const int C = 3, ns = aniso ? 4 : 3; /* scalars per lobe */
    bf_model *m = NULL;
    bf_model_new(spec, C, &m, NULL);
    assert_non_null(m);
    assert_int_equal(bf_model_nvalues(m), C + K * (C + ns));
    ts_rng r = {seed};
    for (int t = 0; t < 200; t++) {
        double x[64];
        lobe_p lp[3][2]; /* per channel, per lobe */
        for (int c = 0; c < C; c++)
            x[c] = ts_uniform(&r);
        for (int k = 0; k < K; k++) {
            double *p = x + C + k * (C + ns);
            double cc[3];
            for (int q = 0; q < 3; q++) {
                double u = ts_uniform(&r);
                cc[q] = u < 0.15 ? -1.0 : u < 0.3 ? 1.0 : 2.0 * ts_uniform(&r) - 1.0;
            }
            if (!aniso)
                cc[1] = cc[0];
            double n = expm1(ts_uniform(&r) * log(61.0));
            for (int c = 0; c < C; c++)
                p[c] = ts_uniform(&r);
            p[C] = cc[0];
            if (aniso)
                p[C + 1] = cc[1];
            p[C + ns - 2] = cc[2];
            p[C + ns - 1] = n;
            for (int c = 0; c < C; c++)
                lp[c][k] = (lobe_p){p[c], cc[0], cc[1], cc[2], n};
        }
        double ti = 89.0 * ts_uniform(&r), pi_ = 360.0 * ts_uniform(&r);
        double to = 89.0 * ts_uniform(&r), po = 360.0 * ts_uniform(&r);
        if (t % 3 == 0) {
            to = fmin(89.0, ti + 4.0 * (ts_uniform(&r) - 0.5));
            po = pi_ + 180.0 + 4.0 * (ts_uniform(&r) - 0.5);
        }
        for (int c = 0; c < C; c++)
            assert_close(ts_eval1(m, x, ti, pi_, to, po, c), laf_ref(x[c], K, lp[c], ti, pi_, to, po), 1e-12, spec);
    }
    bf_model_free(m);
}

static void test_random(void **state)
{
    (void)state;
    random_case("lafortune", 0, 1, 0x1111ULL);
    random_case("lafortune:lobes=2", 0, 2, 0x2222ULL);
    random_case("lafortune_aniso", 1, 1, 0x3333ULL);
    random_case("lafortune_aniso:lobes=2", 1, 2, 0x4444ULL);
}

/* One published fit: Ngan et al. 2005 as published in bsdfbenchmark/bbm
 * fits/ngan_lafortune.fit (blue-acrylic: albedo [0.0238, 0.0164, 0.01], Cxy = -0.577,
 * Cz = 0.577, sharpness 4060), which lafortune takes unchanged (rho_s = albedo). cmax^n
 * underflows here (0.577^4060), so the formula is written (n+2)/(2 pi) max(0, d/cmax)^n.
 * The digits are from tests/published/ref_nganlafortune.py, an independent implementation. */
static void test_ngan_published(void **state)
{
    (void)state;
    bf_model *m = ts_model("lafortune", 3);
    const double x[10] = {0.0145, 0.0332, 0.064, 0.0238, 0.0164, 0.01, -0.577, 0.577, 4060.0};
    const double want[3] = {14.991773666784496, 10.337853352268834, 6.317497115671574};
    double L[3], V[3];
    ts_dirs_deg(30.0, 10.0, 30.2, 190.1, L, V);
    double d = (-0.577 * (L[0] * V[0] + L[1] * V[1]) + 0.577 * L[2] * V[2]) / 0.577;
    double lobe = 4062.0 / (2.0 * M_PI) * pow(fmax(0.0, d), 4060.0);
    for (int c = 0; c < 3; c++) {
        double v = ts_eval1(m, x, 30.0, 10.0, 30.2, 190.1, c);
        assert_close(v, want[c], 1e-11, "Ngan Lafortune blue-acrylic");
        assert_close(v, x[c] / M_PI + x[3 + c] * lobe, 1e-11, "Ngan Lafortune formula");
    }
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tables),         cmocka_unit_test(test_equals_phong),
        cmocka_unit_test(test_normalisation),  cmocka_unit_test(test_hand),
        cmocka_unit_test(test_aniso_reduces),  cmocka_unit_test(test_random),
        cmocka_unit_test(test_ngan_published),
    };
    return cmocka_run_group_tests_name("values_lafortune", tests, NULL, NULL);
}
