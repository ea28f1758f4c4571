/* Values of student_t (Ribardiere et al. 2017) against the docs/models.md formula written
 * out plainly from the angles, with the Smith Lambda by quadrature of its defining
 * integral (nothing shared with the library's continued fraction); the closed form at
 * normal incidence; gamma = 2 against walter (GGX with Smith-GGX) to rounding; gamma = 1e6
 * against Beckmann with its exact Smith term and against microfacet's Beckmann preset; D
 * normalised; the masking consistent with D (Heitz's weak white furnace). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "support.h"

/* ---- The formula, plainly ---------------------------------------------------------- */

/* D(theta_h) = 1 / (pi alpha^2 cos^4 (1 + tan^2 / ((gamma - 1) alpha^2))^gamma). */
static double ref_d(double cos_h, double alpha, double gamma)
{
    double c2 = cos_h * cos_h, t2 = (1.0 - c2) / c2;
    return 1.0 / (M_PI * alpha * alpha * c2 * c2 * pow(1.0 + t2 / ((gamma - 1.0) * alpha * alpha), gamma));
}

/* The marginal density of one slope component over alpha, P2(q) = Gamma(gamma - 1/2) /
 * (sqrt(pi (gamma - 1)) Gamma(gamma - 1)) (1 + q^2/(gamma - 1))^(1/2 - gamma). */
static double ref_p2(double q, double gamma)
{
    double k = exp(lgamma(gamma - 0.5) - lgamma(gamma - 1.0)) / sqrt(M_PI * (gamma - 1.0));
    return k * pow(1.0 + q * q / (gamma - 1.0), 0.5 - gamma);
}

/* Lambda(z) = (1/z) int_z^inf (q - z) P2(q) dq: the q P2 part in closed form,
 * (gamma - 1)/(2 gamma - 3) (1 + z^2/(gamma - 1))^(3/2 - gamma) times P2's constant; the
 * tail int_z^inf P2 by the trapezoidal rule in s, q = z + e^s (smooth, decaying at both
 * ends, where the rule converges geometrically). */
static double ref_lambda(double z, double gamma)
{
    double k = exp(lgamma(gamma - 0.5) - lgamma(gamma - 1.0)) / sqrt(M_PI * (gamma - 1.0));
    double first = k * (gamma - 1.0) / (2.0 * gamma - 3.0) * pow(1.0 + z * z / (gamma - 1.0), 1.5 - gamma) / z;
    const double h = 0.02;
    double tail = 0.0;
    for (double s = -45.0; s <= 80.0; s += h) {
        double e = exp(s);
        tail += e * ref_p2(z + e, gamma);
    }
    return first - tail * h;
}

static double ref_g1(const double W[3], double alpha, double gamma)
{
    double s = sqrt(W[0] * W[0] + W[1] * W[1]);
    if (s == 0.0)
        return 1.0;
    return 1.0 / (1.0 + ref_lambda(W[2] / (alpha * s), gamma));
}

typedef struct params {
    double rd, rs, alpha, gamma, f0;
} params;

/* f = rho_d/pi + rho_s D G1(L) G1(V) F / (4 NL NV), F Schlick's with f0. */
static double ref_f(const params *p, double ti, double pi_, double to, double po)
{
    double L[3], V[3];
    ts_dirs_deg(ti, pi_, to, po, L, V);
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double n = sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
    double vh = (V[0] * H[0] + V[1] * H[1] + V[2] * H[2]) / n;
    double F = p->f0 + (1.0 - p->f0) * pow(1.0 - vh, 5.0);
    double G = ref_g1(L, p->alpha, p->gamma) * ref_g1(V, p->alpha, p->gamma);
    return p->rd / M_PI + p->rs * ref_d(H[2] / n, p->alpha, p->gamma) * G * F / (4.0 * L[2] * V[2]);
}

static void set_x(const bf_model *m, double *x, const params *p)
{
    int C = bf_model_channels(m);
    for (int c = 0; c < C; c++) {
        x[c] = p->rd;
        x[C + c] = p->rs;
    }
    x[2 * C] = p->alpha;
    x[2 * C + 1] = p->gamma;
    x[2 * C + 2] = p->f0;
}

/* ---- Tests ----------------------------------------------------------------------- */

static void test_table(void **state)
{
    (void)state;
    bf_model *m = ts_model("student_t", 3);
    const char *names[] = {"rho_d", "rho_s", "alpha", "gamma", "f0"};
    assert_int_equal(bf_model_nparams(m), 5);
    for (int i = 0; i < 5; i++)
        assert_string_equal(bf_model_param(m, i)->name, names[i]);
    const bf_param_info *a = bf_model_param(m, 2), *g = bf_model_param(m, 3);
    assert_true(a->lo == 1e-4 && a->hi == 1.0 && a->scale == BF_SCALE_LOG);
    assert_true(g->lo == 1.51 && g->hi == 1e6 && g->def == 2.0 && g->scale == BF_SCALE_LOG);
    assert_int_equal(bf_model_energy_conserving(m), 1);
    assert_string_equal(bf_model_spec(m), "student_t:fresnel=schlick,lobes=1");
    bf_model_free(m);
    m = ts_model("student_t:fresnel=dielectric", 1);
    assert_string_equal(bf_model_param(m, 4)->name, "ior");
    bf_model_free(m);
    m = ts_model("student_t:fresnel=none", 1);
    assert_int_equal(bf_model_nparams(m), 4);
    bf_model_free(m);
}

/* L = V = N: H = N, tan = 0, so D = 1/(pi alpha^2), G = 1, F = f0 whatever gamma:
 * f = rho_d/pi + rho_s f0 / (4 pi alpha^2). */
static void test_normal(void **state)
{
    (void)state;
    bf_model *m = ts_model("student_t", 1);
    double gam[] = {1.51, 2.0, 7.5, 1e6};
    for (int k = 0; k < 4; k++) {
        params p = {0.25, 0.8, 0.3, gam[k], 0.05};
        double x[5];
        set_x(m, x, &p);
        double want = 0.25 / M_PI + 0.8 * 0.05 / (4.0 * M_PI * 0.09);
        ts_assert_rel(ts_eval1(m, x, 0.0, 0.0, 0.0, 0.0, 0), want, 1e-14, "student_t at normal incidence");
    }
    bf_model_free(m);
}

/* The library against the plain formula at random parameters and directions. */
static void test_random(void **state)
{
    (void)state;
    ts_rng r = {0x5747D15742ULL};
    bf_model *m = ts_model("student_t", 1);
    for (int k = 0; k < 150; k++) {
        params p = {ts_uniform(&r), ts_uniform(&r), 0.02 * pow(50.0, ts_uniform(&r)),
                    1.51 + pow(10.0, 4.0 * ts_uniform(&r) - 1.0), ts_uniform(&r)};
        double x[5];
        set_x(m, x, &p);
        double ti, pi_, to, po;
        ts_random_pair_deg(&r, k % 3 == 0, &ti, &pi_, &to, &po);
        ts_assert_rel(ts_eval1(m, x, ti, pi_, to, po, 0), ref_f(&p, ti, pi_, to, po), 1e-10, "student_t random");
    }
    bf_model_free(m);
}

/* The quadrature Lambda against a hand-checked closed form: at gamma = 3 the tail
 * integrals are elementary. */
static void test_lambda_gamma3(void **state)
{
    (void)state;
    /* With u = q / sqrt 2: P2 dq = (3/4) (1 + u^2)^(-5/2) du, int_w^inf (1 + u^2)^(-5/2) du
     * = 2/3 - w (2 w^2 + 3) / (3 (1 + w^2)^(3/2)), int_w^inf u (1 + u^2)^(-5/2) du =
     * (1 + w^2)^(-3/2) / 3, and Lambda(z) = (sqrt 2 * first - z * tail) / z, w = z/sqrt 2. */
    double zs[] = {0.05, 0.5, 1.0, 2.0, 6.0};
    for (int i = 0; i < 5; i++) {
        double z = zs[i], w = z / sqrt(2.0), s = 1.0 + w * w;
        double tail = 0.75 * (2.0 / 3.0 - w * (2.0 * w * w + 3.0) / (3.0 * pow(s, 1.5)));
        double first = 0.75 * sqrt(2.0) * pow(s, -1.5) / 3.0;
        ts_assert_rel(ref_lambda(z, 3.0), (first - z * tail) / z, 1e-11, "Lambda at gamma 3");
    }
}

/* gamma = 2 is GGX with Smith-GGX: f equals walter's to rounding, for every Fresnel. */
static void test_ggx(void **state)
{
    (void)state;
    const char *fs[] = {"schlick", "dielectric", "none"};
    ts_rng r = {0x66A2ULL};
    for (int f = 0; f < 3; f++) {
        char a[64], b[64];
        snprintf(a, sizeof a, "student_t:fresnel=%s", fs[f]);
        snprintf(b, sizeof b, "walter:fresnel=%s", fs[f]);
        bf_model *ms = ts_model(a, 1), *mw = ts_model(b, 1);
        for (int k = 0; k < 300; k++) {
            double alpha = 1e-3 * pow(1e3, ts_uniform(&r)), fp = f == 1 ? 1.0 + 2.0 * ts_uniform(&r) : ts_uniform(&r);
            double xs[5] = {0.3, 0.7, alpha, 2.0, fp}, xw[4] = {0.3, 0.7, alpha, fp};
            double ti, pi_, to, po;
            ts_random_pair_deg(&r, k % 2 == 0, &ti, &pi_, &to, &po);
            ts_assert_rel(ts_eval1(ms, xs, ti, pi_, to, po, 0), ts_eval1(mw, xw, ti, pi_, to, po, 0), 1e-13,
                          "student_t at gamma 2 against walter");
        }
        bf_model_free(ms);
        bf_model_free(mw);
    }
}

/* Exact Smith-Beckmann Lambda = (exp(-z^2)/(z sqrt pi) - erfc z) / 2. */
static double beckmann_g1(const double W[3], double m)
{
    double s = sqrt(W[0] * W[0] + W[1] * W[1]);
    if (s == 0.0)
        return 1.0;
    double z = W[2] / (m * s);
    return 1.0 / (1.0 + 0.5 * (exp(-z * z) / (z * sqrt(M_PI)) - erfc(z)));
}

/* gamma = 1e6: D is Beckmann's and G its exact Smith term to within 3e-4 relative: what
 * remains is gamma log(1 + u/(gamma - 1)) against u, (u + u^2/2)/gamma <= 2.2e-4 for
 * u = tan^2/alpha^2 <= 20 (D above e^-20 of its peak), and G's O(1/gamma). Against
 * microfacet D=beckmann,G=smith_beckmann, whose G is Walter's rational fit of that term,
 * to the fit's accuracy: 0.58 % at worst here (two G1 of 0.3 % each), printed below. */
static void test_beckmann(void **state)
{
    (void)state;
    bf_model *ms = ts_model("student_t:fresnel=none", 1);
    bf_model *mb = ts_model("microfacet:D=beckmann,G=smith_beckmann,F=none", 1);
    ts_rng r = {0xBEC4ULL};
    double worst_exact = 0.0, worst_fit = 0.0;
    for (int k = 0; k < 400; k++) {
        double m = 0.03 * pow(30.0, ts_uniform(&r));
        double xs[4] = {0.0, 1.0, m, 1e6}, xb[3] = {0.0, 1.0, m};
        double ti, pi_, to, po, L[3], V[3];
        ts_random_pair_deg(&r, k % 2 == 0, &ti, &pi_, &to, &po);
        ts_dirs_deg(ti, pi_, to, po, L, V);
        double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
        double n = sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
        double ch = H[2] / n, t2 = (1.0 - ch * ch) / (ch * ch);
        if (t2 / (m * m) > 20.0) /* D < e^-20 of its peak: the O(u^2/gamma) term grows */
            continue;
        double Db = exp(-t2 / (m * m)) / (M_PI * m * m * pow(ch, 4.0));
        double want = Db * beckmann_g1(L, m) * beckmann_g1(V, m) / (4.0 * L[2] * V[2]);
        double got = ts_eval1(ms, xs, ti, pi_, to, po, 0);
        ts_assert_rel(got, want, 3e-4, "student_t at gamma 1e6 against exact Beckmann");
        double fit = ts_eval1(mb, xb, ti, pi_, to, po, 0);
        ts_assert_rel(got, fit, 1e-2, "student_t at gamma 1e6 against microfacet's Beckmann");
        worst_exact = fmax(worst_exact, fabs(got - want) / want);
        worst_fit = fmax(worst_fit, fabs(got - fit) / fit);
    }
    printf("gamma 1e6: worst relative difference %.3g from exact Beckmann, %.3g from microfacet's\n", worst_exact,
           worst_fit);
    bf_model_free(ms);
    bf_model_free(mb);
}

/* int D(h) cos(theta_h) dh = 1 over the hemisphere, by the trapezoidal rule in
 * s = log(tan(theta_h)/alpha) (smooth, and it reaches the heavy tails of gamma near 3/2). */
static void test_normalised(void **state)
{
    (void)state;
    double al[] = {0.05, 0.3, 1.0}, ga[] = {1.6, 2.0, 5.0, 100.0, 1e4};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 5; j++) {
            const double h = 0.01;
            double sum = 0.0;
            for (double s = -40.0; s <= 120.0; s += h) {
                /* cos and sin from t, not through atan: cos(atan(t)) is wrong past t = 1e15 */
                double t = al[i] * exp(s), c = 1.0 / sqrt(1.0 + t * t), dth = t / (1.0 + t * t);
                sum += ref_d(c, al[i], ga[j]) * c * (t * c) * 2.0 * M_PI * dth;
            }
            ts_assert_rel(sum * h, 1.0, 1e-9, "integral of D cos");
        }
}

/* The masking belongs to D: int D(m) G1(V) <V.m>+ dm = NV (Heitz 2014, the weak white
 * furnace), by quadrature over the microfacet normals, with G1 = 1/(1 + Lambda) from the
 * quadrature Lambda, which test_random ties to the library. */
static void test_white_furnace(void **state)
{
    (void)state;
    double ga[] = {1.6, 2.0, 4.0, 50.0}, th[] = {20.0, 60.0, 85.0};
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 3; j++) {
            const double alpha = 0.5;
            double V[3] = {sin(th[j] * DEG), 0.0, cos(th[j] * DEG)};
            double g1 = ref_g1(V, alpha, ga[i]);
            /* Over theta_m in s = log(tan/alpha); over phi_m in closed form: with V.m =
             * A cos(phi) + B, int_0^2pi max(0, V.m) dphi = 2 (B p + A sin p), p = acos(-B/A). */
            const double h = 0.01;
            double sum = 0.0;
            for (double s = -30.0; s <= 80.0; s += h) {
                double t = alpha * exp(s), c = 1.0 / sqrt(1.0 + t * t), dth = t / (1.0 + t * t);
                double A = V[0] * t * c, B = V[2] * c;
                double p = B >= A ? M_PI : acos(-B / A);
                double ring = 2.0 * (B * p + A * sin(p));
                sum += ref_d(c, alpha, ga[i]) * ring * t * c * dth;
            }
            /* 5e-7: the trapezoidal rule across the kink where the ring starts to dip below V's horizon */
            ts_assert_rel(sum * h * g1, V[2], 5e-7, "weak white furnace");
        }
}

/* Large gamma through z^2 ~ 1.5, where the incomplete beta changes sides and its fraction
 * needs ~sqrt(gamma) terms whose convergents shrink below the smallest double (they once
 * underflowed to an infinite fraction and a NaN gradient at gamma = 1e6, z = 1.32): values
 * against the plain formula, gradients finite, on a fine sweep of theta_i. */
static void test_large_gamma_transition(void **state)
{
    (void)state;
    bf_model *m = ts_model("student_t", 1);
    enum { N = 4000 };
    double ti[N], pi_[N], to[N], po[N];
    const double alpha = 0.15, gam[] = {3e3, 3e5, 1e6};
    for (int i = 0; i < N; i++) { /* z = 1 / (alpha tan(theta_i)) from 1.0 to 1.6 */
        ti[i] = atan(1.0 / (alpha * (1.0 + 0.6 * i / (N - 1)))) / DEG;
        pi_[i] = 0.0, to[i] = 10.0, po[i] = 180.0;
    }
    bf_geometry *g = ts_geometry_deg(N, ti, pi_, to, po);
    static double val[N], grad[N * 5]; /* 190 kB: off the stack */
    for (int k = 0; k < 3; k++) {
        params p = {0.1, 0.9, alpha, gam[k], 0.04};
        double x[5];
        set_x(m, x, &p);
        bf_model_eval(m, x, g, val, grad);
        for (int i = 0; i < N; i++) {
            for (int j = 0; j < 5; j++)
                if (!isfinite(grad[i * 5 + j]))
                    fail_msg("gamma %g, theta_i %.9g: gradient %d is %g", gam[k], ti[i], j, grad[i * 5 + j]);
            if (i % 250 == 0)
                ts_assert_rel(val[i], ref_f(&p, ti[i], pi_[i], to[i], po[i]), 1e-10, "student_t at large gamma");
        }
    }
    bf_geometry_free(g);
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table),
        cmocka_unit_test(test_normal),
        cmocka_unit_test(test_random),
        cmocka_unit_test(test_lambda_gamma3),
        cmocka_unit_test(test_ggx),
        cmocka_unit_test(test_beckmann),
        cmocka_unit_test(test_normalised),
        cmocka_unit_test(test_white_furnace),
        cmocka_unit_test(test_large_gamma_transition),
    };
    return cmocka_run_group_tests_name("values_student_t", tests, NULL, NULL);
}
