/* Normalisation of the normal distributions in terms.h: integral over the hemisphere of
 * D(h) cos(theta_h) d omega_h = 1 (to 1e-10) for Beckmann, GGX and normalised Blinn at
 * roughness values down to their lower bounds; the Gaussian highlight is not normalised,
 * and its integral is checked against its series 1 - 2m^2/3 + 4m^4/15 instead. The roughness
 * derivative of each NDF must integrate to the derivative of the normalisation (0).
 *
 * Quadrature: with t = tan(theta_h), d omega cos = 2 pi t/(1+t^2)^2 dt; t = w u/(1-u)
 * maps u in [0, 1) onto [0, inf) with w the lobe width, so a lobe of any width spans the
 * whole u interval; composite 8-point Gauss-Legendre in u. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>

#include <cmocka.h>

#include "models/terms.h"
#include "support.h"

enum { NDF_GGX, NDF_BECKMANN, NDF_BLINN, NDF_GAUSSIAN };

static double ndf(int kind, double t, double r, double *dD)
{
    double c2 = 1.0 / (1.0 + t * t);
    double nh = sqrt(c2), s2 = t * t * c2;
    switch (kind) {
    case NDF_GGX: return bf_d_ggx(nh, s2, r, dD);
    case NDF_BECKMANN: return bf_d_beckmann(nh, s2, r, dD);
    case NDF_BLINN: return bf_d_blinn(nh, s2, r, dD);
    default: return bf_d_gaussian(nh, s2, r, dD);
    }
}

/* Integral of D cos and of |dD/dr| cos and dD/dr cos over the hemisphere. */
static void integrate(int kind, double r, double *I, double *dI, double *dIabs)
{
    static const double x8[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
    static const double w8[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
    /* Lobe width in tan(theta_h): m for Beckmann/Gaussian, alpha for GGX, the Beckmann
     * equivalent sqrt(2/(n+2)) for Blinn. */
    double w = kind == NDF_BLINN ? sqrt(2.0 / (r + 2.0)) : r;
    const int N = 1000;
    double s = 0.0, ds = 0.0, dsa = 0.0;
    for (int p = 0; p < N; p++) {
        double a = (double)p / N, b = (double)(p + 1) / N, mid = 0.5 * (a + b), half = 0.5 * (b - a);
        for (int q = 0; q < 8; q++) {
            double u = mid + (q < 4 ? -1.0 : 1.0) * half * x8[q % 4];
            double wq = half * w8[q % 4];
            double t = w * u / (1.0 - u), dt = w / ((1.0 - u) * (1.0 - u));
            double c2 = 1.0 / (1.0 + t * t);
            double jac = 2.0 * M_PI * t * c2 * c2 * dt;
            double dD;
            double D = ndf(kind, t, r, &dD);
            s += wq * D * jac;
            ds += wq * dD * jac;
            dsa += wq * fabs(dD) * jac;
        }
    }
    *I = s;
    *dI = ds;
    *dIabs = dsa;
}

static void check_normalised(int kind, const char *name, const double *rs, int n)
{
    for (int i = 0; i < n; i++) {
        double I, dI, dIabs;
        integrate(kind, rs[i], &I, &dI, &dIabs);
        if (!(fabs(I - 1.0) < 1e-10))
            fail_msg("%s(%g): integral of D cos = %.12f, not 1", name, rs[i], I);
        if (!(fabs(dI) < 1e-9 * dIabs))
            fail_msg("%s(%g): integral of dD/dr cos = %.6g (scale %.6g), not 0", name, rs[i], dI, dIabs);
    }
}

static void test_ggx(void **state)
{
    (void)state;
    const double a[] = {1e-4, 1e-3, 0.01, 0.05, 0.1, 0.3, 0.5, 0.8, 1.0};
    check_normalised(NDF_GGX, "ggx", a, sizeof a / sizeof a[0]);
}

static void test_beckmann(void **state)
{
    (void)state;
    const double m[] = {1e-3, 0.01, 0.05, 0.1, 0.3, 0.5, 0.8, 1.0};
    check_normalised(NDF_BECKMANN, "beckmann", m, sizeof m / sizeof m[0]);
}

static void test_blinn(void **state)
{
    (void)state;
    const double n[] = {0.0, 0.5, 1.0, 10.0, 100.0, 1e3, 1e4, 1e5, 1e6};
    check_normalised(NDF_BLINN, "blinn", n, sizeof n / sizeof n[0]);
}

/* exp(-(theta/m)^2)/(pi m^2) integrates to (1/m^2) int_0^{pi/2} exp(-theta^2/m^2)
 * sin(2 theta) d theta = 1 - 2m^2/3 + 4m^4/15 - ... < 1: not normalised (the mass lost
 * grows with m). Checked against the series for small m and against a plain quadrature
 * in theta for all m; printed for the report. */
static void test_gaussian(void **state)
{
    (void)state;
    const double m[] = {1e-3, 0.01, 0.03, 0.05, 0.1, 0.3, 0.5, 1.0};
    for (size_t i = 0; i < sizeof m / sizeof m[0]; i++) {
        double I, dI, dIabs;
        integrate(NDF_GAUSSIAN, m[i], &I, &dI, &dIabs);
        /* Independent: Simpson in theta over [0, min(pi/2, 12 m)] (the rest is < e^-144). */
        double top = fmin(M_PI / 2.0, 12.0 * m[i]);
        const int N = 200000;
        double h = top / N, s = 0.0;
        for (int k = 0; k <= N; k++) {
            double th = k * h;
            double f = exp(-(th / m[i]) * (th / m[i])) * sin(2.0 * th);
            s += f * (k == 0 || k == N ? 1.0 : (k % 2 ? 4.0 : 2.0));
        }
        double ref = s * h / 3.0 / (m[i] * m[i]);
        print_message("gaussian m=%g: integral of D cos = %.10f\n", m[i], I);
        if (!(fabs(I - ref) < 1e-8))
            fail_msg("gaussian(%g): %.12f by tan substitution, %.12f by Simpson", m[i], I, ref);
        assert_true(I < 1.0);
        if (m[i] <= 0.05) {
            double m2 = m[i] * m[i];
            double series = 1.0 - 2.0 * m2 / 3.0 + 4.0 * m2 * m2 / 15.0;
            if (!(fabs(I - series) < 1e-6))
                fail_msg("gaussian(%g): %.12f, series %.12f", m[i], I, series);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ggx),
        cmocka_unit_test(test_beckmann),
        cmocka_unit_test(test_blinn),
        cmocka_unit_test(test_gaussian),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
