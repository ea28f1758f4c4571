/* Values of the glTF metallic-roughness model: closed forms at normal incidence, and
 * the specification's appendix B (with KHR_materials_specular and KHR_materials_ior)
 * written out as the specification states it, from vectors, at random geometries and
 * parameters. Nothing here is shared with the library. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "support.h"

enum { MAXC = 5 };

typedef struct gp {
    double base[MAXC], metallic, roughness, specular, specular_color[MAXC], ior;
} gp;

static bf_model *make(int C)
{
    bf_error err;
    bf_model *m = NULL;
    if (bf_model_new("gltf", C, &m, &err) != BF_OK)
        fail_msg("gltf: %s", err.msg);
    return m;
}

/* Layout: base_color[C], metallic, roughness, specular, specular_color[C], ior. */
static void pack(const bf_model *m, const gp *p, double *x)
{
    int C = bf_model_channels(m);
    assert_int_equal(bf_model_nvalues(m), 2 * C + 4);
    assert_int_equal(bf_model_param_offset(m, bf_model_find_param(m, "specular_color")), C + 3);
    assert_int_equal(bf_model_param_offset(m, bf_model_find_param(m, "ior")), 2 * C + 3);
    for (int c = 0; c < C; c++) {
        x[c] = p->base[c];
        x[C + 3 + c] = p->specular_color[c];
    }
    x[C] = p->metallic;
    x[C + 1] = p->roughness;
    x[C + 2] = p->specular;
    x[2 * C + 3] = p->ior;
}

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* Appendix B: D_GGX with the Heaviside factor, the separable Smith visibility written
 * as G / (4 |N.L| |N.V|) with G1 = 2 N.X / (N.X + sqrt(a^2 + (1 - a^2) (N.X)^2)). */
static double specular_brdf(double alpha, double NL, double NV, double NH)
{
    double a2 = alpha * alpha;
    double den = NH * NH * (a2 - 1.0) + 1.0;
    double D = NH > 0.0 ? a2 / (M_PI * den * den) : 0.0;
    double G1L = 2.0 * NL / (NL + sqrt(a2 + (1.0 - a2) * NL * NL));
    double G1V = 2.0 * NV / (NV + sqrt(a2 + (1.0 - a2) * NV * NV));
    return G1L * G1V / (4.0 * NL * NV) * D;
}

/* Channel c of the material, angles in degrees. */
static double ref_gltf(const gp *p, int C, double ti, double pi_, double to, double po, int c)
{
    double L[3], V[3];
    ts_dirs_deg(ti, pi_, to, po, L, V);
    double NL = L[2], NV = V[2];
    if (NL <= 0.0 || NV <= 0.0)
        return 0.0;
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double len = sqrt(dot3(H, H));
    for (int k = 0; k < 3; k++)
        H[k] /= len;
    double NH = H[2], VH = fabs(dot3(V, H));
    double alpha = p->roughness * p->roughness;
    double spec = specular_brdf(alpha, NL, NV, NH);
    double fw = pow(1.0 - VH, 5.0);

    /* metal_brdf = specular_brdf * conductor_fresnel(f0 = baseColor). */
    double metal = spec * (p->base[c] + (1.0 - p->base[c]) * fw);

    /* dielectric_f0 = min(((ior - 1)/(ior + 1))^2 specularColor, 1) specular,
     * dielectric_f90 = specular, the base weighted by 1 - max over the channels. */
    double Fmax = 0.0, fc = 0.0;
    for (int k = 0; k < C; k++) {
        double f0 = fmin(pow((p->ior - 1.0) / (p->ior + 1.0), 2.0) * p->specular_color[k], 1.0) * p->specular;
        double F = f0 + (p->specular - f0) * fw;
        Fmax = k == 0 ? F : fmax(Fmax, F);
        if (k == c)
            fc = F;
    }
    double dielectric = fc * spec + (1.0 - Fmax) * p->base[c] / M_PI;
    return (1.0 - p->metallic) * dielectric + p->metallic * metal;
}

static gp defaults(void)
{
    gp p = {.metallic = 0.0, .roughness = 0.5, .specular = 1.0, .ior = 1.5};
    for (int c = 0; c < MAXC; c++) {
        p.base[c] = 0.5;
        p.specular_color[c] = 1.0;
    }
    return p;
}

/* L = V = N: w = 0, D = 1/(pi a^2), G1 = 1, so S = 1/(4 pi a^2). */
static void test_normal_incidence(void **state)
{
    (void)state;
    bf_model *m = make(3);
    double x[10], xd[10];
    gp p = defaults();
    pack(m, &p, x);
    /* The library's defaults are glTF's, with base colour .5. */
    bf_model_defaults(m, xd);
    for (int k = 0; k < 10; k++)
        assert_true(xd[k] == x[k]);
    /* F0 = .04: .04 / (4 pi .0625) + .96 * .5 / pi = .64 / pi. */
    for (int c = 0; c < 3; c++)
        ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, c), 0.64 / M_PI, 1e-14, "defaults");

    /* A metal: base_color S per channel. */
    p.metallic = 1.0;
    p.base[0] = 0.9, p.base[1] = 0.6, p.base[2] = 0.3;
    pack(m, &p, x);
    for (int c = 0; c < 3; c++)
        ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, c), p.base[c] / (4.0 * M_PI * 0.0625), 1e-14, "metal");

    /* specular 0: a Lambertian base alone. */
    p = defaults();
    p.specular = 0.0;
    pack(m, &p, x);
    ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, 1), 0.5 / M_PI, 1e-14, "specular 0");

    /* A red specular colour: F0 = (.04 * 5, .04, .04); the base loses the largest, .2. */
    p = defaults();
    p.specular_color[0] = 5.0;
    pack(m, &p, x);
    ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, 0), 0.2 * 4.0 / M_PI + 0.8 * 0.5 / M_PI, 1e-14, "red F0");
    ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, 1), 0.04 * 4.0 / M_PI + 0.8 * 0.5 / M_PI, 1e-14, "red F0 g");

    /* ior 3: F0 = .25; specular_color 10 clamps F0 at 1, leaving no diffuse. */
    p = defaults();
    p.ior = 3.0;
    pack(m, &p, x);
    ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, 2), 0.25 * 4.0 / M_PI + 0.75 * 0.5 / M_PI, 1e-14, "ior 3");
    for (int c = 0; c < 3; c++)
        p.specular_color[c] = 10.0;
    pack(m, &p, x);
    ts_assert_rel(ts_eval1(m, x, 0, 0, 0, 0, 2), 4.0 / M_PI, 1e-14, "clamped");
    bf_model_free(m);
}

/* Random parameters for the comparison, packed into x. */
static void draw(ts_rng *r, const bf_model *m, double *x, void *ctx)
{
    gp *p = ctx;
    for (int c = 0; c < bf_model_channels(m); c++) {
        p->base[c] = ts_uniform(r);
        p->specular_color[c] = ts_uniform(r) < 0.1 ? 25.0 * ts_uniform(r) : 2.0 * ts_uniform(r);
    }
    p->metallic = ts_uniform_ends(r);
    /* Roughness from .05: below that the peak is a near-delta whose value is set by the
     * rounding of N.H (checked at the mirror by test_normal_incidence). */
    p->roughness = 0.05 + 0.95 * ts_uniform(r);
    p->specular = ts_uniform(r);
    p->ior = 1.0 + 2.0 * ts_uniform(r);
    pack(m, p, x);
}

static double ref(const void *ctx, int C, double ti, double pi_, double to, double po, int c)
{
    return ref_gltf(ctx, C, ti, pi_, to, po, c);
}

/* The specification written out at random geometries and parameters. */
static void test_against_spec(void **state)
{
    (void)state;
    gp p;
    ts_compare_reference("gltf", 0x9E3779B97F4A7C15ULL, draw, ref, &p, 1e-9);
}

/* The max over channels couples them: raising specular_color of channel 2 past the
 * others takes diffuse from channel 0. */
static void test_channel_coupling(void **state)
{
    (void)state;
    bf_model *m = make(3);
    double x[10];
    gp p = defaults();
    pack(m, &p, x);
    double f0 = ts_eval1(m, x, 40, 0, 30, 150, 0);
    p.specular_color[2] = 3.0;
    pack(m, &p, x);
    double f1 = ts_eval1(m, x, 40, 0, 30, 150, 0);
    assert_true(f1 < f0);
    ts_assert_rel(f1, ref_gltf(&p, 3, 40, 0, 30, 150, 0), 1e-12, "coupled");
    /* Below the horizon: 0. */
    assert_true(ts_eval1(m, x, 95, 0, 30, 0, 0) == 0.0);
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_normal_incidence),
        cmocka_unit_test(test_against_spec),
        cmocka_unit_test(test_channel_coupling),
    };
    return cmocka_run_group_tests_name("values_gltf", tests, NULL, NULL);
}
