/* Shared terms (terms.h) at the edges of their conditioning. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>

#include <cmocka.h>

#include "models/terms.h"
#include "support.h"

/* Unpolarised Fresnel reflectance from Snell's law, an independent route. */
static double fresnel_snell(double ci, double n)
{
    double si = sqrt(1.0 - ci * ci), st = si / n, ct = sqrt(1.0 - st * st);
    double rs = (ci - n * ct) / (ci + n * ct), rp = (ct - n * ci) / (ct + n * ci);
    return 0.5 * (rs * rs + rp * rp);
}

static void test_dielectric_values(void **state)
{
    (void)state;
    ts_assert_rel(bf_dielectric(1.0, 1.5, NULL), 0.04, 1e-15, "ior 1.5 at normal incidence");
    const double cs[] = {0.05, 0.2, 0.5, 0.8, 0.99};
    const double ns[] = {1.01, 1.33, 1.5, 2.4, 3.0};
    for (int i = 0; i < 5; i++)
        for (int j = 0; j < 5; j++)
            ts_assert_rel(bf_dielectric(cs[i], ns[j], NULL), fresnel_snell(cs[i], ns[j]), 1e-12,
                          "dielectric vs Snell");
}

/* At ior = 1 nothing reflects: F is exactly 0 at every angle, grazing included (the
 * literal g - c lost this to rounding when c^2 is below the ulp of 1). */
static void test_dielectric_ior_one(void **state)
{
    (void)state;
    const double cs[] = {1e-12, 1e-8, 1.7e-5, 1e-3, 0.5, 1.0};
    for (int i = 0; i < 6; i++) {
        double dF;
        assert_true(bf_dielectric(cs[i], 1.0, &dF) == 0.0);
        assert_true(dF == 0.0);
    }
    /* End to end: a sharp dielectric lobe at ior = 1, grazing mirror pair, adds nothing. */
    bf_model *m = ts_model("walter:fresnel=dielectric", 1);
    double x[4] = {0.3, 1.0, 1e-4, 1.0};
    ts_assert_rel(ts_eval1(m, x, 89.999, 0.0, 89.999, 180.0, 0), 0.3 / M_PI, 1e-15, "grazing, ior 1");
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dielectric_values),
        cmocka_unit_test(test_dielectric_ior_one),
    };
    return cmocka_run_group_tests_name("terms", tests, NULL, NULL);
}
