/* Values of ashikhmin_shirley and ashikhmin_shirley_iso against hand-computed cases and
 * a plain re-implementation of the docs/models.md formula from the angles. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "support.h"

static double p5(double t)
{
    return t * t * t * t * t;
}

static double diffuse_ref(double rd, double rs, double nl, double nv)
{
    return 28.0 * rd / (23.0 * M_PI) * (1.0 - rs) * (1.0 - p5(1.0 - nl / 2.0)) * (1.0 - p5(1.0 - nv / 2.0));
}

/* docs/models.md's formula from the angles (degrees). The exponent is written as in the paper,
 * e = nu cos^2(phi_h) + nv sin^2(phi_h), and NH^e with pow: an independent route. */
static double as_ref(double rd, double rs, double nu, double nv, double ti, double pi_, double to, double po)
{
    double a = ti * DEG, b = pi_ * DEG, c = to * DEG, d = po * DEG;
    double L[3] = {sin(a) * cos(b), sin(a) * sin(b), cos(a)};
    double V[3] = {sin(c) * cos(d), sin(c) * sin(d), cos(c)};
    if (L[2] <= 0.0 || V[2] <= 0.0)
        return 0.0;
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double len = sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
    for (int k = 0; k < 3; k++)
        H[k] /= len;
    double phih = atan2(H[1], H[0]);
    double e = nu * cos(phih) * cos(phih) + nv * sin(phih) * sin(phih);
    double vh = V[0] * H[0] + V[1] * H[1] + V[2] * H[2];
    double F = rs + (1.0 - rs) * p5(1.0 - vh);
    double spec = sqrt((nu + 1.0) * (nv + 1.0)) / (8.0 * M_PI) * pow(H[2], e) / (vh * fmax(L[2], V[2])) * F;
    return spec + diffuse_ref(rd, rs, L[2], V[2]);
}

static void test_table(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("ashikhmin_shirley", 3, &m, NULL);
    assert_non_null(m);
    assert_int_equal(bf_model_nvalues(m), 3 + 3 + 2);
    const char *names[] = {"rho_d", "rho_s", "nu", "nv"};
    for (int i = 0; i < 4; i++)
        assert_string_equal(bf_model_param(m, i)->name, names[i]);
    assert_true(bf_model_param(m, 1)->color && bf_model_param(m, 1)->hi == 1.0);
    assert_true(bf_model_param(m, 2)->lo == 1.0 && bf_model_param(m, 2)->hi == 1e6);
    bf_model_free(m);
    bf_model_new("ashikhmin_shirley_iso", 1, &m, NULL);
    assert_non_null(m);
    assert_int_equal(bf_model_nparams(m), 3);
    assert_string_equal(bf_model_param(m, 2)->name, "n");
    bf_model_free(m);
}

/* Normal incidence and viewing: H = N, VH = NL = NV = 1, NH^e = 1, F = rho_s:
 * f = sqrt((nu+1)(nv+1))/(8 pi) rho_s + 28/(23 pi) rho_d (1 - rho_s) (31/32)^2. */
static void test_normal(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("ashikhmin_shirley", 3, &m, NULL);
    double x[8] = {0.2, 0.5, 0.9, 0.3, 0.04, 1.0, 3.0, 99.0};
    for (int c = 0; c < 3; c++) {
        double want = sqrt(4.0 * 100.0) / (8.0 * M_PI) * x[3 + c] +
                      28.0 / (23.0 * M_PI) * x[c] * (1.0 - x[3 + c]) * (31.0 / 32.0) * (31.0 / 32.0);
        ts_assert_rel(ts_eval1(m, x, 0.0, 0.0, 0.0, 0.0, c), want, 1e-14, "A-S normal");
    }
    /* By hand for channel 0: 20/(8 pi) 0.3 + 28/(23 pi) 0.2 0.7 (31/32)^2. */
    ts_assert_rel(ts_eval1(m, x, 0.0, 0.0, 0.0, 0.0, 0), 0.28964577819255943, 1e-13, "A-S digits");
    bf_model_free(m);
}

/* Mirror direction at theta: H = N, VH = NL = NV = cos(theta). Azimuths 0 and 180
 * (exact in double) keep the input itself on the mirror direction. */
static void test_mirror(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("ashikhmin_shirley", 1, &m, NULL);
    double x[4] = {0.6, 0.1, 1e6, 7.0};
    double th[] = {10.0, 45.0, 80.0, 89.9};
    for (int k = 0; k < 4; k++) {
        double u = cos(th[k] * DEG);
        double F = 0.1 + 0.9 * p5(1.0 - u);
        double want = sqrt((1e6 + 1.0) * 8.0) / (8.0 * M_PI) * F / (u * u) + diffuse_ref(0.6, 0.1, u, u);
        ts_assert_rel(ts_eval1(m, x, th[k], 0.0, th[k], 180.0, 0), want, 1e-12, "A-S mirror");
    }
    bf_model_free(m);
}

/* A hair off the peak (theta_h ~ 1e-9 rad) with nu != nv: e from sin^2(theta_h) stays
 * finite (1 - NH^2 would be 0 there), NH^e ~ 1. In-plane geometry, so theta_h is
 * exactly (to - ti)/2 and VH = cos((ti + to)/2). */
static void test_near_peak(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("ashikhmin_shirley", 1, &m, NULL);
    double x[4] = {0.0, 1.0, 1e6, 1.0};
    /* 1e-7 deg: NH rounds to 1; 1e-4 deg: NH^e = exp(-0.38), where 1 - NH^2 in e
     * would already be off by ~1e-4 relative. */
    const double dt[] = {1e-7, 1e-4};
    for (int k = 0; k < 2; k++) {
        double ti = 30.0, to = 30.0 + dt[k];
        double thh = (to - ti) / 2.0 * DEG, thd = (to + ti) / 2.0 * DEG;
        /* H lies along X: e = nu, NH^e = exp(nu log cos(theta_h)). */
        double nhe = exp(1e6 * 0.5 * log1p(-sin(thh) * sin(thh)));
        double want = sqrt((1e6 + 1.0) * 2.0) / (8.0 * M_PI) * nhe / (cos(thd) * cos(ti * DEG));
        ts_assert_rel(ts_eval1(m, x, ti, 180.0, to, 0.0, 0), want, 1e-9, "A-S near peak");
    }
    bf_model_free(m);
}

/* Off the peak with nu = nv = 1e6 the specular term underflows to exactly 0. */
static void test_underflow(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("ashikhmin_shirley_iso", 1, &m, NULL);
    double x[3] = {0.7, 0.2, 1e6};
    double want = diffuse_ref(0.7, 0.2, cos(30.0 * DEG), cos(40.0 * DEG));
    ts_assert_rel(ts_eval1(m, x, 30.0, 0.0, 40.0, 90.0, 0), want, 1e-14, "A-S underflow");
    assert_true(ts_eval1(m, x, 95.0, 0.0, 30.0, 180.0, 0) == 0.0);
    bf_model_free(m);
}

static void test_random(void **state)
{
    (void)state;
    ts_rng r = {0x0DDB1A5E5BAD5EEDULL};
    bf_model *m = NULL;
    bf_model_new("ashikhmin_shirley", 3, &m, NULL);
    bf_model *mi = NULL;
    bf_model_new("ashikhmin_shirley_iso", 3, &mi, NULL);
    double x[8], xi[7], xa[8];
    for (int k = 0; k < 300; k++) {
        for (int c = 0; c < 3; c++) {
            x[c] = ts_uniform(&r);
            x[3 + c] = ts_uniform(&r);
        }
        /* Exponents up to 1e3: pow() in the reference then still agrees to ~1e-13. */
        x[6] = pow(1e3, ts_uniform(&r));
        x[7] = pow(1e3, ts_uniform(&r));
        double ti = 88.0 * ts_uniform(&r), pi_ = 360.0 * ts_uniform(&r);
        double to = 88.0 * ts_uniform(&r), po = 360.0 * ts_uniform(&r);
        if (k % 2) { /* near the mirror direction */
            double w = 60.0 / sqrt(fmin(x[6], x[7]));
            to = fabs(fmin(88.0, ti + w * (ts_uniform(&r) - 0.5)));
            po = pi_ + 180.0 + w * (ts_uniform(&r) - 0.5);
        }
        for (int c = 0; c < 3; c++) {
            double want = as_ref(x[c], x[3 + c], x[6], x[7], ti, pi_, to, po);
            ts_assert_rel(ts_eval1(m, x, ti, pi_, to, po, c), want, 1e-12, "A-S random");
        }
        /* Isotropic = anisotropic with nu = nv. */
        memcpy(xi, x, 7 * sizeof *x);
        memcpy(xa, x, sizeof xa);
        xa[7] = x[6];
        for (int c = 0; c < 3; c++) {
            double want = as_ref(x[c], x[3 + c], x[6], x[6], ti, pi_, to, po);
            double iso = ts_eval1(mi, xi, ti, pi_, to, po, c);
            ts_assert_rel(iso, want, 1e-12, "A-S iso random");
            ts_assert_rel(iso, ts_eval1(m, xa, ti, pi_, to, po, c), 1e-13, "A-S iso vs aniso");
        }
    }
    bf_model_free(m);
    bf_model_free(mi);
}

/* diffuse=lambert (Ngan 2005's variant): rho_d/pi beside rho_s times the lobe with
 * Schlick's F of f0, written out from the angles (pow for NH^e, as as_ref). */
static double lambert_ref(double rd, double rs, double nu, double nv, double f0, double ti, double pi_, double to,
                          double po)
{
    double a = ti * DEG, b = pi_ * DEG, c = to * DEG, d = po * DEG;
    double L[3] = {sin(a) * cos(b), sin(a) * sin(b), cos(a)};
    double V[3] = {sin(c) * cos(d), sin(c) * sin(d), cos(c)};
    if (L[2] <= 0.0 || V[2] <= 0.0)
        return 0.0;
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double len = sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
    for (int k = 0; k < 3; k++)
        H[k] /= len;
    double phih = atan2(H[1], H[0]);
    double e = nu * cos(phih) * cos(phih) + nv * sin(phih) * sin(phih);
    double lh = L[0] * H[0] + L[1] * H[1] + L[2] * H[2];
    double F = f0 + (1.0 - f0) * p5(1.0 - lh);
    return rd / M_PI + rs * sqrt((nu + 1.0) * (nv + 1.0)) / (8.0 * M_PI) * pow(H[2], e) / (lh * fmax(L[2], V[2])) * F;
}

/* The option's table (f0 after the exponents, which reach down to 0) and canonical specs
 * (the default keeps the old spec); by hand at normal incidence, where F = f0 and
 * f = rho_d/pi + rho_s (n+1) f0/(8 pi); the plain formula at random directions. */
static void test_lambert(void **state)
{
    (void)state;
    bf_model *m = ts_model("ashikhmin_shirley_iso:diffuse=lambert", 3);
    bf_model *ma = ts_model("ashikhmin_shirley:diffuse=lambert", 1);
    bf_model *old = ts_model("ashikhmin_shirley_iso", 1);
    assert_string_equal(bf_model_spec(old), "ashikhmin_shirley_iso");
    assert_string_equal(bf_model_spec(m), "ashikhmin_shirley_iso:diffuse=lambert");
    assert_int_equal(bf_model_nparams(m), 4);
    assert_int_equal(bf_model_nparams(ma), 5);
    assert_string_equal(bf_model_param(m, 3)->name, "f0");
    assert_string_equal(bf_model_param(ma, 4)->name, "f0");
    assert_true(bf_model_param(m, 2)->lo == 0.0 && bf_model_param(m, 2)->hi == 1e6);
    assert_int_equal(bf_model_energy_conserving(m), 1);
    double x[8] = {0.2, 0.5, 0.9, 0.3, 0.04, 1.0, 99.0, 0.05};
    for (int c = 0; c < 3; c++)
        ts_assert_rel(ts_eval1(m, x, 0.0, 0.0, 0.0, 0.0, c), x[c] / M_PI + x[3 + c] * 100.0 * 0.05 / (8.0 * M_PI),
                      1e-14, "A-S lambert normal");
    /* By hand, channel 0: 0.2/pi + 0.3 * 100 * 0.05/(8 pi). */
    ts_assert_rel(ts_eval1(m, x, 0.0, 0.0, 0.0, 0.0, 0), 0.12334508089621889, 1e-13, "A-S lambert digits");
    ts_rng r = {0xA5A5A5A55A5A5A5AULL};
    for (int k = 0; k < 200; k++) {
        double xa[5] = {ts_uniform(&r), ts_uniform(&r), pow(1e3, ts_uniform(&r)), pow(1e3, ts_uniform(&r)),
                        ts_uniform(&r)};
        double ti = 88.0 * ts_uniform(&r), pi_ = 360.0 * ts_uniform(&r);
        double w = 60.0 / sqrt(fmin(xa[2], xa[3]));
        double to = fabs(fmin(88.0, ti + w * (ts_uniform(&r) - 0.5))), po = pi_ + 180.0 + w * (ts_uniform(&r) - 0.5);
        ts_assert_rel(ts_eval1(ma, xa, ti, pi_, to, po, 0),
                      lambert_ref(xa[0], xa[1], xa[2], xa[3], xa[4], ti, pi_, to, po), 1e-12, "A-S lambert random");
    }
    bf_model_free(m);
    bf_model_free(ma);
    bf_model_free(old);
}

/* One published fit: Ngan et al. 2005 as published in bsdfbenchmark/bbm
 * fits/ngan_ashikhminshirley.fit (blue-acrylic: albedo, fresnelReflectance, sharpness
 * map to rho_s, f0, n), near the mirror direction. The digits are from
 * tests/published/ref_nganashikhminshirley.py, an independent implementation. */
static void test_published(void **state)
{
    (void)state;
    bf_model *m = ts_model("ashikhmin_shirley_iso:diffuse=lambert", 3);
    const double x[8] = {0.0143, 0.0331, 0.0639, 0.0366, 0.0241, 0.0147, 11600.0, 0.0949};
    const double want[3] = {2.1046862174833314, 1.3934114316936879, 0.86383659942742497};
    for (int c = 0; c < 3; c++) {
        double v = ts_eval1(m, x, 30.0, 10.0, 30.2, 190.1, c);
        ts_assert_rel(v, want[c], 1e-11, "Ngan A-S blue-acrylic");
        ts_assert_rel(v, lambert_ref(x[c], x[3 + c], 11600.0, 11600.0, 0.0949, 30.0, 10.0, 30.2, 190.1), 1e-11,
                      "Ngan A-S formula");
    }
    bf_model_free(m);
}

/* fresnel=dielectric (Löw et al. 2012's variant): Snell's-law Fresnel of ior at L.H in
 * place of Schlick's, rho_s weighing the lobe. lambert: rho_d/pi + rho_s lobe F_d; at
 * normal incidence F_d = ((n-1)/(n+1))^2. coupled: the diffuse keeps its (1 - rho_s). */
static double fresnel_snell(double ci, double n)
{
    double st = sqrt(1.0 - ci * ci) / n, ct = sqrt(1.0 - st * st);
    double rs = (ci - n * ct) / (ci + n * ct), rp = (ct - n * ci) / (ct + n * ci);
    return 0.5 * (rs * rs + rp * rp);
}

static void test_dielectric(void **state)
{
    (void)state;
    bf_model *m = ts_model("ashikhmin_shirley_iso:diffuse=lambert,fresnel=dielectric", 1);
    bf_model *mc = ts_model("ashikhmin_shirley_iso:fresnel=dielectric", 1);
    assert_string_equal(bf_model_spec(m), "ashikhmin_shirley_iso:diffuse=lambert,fresnel=dielectric");
    assert_int_equal(bf_model_nparams(m), 4);
    assert_string_equal(bf_model_param(m, 3)->name, "ior");
    assert_string_equal(bf_model_param(mc, 3)->name, "ior");
    assert_true(bf_model_param(m, 3)->hi == 100.0);
    /* Published fit: Löw et al. 2012, E1, aluminium (red), as published in bsdfbenchmark/bbm
     * fits/low_ashikhminshirley_E1.fit: kd 0.0974, albedo 0.02902, sharpness 292101.373392,
     * fresnelReflectance (an index of refraction) 9.79957. */
    double x[4] = {0.0974, 0.02902, 292101.373392, 9.79957};
    double r = 8.79957 / 10.79957;
    ts_assert_rel(ts_eval1(m, x, 0.0, 0.0, 0.0, 0.0, 0), 0.0974 / M_PI + 0.02902 * 292102.373392 / (8.0 * M_PI) * r * r,
                  1e-13, "A-S dielectric normal");
    ts_rng rng = {0x5DEECE66DULL};
    for (int k = 0; k < 100; k++) {
        double y[4] = {ts_uniform(&rng), ts_uniform(&rng), pow(1e3, ts_uniform(&rng)), 1.0 + 20.0 * ts_uniform(&rng)};
        double ti = 88.0 * ts_uniform(&rng), pi_ = 360.0 * ts_uniform(&rng);
        double w = 60.0 / sqrt(y[2]);
        double to = fabs(fmin(88.0, ti + w * (ts_uniform(&rng) - 0.5))),
               po = pi_ + 180.0 + w * (ts_uniform(&rng) - 0.5);
        double a = ti * DEG, b = pi_ * DEG, c = to * DEG, d = po * DEG;
        double L[3] = {sin(a) * cos(b), sin(a) * sin(b), cos(a)}, V[3] = {sin(c) * cos(d), sin(c) * sin(d), cos(c)};
        double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
        double len = sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
        double lh = (L[0] * H[0] + L[1] * H[1] + L[2] * H[2]) / len;
        double lobe = y[1] * (y[2] + 1.0) / (8.0 * M_PI) * pow(H[2] / len, y[2]) / (lh * fmax(L[2], V[2])) *
                      fresnel_snell(lh, y[3]);
        ts_assert_rel(ts_eval1(m, y, ti, pi_, to, po, 0), y[0] / M_PI + lobe, 1e-11, "A-S dielectric lambert");
        double p5l = pow(1.0 - 0.5 * L[2], 5.0), p5v = pow(1.0 - 0.5 * V[2], 5.0);
        double diff = 28.0 * y[0] / (23.0 * M_PI) * (1.0 - y[1]) * (1.0 - p5l) * (1.0 - p5v);
        ts_assert_rel(ts_eval1(mc, y, ti, pi_, to, po, 0), diff + lobe, 1e-11, "A-S dielectric coupled");
    }
    bf_model_free(m);
    bf_model_free(mc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table),     cmocka_unit_test(test_normal),    cmocka_unit_test(test_mirror),
        cmocka_unit_test(test_near_peak), cmocka_unit_test(test_underflow), cmocka_unit_test(test_random),
        cmocka_unit_test(test_lambert),   cmocka_unit_test(test_published), cmocka_unit_test(test_dielectric),
    };
    return cmocka_run_group_tests_name("values_ashikhmin_shirley", tests, NULL, NULL);
}
