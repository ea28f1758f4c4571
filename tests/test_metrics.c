/* Metrics on hand-built sample sets with values worked out here: RMSE family, max
 * error, AIC and BIC; samples below the horizon left out; the edge cases. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/metrics.h"
#include "support.h"

/* Lambert, C = 2, rho_d = (0.5, 0.25): f = (0.5, 0.25) / pi at every direction.
 * Sample 0 at theta_i = 0 (c = 1), sample 1 at 60 (c = cos 60), sample 2 below the
 * horizon (not counted), sample 3 at theta_i = 0. Measurements include a 0 (left out of
 * rmse_rel) and a negative value. */
static void test_metrics_values(void **state)
{
    (void)state;
    bf_model *m = ts_model("lambert", 2);
    bf_samples *s = bf_samples_new(4, 2, NULL);
    const double ti[4] = {0, 60, 120, 0};
    const double meas[8] = {0.2, 0.0, 0.1, 0.05, 9.0, 9.0, -0.01, 0.1};
    for (int i = 0; i < 4; i++) {
        s->theta_i[i] = ti[i];
        s->theta_o[i] = 30;
        s->phi_o[i] = 180;
    }
    memcpy(s->value, meas, sizeof meas);
    const double x[2] = {0.5, 0.25};
    bf_metrics mt;
    bf_error err = {0};
    assert_int_equal(bf_metrics_compute(m, x, s, 2, 1, &mt, &err), BF_OK);

    const double f[2] = {0.5 / M_PI, 0.25 / M_PI}, cs[4] = {1, cos(60 * DEG), 0, 1};
    const int used[3] = {0, 1, 3};
    double ssr = 0, scos = 0, slog = 0, srel = 0, maxe = 0;
    int nrel = 0;
    for (int u = 0; u < 3; u++) {
        int i = used[u];
        for (int c = 0; c < 2; c++) {
            double mm = meas[2 * i + c], d = f[c] - mm;
            ssr += d * d;
            scos += d * cs[i] * d * cs[i];
            double dl = log(1 + f[c] * cs[i]) - log(1 + mm * cs[i]);
            slog += dl * dl;
            if (mm != 0) {
                srel += (d / fabs(mm)) * (d / fabs(mm));
                nrel++;
            }
            maxe = fmax(maxe, fabs(d));
        }
    }
    assert_int_equal(mt.n, 6);
    assert_int_equal(mt.k, 2);
    assert_int_equal(nrel, 5);
    ts_assert_rel(mt.rmse, sqrt(ssr / 6), 1e-15, "rmse");
    ts_assert_rel(mt.rmse_cos, sqrt(scos / 6), 1e-15, "rmse_cos");
    ts_assert_rel(mt.rmse_log, sqrt(slog / 6), 1e-14, "rmse_log");
    ts_assert_rel(mt.rmse_rel, sqrt(srel / 5), 1e-15, "rmse_rel");
    ts_assert_rel(mt.max_err, maxe, 1e-15, "max_err");
    ts_assert_rel(mt.max_err, 0.5 / M_PI + 0.01, 1e-15, "max_err by hand (sample 3, channel 0)");
    ts_assert_rel(mt.aic, 6 * log(ssr / 6) + 4, 1e-15, "aic");
    ts_assert_rel(mt.bic, 6 * log(ssr / 6) + 2 * log(6.0), 1e-15, "bic");
    bf_samples_free(s);
    bf_model_free(m);
}

/* A value with m c < -1 keeps rmse_log finite (1 + m c floored at 1e-12); an exact fit
 * gives finite AIC/BIC; all-zero measurements give rmse_rel NaN. */
static void test_metrics_edges(void **state)
{
    (void)state;
    bf_model *m = ts_model("lambert", 1);
    bf_samples *s = bf_samples_new(2, 1, NULL);
    s->theta_o[0] = s->theta_o[1] = 10;
    double x = 0.5;
    s->value[0] = s->value[1] = 0.5 / M_PI;
    bf_metrics mt;
    assert_int_equal(bf_metrics_compute(m, &x, s, 1, 1, &mt, NULL), BF_OK);
    assert_true(mt.rmse == 0.0 && mt.max_err == 0.0 && mt.rmse_rel == 0.0);
    assert_true(isfinite(mt.aic) && isfinite(mt.bic));
    ts_assert_rel(mt.aic, 2 * log(DBL_MIN) + 2, 1e-15, "aic of an exact fit");

    s->value[0] = -3.0; /* c = 1: 1 + m c = -2 */
    s->value[1] = 0.0;
    assert_int_equal(bf_metrics_compute(m, &x, s, 1, 1, &mt, NULL), BF_OK);
    double dl = log1p(0.5 / M_PI) - log(1e-12), dl1 = log1p(0.5 / M_PI);
    ts_assert_rel(mt.rmse_log, sqrt((dl * dl + dl1 * dl1) / 2), 1e-6, "floored log");
    ts_assert_rel(mt.rmse_rel, fabs(0.5 / M_PI + 3.0) / 3.0, 1e-15, "rel over m != 0");

    s->value[0] = 0.0;
    assert_int_equal(bf_metrics_compute(m, &x, s, 1, 1, &mt, NULL), BF_OK);
    assert_true(isnan(mt.rmse_rel));
    assert_true(isfinite(mt.rmse));

    /* Nothing above the horizon; channel mismatch. */
    bf_samples_free(s);
    s = bf_samples_new(1, 1, NULL);
    s->theta_i[0] = 90;
    bf_error err = {0};
    assert_int_equal(bf_metrics_compute(m, &x, s, 1, 1, &mt, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "horizon"));
    bf_model *m3 = ts_model("lambert", 3);
    double x3[3] = {0.5, 0.5, 0.5};
    assert_int_equal(bf_metrics_compute(m3, x3, s, 1, 1, &mt, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "channels"));
    bf_model_free(m3);
    bf_samples_free(s);
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_metrics_values),
        cmocka_unit_test(test_metrics_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
