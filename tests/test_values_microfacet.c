/* Values of the microfacet family (microfacet, cook_torrance, walter) and walter_aniso:
 * closed forms at normal incidence, the dielectric Fresnel against the Fresnel
 * equations, an independent plain re-implementation of the docs/models.md formulas from the
 * angles for every D x G x F combination, presets against the equivalent microfacet
 * options, finiteness at cos = 2e-15, and the energy-conservation flags (with the
 * albedo > 1 that makes the unflagged ones so). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "models/terms.h"
#include "support.h"

static const char *const Ds[] = {"ggx", "beckmann", "blinn", "gaussian"};
static const char *const Gs[] = {"smith_ggx", "implicit", "cook_torrance", "smith_beckmann", "smith_schlick", "none"};
static const char *const Fs[] = {"schlick", "dielectric", "none"};
enum { ND = 4, NG = 6, NF = 3 };

/* Sets parameter `name` (all channels of a colour parameter to v). */
static void set(const bf_model *m, double *x, const char *name, double v)
{
    int i = bf_model_find_param(m, name);
    if (i < 0)
        fail_msg("%s has no parameter %s", bf_model_spec(m), name);
    int n = bf_model_param(m, i)->color ? bf_model_channels(m) : 1;
    for (int c = 0; c < n; c++)
        x[bf_model_param_offset(m, i) + c] = v;
}

static void set_c(const bf_model *m, double *x, const char *name, int c, double v)
{
    int i = bf_model_find_param(m, name);
    if (i < 0 || !bf_model_param(m, i)->color)
        fail_msg("%s has no colour parameter %s", bf_model_spec(m), name);
    x[bf_model_param_offset(m, i) + c] = v;
}

/* ---- Parameter tables ------------------------------------------------------------ */

static void expect_names(const char *spec, const char *const *names, int n)
{
    bf_model *m = ts_model(spec, 1);
    if (bf_model_nparams(m) != n)
        fail_msg("%s: %d parameters, want %d", spec, bf_model_nparams(m), n);
    for (int i = 0; i < n; i++)
        if (strcmp(bf_model_param(m, i)->name, names[i]) != 0)
            fail_msg("%s: parameter %d is %s, want %s", spec, i, bf_model_param(m, i)->name, names[i]);
    bf_model_free(m);
}

static void test_parameter_tables(void **state)
{
    (void)state;
    const char *ct[] = {"rho_d", "rho_s", "m", "f0"};
    expect_names("cook_torrance", ct, 4);
    const char *ctd[] = {"rho_d", "rho_s", "m", "ior"};
    expect_names("cook_torrance:fresnel=dielectric", ctd, 4);
    const char *ctn[] = {"rho_d", "rho_s", "m"};
    expect_names("cook_torrance:fresnel=none", ctn, 3);
    const char *wa[] = {"rho_d", "rho_s", "alpha", "f0"};
    expect_names("walter", wa, 4);
    const char *wa2[] = {"rho_d", "rho_s_1", "alpha_1", "f0_1", "rho_s_2", "alpha_2", "f0_2"};
    expect_names("walter:lobes=2", wa2, 7);
    const char *an[] = {"rho_d", "rho_s", "alpha_x", "alpha_y", "f0"};
    expect_names("walter_aniso", an, 5);
    const char *bl[] = {"rho_d", "rho_s", "n", "ior"};
    expect_names("microfacet:D=blinn,F=dielectric", bl, 4);
    const char *ga[] = {"rho_d", "rho_s", "m"};
    expect_names("microfacet:D=gaussian,G=none,F=none", ga, 3);

    /* Defaults are D=ggx, G=smith_ggx, F=schlick, the canonical spec lists them all. */
    bf_model *m = ts_model("microfacet", 3);
    assert_string_equal(bf_model_spec(m), "microfacet:D=ggx,G=smith_ggx,F=schlick,lobes=1");
    assert_int_equal(bf_model_nvalues(m), 3 + 3 + 1 + 1);
    bf_model_free(m);

    /* Bounds and scales. */
    struct {
        const char *spec, *name;
        double lo, hi;
        bf_scale scale;
    } b[] = {
        {"microfacet:D=blinn", "n", 0.0, 1e6, BF_SCALE_LOG1P},
        {"microfacet:D=beckmann", "m", 1e-3, 1.0, BF_SCALE_LOG},
        {"microfacet:D=ggx", "alpha", 1e-4, 1.0, BF_SCALE_LOG},
        {"microfacet:D=gaussian", "m", 1e-3, 1.0, BF_SCALE_LOG},
        {"microfacet:F=dielectric", "ior", 1.0, 100.0, BF_SCALE_LOG},
        {"microfacet", "f0", 0.0, 1.0, BF_SCALE_LINEAR},
        {"cook_torrance", "m", 1e-3, 1.0, BF_SCALE_LOG},
        {"walter", "alpha", 1e-4, 1.0, BF_SCALE_LOG},
        {"walter_aniso", "alpha_x", 1e-4, 1.0, BF_SCALE_LOG},
        {"walter_aniso", "alpha_y", 1e-4, 1.0, BF_SCALE_LOG},
        {"walter_aniso", "f0", 0.0, 1.0, BF_SCALE_LINEAR},
    };
    for (size_t i = 0; i < sizeof b / sizeof b[0]; i++) {
        m = ts_model(b[i].spec, 1);
        const bf_param_info *p = bf_model_param(m, bf_model_find_param(m, b[i].name));
        assert_non_null(p);
        if (p->lo != b[i].lo || p->hi != b[i].hi || p->scale != b[i].scale || p->color || p->lo_open || p->hi_open)
            fail_msg("%s %s: [%g, %g] scale %d", b[i].spec, b[i].name, p->lo, p->hi, p->scale);
        bf_model_free(m);
    }
    /* Family info: only walter_aniso is anisotropic; the microfacet family takes lobes. */
    int seen = 0;
    for (int f = 0; f < bf_family_count(); f++) {
        const bf_family_info *fi = bf_family_get(f);
        int is_aniso = strcmp(fi->name, "walter_aniso") == 0;
        if (is_aniso || strcmp(fi->name, "walter") == 0 || strcmp(fi->name, "cook_torrance") == 0 ||
            strcmp(fi->name, "microfacet") == 0) {
            seen++;
            assert_int_equal(fi->anisotropic, is_aniso);
            assert_int_equal(fi->lobes, !is_aniso);
        }
    }
    assert_int_equal(seen, 4);
}

/* ---- Closed forms at normal incidence (L = V = N: NH = VH = 1, G = 1, F = f0) ------- */

static void test_cook_torrance_normal(void **state)
{
    (void)state;
    const double ms[] = {1e-3, 0.05, 0.3, 1.0}, f0s[] = {0.0, 0.04, 0.7, 1.0};
    bf_model *m = ts_model("cook_torrance", 3);
    double x[3 + 3 + 2];
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 4; b++) {
            for (int c = 0; c < 3; c++) {
                set_c(m, x, "rho_d", c, 0.1 + 0.2 * c);
                set_c(m, x, "rho_s", c, 0.9 - 0.3 * c);
            }
            set(m, x, "m", ms[a]);
            set(m, x, "f0", f0s[b]);
            for (int c = 0; c < 3; c++) {
                double want = (0.1 + 0.2 * c) / M_PI + (0.9 - 0.3 * c) * f0s[b] / (4.0 * M_PI * ms[a] * ms[a]);
                ts_assert_rel(ts_eval1(m, x, 0.0, 0.0, 0.0, 0.0, c), want, 1e-14, "cook_torrance N");
                /* Any azimuth at theta = 0 is the same direction. */
                ts_assert_rel(ts_eval1(m, x, 0.0, 37.0, 0.0, 211.0, c), want, 1e-14, "cook_torrance N, phi");
            }
        }
    bf_model_free(m);
}

/* Ngan et al. 2005's Cook-Torrance as bsdfbenchmark/bbm evaluates it, written out from
 * the angles: s D G F / (pi NL NV) with D = exp(-tan^2/m^2) / (pi m^2 NH^4), the V-groove
 * G and Schlick's F of f0 (bbm's eta). cook_torrance is rho_s D G F / (4 NL NV), so
 * rho_s = 4 s / pi reproduces it. */
static double ngan_ct_ref(double kd, double s, double m, double f0, double ti, double pi_, double to, double po)
{
    double a = ti * DEG, b = pi_ * DEG, c = to * DEG, d = po * DEG;
    double L[3] = {sin(a) * cos(b), sin(a) * sin(b), cos(a)};
    double V[3] = {sin(c) * cos(d), sin(c) * sin(d), cos(c)};
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double len = sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
    for (int k = 0; k < 3; k++)
        H[k] /= len;
    double nl = L[2], nv = V[2], nh = H[2], vh = V[0] * H[0] + V[1] * H[1] + V[2] * H[2];
    double t2 = (H[0] * H[0] + H[1] * H[1]) / (nh * nh);
    double D = exp(-t2 / (m * m)) / (M_PI * m * m * pow(nh, 4.0));
    double G = fmin(1.0, fmin(2.0 * nh * nv / vh, 2.0 * nh * nl / vh));
    double F = f0 + (1.0 - f0) * pow(1.0 - vh, 5.0);
    return kd / M_PI + s * D * G * F / (M_PI * nl * nv);
}

/* One published fit: Ngan et al. 2005 as published in bsdfbenchmark/bbm
 * fits/ngan_cooktorrance.fit (blue-acrylic: albedo [0.0291, 0.0193, 0.0118], eta 0.117,
 * roughness 0.0137), through rho_s = 4 albedo / pi; the digits are from
 * tests/published/ref_ngancooktorrance.py, an independent implementation. Also random
 * directions against the formula above, masking (G < 1) included. */
static void test_ngan_published(void **state)
{
    (void)state;
    bf_model *m = ts_model("cook_torrance", 3);
    const double kd[3] = {0.0143, 0.033, 0.0639}, s[3] = {0.0291, 0.0193, 0.0118};
    const double want[3] = {2.418143644150379, 1.611271304821881, 0.99904733474363272};
    double x[8];
    for (int c = 0; c < 3; c++) {
        set_c(m, x, "rho_d", c, kd[c]);
        set_c(m, x, "rho_s", c, 4.0 * s[c] / M_PI);
    }
    set(m, x, "m", 0.0137);
    set(m, x, "f0", 0.117);
    for (int c = 0; c < 3; c++)
        ts_assert_rel(ts_eval1(m, x, 30.0, 10.0, 30.2, 190.1, c), want[c], 1e-11, "Ngan C-T blue-acrylic");
    /* A rough fit at grazing angles, where the V-groove masks. */
    set(m, x, "m", 0.4);
    ts_rng r = {0xC0C0A5A5F00DBEEFULL};
    int masked = 0;
    for (int k = 0; k < 200; k++) {
        double ti = 89.0 * ts_uniform(&r), pi_ = 360.0 * ts_uniform(&r);
        double to = 89.0 * ts_uniform(&r), po = 360.0 * ts_uniform(&r);
        masked += ti > 70.0 || to > 70.0;
        for (int c = 0; c < 3; c++)
            ts_assert_rel(ts_eval1(m, x, ti, pi_, to, po, c), ngan_ct_ref(kd[c], s[c], 0.4, 0.117, ti, pi_, to, po),
                          1e-12, "Ngan C-T formula");
    }
    assert_true(masked > 20);
    bf_model_free(m);
}

static void test_walter_normal(void **state)
{
    (void)state;
    const double as[] = {1e-4, 0.02, 0.25, 1.0}, f0s[] = {0.0, 0.04, 1.0};
    bf_model *m = ts_model("walter", 1);
    bf_model *an = ts_model("walter_aniso", 1);
    double x[4], y[5];
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 3; b++) {
            set(m, x, "rho_d", 0.25);
            set(m, x, "rho_s", 0.75);
            set(m, x, "alpha", as[a]);
            set(m, x, "f0", f0s[b]);
            double want = 0.25 / M_PI + 0.75 * f0s[b] / (4.0 * M_PI * as[a] * as[a]);
            ts_assert_rel(ts_eval1(m, x, 0.0, 0.0, 0.0, 0.0, 0), want, 1e-14, "walter N");
            /* walter_aniso: D(N) = 1/(pi ax ay) */
            double ay = as[(a + 1) % 4];
            set(an, y, "rho_d", 0.25);
            set(an, y, "rho_s", 0.75);
            set(an, y, "alpha_x", as[a]);
            set(an, y, "alpha_y", ay);
            set(an, y, "f0", f0s[b]);
            want = 0.25 / M_PI + 0.75 * f0s[b] / (4.0 * M_PI * as[a] * ay);
            ts_assert_rel(ts_eval1(an, y, 0.0, 0.0, 0.0, 0.0, 0), want, 1e-14, "walter_aniso N");
        }
    bf_model_free(m);
    bf_model_free(an);
}

/* ---- Fresnel ---------------------------------------------------------------------- */

static void test_dielectric_fresnel(void **state)
{
    (void)state;
    /* ((n-1)/(n+1))^2 = 0.04 for n = 1.5 at normal incidence. */
    ts_assert_rel(bf_dielectric(1.0, 1.5, NULL), 0.04, 1e-15, "F(0 deg, 1.5)");
    /* The Cook-Torrance form is the unpolarised Fresnel reflectance: (rs^2 + rp^2)/2. */
    const double ns[] = {1.0001, 1.2, 1.5, 2.4, 3.0};
    for (int a = 0; a < 5; a++)
        for (int k = 0; k <= 20; k++) {
            double ci = k == 0 ? 1e-3 : k / 20.0, n = ns[a];
            double ct = sqrt(1.0 - (1.0 - ci * ci) / (n * n));
            double rs = (ci - n * ct) / (ci + n * ct), rp = (n * ci - ct) / (n * ci + ct);
            double want = 0.5 * (rs * rs + rp * rp);
            ts_assert_rel(bf_dielectric(ci, n, NULL), want, 1e-11, "dielectric vs Fresnel equations");
        }
    /* Through the model at normal incidence: f = rho_s 0.04 / (4 pi m^2). */
    bf_model *m = ts_model("cook_torrance:fresnel=dielectric", 1);
    double x[4];
    set(m, x, "rho_d", 0.0);
    set(m, x, "rho_s", 1.0);
    set(m, x, "m", 0.2);
    set(m, x, "ior", 1.5);
    ts_assert_rel(ts_eval1(m, x, 0.0, 0.0, 0.0, 0.0, 0), 0.04 / (4.0 * M_PI * 0.04), 1e-14,
                  "cook_torrance dielectric N");
    /* ior = 1: no reflection at all. */
    set(m, x, "ior", 1.0);
    assert_true(ts_eval1(m, x, 40.0, 10.0, 35.0, 200.0, 0) == 0.0);
    bf_model_free(m);
}

/* ---- Independent re-implementation from the angles ------------------------------- */

typedef struct ref_geo {
    double nl, nv, sl, sv;  /* cos, sin of theta_i, theta_o (from the angles) */
    double pl, pv;          /* phi_i, phi_o */
    double nh, th, phh, vh; /* cos theta_h, theta_h, phi_h, cos theta_d */
} ref_geo;

static ref_geo ref_geometry(double ti, double pi_, double to, double po)
{
    ref_geo r;
    ti *= DEG, pi_ *= DEG, to *= DEG, po *= DEG;
    double L[3] = {sin(ti) * cos(pi_), sin(ti) * sin(pi_), cos(ti)};
    double V[3] = {sin(to) * cos(po), sin(to) * sin(po), cos(to)};
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double len = sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
    for (int k = 0; k < 3; k++)
        H[k] /= len;
    r.nl = cos(ti), r.nv = cos(to), r.sl = sin(ti), r.sv = sin(to), r.pl = pi_, r.pv = po;
    r.nh = H[2];
    r.th = atan2(hypot(H[0], H[1]), H[2]);
    r.phh = atan2(H[1], H[0]);
    r.vh = 0.5 * len; /* |L + V| = 2 cos(theta_d) */
    return r;
}

static double ref_D(int d, double r, const ref_geo *g)
{
    double t2 = tan(g->th) * tan(g->th), c = g->nh;
    switch (d) {
    case 0: /* GGX a^2 / (pi (NH^2 (a^2 - 1) + 1)^2) */ return r * r / (M_PI * pow(c * c * (r * r - 1.0) + 1.0, 2));
    case 1: /* Beckmann */ return exp(-t2 / (r * r)) / (M_PI * r * r * pow(c, 4));
    case 2: /* normalised Blinn */ return (r + 2.0) / (2.0 * M_PI) * pow(c, r);
    default: /* Gaussian highlight */ return exp(-pow(g->th / r, 2)) / (M_PI * r * r);
    }
}

static double ref_G1(int gk, double m, double cosw, double sinw)
{
    switch (gk) {
    case 0: return 2.0 / (1.0 + sqrt(1.0 + m * m * pow(sinw / cosw, 2)));
    case 3: {
        double c = cosw / (m * sinw);
        return c < 1.6 ? (3.535 * c + 2.181 * c * c) / (1.0 + 2.276 * c + 2.577 * c * c) : 1.0;
    }
    default: { /* 4: Schlick */ double k = m * sqrt(2.0 / M_PI); return cosw / (cosw * (1.0 - k) + k);
    }
    }
}

static double ref_G(int gk, int d, double r, const ref_geo *g)
{
    double m = d == 2 ? sqrt(2.0 / (r + 2.0)) : r; /* blinn: Beckmann-equivalent m */
    switch (gk) {
    case 1: return g->nl * g->nv;
    case 2: return fmin(1.0, fmin(2.0 * g->nh * g->nv / g->vh, 2.0 * g->nh * g->nl / g->vh));
    case 5: return 1.0;
    default: return ref_G1(gk, m, g->nl, g->sl) * ref_G1(gk, m, g->nv, g->sv);
    }
}

static double ref_F(int f, double p, double c)
{
    if (f == 0)
        return p + (1.0 - p) * pow(1.0 - c, 5);
    if (f == 1) {
        double gg = sqrt(p * p + c * c - 1.0);
        return 0.5 * pow(gg - c, 2) / pow(gg + c, 2) * (1.0 + pow(c * (gg + c) - 1.0, 2) / pow(c * (gg - c) + 1.0, 2));
    }
    return 1.0;
}

static void test_microfacet_reference(void **state)
{
    (void)state;
    ts_rng rng = {0x51A7E5EEDULL};
    const char *rname[] = {"alpha", "m", "n", "m"};
    const char *fname[] = {"f0", "ior", NULL};
    int compared = 0;
    for (int d = 0; d < ND; d++)
        for (int gk = 0; gk < NG; gk++)
            for (int f = 0; f < NF; f++)
                for (int K = 1; K <= 2; K++) {
                    char spec[128];
                    snprintf(spec, sizeof spec, "microfacet:D=%s,G=%s,F=%s,lobes=%d", Ds[d], Gs[gk], Fs[f], K);
                    bf_model *m = ts_model(spec, 2);
                    double x[2 + 2 * (2 + 2)];
                    double rho_s[2][2], rough[2], fp[2];
                    for (int t = 0; t < 40; t++) {
                        /* channel 0: specular only; channel 1: diffuse + specular */
                        set_c(m, x, "rho_d", 0, 0.0);
                        set_c(m, x, "rho_d", 1, 0.3);
                        for (int k = 0; k < K; k++) {
                            char nm[32];
                            double mm = 0.05 * pow(16.0, ts_uniform(&rng)); /* 0.05 .. 0.8 */
                            rough[k] = d == 2 ? 2.0 / (mm * mm) - 2.0 : mm;
                            fp[k] = f == 0 ? ts_uniform(&rng) : 1.0 + 2.0 * ts_uniform(&rng);
                            rho_s[k][0] = 1.0 / K;
                            rho_s[k][1] = 0.6 * ts_uniform(&rng) / K;
                            snprintf(nm, sizeof nm, K > 1 ? "rho_s_%d" : "rho_s", k + 1);
                            set_c(m, x, nm, 0, rho_s[k][0]);
                            set_c(m, x, nm, 1, rho_s[k][1]);
                            snprintf(nm, sizeof nm, K > 1 ? "%s_%d" : "%s", rname[d], k + 1);
                            set(m, x, nm, rough[k]);
                            if (fname[f]) {
                                snprintf(nm, sizeof nm, K > 1 ? "%s_%d" : "%s", fname[f], k + 1);
                                set(m, x, nm, fp[k]);
                            }
                        }
                        /* A geometry at least 3 degrees off the mirror direction, so the
                         * plain 1 - NH^2 of the GGX form keeps 1e-13 accuracy. */
                        double ti, pi_, to, po;
                        ref_geo g;
                        do {
                            ti = 85.0 * ts_uniform(&rng), pi_ = 360.0 * ts_uniform(&rng);
                            to = 85.0 * ts_uniform(&rng), po = 360.0 * ts_uniform(&rng);
                            if (t % 2) { /* within 20 degrees of the mirror direction */
                                to = fmin(85.0, fabs(ti + 20.0 * (ts_uniform(&rng) - 0.5)));
                                po = pi_ + 180.0 + 40.0 * (ts_uniform(&rng) - 0.5);
                            }
                            g = ref_geometry(ti, pi_, to, po);
                        } while (g.th < 3.0 * DEG);
                        for (int c = 0; c < 2; c++) {
                            double want = (c ? 0.3 : 0.0) / M_PI;
                            for (int k = 0; k < K; k++)
                                want += rho_s[k][c] * ref_D(d, rough[k], &g) * ref_G(gk, d, rough[k], &g) *
                                        ref_F(f, fp[k], g.vh) / (4.0 * g.nl * g.nv);
                            double got = ts_eval1(m, x, ti, pi_, to, po, c);
                            if (!(fabs(got - want) <= 1e-12 * fabs(want) + 1e-300))
                                fail_msg("%s channel %d at (%g, %g, %g, %g): %.17g, reference %.17g", spec, c, ti, pi_,
                                         to, po, got, want);
                            compared += want > 0.0;
                        }
                    }
                    bf_model_free(m);
                }
    assert_true(compared > ND * NG * NF * 2 * 40); /* most references are nonzero */
}

/* walter_aniso against docs/models.md's form with tan(theta_h) and phi_h, and the projected
 * roughness alpha_w^2 = cos^2(phi_w) ax^2 + sin^2(phi_w) ay^2 of each direction. */
static void test_walter_aniso_reference(void **state)
{
    (void)state;
    ts_rng rng = {0xA2150ULL};
    bf_model *m = ts_model("walter_aniso", 1);
    double x[5];
    for (int t = 0; t < 400; t++) {
        double ax = 0.03 * pow(30.0, ts_uniform(&rng)), ay = 0.03 * pow(30.0, ts_uniform(&rng));
        double f0 = ts_uniform(&rng), rd = 0.5 * ts_uniform(&rng);
        set(m, x, "rho_d", rd);
        set(m, x, "rho_s", 0.8);
        set(m, x, "alpha_x", ax);
        set(m, x, "alpha_y", ay);
        set(m, x, "f0", f0);
        double ti, pi_, to, po;
        ref_geo g;
        do {
            ti = 85.0 * ts_uniform(&rng), pi_ = 360.0 * ts_uniform(&rng);
            to = 85.0 * ts_uniform(&rng), po = 360.0 * ts_uniform(&rng);
            g = ref_geometry(ti, pi_, to, po);
        } while (g.th < 1.0 * DEG);
        double t2 = pow(tan(g.th), 2);
        double D = 1.0 / (M_PI * ax * ay * pow(g.nh, 4) *
                          pow(1.0 + t2 * (pow(cos(g.phh) / ax, 2) + pow(sin(g.phh) / ay, 2)), 2));
        double al = sqrt(pow(cos(g.pl) * ax, 2) + pow(sin(g.pl) * ay, 2));
        double av = sqrt(pow(cos(g.pv) * ax, 2) + pow(sin(g.pv) * ay, 2));
        double G = ref_G1(0, al, g.nl, g.sl) * ref_G1(0, av, g.nv, g.sv);
        double want = rd / M_PI + 0.8 * D * G * ref_F(0, f0, g.vh) / (4.0 * g.nl * g.nv);
        ts_assert_rel(ts_eval1(m, x, ti, pi_, to, po, 0), want, 1e-12, "walter_aniso reference");
    }
    /* Anisotropy has the right orientation: with ax > ay the highlight is wider along X,
     * so tilting H towards X costs less than tilting it towards Y. */
    set(m, x, "rho_d", 0.0);
    set(m, x, "f0", 1.0);
    set(m, x, "alpha_x", 0.4);
    set(m, x, "alpha_y", 0.1);
    double along_x = ts_eval1(m, x, 40.0, 180.0, 20.0, 0.0, 0);  /* H tilted in the XZ plane */
    double along_y = ts_eval1(m, x, 40.0, 270.0, 20.0, 90.0, 0); /* same, in the YZ plane */
    assert_true(along_x > 3.0 * along_y);
    bf_model_free(m);
}

/* walter_aniso with ax = ay is walter (separate code paths). */
static void test_walter_aniso_isotropic(void **state)
{
    (void)state;
    ts_rng rng = {0x150ULL};
    bf_model *w = ts_model("walter", 2), *an = ts_model("walter_aniso", 2);
    double x[2 + 2 + 2], y[2 + 2 + 3];
    double ti[64], pi_[64], to[64], po[64];
    ts_random_dirs(&rng, 64, ti, pi_, to, po);
    bf_geometry *g = NULL;
    bf_geometry_from_angles(64, ti, pi_, to, po, &g, NULL);
    for (int t = 0; t < 10; t++) {
        ts_random_params(w, &rng, TS_PARAMS_ANY, x);
        /* same rho_d, rho_s (2 channels each), alpha, f0 */
        memcpy(y, x, 5 * sizeof *x);
        y[5] = x[4];
        y[6] = x[5];
        double *a = ts_eval(w, x, g), *b = ts_eval(an, y, g);
        for (int i = 0; i < 128; i++)
            ts_assert_rel(b[i], a[i], 1e-12, "walter_aniso(ax = ay) vs walter");
        free(a);
        free(b);
    }
    bf_geometry_free(g);
    bf_model_free(w);
    bf_model_free(an);
}

/* ---- Presets ------------------------------------------------------------------------ */

static void compare_specs(const char *s1, const char *s2)
{
    enum { N = 300 };
    for (int C = 1; C <= 3; C += 2) {
        bf_model *a = ts_model(s1, C), *b = ts_model(s2, C);
        int P = bf_model_nvalues(a);
        assert_int_equal(P, bf_model_nvalues(b));
        assert_int_equal(bf_model_nparams(a), bf_model_nparams(b));
        for (int i = 0; i < bf_model_nparams(a); i++) {
            const bf_param_info *p = bf_model_param(a, i), *q = bf_model_param(b, i);
            assert_string_equal(p->name, q->name);
            assert_true(p->lo == q->lo && p->hi == q->hi && p->def == q->def && p->scale == q->scale &&
                        p->color == q->color);
        }
        assert_int_equal(bf_model_energy_conserving(a), bf_model_energy_conserving(b));
        ts_rng rng = {0xC0FFEEULL + (uint64_t)C};
        double ti[N], pi_[N], to[N], po[N];
        ts_random_dirs(&rng, N, ti, pi_, to, po);
        bf_geometry *g = NULL;
        bf_geometry_from_angles(N, ti, pi_, to, po, &g, NULL);
        double *x = malloc((size_t)P * sizeof *x);
        size_t nv = (size_t)N * (size_t)C;
        double *va = malloc(nv * sizeof *va), *vb = malloc(nv * sizeof *vb);
        double *ga = malloc(nv * (size_t)P * sizeof *ga), *gb = malloc(nv * (size_t)P * sizeof *gb);
        for (int t = 0; t < 6; t++) {
            ts_random_params(a, &rng, TS_PARAMS_ANY, x);
            bf_model_eval(a, x, g, va, ga);
            bf_model_eval(b, x, g, vb, gb);
            for (size_t i = 0; i < nv; i++) {
                ts_assert_rel(va[i], vb[i], 1e-14, s1);
                for (int k = 0; k < P; k++)
                    ts_assert_rel(ga[i * (size_t)P + (size_t)k], gb[i * (size_t)P + (size_t)k], 1e-14, s1);
            }
        }
        free(x);
        free(va);
        free(vb);
        free(ga);
        free(gb);
        bf_geometry_free(g);
        bf_model_free(a);
        bf_model_free(b);
    }
}

static void test_presets(void **state)
{
    (void)state;
    for (int f = 0; f < NF; f++)
        for (int K = 1; K <= 3; K++) {
            char p[128], q[128];
            snprintf(p, sizeof p, "cook_torrance:fresnel=%s,lobes=%d", Fs[f], K);
            snprintf(q, sizeof q, "microfacet:D=beckmann,G=cook_torrance,F=%s,lobes=%d", Fs[f], K);
            compare_specs(p, q);
            snprintf(p, sizeof p, "walter:fresnel=%s,lobes=%d", Fs[f], K);
            snprintf(q, sizeof q, "microfacet:D=ggx,G=smith_ggx,F=%s,lobes=%d", Fs[f], K);
            compare_specs(p, q);
        }
    /* The default preset is Schlick. */
    bf_model *m = ts_model("cook_torrance", 1);
    assert_string_equal(bf_model_option(m, "fresnel"), "schlick");
    bf_model_free(m);
}

/* ---- Numerics at the smallest cosine above the horizon ------------------------------ */

static void check_grazing(const char *spec)
{
    /* L at cos = 2e-15 (the geometry takes cosines below 1e-15 as the horizon) against
     * V: opposite (H = N), equal (NH = 2e-15), sideways, normal, and also grazing. */
    const double e = 2e-15;
    const double Ls[][3] = {{1, 0, e}, {1, 0, e}, {1, 0, e}, {1, 0, e}, {1, 0, e}, {0, 0, 1}, {0.6, 0.8, e}, {1, 0, e}};
    const double Vs[][3] = {{-1, 0, e},   {1, 0, e}, {0, 1, e},        {0, 0, 1},
                            {-1, 0, 0.3}, {1, 0, e}, {0.6, 0.8, 1e-9}, {-0.6, 0.8, e}};
    enum { N = sizeof Ls / sizeof Ls[0] };
    bf_geometry *g = NULL;
    bf_geometry_from_vectors(N, &Ls[0][0], &Vs[0][0], &g, NULL);
    for (int C = 1; C <= 2; C++) {
        bf_model *m = ts_model(spec, C);
        int P = bf_model_nvalues(m), np = bf_model_nparams(m);
        double *x = malloc((size_t)P * sizeof *x);
        double *v = malloc((size_t)N * C * sizeof *v), *gr = malloc((size_t)N * C * P * sizeof *gr);
        ts_rng rng = {0xE17ULL};
        for (int t = 0; t < 12; t++) {
            if (t < 2) {
                for (int i = 0; i < np; i++) {
                    const bf_param_info *p = bf_model_param(m, i);
                    for (int c = 0; c < (p->color ? C : 1); c++)
                        x[bf_model_param_offset(m, i) + c] = t ? p->hi : p->lo;
                }
            } else {
                ts_random_params(m, &rng, TS_PARAMS_ANY, x);
            }
            bf_model_eval(m, x, g, v, gr);
            for (int i = 0; i < N * C; i++) {
                if (!isfinite(v[i]) || v[i] < 0.0)
                    fail_msg("%s: value %g at grazing sample %d", spec, v[i], i / C);
                for (int k = 0; k < P; k++)
                    if (!isfinite(gr[(size_t)i * P + k]))
                        fail_msg("%s: gradient slot %d = %g at grazing sample %d", spec, k, gr[(size_t)i * P + k],
                                 i / C);
            }
        }
        free(x);
        free(v);
        free(gr);
        bf_model_free(m);
    }
    bf_geometry_free(g);
}

static void test_grazing(void **state)
{
    (void)state;
    char spec[128];
    for (int d = 0; d < ND; d++)
        for (int gk = 0; gk < NG; gk++)
            for (int f = 0; f < NF; f++) {
                snprintf(spec, sizeof spec, "microfacet:D=%s,G=%s,F=%s,lobes=2", Ds[d], Gs[gk], Fs[f]);
                check_grazing(spec);
            }
    check_grazing("walter_aniso");
}

/* ---- Energy conservation flags -------------------------------------------------------- */

/* Directional albedo of the specular lobe alone (rho_d = 0, rho_s = 1, F = none) by
 * quadrature over the half vector: albedo = int f(L, V(h)) NV 4 (L.h) d omega_h, with
 * tan(theta_h) = w u/(1-u) (w: the lobe width), midpoint in u and phi_h over [0, pi]
 * (L in the XZ plane, the integrand is symmetric in phi_h). */
static double spec_albedo(const char *spec, double rough, double w, double ti_deg)
{
    enum { NT = 600, NP = 180 };
    size_t n = (size_t)NT * NP;
    double *L = malloc(3 * n * sizeof *L), *V = malloc(3 * n * sizeof *V);
    double *wt = malloc(n * sizeof *wt), *f = malloc(n * sizeof *f);
    double ti = ti_deg * DEG, l[3] = {sin(ti), 0.0, cos(ti)};
    size_t k = 0;
    for (int a = 0; a < NT; a++) {
        double u = (a + 0.5) / NT;
        double t = w * u / (1.0 - u), dth = w / ((1.0 - u) * (1.0 - u)) / (1.0 + t * t) / NT;
        double th = atan(t);
        for (int b = 0; b < NP; b++, k++) {
            double ph = (b + 0.5) * M_PI / NP;
            double h[3] = {sin(th) * cos(ph), sin(th) * sin(ph), cos(th)};
            double lh = l[0] * h[0] + l[1] * h[1] + l[2] * h[2];
            for (int c = 0; c < 3; c++) {
                L[3 * k + c] = l[c];
                V[3 * k + c] = 2.0 * lh * h[c] - l[c];
            }
            wt[k] = lh > 0.0 && V[3 * k + 2] > 0.0 ? 2.0 * V[3 * k + 2] * 4.0 * lh * sin(th) * dth * (M_PI / NP) : 0.0;
            if (wt[k] == 0.0) { /* below the horizon: any valid vector, weight 0 */
                V[3 * k] = 0.0, V[3 * k + 1] = 0.0, V[3 * k + 2] = 1.0;
            }
        }
    }
    bf_geometry *g = NULL;
    bf_geometry_from_vectors(n, L, V, &g, NULL);
    bf_model *m = ts_model(spec, 1);
    double x[3] = {0.0, 1.0, rough};
    bf_model_eval(m, x, g, f, NULL);
    double s = 0.0;
    for (size_t i = 0; i < n; i++)
        s += f[i] * wt[i];
    bf_model_free(m);
    bf_geometry_free(g);
    free(L);
    free(V);
    free(wt);
    free(f);
    return s;
}

static void test_energy_flags(void **state)
{
    (void)state;
    /* Which D x G combinations are energy conserving (F never changes it: F <= 1). */
    static const int ec[ND][NG] = {
        /* smith_ggx implicit cook_torrance smith_beckmann smith_schlick none */
        {1, 0, 1, 0, 1, 0}, /* ggx */
        {1, 0, 1, 1, 1, 0}, /* beckmann */
        {1, 0, 1, 0, 1, 0}, /* blinn */
        {1, 0, 1, 1, 1, 0}, /* gaussian */
    };
    char spec[128];
    for (int d = 0; d < ND; d++)
        for (int gk = 0; gk < NG; gk++)
            for (int f = 0; f < NF; f++) {
                snprintf(spec, sizeof spec, "microfacet:D=%s,G=%s,F=%s", Ds[d], Gs[gk], Fs[f]);
                bf_model *m = ts_model(spec, 1);
                if (bf_model_energy_conserving(m) != ec[d][gk])
                    fail_msg("%s: energy_conserving = %d", spec, bf_model_energy_conserving(m));
                bf_model_free(m);
            }
    const char *yes[] = {"cook_torrance", "walter", "walter_aniso"};
    for (int i = 0; i < 3; i++) {
        bf_model *m = ts_model(yes[i], 1);
        assert_int_equal(bf_model_energy_conserving(m), 1);
        bf_model_free(m);
    }

    /* The quadrature itself: matched GGX/Smith-GGX is 1 at normal incidence for a smooth
     * surface (up to the G1 deficit) and below 1 at grazing. */
    double a0 = spec_albedo("microfacet:D=ggx,G=smith_ggx,F=none", 0.05, 0.05, 0.0);
    assert_true(a0 > 0.995 && a0 <= 1.0 + 1e-4);
    /* The unflagged ones exceed 1: no masking, or a Smith term derived for a lighter-tailed
     * NDF than the D it is paired with. */
    double a1 = spec_albedo("microfacet:D=ggx,G=none,F=none", 0.3, 0.3, 80.0);
    double a2 = spec_albedo("microfacet:D=ggx,G=smith_beckmann,F=none", 0.1, 0.1, 89.0);
    double a3 = spec_albedo("microfacet:D=blinn,G=smith_beckmann,F=none", 0.0, 1.0, 89.0);
    print_message("albedo: ggx/none %.4f, ggx/smith_beckmann %.4f, blinn(n=0)/smith_beckmann %.4f\n", a1, a2, a3);
    assert_true(a1 > 1.1);
    assert_true(a2 > 1.1);
    assert_true(a3 > 1.1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parameter_tables),
        cmocka_unit_test(test_cook_torrance_normal),
        cmocka_unit_test(test_walter_normal),
        cmocka_unit_test(test_dielectric_fresnel),
        cmocka_unit_test(test_microfacet_reference),
        cmocka_unit_test(test_walter_aniso_reference),
        cmocka_unit_test(test_walter_aniso_isotropic),
        cmocka_unit_test(test_presets),
        cmocka_unit_test(test_grazing),
        cmocka_unit_test(test_energy_flags),
        cmocka_unit_test(test_ngan_published),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
