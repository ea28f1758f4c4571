/* The objective's passes (the fused pass, metrics, standard errors) and whole fits
 * (Ceres and NLopt, with and without a presolve) give the same bits for any thread
 * count: fixed chunks, partial sums added in chunk order. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/fit.h"
#include "brdfit/metrics.h"
#include "brdfit/objective.h"
#include "support.h"

/* Walter data at random directions with a deterministic wobble, enough samples for
 * several chunks (8192 samples per metrics chunk, 4096 rows per stderr chunk). */
static bf_samples *make_samples(const bf_model *m, const double *x, size_t n)
{
    bf_samples *s = NULL;
    bf_samples_new(n, 3, &s, NULL);
    ts_rng r = {12345};
    double *ti = malloc(4 * n * sizeof *ti), *pi_ = ti + n, *to = ti + 2 * n, *po = ti + 3 * n;
    ts_random_dirs(&r, n, ti, pi_, to, po);
    for (size_t i = 0; i < n; i++) {
        s->theta_i[i] = ti[i] / DEG;
        s->phi_i[i] = pi_[i] / DEG;
        s->theta_o[i] = to[i] / DEG;
        s->phi_o[i] = po[i] / DEG;
    }
    free(ti);
    bf_model_eval(m, x, ts_samples_geometry(s), s->value, NULL);
    for (size_t k = 0; k < 3 * n; k++)
        s->value[k] *= 1.0 + 0.02 * sin(1.7 * (double)k);
    return s;
}

static void test_thread_count_independence(void **state)
{
    (void)state;
    bf_model *m = ts_model("walter", 3);
    double x[8] = {0.3, 0.4, 0.5, 0.6, 0.6, 0.6, 0.15, 0.04};
    bf_samples *s = make_samples(m, x, 30000);
    bf_metrics ref, mt;
    double se_ref[8], se[8];
    for (int threads = 1; threads <= 4; threads++) {
        assert_int_equal(bf_metrics_compute(m, x, s, 8, threads, &mt, NULL), BF_OK);
        bf_objective_options oo;
        bf_objective_options_init(&oo);
        oo.residual = BF_RESIDUAL_LOG;
        oo.threads = threads;
        bf_objective *obj = NULL;
        bf_objective_new(m, s, &oo, &obj, NULL);
        assert_non_null(obj);
        assert_int_equal(bf_objective_stderr(obj, x, se, NULL), BF_OK);
        bf_objective_free(obj);
        if (threads == 1) {
            ref = mt;
            memcpy(se_ref, se, sizeof se);
            assert_true(ref.n == 90000 && ref.rmse > 0.0);
            for (int k = 0; k < 8; k++)
                assert_true(se_ref[k] > 0.0 && isfinite(se_ref[k]));
            continue;
        }
        assert_memory_equal(&mt, &ref, sizeof mt);
        assert_memory_equal(se, se_ref, sizeof se);
    }
    bf_samples_free(s);
    bf_model_free(m);
}

/* Whole fits: parameters, metrics, costs and counts to the bit for 1 to 4 threads. */
static void check_fit_threads(bf_samples *s, const char *spec, bf_backend backend, long presolve)
{
    bf_fit_result ref, r;
    for (int threads = 1; threads <= 4; threads++) {
        bf_fit_options o;
        ts_fit_defaults(&o);
        o.solver.backend = backend;
        o.solver.threads = threads;
        o.presolve = presolve;
        ts_fit_ok(s, spec, &o, threads == 1 ? &ref : &r);
        if (threads == 1) {
            assert_int_equal(ref.presolve.samples, presolve > 0 ? (size_t)presolve : 0);
            continue;
        }
        const int P = bf_model_nvalues(r.model);
        assert_memory_equal(r.x, ref.x, (size_t)P * sizeof *r.x);
        assert_memory_equal(r.stderr_, ref.stderr_, (size_t)P * sizeof *r.x);
        assert_memory_equal(&r.metrics, &ref.metrics, sizeof r.metrics);
        assert_memory_equal(&r.solution.final_cost, &ref.solution.final_cost, sizeof(double));
        assert_int_equal(r.solution.iterations, ref.solution.iterations);
        assert_int_equal(r.solution.evaluations, ref.solution.evaluations);
        assert_int_equal(r.presolve.evaluations, ref.presolve.evaluations);
        bf_fit_result_clear(&r);
    }
    bf_fit_result_clear(&ref);
}

static void test_fit_thread_independence(void **state)
{
    (void)state;
    bf_model *m = ts_model("walter", 3);
    double x[8] = {0.3, 0.4, 0.5, 0.6, 0.6, 0.6, 0.15, 0.04};
    bf_samples *s = make_samples(m, x, 30000);
    check_fit_threads(s, "walter", BF_BACKEND_CERES, -1);
    check_fit_threads(s, "walter", BF_BACKEND_CERES, 6000);
    check_fit_threads(s, "cook_torrance:mono=specular", BF_BACKEND_CERES, 6000);
    check_fit_threads(s, "ashikhmin_shirley", BF_BACKEND_NLOPT, -1);
    bf_samples_free(s);
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_thread_count_independence),
                                       cmocka_unit_test(test_fit_thread_independence)};
    return cmocka_run_group_tests_name("fit_threads", tests, NULL, NULL);
}
