/* bf_samples_describe on hand-built sets with known coverage, counts and values. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>

#include <cmocka.h>

#include "brdfit/prep.h"
#include "support.h"

/* In-plane pair with half angle th and difference angle td (degrees). */
static void set_half_diff(bf_samples *s, size_t i, double th, double td)
{
    s->theta_i[i] = td + th;
    s->phi_i[i] = 0;
    s->theta_o[i] = td - th;
    s->phi_o[i] = 180;
}

static void assert_range(bf_range r, double lo, double hi, const char *what)
{
    ts_assert_near(r.lo, lo, 1e-12, 1e-12, what);
    ts_assert_near(r.hi, hi, 1e-12, 1e-12, what);
}

static void test_describe(void **state)
{
    (void)state;
    bf_samples *s = NULL;
    bf_samples_new(4, 2, &s, NULL);
    /* (theta_h, theta_d) = (1, 10), (20, 30), (40, 45); the fourth is below the
     * horizon, so out of the angle ranges but in the value ranges. */
    set_half_diff(s, 0, 1, 10);
    set_half_diff(s, 1, 20, 30);
    set_half_diff(s, 2, 40, 45);
    s->theta_i[3] = 95;
    s->theta_o[3] = 10;
    const double v[8] = {0.5, 2, -0.1, 0, NAN, 4, 100, 1};
    for (int k = 0; k < 8; k++)
        s->value[k] = v[k];
    bf_samples_info info;
    bf_samples_info_init(&info);
    assert_int_equal(bf_samples_describe(s, &info, NULL), BF_OK);
    assert_int_equal(info.n, 4);
    assert_int_equal(info.channels, 2);
    assert_range(info.theta_i, 11, 85, "theta_i");
    assert_range(info.theta_o, 5, 10, "theta_o");
    assert_range(info.theta_h, 1, 40, "theta_h");
    assert_range(info.theta_d, 10, 45, "theta_d");
    assert_int_equal(info.below_horizon, 1);
    assert_int_equal(info.nonfinite, 1);
    assert_int_equal(info.negative, 1);
    assert_int_equal(info.zero, 1);
    assert_range(info.value[0], -0.1, 100, "channel 0");
    assert_range(info.value[1], 0, 4, "channel 1");
    ts_assert_rel(info.mean[0], (0.5 - 0.1 + 100) / 3, 1e-15, "mean 0 (NaN left out)");
    ts_assert_rel(info.mean[1], 7.0 / 4, 1e-15, "mean 1");
    assert_false(info.weighted);
    assert_non_null(s->geom); /* computed once, kept for the fit */
    bf_samples_info_clear(&info);
    assert_null(info.value);

    assert_int_equal(bf_samples_add_weights(s, NULL), BF_OK);
    assert_int_equal(bf_samples_describe(s, &info, NULL), BF_OK);
    assert_true(info.weighted);
    bf_samples_info_clear(&info);
    bf_samples_free(s);
}

/* Out of the plane of incidence: L and V at 40 degrees, azimuths 0 and 90. */
static void test_describe_half_angles(void **state)
{
    (void)state;
    bf_samples *s = NULL;
    bf_samples_new(1, 1, &s, NULL);
    s->theta_i[0] = s->theta_o[0] = 40;
    s->phi_o[0] = 90;
    s->value[0] = 1;
    double st = sin(40 * DEG), ct = cos(40 * DEG), len = sqrt(2 * st * st + 4 * ct * ct);
    bf_samples_info info;
    bf_samples_info_init(&info);
    assert_int_equal(bf_samples_describe(s, &info, NULL), BF_OK);
    assert_range(info.theta_h, acos(2 * ct / len) / DEG, acos(2 * ct / len) / DEG, "theta_h");
    assert_range(info.theta_d, acos((st * st + 2 * ct * ct) / len) / DEG, acos((st * st + 2 * ct * ct) / len) / DEG,
                 "theta_d");
    bf_samples_info_clear(&info);
    /* L = V (retro-reflection): theta_d is 0 to rounding, not the 1e-6 degrees of acos. */
    s->theta_o[0] = 40;
    s->phi_o[0] = 0;
    bf_geometry_free(s->geom);
    s->geom = NULL;
    assert_int_equal(bf_samples_describe(s, &info, NULL), BF_OK);
    assert_true(info.theta_d.hi < 1e-12);
    ts_assert_rel(info.theta_h.lo, 40, 1e-14, "theta_h of a retro pair");
    bf_samples_info_clear(&info);
    bf_samples_free(s);
}

static void test_describe_nothing_to_cover(void **state)
{
    (void)state;
    /* Every sample below the horizon and one channel all NaN: NaN ranges, not garbage. */
    bf_samples *s = NULL;
    bf_samples_new(2, 2, &s, NULL);
    for (size_t i = 0; i < 2; i++) {
        s->theta_i[i] = 90;
        s->value[2 * i] = NAN;
        s->value[2 * i + 1] = 3.0 * (double)(i + 1);
    }
    bf_samples_info info;
    bf_samples_info_init(&info);
    assert_int_equal(bf_samples_describe(s, &info, NULL), BF_OK);
    assert_int_equal(info.below_horizon, 2);
    assert_int_equal(info.nonfinite, 2);
    assert_true(isnan(info.theta_i.lo) && isnan(info.theta_h.hi));
    assert_true(isnan(info.value[0].lo) && isnan(info.value[0].hi) && isnan(info.mean[0]));
    assert_range(info.value[1], 3, 6, "channel 1");
    ts_assert_rel(info.mean[1], 4.5, 1e-15, "mean");
    bf_samples_info_clear(&info);
    bf_samples_free(s);

    bf_samples_new(0, 3, &s, NULL);
    assert_int_equal(bf_samples_describe(s, &info, NULL), BF_OK);
    assert_int_equal(info.n, 0);
    assert_int_equal(info.channels, 3);
    assert_true(isnan(info.theta_d.lo) && isnan(info.mean[2]));
    bf_samples_info_clear(&info);
    bf_samples_free(s);
}

/* A million near-equal values: the compensated mean is exact to rounding. */
static void test_describe_mean_precision(void **state)
{
    (void)state;
    const size_t n = 1000000;
    bf_samples *s = NULL;
    bf_samples_new(n, 1, &s, NULL);
    for (size_t i = 0; i < n; i++) {
        s->theta_i[i] = 30;
        s->value[i] = 0.1 + (i % 2 ? 1e-9 : -1e-9);
    }
    bf_samples_info info;
    bf_samples_info_init(&info);
    assert_int_equal(bf_samples_describe(s, &info, NULL), BF_OK);
    ts_assert_rel(info.mean[0], 0.1, 1e-14, "mean of a million values");
    assert_range(info.value[0], 0.1 - 1e-9, 0.1 + 1e-9, "range");
    bf_samples_info_clear(&info);
    bf_samples_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_describe),
        cmocka_unit_test(test_describe_half_angles),
        cmocka_unit_test(test_describe_nothing_to_cover),
        cmocka_unit_test(test_describe_mean_precision),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
