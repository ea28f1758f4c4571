/* Values of blender_principled: closed forms at normal incidence, and Cycles 3.4's
 * principled closures (svm closure setup, principled_diffuse, principled_sheen, GGX
 * with interpolate_fresnel_color, GTR1 clearcoat) written out plainly from vectors as
 * Cycles states them (BRDF = closure eval / N.L), at random geometries and parameters.
 * Nothing here is shared with the library. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "support.h"

enum { MAXC = 5, NS = 8 };

/* base_color[C], then these scalars in table order. */
typedef struct bp {
    double base[MAXC];
    double metallic, specular, specular_tint, roughness, sheen, sheen_tint, clearcoat, clearcoat_roughness;
} bp;

static bf_model *make(int C)
{
    bf_error err;
    bf_model *m = NULL;
    if (bf_model_new("blender_principled", C, &m, &err) != BF_OK)
        fail_msg("blender_principled: %s", err.msg);
    return m;
}

static void pack(const bf_model *m, const bp *p, double *x)
{
    static const char *const names[NS] = {"metallic", "specular",   "specular_tint", "roughness",
                                          "sheen",    "sheen_tint", "clearcoat",     "clearcoat_roughness"};
    const double s[NS] = {p->metallic, p->specular,   p->specular_tint, p->roughness,
                          p->sheen,    p->sheen_tint, p->clearcoat,     p->clearcoat_roughness};
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
static double schlick_fresnel(double u)
{
    double m = fmin(fmax(1.0 - u, 0.0), 1.0);
    return m * m * m * m * m;
}
/* Cycles' fresnel_dielectric_cos. */
static double fresnel_dielectric_cos(double cosi, double eta)
{
    double c = fabs(cosi);
    double g = eta * eta - 1.0 + c * c;
    if (g > 0.0) {
        g = sqrt(g);
        double A = (g - c) / (g + c);
        double B = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
        return 0.5 * A * A * (1.0 + B * B);
    }
    return 1.0;
}
static double G1(double alpha2, double cosN)
{
    return 2.0 / (1.0 + sqrt(1.0 + alpha2 * (1.0 - cosN * cosN) / (cosN * cosN)));
}
static double D_GTR1(double NdotH, double alpha)
{
    if (alpha >= 1.0)
        return 1.0 / M_PI;
    double alpha2 = alpha * alpha;
    double t = 1.0 + (alpha2 - 1.0) * NdotH * NdotH;
    return (alpha2 - 1.0) / (M_PI * log(alpha2) * t);
}

/* Channel c; angles in degrees. I = V (outgoing), omega_in = L. */
static double ref_cycles(const bp *p, int C, double ti, double pi_, double to, double po, int c)
{
    double L[3], V[3];
    ts_dirs_deg(ti, pi_, to, po, L, V);
    double cosNI = L[2], cosNO = V[2];
    if (cosNI <= 0.0 || cosNO <= 0.0)
        return 0.0;
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double len = sqrt(dot3(H, H));
    for (int k = 0; k < 3; k++)
        H[k] /= len;
    double lum_s = 0.0, lum_y = 0.0;
    for (int k = 0; k < C; k++) {
        lum_s += (C == 3 ? (k == 0 ? 0.3 : k == 1 ? 0.6 : 0.1) : 1.0 / C) * p->base[k];
        lum_y += (C == 3 ? (k == 0 ? 0.2126729 : k == 1 ? 0.7151522 : 0.0721750) : 1.0 / C) * p->base[k];
    }
    double base = p->base[c];
    double diffuse_weight = 1.0 - p->metallic;

    /* principled_diffuse (FULL): value = NdotL / pi f. */
    double FV = schlick_fresnel(cosNO), FL = schlick_fresnel(cosNI);
    double f = (1.0 - 0.5 * FV) * (1.0 - 0.5 * FL);
    double RR = p->roughness * (dot3(L, V) + 1.0);
    f += RR * (FL + FV + FL * FV * (RR - 1.0));
    double diffuse = base * diffuse_weight * f / M_PI;

    /* principled_sheen: value = schlick_fresnel(L.H) NdotL. */
    double ctint_y = lum_y > 0.0 ? base / lum_y : 1.0;
    double sheen_color = 1.0 - p->sheen_tint + ctint_y * p->sheen_tint;
    double sheen = p->sheen * sheen_color * diffuse_weight * schlick_fresnel(dot3(L, H));

    /* Specular: GGX with the Fresnel interpolated between cspec0 and white. */
    double ctint = lum_s > 0.0 ? base / lum_s : 1.0;
    double tmp_col = 1.0 - p->specular_tint + ctint * p->specular_tint;
    double cspec0 = (p->specular * 0.08 * tmp_col) * (1.0 - p->metallic) + base * p->metallic;
    double ior = 2.0 / (1.0 - sqrt(0.08 * p->specular)) - 1.0;
    double F0 = fresnel_dielectric_cos(1.0, ior);
    double FH = (fresnel_dielectric_cos(dot3(L, H), ior) - F0) / (1.0 - F0);
    double F = cspec0 * (1.0 - FH) + FH;
    double alpha2 = pow(p->roughness, 4.0);
    double cosThetaM2 = H[2] * H[2];
    double tanThetaM2 = (1.0 - cosThetaM2) / cosThetaM2;
    double D = alpha2 / (M_PI * cosThetaM2 * cosThetaM2 * (alpha2 + tanThetaM2) * (alpha2 + tanThetaM2));
    double spec = F * G1(alpha2, cosNO) * G1(alpha2, cosNI) * D * 0.25 / cosNO / cosNI;

    /* Clearcoat: GTR1 of alpha = clearcoat_roughness^2, G with alpha 0.25, Fresnel of ior
     * 1.5 between cspec0 = .04 and white, weighted 0.25 clearcoat. */
    double F0c = fresnel_dielectric_cos(1.0, 1.5);
    double FHc = (fresnel_dielectric_cos(dot3(L, H), 1.5) - F0c) / (1.0 - F0c);
    double Fc = 0.04 * (1.0 - FHc) + FHc;
    double Dc = D_GTR1(H[2], p->clearcoat_roughness * p->clearcoat_roughness);
    double coat = Fc * 0.25 * p->clearcoat * G1(0.0625, cosNO) * G1(0.0625, cosNI) * Dc * 0.25 / cosNO / cosNI;

    return diffuse + sheen + spec + coat;
}

static bp defaults(void)
{
    bp p = {.metallic = 0.0,
            .specular = 0.5,
            .specular_tint = 0.0,
            .roughness = 0.5,
            .sheen = 0.0,
            .sheen_tint = 0.5,
            .clearcoat = 0.0,
            .clearcoat_roughness = 0.03};
    for (int c = 0; c < MAXC; c++)
        p.base[c] = 0.8;
    return p;
}

/* L = V = N: FL = FV = FH = 0, Fd = 1, the Fresnel weight 0 (Fs = cspec0),
 * S = 1/(4 pi a^2), coat = .25 clearcoat .04 (b^2 - 1)/(pi ln(b^2) b^2) / 4. */
static void test_normal_incidence(void **state)
{
    (void)state;
    bf_model *m = make(3);
    double x[3 + NS], xd[3 + NS];
    bp p = defaults();
    pack(m, &p, x);
    bf_model_defaults(m, xd);
    for (int k = 0; k < 3 + NS; k++)
        assert_true(xd[k] == x[k]);
    /* Blender's defaults: .8/pi + .04/(4 pi .0625) = .96/pi. */
    for (int c = 0; c < 3; c++)
        ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, c), 0.96 / M_PI, 1e-13, "defaults");

    /* A metal: base_color S; the sheen goes with the diffuse. */
    p.metallic = 1.0;
    p.sheen = 1.0;
    p.base[0] = 0.9, p.base[1] = 0.5, p.base[2] = 0.2;
    pack(m, &p, x);
    for (int c = 0; c < 3; c++)
        ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, c), p.base[c] / (4.0 * M_PI * 0.0625), 1e-13, "metal");

    /* Specular tint 1: cspec0 = .04 base / (.3 R + .6 G + .1 B). */
    p = defaults();
    p.specular_tint = 1.0;
    p.base[0] = 0.9, p.base[1] = 0.5, p.base[2] = 0.2;
    pack(m, &p, x);
    double lum = 0.3 * 0.9 + 0.6 * 0.5 + 0.1 * 0.2;
    for (int c = 0; c < 3; c++)
        ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, c), p.base[c] / M_PI + 0.04 * p.base[c] / lum * 4.0 / M_PI, 1e-13,
                      "tint");

    /* Clear coat 1 of roughness .5 (b = .25, b^2 = .0625). */
    p = defaults();
    p.clearcoat = 1.0;
    p.clearcoat_roughness = 0.5;
    pack(m, &p, x);
    double b2 = 0.0625, Dc = (b2 - 1.0) / (M_PI * log(b2) * b2);
    ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, 1), 0.96 / M_PI + 0.25 * 0.04 * Dc * 0.25, 1e-13, "coat");
    /* Clear coat roughness 1: GTR1 is flat, 1/pi. */
    p.clearcoat_roughness = 1.0;
    pack(m, &p, x);
    ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, 1), 0.96 / M_PI + 0.25 * 0.04 / M_PI * 0.25, 1e-13, "flat coat");
    bf_model_free(m);
}

/* Random parameters for the comparison, packed into x. */
static void draw(ts_rng *r, const bf_model *m, double *x, void *ctx)
{
    bp *p = ctx;
    for (int c = 0; c < bf_model_channels(m); c++)
        p->base[c] = ts_uniform(r);
    p->metallic = ts_uniform_ends(r), p->specular = ts_uniform_ends(r), p->specular_tint = ts_uniform_ends(r);
    /* Roughness from .05: below that the peak is a near-delta whose value the rounding
     * of N.H decides; the coat's GTR1 is well conditioned down to the bound. */
    p->roughness = 0.05 + 0.95 * ts_uniform(r);
    p->sheen = ts_uniform_ends(r), p->sheen_tint = ts_uniform_ends(r), p->clearcoat = ts_uniform_ends(r);
    p->clearcoat_roughness = 0.018 + 0.982 * ts_uniform(r);
    pack(m, p, x);
}

static double ref(const void *ctx, int C, double ti, double pi_, double to, double po, int c)
{
    return ref_cycles(ctx, C, ti, pi_, to, po, c);
}

/* Cycles' formulas at random geometries and parameters. */
static void test_against_cycles(void **state)
{
    (void)state;
    bp p;
    ts_compare_reference("blender_principled", 0xC0FFEE1234ULL, draw, ref, &p, 1e-9);
}

/* The sheen tint uses the Rec. 709 luminance, not the specular tint's .3/.6/.1. */
static void test_sheen_luminance(void **state)
{
    (void)state;
    bf_model *m = make(3);
    double x[3 + NS];
    bp p = defaults();
    p.specular = 0.0;
    p.sheen = 1.0;
    p.sheen_tint = 1.0;
    p.base[0] = 0.0, p.base[1] = 0.0, p.base[2] = 0.5;
    pack(m, &p, x);
    /* Mirror at 60 degrees: FL = FV = FH = 1/32; sheen on blue = FH / .0721750. */
    double F = 1.0 / 32.0;
    double lv1 = 2.0 * 0.25; /* 1 + L.V with L.V = cos 120 */
    double Fd = (1.0 - 0.5 * F) * (1.0 - 0.5 * F) + 0.5 * lv1 * (2.0 * F + F * F * (0.5 * lv1 - 1.0));
    ts_assert_rel(ts_eval1(m, x, 60, 0, 60, 180, 2), 0.5 / M_PI * Fd + F / 0.0721750, 1e-12, "sheen blue");
    assert_true(ts_eval1(m, x, 60, 0, 60, 180, 0) == 0.0); /* red: no base, tinted sheen 0 */
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_normal_incidence),
        cmocka_unit_test(test_against_cycles),
        cmocka_unit_test(test_sheen_luminance),
    };
    return cmocka_run_group_tests_name("values_blender_principled", tests, NULL, NULL);
}
