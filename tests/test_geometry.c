/* Geometry: half vectors, the horizon, and vector input. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>

#include <cmocka.h>

#include "support.h"

static void test_half_vector(void **state)
{
    (void)state;
    /* theta_i = 30, theta_o = 60, opposite azimuths: H lies in the xz plane at 15 deg
     * from N, towards V. */
    double ti = 30 * DEG, pi_ = 0, to = 60 * DEG, po = M_PI;
    bf_geometry *g = NULL;
    bf_geometry_from_angles(1, &ti, &pi_, &to, &po, &g, NULL);
    assert_true(fabs(g->hz[0] - cos(15 * DEG)) < 1e-15);
    assert_true(fabs(g->hx[0] + sin(15 * DEG)) < 1e-15);
    assert_true(fabs(g->hy[0]) < 1e-15);
    assert_true(fabs(g->vh[0] - cos(45 * DEG)) < 1e-15);
    assert_true(fabs(g->sin2h[0] - pow(sin(15 * DEG), 2)) < 1e-15);
    assert_true(fabs(g->lz[0] - cos(30 * DEG)) < 1e-15);
    assert_true(bf_geometry_valid(g, 0));
    bf_geometry_free(g);
}

/* sin^2(theta_h) keeps full relative precision near the peak, where 1 - NH^2 does not. */
static void test_sin2h_near_peak(void **state)
{
    (void)state;
    double ti = 20 * DEG, pi_ = 0, to = 20 * DEG + 2e-9, po = M_PI;
    bf_geometry *g = NULL;
    bf_geometry_from_angles(1, &ti, &pi_, &to, &po, &g, NULL);
    double th = 1e-9; /* theta_h = half the difference */
    assert_true(fabs(g->sin2h[0] / (th * th) - 1.0) < 1e-6);
    bf_geometry_free(g);
}

/* V.H at grazing mirror pairs (H = N, V.H = cos theta) keeps its relative precision
 * although L and V nearly cancel in x and y. */
static void test_vh_grazing_mirror(void **state)
{
    (void)state;
    const double thetas[] = {89.9, 89.99, 89.999};
    for (int k = 0; k < 3; k++) {
        double t = thetas[k] * DEG, pi_ = 45 * DEG, po = 225 * DEG;
        bf_geometry *g = NULL;
        bf_geometry_from_angles(1, &t, &pi_, &t, &po, &g, NULL);
        ts_assert_rel(g->vh[0], cos(t), 1e-12, "V.H at a grazing mirror pair");
        bf_geometry_free(g);
    }
}

static void test_horizon(void **state)
{
    (void)state;
    double ti[3] = {90 * DEG, 89.999 * DEG, 100 * DEG}, pi_[3] = {0, 0, 0};
    double to[3] = {10 * DEG, 10 * DEG, 10 * DEG}, po[3] = {0, 0, 0};
    bf_geometry *g = NULL;
    bf_geometry_from_angles(3, ti, pi_, to, po, &g, NULL);
    assert_true(g->lz[0] == 0.0); /* exactly 90 degrees is on the horizon */
    assert_false(bf_geometry_valid(g, 0));
    assert_true(g->lz[1] > 1e-5 && bf_geometry_valid(g, 1));
    assert_false(bf_geometry_valid(g, 2));
    bf_geometry_free(g);
}

static void test_from_vectors(void **state)
{
    (void)state;
    double L[6] = {0, 0, 2, 1, 0, 1}, V[6] = {0, 0, 1, -1, 0, 1};
    bf_geometry *g = NULL;
    bf_geometry_from_vectors(2, L, V, &g, NULL);
    assert_true(g->lz[0] == 1.0 && g->hz[0] == 1.0 && g->vh[0] == 1.0);
    assert_true(fabs(g->lx[1] - sqrt(0.5)) < 1e-15 && fabs(g->hz[1] - 1.0) < 1e-15);
    bf_geometry_free(g);
    double Z[3] = {0, 0, 0};
    bf_error err;
    assert_int_equal(bf_geometry_from_vectors(1, Z, V, &g, &err), BF_ERR_RANGE);
    assert_null(g);
    assert_int_equal(err.code, BF_ERR_RANGE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_half_vector),       cmocka_unit_test(test_sin2h_near_peak),
        cmocka_unit_test(test_vh_grazing_mirror), cmocka_unit_test(test_horizon),
        cmocka_unit_test(test_from_vectors),
    };
    return cmocka_run_group_tests_name("geometry", tests, NULL, NULL);
}
