/* Reciprocity f(L, V) = f(V, L) for every reciprocal model configuration. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>

#include <cmocka.h>

#include "support.h"

enum { NDIRS = 200, TRIALS = 8 };

static void check(const char *spec, int C)
{
    bf_error err;
    bf_model *m = NULL;
    if (bf_model_new(spec, C, &m, &err) != BF_OK)
        fail_msg("%s: %s", spec, err.msg);
    if (!bf_model_reciprocal(m)) {
        bf_model_free(m);
        return;
    }
    ts_rng rng = {0xD1B54A32D192ED03ULL + (uint64_t)C};
    double ti[NDIRS], pi_[NDIRS], to[NDIRS], po[NDIRS];
    ts_random_dirs(&rng, NDIRS, ti, pi_, to, po);
    bf_geometry *g = NULL;
    bf_geometry_from_angles(NDIRS, ti, pi_, to, po, &g, NULL);
    bf_geometry *gs = NULL;
    bf_geometry_from_angles(NDIRS, to, po, ti, pi_, &gs, NULL);
    double *x = malloc((size_t)bf_model_nvalues(m) * sizeof *x);
    for (int t = 0; t < TRIALS; t++) {
        ts_random_params(m, &rng, TS_PARAMS_MODERATE, x);
        double *a = ts_eval(m, x, g), *b = ts_eval(m, x, gs);
        for (size_t i = 0; i < (size_t)NDIRS * (size_t)C; i++) {
            double tol = 1e-9 * fmax(fabs(a[i]), fabs(b[i])) + 1e-300;
            if (!(fabs(a[i] - b[i]) <= tol)) {
                size_t s = i / (size_t)C;
                fail_msg("%s C=%d: f(L,V) = %.17g but f(V,L) = %.17g at (%.6g,%.6g,%.6g,%.6g) deg", spec, C, a[i], b[i],
                         ti[s] / DEG, pi_[s] / DEG, to[s] / DEG, po[s] / DEG);
            }
        }
        free(a);
        free(b);
    }
    free(x);
    bf_geometry_free(g);
    bf_geometry_free(gs);
    bf_model_free(m);
}

static void test_spec(void **state)
{
    check(*state, 1);
    check(*state, 3);
}

int main(void)
{
    char **specs;
    int n = ts_all_specs(&specs);
    struct CMUnitTest *tests = calloc((size_t)n, sizeof *tests);
    for (int i = 0; i < n; i++)
        tests[i] = (struct CMUnitTest){specs[i], test_spec, NULL, NULL, specs[i]};
    int rc = _cmocka_run_group_tests("reciprocity", tests, (size_t)n, NULL, NULL);
    free(tests);
    ts_free_specs(specs, n);
    return rc;
}
