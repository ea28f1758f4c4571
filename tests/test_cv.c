/* Cross-validation: the seeded stratified folds (every sample in one fold, folds of
 * equal size within a stratum's rounding, strata shared out evenly, the same folds for
 * the same seed) and bf_fit_cv (zero on exact data, close to the in-sample error on
 * noisy data, the same bits for any thread count, argument errors). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/fit.h"
#include "brdfit/prep.h"
#include "support.h"

/* n samples of lambert (rho_d 0.4, 0.3) at random directions, with relative noise. */
static bf_samples *lambert_samples(size_t n, double noise)
{
    bf_samples *s = NULL;
    bf_samples_new(n, 2, &s, NULL);
    assert_non_null(s);
    ts_rng r = {99};
    for (size_t i = 0; i < n; i++) {
        ts_random_pair_deg(&r, 0, &s->theta_i[i], &s->phi_i[i], &s->theta_o[i], &s->phi_o[i]);
        for (int c = 0; c < 2; c++)
            s->value[2 * i + c] = (c ? 0.3 : 0.4) / M_PI * (1.0 + noise * (2.0 * ts_uniform(&r) - 1.0));
    }
    return s;
}

static void test_folds(void **state)
{
    (void)state;
    const size_t n = 1000;
    bf_samples *s = lambert_samples(n, 0.0);
    /* Two groups far apart in theta_h: the mirror direction, and 60 degrees off it. */
    for (size_t i = 0; i < n; i++) {
        s->theta_i[i] = 30, s->phi_i[i] = 0, s->phi_o[i] = 180;
        s->theta_o[i] = i % 4 == 0 ? 30 : 80;
    }
    unsigned char f1[1000], f2[1000], f3[1000];
    bf_error err;
    for (int K = 2; K <= 7; K++) {
        assert_int_equal(bf_samples_folds(s, K, 5, f1, &err), BF_OK);
        int size[8] = {0}, mirror[8] = {0};
        for (size_t i = 0; i < n; i++) {
            assert_true(f1[i] < K);
            size[f1[i]]++;
            mirror[f1[i]] += i % 4 == 0;
        }
        /* each group is dealt evenly: a fold holds a K-th of it, give or take one */
        for (int k = 0; k < K; k++) {
            assert_true(abs(size[k] * K - (int)n) <= 2 * K);
            assert_true(abs(mirror[k] * K - (int)n / 4) <= K);
        }
    }
    assert_int_equal(bf_samples_folds(s, 5, 5, f1, &err), BF_OK);
    assert_int_equal(bf_samples_folds(s, 5, 5, f2, &err), BF_OK);
    assert_int_equal(bf_samples_folds(s, 5, 6, f3, &err), BF_OK);
    assert_memory_equal(f1, f2, n);
    assert_true(memcmp(f1, f3, n) != 0);
    assert_int_equal(bf_samples_folds(s, 1, 5, f1, &err), BF_ERR_ARG);
    bf_samples_free(s);
}

static void test_cv_error(void **state)
{
    (void)state;
    bf_fit_options o;
    ts_fit_defaults(&o);
    o.objective.residual = BF_RESIDUAL_LOG;
    bf_cv_result cv, cv2;
    bf_error err;
    /* exact data: every held-out residual is (almost) zero */
    bf_samples *s = lambert_samples(600, 0.0);
    assert_int_equal(bf_fit_cv_with(s, "lambert", &o, 4, 1, &cv, &err), BF_OK);
    assert_int_equal(cv.folds, 4);
    assert_int_equal(cv.failed, 0);
    assert_true(cv.error >= 0.0 && cv.error < 1e-9);
    bf_samples_free(s);

    /* noisy data: close to the in-sample error, and a little above it on average */
    s = lambert_samples(2000, 0.2);
    bf_fit_result r;
    ts_fit_ok(s, "lambert", &o, &r);
    const double train = r.metrics.rmse_log;
    bf_fit_result_clear(&r);
    assert_int_equal(bf_fit_cv_with(s, "lambert", &o, 5, 1, &cv, &err), BF_OK);
    printf("  train %.6g, cv %.6g\n", train, cv.error);
    assert_true(cv.error > 0.95 * train && cv.error < 1.2 * train);
    for (int k = 0; k < 5; k++)
        assert_true(isfinite(cv.fold_error[k]) && cv.fold_error[k] > 0.0);
    /* the same bits with more threads; other folds with another seed */
    o.solver.threads = 3;
    assert_int_equal(bf_fit_cv_with(s, "lambert", &o, 5, 1, &cv2, &err), BF_OK);
    assert_memory_equal(&cv, &cv2, sizeof cv);
    assert_int_equal(bf_fit_cv_with(s, "lambert", &o, 5, 2, &cv2, &err), BF_OK);
    assert_true(cv2.error != cv.error);
    /* bad arguments */
    assert_int_equal(bf_fit_cv_with(s, "lambert", &o, 1, 1, &cv, &err), BF_ERR_ARG);
    assert_int_equal(bf_fit_cv_with(s, "lambert", &o, BF_CV_MAX_FOLDS + 1, 1, &cv, &err), BF_ERR_ARG);
    assert_int_equal(bf_fit_cv_with(s, "no_such_model", &o, 5, 1, &cv, &err), BF_ERR_ARG);
    bf_samples_free(s);
    s = lambert_samples(3, 0.0);
    assert_int_equal(bf_fit_cv_with(s, "lambert", &o, 5, 1, &cv, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "3 samples for 5 folds"));
    bf_samples_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_folds),
        cmocka_unit_test(test_cv_error),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
