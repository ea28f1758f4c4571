/* Values of mitsuba_principled: closed forms at normal incidence, and Mitsuba 3's
 * principled eval() (principled.cpp, principledhelpers.h: principled_fresnel,
 * calc_schlick, GTR1Isotropic, smith_ggx1) written out plainly from vectors, value =
 * eval() / cos(theta_o), at random geometries and parameters. Nothing here is shared
 * with the library. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "support.h"

enum { MAXC = 5, NS = 9 };

typedef struct mp {
    double base[MAXC];
    double metallic, specular, spec_tint, roughness, sheen, sheen_tint, flatness, clearcoat, clearcoat_gloss;
} mp;

static const char *const names[NS] = {"metallic",   "specular", "spec_tint", "roughness",      "sheen",
                                      "sheen_tint", "flatness", "clearcoat", "clearcoat_gloss"};

static bf_model *make(int C)
{
    bf_error err;
    bf_model *m = NULL;
    if (bf_model_new("mitsuba_principled", C, &m, &err) != BF_OK)
        fail_msg("mitsuba_principled: %s", err.msg);
    return m;
}

static void pack(const bf_model *m, const mp *p, double *x)
{
    const double s[NS] = {p->metallic,   p->specular, p->spec_tint, p->roughness,      p->sheen,
                          p->sheen_tint, p->flatness, p->clearcoat, p->clearcoat_gloss};
    int C = bf_model_channels(m);
    assert_int_equal(bf_model_nvalues(m), C + NS);
    for (int c = 0; c < C; c++)
        x[c] = p->base[c];
    for (int k = 0; k < NS; k++) {
        int i = bf_model_find_param(m, names[k]);
        assert_true(i >= 0);
        assert_int_equal(bf_model_param_offset(m, i), C + k);
        x[C + k] = s[k];
    }
}

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
static double lerp(double a, double b, double t)
{
    return a + (b - a) * t;
}
static double schlick_weight(double cos_i)
{
    double m = fmin(fmax(1.0 - cos_i, 0.0), 1.0);
    return m * m * m * m * m;
}
/* Exact unpolarised dielectric Fresnel from the refracted cosine (Mitsuba's fresnel()). */
static double fresnel(double cos_i, double eta)
{
    double sin_t2 = (1.0 - cos_i * cos_i) / (eta * eta);
    if (sin_t2 >= 1.0)
        return 1.0;
    double cos_t = sqrt(1.0 - sin_t2);
    double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}
static double calc_schlick(double R0, double cos_i)
{
    return lerp(schlick_weight(fabs(cos_i)), 1.0, R0);
}
static double smith_g1(double alpha, double cos_theta)
{
    double tan2 = (1.0 - cos_theta * cos_theta) / (cos_theta * cos_theta);
    return 2.0 / (1.0 + sqrt(1.0 + alpha * alpha * tan2));
}

/* Channel c; angles in degrees; wi = L, wo = V (the value is symmetric). */
static double ref_mitsuba(const mp *p, int C, double ti, double pi_, double to, double po, int c)
{
    double wi[3], wo[3];
    ts_dirs_deg(ti, pi_, to, po, wi, wo);
    double cos_i = wi[2], cos_o = wo[2];
    if (cos_i <= 0.0 || cos_o <= 0.0)
        return 0.0;
    double wh[3] = {wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]};
    double len = sqrt(dot3(wh, wh));
    for (int k = 0; k < 3; k++)
        wh[k] /= len;
    double lum = 0.0;
    for (int k = 0; k < C; k++)
        lum += (C == 3 ? (k == 0 ? 0.212671 : k == 1 ? 0.715160 : 0.072169) : 1.0 / C) * p->base[k];
    double base = p->base[c], c_tint = lum > 0.0 ? base / lum : 1.0;
    double brdf = 1.0 - p->metallic;
    double eta = 2.0 / (1.0 - sqrt(0.08 * p->specular)) - 1.0;

    /* Main specular. */
    double alpha = fmax(0.001, p->roughness * p->roughness);
    double ct = wh[2], ct2 = ct * ct;
    double tan2h = (wh[0] * wh[0] + wh[1] * wh[1]) / ct2;
    double D = 1.0 / (M_PI * alpha * alpha * ct2 * ct2 * pow(1.0 + tan2h / (alpha * alpha), 2.0));
    double G = smith_g1(alpha, cos_i) * smith_g1(alpha, cos_o);
    double cos_d = dot3(wi, wh);
    double F_diel = fresnel(cos_d, eta);
    double F = (1.0 - p->metallic) * (1.0 - p->spec_tint) * F_diel + p->metallic * calc_schlick(base, cos_d) +
               (1.0 - p->metallic) * p->spec_tint * calc_schlick(c_tint * pow((eta - 1.0) / (eta + 1.0), 2.0), cos_d);
    double value = F * D * G / (4.0 * cos_i); /* eval() returns this times cos_o */

    /* Clear coat: (clearcoat 0.25) Fcc Dcc Gcc cos_o. */
    double a = lerp(0.1, 0.001, p->clearcoat_gloss), a2 = a * a;
    double Dcc = (a2 - 1.0) / (M_PI * log(a2) * (1.0 + (a2 - 1.0) * ct2));
    double Gcc = smith_g1(0.25, cos_i) * smith_g1(0.25, cos_o);
    value += p->clearcoat * 0.25 * calc_schlick(0.04, cos_d) * Dcc * Gcc * cos_o;

    /* Diffuse, retro-reflection, fake subsurface, sheen. */
    double Fo = schlick_weight(cos_o), Fi = schlick_weight(cos_i);
    double f_diff = (1.0 - 0.5 * Fi) * (1.0 - 0.5 * Fo);
    double cos_theta_d = dot3(wh, wo);
    double Rr = 2.0 * p->roughness * cos_theta_d * cos_theta_d;
    double f_retro = Rr * (Fo + Fi + Fo * Fi * (Rr - 1.0));
    double Fss90 = Rr / 2.0;
    double Fss = lerp(1.0, Fss90, Fo) * lerp(1.0, Fss90, Fi);
    double f_ss = 1.25 * (Fss * (1.0 / (cos_o + cos_i) - 0.5) + 0.5);
    value += brdf * cos_o * base / M_PI * lerp(f_diff + f_retro, f_ss, p->flatness);
    double c_sheen = lerp(1.0, c_tint, p->sheen_tint);
    value += p->sheen * (1.0 - p->metallic) * schlick_weight(cos_theta_d) * c_sheen * cos_o;
    return value / cos_o;
}

static mp defaults(void)
{
    mp p = {.metallic = 0.0, .specular = 0.5, .roughness = 0.5};
    for (int c = 0; c < MAXC; c++)
        p.base[c] = 0.5;
    return p;
}

/* L = V = N: every Schlick weight 0, Fd = 1, ss = .625, F = F0, D = 1/(pi a^2), G = 1. */
static void test_normal_incidence(void **state)
{
    (void)state;
    bf_model *m = make(3);
    double x[3 + NS], xd[3 + NS];
    mp p = defaults();
    pack(m, &p, x);
    bf_model_defaults(m, xd);
    for (int k = 0; k < 3 + NS; k++)
        assert_true(xd[k] == x[k]);
    /* Mitsuba's defaults: .5/pi + .04/(4 pi .0625) = .66/pi. */
    for (int c = 0; c < 3; c++)
        ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, c), 0.66 / M_PI, 1e-13, "defaults");
    /* Flatness 1: ss = 1.25 (1 * (1/2 - 1/2) + 1/2) = .625. */
    p.flatness = 1.0;
    pack(m, &p, x);
    ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, 0), (0.625 * 0.5 + 0.16) / M_PI, 1e-13, "flatness");
    /* Metal: base_color S. */
    p = defaults();
    p.metallic = 1.0;
    p.base[0] = 0.9, p.base[1] = 0.6, p.base[2] = 0.3;
    pack(m, &p, x);
    for (int c = 0; c < 3; c++)
        ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, c), p.base[c] * 4.0 / M_PI, 1e-13, "metal");
    /* Clear coat 1, gloss 1 (a = .001): .25 .04 Dcc with Dcc = (a^2 - 1)/(pi ln(a^2) a^2), no 1/4. */
    p = defaults();
    p.clearcoat = 1.0;
    p.clearcoat_gloss = 1.0;
    pack(m, &p, x);
    double a2 = 1e-6, Dcc = (a2 - 1.0) / (M_PI * log(a2) * a2);
    ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, 1), 0.66 / M_PI + 0.25 * 0.04 * Dcc, 1e-12, "coat");
    /* Roughness below sqrt(.001): the floor a = .001. */
    p = defaults();
    p.roughness = 0.01;
    pack(m, &p, x);
    ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, 2), 0.5 / M_PI + 0.04 / (4.0 * M_PI * 1e-6), 1e-12, "floor");
    bf_model_free(m);
}

/* Random parameters for the comparison, packed into x. */
static void draw(ts_rng *r, const bf_model *m, double *x, void *ctx)
{
    mp *p = ctx;
    for (int c = 0; c < bf_model_channels(m); c++)
        p->base[c] = ts_uniform(r);
    p->metallic = ts_uniform_ends(r), p->specular = ts_uniform_ends(r), p->spec_tint = ts_uniform_ends(r);
    /* Roughness from .05: below that the peak is a near-delta whose value the rounding
     * of N.H decides (the floor is checked at normal incidence). */
    p->roughness = 0.05 + 0.95 * ts_uniform(r);
    p->sheen = ts_uniform_ends(r), p->sheen_tint = ts_uniform_ends(r), p->flatness = ts_uniform_ends(r);
    p->clearcoat = ts_uniform_ends(r);
    /* The coat's GTR1 is as sharp as a = .001: keep it where its value is not set by the
     * rounding of N.H either. */
    p->clearcoat_gloss = 0.8 * ts_uniform(r);
    pack(m, p, x);
}

static double ref(const void *ctx, int C, double ti, double pi_, double to, double po, int c)
{
    return ref_mitsuba(ctx, C, ti, pi_, to, po, c);
}

/* Mitsuba's eval written out, at random geometries and parameters. */
static void test_against_mitsuba(void **state)
{
    (void)state;
    mp p;
    ts_compare_reference("mitsuba_principled", 0x1234567887654321ULL, draw, ref, &p, 1e-9);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_normal_incidence),
        cmocka_unit_test(test_against_mitsuba),
    };
    return cmocka_run_group_tests_name("values_mitsuba_principled", tests, NULL, NULL);
}
