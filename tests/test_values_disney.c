/* Values of the Disney principled BRDF: closed forms at normal incidence and at the
 * mirror direction, and a plain re-implementation of the BRDF Explorer shader
 * (disney.brdf, base_color linear) at random geometries and parameters. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "support.h"

/* Parameter vector layout: base_color[C], then the ten scalars in this order. */
typedef struct dp {
    double metallic, subsurface, specular, roughness, specular_tint, anisotropic, sheen, sheen_tint, clearcoat,
        clearcoat_gloss;
} dp;

static bf_model *make(int C)
{
    bf_error err;
    bf_model *m = NULL;
    if (bf_model_new("disney", C, &m, &err) != BF_OK)
        fail_msg("disney: %s", err.msg);
    return m;
}

static void pack(const bf_model *m, const double *base, const dp *p, double *x)
{
    int C = bf_model_channels(m);
    assert_int_equal(bf_model_nvalues(m), C + 10);
    const double s[10] = {p->metallic,    p->subsurface, p->specular,   p->roughness, p->specular_tint,
                          p->anisotropic, p->sheen,      p->sheen_tint, p->clearcoat, p->clearcoat_gloss};
    static const char *const names[10] = {"metallic",    "subsurface", "specular",   "roughness", "specular_tint",
                                          "anisotropic", "sheen",      "sheen_tint", "clearcoat", "clearcoat_gloss"};
    assert_int_equal(bf_model_param_offset(m, bf_model_find_param(m, "base_color")), 0);
    for (int c = 0; c < C; c++)
        x[c] = base[c];
    for (int k = 0; k < 10; k++) {
        int i = bf_model_find_param(m, names[k]);
        assert_true(i >= 0);
        assert_int_equal(bf_model_param_offset(m, i), C + k);
        x[C + k] = s[k];
    }
}

/* ---- The shader, written out plainly ------------------------------------------ */

static double sqr(double v)
{
    return v * v;
}
static double mix(double a, double b, double t)
{
    return a * (1.0 - t) + b * t;
}
static double schlick_fresnel(double u)
{
    double m = 1.0 - u;
    m = m < 0.0 ? 0.0 : m > 1.0 ? 1.0 : m;
    return pow(m, 5.0);
}
static double gtr1(double nh, double a)
{
    if (a >= 1.0)
        return 1.0 / M_PI;
    double a2 = a * a;
    double t = 1.0 + (a2 - 1.0) * nh * nh;
    return (a2 - 1.0) / (M_PI * log(a2) * t);
}
static double gtr2_aniso(double nh, double hx, double hy, double ax, double ay)
{
    return 1.0 / (M_PI * ax * ay * sqr(sqr(hx / ax) + sqr(hy / ay) + nh * nh));
}
static double smith_g_ggx(double n, double alpha_g)
{
    double a = alpha_g * alpha_g, b = n * n;
    return 1.0 / (n + sqrt(a + b - a * b));
}
static double smith_g_ggx_aniso(double n, double x, double y, double ax, double ay)
{
    return 1.0 / (n + sqrt(sqr(x * ax) + sqr(y * ay) + sqr(n)));
}

/* Channel c of the shader for C channels; angles in degrees. */
static double ref_disney(const double *base, int C, const dp *p, double ti, double pi_, double to, double po, int c)
{
    double L[3] = {sin(ti * DEG) * cos(pi_ * DEG), sin(ti * DEG) * sin(pi_ * DEG), cos(ti * DEG)};
    double V[3] = {sin(to * DEG) * cos(po * DEG), sin(to * DEG) * sin(po * DEG), cos(to * DEG)};
    double NdotL = L[2], NdotV = V[2];
    if (NdotL <= 0.0 || NdotV <= 0.0)
        return 0.0;
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double len = sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
    for (int k = 0; k < 3; k++)
        H[k] /= len;
    double NdotH = H[2], LdotH = L[0] * H[0] + L[1] * H[1] + L[2] * H[2];

    /* Luminance: shader weights for RGB, the plain mean otherwise. */
    double Cdlum = 0.0;
    for (int k = 0; k < C; k++)
        Cdlum += (C == 3 ? (k == 0 ? 0.3 : k == 1 ? 0.6 : 0.1) : 1.0 / C) * base[k];
    double Cdlin = base[c];
    double Ctint = Cdlum > 0.0 ? Cdlin / Cdlum : 1.0;
    double Cspec0 = mix(p->specular * 0.08 * mix(1.0, Ctint, p->specular_tint), Cdlin, p->metallic);
    double Csheen = mix(1.0, Ctint, p->sheen_tint);

    double FL = schlick_fresnel(NdotL), FV = schlick_fresnel(NdotV);
    double Fd90 = 0.5 + 2.0 * LdotH * LdotH * p->roughness;
    double Fd = mix(1.0, Fd90, FL) * mix(1.0, Fd90, FV);
    double Fss90 = LdotH * LdotH * p->roughness;
    double Fss = mix(1.0, Fss90, FL) * mix(1.0, Fss90, FV);
    double ss = 1.25 * (Fss * (1.0 / (NdotL + NdotV) - 0.5) + 0.5);

    double aspect = sqrt(1.0 - p->anisotropic * 0.9);
    double ax = fmax(0.001, sqr(p->roughness) / aspect);
    double ay = fmax(0.001, sqr(p->roughness) * aspect);
    double Ds = gtr2_aniso(NdotH, H[0], H[1], ax, ay);
    double FH = schlick_fresnel(LdotH);
    double Fs = mix(Cspec0, 1.0, FH);
    double Gs = smith_g_ggx_aniso(NdotL, L[0], L[1], ax, ay) * smith_g_ggx_aniso(NdotV, V[0], V[1], ax, ay);

    double Fsheen = FH * p->sheen * Csheen;

    double Dr = gtr1(NdotH, mix(0.1, 0.001, p->clearcoat_gloss));
    double Fr = mix(0.04, 1.0, FH);
    double Gr = smith_g_ggx(NdotL, 0.25) * smith_g_ggx(NdotV, 0.25);

    return ((1.0 / M_PI) * mix(Fd, ss, p->subsurface) * Cdlin + Fsheen) * (1.0 - p->metallic) + Gs * Fs * Ds +
           0.25 * p->clearcoat * Gr * Fr * Dr;
}

static const dp shader_defaults = {0.0, 0.0, 0.5, 0.5, 0.0, 0.0, 0.0, 0.5, 0.0, 1.0};

/* ---- Closed forms ------------------------------------------------------------- */

/* L = V = N: NL = NV = NH = LH = 1, so FL = FV = FH = 0, Fd = 1, ss = 1.25 * .5,
 * Gs = (1/2)^2, Ds = 1/(pi ax ay) = 1/(pi r^4), Gr = (1/2)^2, Fs = Cspec0, Fr = .04,
 * Dr = (a^2 - 1)/(pi log(a^2) a^2). */
static void test_normal_incidence(void **state)
{
    (void)state;
    bf_model *m = make(3);
    double x[13];
    const double base[3] = {0.5, 0.5, 0.5};

    /* Shader defaults (metallic 0, specular .5, roughness .5, the rest 0): the diffuse
     * B/pi plus the specular .25 * .04 * 16/pi. */
    dp p = shader_defaults;
    pack(m, base, &p, x);
    for (int c = 0; c < 3; c++)
        ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, c), (0.5 + 0.16) / M_PI, 1e-14, "defaults");
    /* The library's own defaults are the shader's with base_color .5. */
    double xd[13];
    bf_model_defaults(m, xd);
    for (int k = 0; k < 13; k++)
        assert_true(xd[k] == x[k]);

    /* Subsurface 1: ss = .625 replaces Fd = 1. */
    p.subsurface = 1.0;
    pack(m, base, &p, x);
    ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, 1), (0.625 * 0.5 + 0.16) / M_PI, 1e-14, "subsurface");
    /* Half subsurface, roughness .8, specular 1: Ds = 1/(pi .8^4), Cspec0 = .08. */
    p.subsurface = 0.5;
    p.roughness = 0.8;
    p.specular = 1.0;
    pack(m, base, &p, x);
    ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, 0), 0.8125 * 0.5 / M_PI + 0.25 * 0.08 / (M_PI * pow(0.8, 4)), 1e-14,
                  "rough .8");

    /* Anisotropy leaves ax ay = r^4 unchanged, so at normal incidence nothing changes. */
    p = shader_defaults;
    p.anisotropic = 0.7;
    pack(m, base, &p, x);
    ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, 2), (0.5 + 0.16) / M_PI, 1e-14, "anisotropic");

    /* Metallic 1: only Gs Ds Cspec0 = .25 B / (pi r^4) with Cspec0 = B, per channel. */
    const double col[3] = {0.9, 0.4, 0.2};
    p = shader_defaults;
    p.metallic = 1.0;
    p.sheen = 1.0; /* killed by (1 - metallic), and FH = 0 anyway */
    pack(m, col, &p, x);
    for (int c = 0; c < 3; c++)
        ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, c), 0.25 * col[c] * 16.0 / M_PI, 1e-14, "metallic");

    /* Clearcoat 1 with gloss 1 (a = .001) and gloss 0 (a = .1). */
    for (int gl = 0; gl < 2; gl++) {
        double a = gl ? 0.001 : 0.1, a2 = a * a;
        p = shader_defaults;
        p.clearcoat = 1.0;
        p.clearcoat_gloss = gl;
        pack(m, base, &p, x);
        double Dr = (a2 - 1.0) / (M_PI * log(a2) * a2);
        ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, 0), (0.5 + 0.16) / M_PI + 0.25 * 0.25 * 0.04 * Dr, 1e-13, "clearcoat");
    }

    /* Specular tint 1 with C = 3: Ctint = B / (.3 B_r + .6 B_g + .1 B_b). */
    p = shader_defaults;
    p.specular_tint = 1.0;
    pack(m, col, &p, x);
    double lum = 0.3 * 0.9 + 0.6 * 0.4 + 0.1 * 0.2;
    for (int c = 0; c < 3; c++)
        ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, c), col[c] / M_PI + 0.25 * 0.04 * (col[c] / lum) * 16.0 / M_PI, 1e-14,
                      "tint");
    bf_model_free(m);

    /* C = 1: Ctint = 1, so specular_tint and sheen_tint change nothing. */
    m = make(1);
    double b1 = 0.3, x1[11], x2[11];
    p = shader_defaults;
    p.sheen = 0.8;
    p.sheen_tint = 0.0;
    pack(m, &b1, &p, x1);
    p.specular_tint = 1.0;
    p.sheen_tint = 1.0;
    pack(m, &b1, &p, x2);
    ts_assert_rel(ts_eval1(m, x1, 0, 0, 0, 0, 0), (0.3 + 0.16) / M_PI, 1e-14, "C=1");
    ts_assert_rel(ts_eval1(m, x2, 0, 0, 0, 0, 0), (0.3 + 0.16) / M_PI, 1e-14, "C=1 tinted");
    ts_assert_rel(ts_eval1(m, x2, 40, 10, 55, 100, 0), ts_eval1(m, x1, 40, 10, 55, 100, 0), 1e-14, "C=1 tint-free");
    bf_model_free(m);
}

/* Mirror direction at theta: H = N, so NH = 1, LH = cos theta = NL = NV and
 * FL = FV = FH = (1 - cos theta)^5; Ds = 1/(pi ax ay); Gs = G1^2 with
 * G1 = 1/(c + sqrt(s^2 ax^2 + c^2)) for L in the XZ plane. */
static void test_mirror(void **state)
{
    (void)state;
    bf_model *m = make(1);
    double x[11], b = 0.6;
    dp p = shader_defaults;
    p.roughness = 0.3;
    p.anisotropic = 0.5;
    p.sheen = 0.7;
    p.clearcoat = 0.5;
    p.clearcoat_gloss = 0.5;
    pack(m, &b, &p, x);
    const double th = 60.0, c = 0.5, s2 = 0.75;
    double F = pow(1.0 - c, 5.0); /* 1/32 */
    double aspect = sqrt(1.0 - 0.45), ax = 0.09 / aspect, ay = 0.09 * aspect;
    double Fd90 = 0.5 + 2.0 * c * c * 0.3;
    double Fd = sqr(1.0 - F + Fd90 * F);
    double diffuse = Fd * b / M_PI;
    double sheen = F * 0.7 * 1.0; /* C = 1: Csheen = 1 */
    double G1 = 1.0 / (c + sqrt(s2 * ax * ax + c * c));
    double spec = G1 * G1 * (0.04 * (1.0 - F) + F) / (M_PI * ax * ay);
    double a = 0.0505, a2 = a * a;
    double Gr1 = 1.0 / (c + sqrt(0.0625 + c * c - 0.0625 * c * c));
    double coat = 0.25 * 0.5 * Gr1 * Gr1 * (0.04 * (1.0 - F) + F) * (a2 - 1.0) / (M_PI * log(a2) * a2);
    ts_assert_rel(ts_eval1(m, x, th, 0, th, 180, 0), diffuse + sheen + spec + coat, 1e-12, "mirror X");
    /* In the YZ plane the projected roughness is ay instead. */
    G1 = 1.0 / (c + sqrt(s2 * ay * ay + c * c));
    spec = G1 * G1 * (0.04 * (1.0 - F) + F) / (M_PI * ax * ay);
    ts_assert_rel(ts_eval1(m, x, th, 90, th, 270, 0), diffuse + sheen + spec + coat, 1e-12, "mirror Y");
    bf_model_free(m);
}

/* Roughness 0: ax = ay = .001 (the shader's floor), still finite at the peak. */
static void test_roughness_floor(void **state)
{
    (void)state;
    bf_model *m = make(3);
    double x[13];
    const double base[3] = {0.2, 0.5, 0.7};
    dp p = shader_defaults;
    p.roughness = 0.0;
    pack(m, base, &p, x);
    for (int c = 0; c < 3; c++)
        ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, c), base[c] / M_PI + 0.25 * 0.04 / (M_PI * 1e-6), 1e-13, "floor");
    bf_model_free(m);
}

/* The plain shader at random geometries and parameters, C = 1, 3 and 5. */
static void test_against_shader(void **state)
{
    (void)state;
    static const int chans[] = {1, 3, 5};
    ts_rng rng = {0x5DEECE66DULL};
    for (int ci = 0; ci < 3; ci++) {
        int C = chans[ci];
        bf_model *m = make(C);
        double base[5], x[15];
        int tested = 0;
        for (int t = 0; t < 400; t++) {
            for (int c = 0; c < C; c++)
                base[c] = ts_uniform(&rng);
            double s[10];
            for (int k = 0; k < 10; k++) {
                double u = ts_uniform(&rng);
                /* Bounds often, so the 0/1 corners and the .001 floor are covered. */
                s[k] = u < 0.1 ? 0.0 : u < 0.2 ? 1.0 : ts_uniform(&rng);
            }
            dp p = {s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7], s[8], s[9]};
            pack(m, base, &p, x);
            double ti = 85.0 * ts_uniform(&rng), pi_ = 360.0 * ts_uniform(&rng);
            double to = 85.0 * ts_uniform(&rng), po = 360.0 * ts_uniform(&rng);
            /* Keep away from the exact peak, where rounding of H.X / .001 dominates. */
            double L[3] = {sin(ti * DEG) * cos(pi_ * DEG), sin(ti * DEG) * sin(pi_ * DEG), cos(ti * DEG)};
            double V[3] = {sin(to * DEG) * cos(po * DEG), sin(to * DEG) * sin(po * DEG), cos(to * DEG)};
            if (hypot(L[0] + V[0], L[1] + V[1]) < 1e-3)
                continue;
            for (int c = 0; c < C; c++)
                ts_assert_rel(ts_eval1(m, x, ti, pi_, to, po, c), ref_disney(base, C, &p, ti, pi_, to, po, c), 1e-12,
                              "shader");
            tested++;
        }
        assert_true(tested > 350);
        bf_model_free(m);
    }
}

/* Ctint couples the channels: changing base_color[2] alone changes channel 0 through
 * the luminance when specular or sheen is tinted, and not otherwise. */
static void test_channel_coupling(void **state)
{
    (void)state;
    bf_model *m = make(3);
    double x[13], b[3] = {0.4, 0.3, 0.2};
    dp p = shader_defaults;
    p.specular_tint = 1.0;
    p.sheen = 1.0;
    p.sheen_tint = 1.0;
    pack(m, b, &p, x);
    double f0 = ts_eval1(m, x, 50, 0, 30, 120, 0);
    x[2] = 0.9;
    double f1 = ts_eval1(m, x, 50, 0, 30, 120, 0);
    assert_true(f1 < f0); /* larger luminance, smaller tint of channel 0 */
    b[2] = 0.9;
    ts_assert_rel(f1, ref_disney(b, 3, &p, 50, 0, 30, 120, 0), 1e-12, "coupled");
    p.specular_tint = 0.0;
    p.sheen_tint = 0.0;
    pack(m, b, &p, x);
    f0 = ts_eval1(m, x, 50, 0, 30, 120, 0);
    x[2] = 0.1;
    assert_true(ts_eval1(m, x, 50, 0, 30, 120, 0) == f0);

    /* Base colour black: Ctint = 1 (the shader's Cdlum > 0 branch). */
    const double black[3] = {0.0, 0.0, 0.0};
    p.specular_tint = 0.6;
    p.sheen_tint = 0.6;
    pack(m, black, &p, x);
    for (int c = 0; c < 3; c++)
        ts_assert_rel(ts_eval1(m, x, 50, 0, 30, 120, c), ref_disney(black, 3, &p, 50, 0, 30, 120, c), 1e-12, "black");
    bf_model_free(m);
}

static void test_table(void **state)
{
    (void)state;
    bf_model *m = make(3);
    assert_int_equal(bf_model_nparams(m), 11);
    assert_false(bf_model_energy_conserving(m));
    assert_true(bf_model_reciprocal(m));
    for (int i = 0; i < 11; i++) {
        const bf_param_info *pi_ = bf_model_param(m, i);
        assert_true(pi_->lo == 0.0 && pi_->hi == 1.0);
        assert_int_equal(pi_->color, i == 0);
    }
    /* Below the horizon: 0. */
    double x[13];
    bf_model_defaults(m, x);
    assert_true(ts_eval1(m, x, 95, 0, 30, 0, 0) == 0.0);
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table),          cmocka_unit_test(test_normal_incidence),
        cmocka_unit_test(test_mirror),         cmocka_unit_test(test_roughness_floor),
        cmocka_unit_test(test_against_shader), cmocka_unit_test(test_channel_coupling),
    };
    return cmocka_run_group_tests_name("values_disney", tests, NULL, NULL);
}
