/* Energy: directional albedo by quadrature stays <= 1 for every model configuration
 * that declares itself energy conserving, whenever its colour parameters sum to <= 1. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>

#include <cmocka.h>

#include "support.h"

enum { NU = 160, NPHI = 320, TRIALS = 3 };
static const double incident_deg[] = {0.0, 30.0, 60.0, 80.0, 89.0};
enum { NINC = sizeof incident_deg / sizeof incident_deg[0] };

/* Midpoint rule in (u = cos theta_o, phi_o): albedo = integral f u du dphi. Geometry
 * for all incident angles at once. */
static bf_geometry *quadrature_geometry(void)
{
    size_t n = (size_t)NINC * NU * NPHI;
    double *a = malloc(4 * n * sizeof *a);
    size_t k = 0;
    for (int j = 0; j < NINC; j++)
        for (int iu = 0; iu < NU; iu++)
            for (int ip = 0; ip < NPHI; ip++, k++) {
                double u = (iu + 0.5) / NU;
                a[k] = incident_deg[j] * DEG;
                a[n + k] = 0.0;
                a[2 * n + k] = acos(u);
                a[3 * n + k] = (ip + 0.5) * 2.0 * M_PI / NPHI;
            }
    bf_geometry *g = NULL;
    bf_geometry_from_angles(n, a, a + n, a + 2 * n, a + 3 * n, &g, NULL);
    free(a);
    return g;
}

static bf_geometry *geom;

static void check(const char *spec, int C)
{
    bf_error err;
    bf_model *m = NULL;
    if (bf_model_new(spec, C, &m, &err) != BF_OK)
        fail_msg("%s: %s", spec, err.msg);
    if (!bf_model_energy_conserving(m)) {
        bf_model_free(m);
        return;
    }
    ts_rng rng = {0x2545F4914F6CDD1DULL + (uint64_t)C};
    double *x = malloc((size_t)bf_model_nvalues(m) * sizeof *x);
    for (int t = 0; t < TRIALS; t++) {
        ts_random_params(m, &rng, TS_PARAMS_MODERATE, x);
        double *v = ts_eval(m, x, geom);
        for (int j = 0; j < NINC; j++)
            for (int c = 0; c < C; c++) {
                double sum = 0.0;
                for (size_t k = 0; k < (size_t)NU * NPHI; k++) {
                    size_t s = (size_t)j * NU * NPHI + k;
                    double u = (k / NPHI + 0.5) / NU;
                    sum += v[s * (size_t)C + (size_t)c] * u;
                }
                double albedo = sum * (1.0 / NU) * (2.0 * M_PI / NPHI);
                if (!(albedo <= 1.0 + 0.02))
                    fail_msg("%s C=%d: albedo %.6f > 1 at theta_i = %g deg, channel %d", spec, C, albedo,
                             incident_deg[j], c);
            }
        free(v);
    }
    free(x);
    bf_model_free(m);
}

/* One channel suffices: channels share the lobe shapes (the gradient test covers C = 3). */
static void test_spec(void **state)
{
    check(*state, 1);
}

/* Lambert's albedo is exactly rho_d: checks the quadrature itself. */
static void test_quadrature_lambert(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("lambert", 1, &m, NULL);
    double x = 0.7;
    double *v = ts_eval(m, &x, geom);
    double sum = 0.0;
    for (size_t k = 0; k < (size_t)NU * NPHI; k++)
        sum += v[k] * ((k / NPHI + 0.5) / NU);
    assert_true(fabs(sum * (1.0 / NU) * (2.0 * M_PI / NPHI) - 0.7) < 1e-9);
    free(v);
    bf_model_free(m);
}

int main(void)
{
    geom = quadrature_geometry();
    char **specs;
    int n = ts_all_specs(&specs);
    struct CMUnitTest *tests = calloc((size_t)n + 1, sizeof *tests);
    tests[0] = (struct CMUnitTest){"quadrature_lambert", test_quadrature_lambert, NULL, NULL, NULL};
    for (int i = 0; i < n; i++)
        tests[i + 1] = (struct CMUnitTest){specs[i], test_spec, NULL, NULL, specs[i]};
    int rc = _cmocka_run_group_tests("energy", tests, (size_t)n + 1, NULL, NULL);
    free(tests);
    ts_free_specs(specs, n);
    bf_geometry_free(geom);
    return rc;
}
