/* Extremes: no NaN or Inf in values or gradients at theta = 0, 89.9, 89.999 and exactly
 * 90 degrees, with every parameter at its bounds (roughness at its lower bound,
 * exponents of 1e6, f0 at 0 and 1) and at random interior points, for every model;
 * values are also non-negative except for the families may_be_negative names. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "support.h"

static const double thetas[] = {0.0, 1e-6, 30.0, 60.0, 89.9, 89.999, 90.0};
static const double phis[] = {0.0, 45.0, 90.0, 180.0, 270.0};
enum { NT = sizeof thetas / sizeof thetas[0], NP = sizeof phis / sizeof phis[0] };
enum { NDIR = NT * NP * NT * NP };

static bf_geometry *geom, *near_horizon;

/* Vectors at the smallest cosine the geometry keeps above the horizon (2e-15), paired
 * every way: mirror (H = N), equal (NH tiny), crossed, against the normal. */
static bf_geometry *near_horizon_geometry(void)
{
    const double e = 2e-15;
    const double dirs[][3] = {{1, 0, e}, {-1, 0, e}, {0, 1, e}, {0.6, -0.8, e}, {0, 0, 1}, {1, 0, 1e-9}};
    enum { ND = sizeof dirs / sizeof dirs[0] };
    double L[ND * ND * 3], V[ND * ND * 3];
    for (int a = 0; a < ND; a++)
        for (int b = 0; b < ND; b++)
            for (int k = 0; k < 3; k++) {
                L[(a * ND + b) * 3 + k] = dirs[a][k];
                V[(a * ND + b) * 3 + k] = dirs[b][k];
            }
    bf_geometry *g;
    assert_int_equal(bf_geometry_from_vectors(ND * ND, L, V, &g, NULL), BF_OK);
    return g;
}

static bf_geometry *extreme_geometry(void)
{
    double ti[NDIR], pi_[NDIR], to[NDIR], po[NDIR];
    int k = 0;
    for (int a = 0; a < NT; a++)
        for (int b = 0; b < NP; b++)
            for (int c = 0; c < NT; c++)
                for (int d = 0; d < NP; d++, k++) {
                    ti[k] = thetas[a];
                    pi_[k] = phis[b];
                    to[k] = thetas[c];
                    po[k] = phis[d];
                }
    return ts_geometry_deg(NDIR, ti, pi_, to, po);
}

/* Families whose published form goes below zero, so only finiteness is checked: sgd's
 * fitted Fresnel (f1 > f0) and shadowing (lambda (1 - exp w) < -1) do, in 38 of Bagher et
 * al.'s 100 MERL fits (6 of them with a negative BRDF), and those fits must stay exact. */
static int may_be_negative(const char *spec)
{
    return !strncmp(spec, "sgd", 3);
}

static void check_geometry(const char *spec, const bf_model *m, const double *x, const char *what,
                           const bf_geometry *geo)
{
    const int signed_ok = may_be_negative(spec);
    const int C = bf_model_channels(m), P = bf_model_nvalues(m);
    size_t nv = geo->n * (size_t)C;
    double *v = malloc(nv * sizeof *v), *g = malloc(nv * (size_t)P * sizeof *g);
    bf_model_eval(m, x, geo, v, g);
    for (size_t i = 0; i < nv; i++) {
        if (!isfinite(v[i]) || (v[i] < 0.0 && !signed_ok))
            fail_msg("%s C=%d (%s): value %g at sample %zu", spec, C, what, v[i], i / (size_t)C);
        for (int k = 0; k < P; k++)
            if (!isfinite(g[i * (size_t)P + (size_t)k]))
                fail_msg("%s C=%d (%s): gradient slot %d is %g at sample %zu", spec, C, what, k,
                         g[i * (size_t)P + (size_t)k], i / (size_t)C);
    }
    free(v);
    free(g);
}

static void check_point(const char *spec, const bf_model *m, const double *x, const char *what)
{
    check_geometry(spec, m, x, what, geom);
    check_geometry(spec, m, x, what, near_horizon);
}

static void check(const char *spec, int C)
{
    bf_error err;
    bf_model *m = NULL;
    if (bf_model_new(spec, C, &m, &err) != BF_OK)
        fail_msg("%s: %s", spec, err.msg);
    int P = bf_model_nvalues(m), np = bf_model_nparams(m);
    double *x = malloc((size_t)P * sizeof *x);
    ts_rng rng = {0xA0761D6478BD642FULL};

    for (int corner = 0; corner < 2; corner++) { /* every parameter at lo, then at hi */
        for (int i = 0; i < np; i++) {
            const bf_param_info *p = bf_model_param(m, i);
            for (int c = 0; c < (p->color ? C : 1); c++)
                x[bf_model_param_offset(m, i) + c] = corner ? ts_param_hi(p) : ts_param_lo(p);
        }
        check_point(spec, m, x, corner ? "all at upper bounds" : "all at lower bounds");
    }
    /* Each parameter alone at each bound, the rest at random. */
    for (int i = 0; i < np; i++)
        for (int side = 0; side < 2; side++) {
            ts_random_params(m, &rng, TS_PARAMS_ANY, x);
            const bf_param_info *p = bf_model_param(m, i);
            for (int c = 0; c < (p->color ? C : 1); c++)
                x[bf_model_param_offset(m, i) + c] = side ? ts_param_hi(p) : ts_param_lo(p);
            check_point(spec, m, x, p->name);
        }
    free(x);
    bf_model_free(m);
}

static void test_spec(void **state)
{
    check(*state, 1);
    check(*state, 3);
}

/* Exactly 90 degrees is on the horizon: the value is exactly 0 for every model. */
static void test_horizon_is_zero(void **state)
{
    (void)state;
    for (int f = 0; f < bf_family_count(); f++) {
        bf_model *m = NULL;
        bf_model_new(bf_family_get(f)->name, 1, &m, NULL);
        double *x = malloc((size_t)bf_model_nvalues(m) * sizeof *x);
        bf_model_defaults(m, x);
        assert_true(ts_eval1(m, x, 90.0, 0.0, 30.0, 180.0, 0) == 0.0);
        assert_true(ts_eval1(m, x, 30.0, 0.0, 90.0, 180.0, 0) == 0.0);
        assert_true(ts_eval1(m, x, 100.0, 0.0, 30.0, 180.0, 0) == 0.0);
        free(x);
        bf_model_free(m);
    }
}

int main(void)
{
    geom = extreme_geometry();
    near_horizon = near_horizon_geometry();
    if (!(near_horizon->lz[0] > 0.0)) { /* must stay above the horizon to mean anything */
        fprintf(stderr, "near-horizon geometry was snapped to the horizon\n");
        return 1;
    }
    char **specs;
    int n = ts_all_specs(&specs);
    struct CMUnitTest *tests = calloc((size_t)n + 1, sizeof *tests);
    tests[0] = (struct CMUnitTest){"horizon_is_zero", test_horizon_is_zero, NULL, NULL, NULL};
    for (int i = 0; i < n; i++)
        tests[i + 1] = (struct CMUnitTest){specs[i], test_spec, NULL, NULL, specs[i]};
    int rc = _cmocka_run_group_tests("extremes", tests, (size_t)n + 1, NULL, NULL);
    free(tests);
    ts_free_specs(specs, n);
    bf_geometry_free(geom);
    bf_geometry_free(near_horizon);
    return rc;
}
