/* Metrics on hand-built sample sets with values worked out here: RMSE family, max
 * error; the information criteria's formulas; samples below the horizon left out; the edge cases. */
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
    bf_samples *s = NULL;
    bf_samples_new(4, 2, &s, NULL);
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
    /* criteria belong to fits (bf_fit), not to metrics of a model on data */
    assert_true(isnan(mt.aic) && isnan(mt.aicc) && isnan(mt.bic) && isnan(mt.loglik));
    assert_int_equal(mt.crit_n, 0);
    bf_samples_free(s);
    bf_model_free(m);
}

/* The criteria from N, k, WSSR and sum ln w, against the formulas written out: unit
 * weights, weights (which shift the log-likelihood by half their log sum), an exact
 * fit (floored, finite), too few residuals for AICc, and nothing to go on. */
static void test_criteria_formulas(void **state)
{
    (void)state;
    bf_metrics mt;
    const double n = 50, k = 3, wssr = 0.8, two_pi = 2 * M_PI;
    bf_metrics_criteria(&mt, 50, 3, wssr, 0.0);
    const double ll = -n / 2 * (log(two_pi * wssr / n) + 1);
    assert_int_equal(mt.crit_n, 50);
    ts_assert_rel(mt.loglik, ll, 1e-15, "loglik");
    ts_assert_rel(mt.aic, -2 * ll + 2 * (k + 1), 1e-15, "aic");
    ts_assert_rel(mt.aicc, -2 * ll + 2 * (k + 1) + 2 * (k + 1) * (k + 2) / (n - k - 2), 1e-15, "aicc");
    ts_assert_rel(mt.bic, -2 * ll + (k + 1) * log(n), 1e-15, "bic");
    /* BIC penalises a parameter by ln N, AIC by 2: more parameters, same residuals */
    bf_metrics m5;
    bf_metrics_criteria(&m5, 50, 5, wssr, 0.0);
    ts_assert_rel(m5.bic - mt.bic, 2 * log(n), 1e-12, "bic step");
    ts_assert_rel(m5.aic - mt.aic, 4.0, 1e-12, "aic step");
    /* weights: loglik + sum ln w / 2, the rest follows */
    bf_metrics mw;
    bf_metrics_criteria(&mw, 50, 3, wssr, 7.5);
    ts_assert_rel(mw.loglik, ll + 3.75, 1e-15, "weighted loglik");
    ts_assert_rel(mw.bic, mt.bic - 7.5, 1e-13, "weighted bic");
    /* exact fit: floored at DBL_MIN, finite */
    bf_metrics_criteria(&mt, 2, 1, 0.0, 0.0);
    assert_true(isfinite(mt.aic) && isfinite(mt.bic));
    ts_assert_rel(mt.loglik, -(log(two_pi * DBL_MIN) + 1), 1e-15, "exact fit");
    assert_true(isnan(mt.aicc)); /* N = 2 <= k + 2 */
    /* nothing to go on */
    bf_metrics_criteria(&mt, 0, 1, 0.0, 0.0);
    assert_true(isnan(mt.aic) && isnan(mt.bic) && isnan(mt.loglik));
    bf_metrics_criteria(&mt, 10, 1, NAN, 0.0);
    assert_true(isnan(mt.aic) && isnan(mt.bic));
}

/* A value with m c < -1 keeps rmse_log finite (1 + m c floored at 1e-12); all-zero
 * measurements give rmse_rel NaN. */
static void test_metrics_edges(void **state)
{
    (void)state;
    bf_model *m = ts_model("lambert", 1);
    bf_samples *s = NULL;
    bf_samples_new(2, 1, &s, NULL);
    s->theta_o[0] = s->theta_o[1] = 10;
    double x = 0.5;
    s->value[0] = s->value[1] = 0.5 / M_PI;
    bf_metrics mt;
    assert_int_equal(bf_metrics_compute(m, &x, s, 1, 1, &mt, NULL), BF_OK);
    assert_true(mt.rmse == 0.0 && mt.max_err == 0.0 && mt.rmse_rel == 0.0);

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
    bf_samples_new(1, 1, &s, NULL);
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
        cmocka_unit_test(test_criteria_formulas),
        cmocka_unit_test(test_metrics_edges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
