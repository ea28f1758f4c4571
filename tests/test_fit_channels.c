/* A fit whose channels are independent (sgd: every parameter a colour) runs
 * one fit per channel (lib/src/fit/fit_channels.h): each channel's parameters are those
 * of a fit of that channel's data alone, and the merged result's metrics, cost and
 * standard errors are those of its point judged over all channels. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/fit.h"
#include "fit_channels.h"
#include "support.h"

#define NS 3000

/* sgd data at random directions, each channel its own material, with a deterministic
 * wobble so that the optimum is not the generating point. */
static bf_samples *make_samples(const char *spec, const double *x, int C)
{
    bf_model *m = ts_model(spec, C);
    bf_samples *s = NULL;
    assert_int_equal(bf_samples_new(NS, C, &s, NULL), BF_OK);
    ts_rng r = {777};
    double *ti = malloc(4 * NS * sizeof *ti), *pi_ = ti + NS, *to = ti + 2 * NS, *po = ti + 3 * NS;
    ts_random_dirs(&r, NS, ti, pi_, to, po);
    for (size_t i = 0; i < NS; i++) {
        s->theta_i[i] = ti[i] / DEG;
        s->phi_i[i] = pi_[i] / DEG;
        s->theta_o[i] = to[i] / DEG;
        s->phi_o[i] = po[i] / DEG;
    }
    free(ti);
    bf_model_eval(m, x, ts_samples_geometry(s), s->value, NULL);
    for (size_t k = 0; k < (size_t)C * NS; k++)
        s->value[k] *= 1.0 + 0.02 * sin(1.3 * (double)k);
    bf_model_free(m);
    return s;
}

/* Channel c of s alone. */
static bf_samples *channel_of(const bf_samples *s, int c)
{
    bf_samples *o = NULL;
    assert_int_equal(bf_samples_new(s->n, 1, &o, NULL), BF_OK);
    for (size_t i = 0; i < s->n; i++) {
        o->theta_i[i] = s->theta_i[i], o->phi_i[i] = s->phi_i[i];
        o->theta_o[i] = s->theta_o[i], o->phi_o[i] = s->phi_o[i];
        o->value[i] = s->value[i * (size_t)s->channels + (size_t)c];
    }
    return o;
}

static void fit_options(bf_fit_options *o)
{
    ts_fit_defaults(o);
    o->objective.residual = BF_RESIDUAL_LOG;
    o->starts = 3; /* the screened search, as brdfit fit runs it, on a small scale */
    o->screen = 12;
    o->seed = 11;
}

/* The separable fit of spec on s against C fits of one channel each, and its figures
 * against a direct evaluation of its point. */
static void check_separable(const char *spec, bf_samples *s)
{
    const int C = s->channels;
    bf_fit_options o;
    fit_options(&o);
    bf_fit_result r;
    bf_fit_result_init(&r);
    assert_int_equal(bf_fit_with(s, spec, &o, &r, NULL), BF_OK);
    assert_true(r.ok);
    const int P = bf_model_nvalues(r.model), P1 = P / C;
    double cost1 = 0.0;
    int iterations = 0, at_best = 1 << 30;
    for (int c = 0; c < C; c++) {
        bf_samples *sc = channel_of(s, c);
        bf_fit_result r1;
        bf_fit_result_init(&r1);
        assert_int_equal(bf_fit_with(sc, spec, &o, &r1, NULL), BF_OK);
        assert_true(r1.ok);
        assert_int_equal(bf_model_nvalues(r1.model), P1);
        for (int k1 = 0; k1 < P1; k1++) /* every parameter a colour: entry k1's channel c */
            assert_true(fabs(r.x[k1 * C + c] - r1.x[k1]) <= 1e-12 * (1.0 + fabs(r1.x[k1])));
        cost1 += r1.solution.final_cost;
        iterations += r1.solution.iterations;
        assert_int_equal(r.starts, r1.starts); /* the option's, in each channel */
        at_best = r1.starts_at_best < at_best ? r1.starts_at_best : at_best;
        bf_fit_result_clear(&r1);
        bf_samples_free(sc);
    }
    assert_true(fabs(r.solution.final_cost - cost1) <= 1e-12 * cost1);
    assert_int_equal(r.solution.iterations, iterations);
    assert_int_equal(r.starts_at_best, at_best);
    /* The metrics and the cost of the merged point, judged over every channel at once. */
    double cost;
    bf_metrics mt;
    assert_int_equal(bf_fit_evaluate_with(s, r.model, r.x, &o, &cost, &mt, NULL), BF_OK);
    assert_true(fabs(cost - r.solution.final_cost) <= 1e-10 * cost);
    assert_true(mt.n == r.metrics.n && mt.n == (size_t)C * NS);
    int inactive = 0; /* entries without effect at the point: not counted in the fit's k */
    for (int k = 0; k < P; k++)
        inactive += r.inactive[k];
    assert_int_equal(mt.k - inactive, r.metrics.k);
    assert_true(mt.rmse == r.metrics.rmse && mt.rmse_log == r.metrics.rmse_log && mt.max_err == r.metrics.max_err);
    assert_true(mt.loglik == r.metrics.loglik && mt.crit_n == r.metrics.crit_n);
    /* The standard errors come from J^T J of all channels, which couples none: the
     * covariance between two channels' entries is 0. */
    for (int a = 0; a < P; a++) {
        if (r.inactive[a])
            continue;
        assert_false(r.stderr_[a] <= 0.0); /* positive, or NaN on a bound */
        for (int b = 0; b < P; b++)
            if (a % C != b % C && !r.inactive[b] && isfinite(r.covariance[a * P + b]))
                assert_true(fabs(r.covariance[a * P + b]) <= 1e-12 * r.stderr_[a] * r.stderr_[b]);
    }
    bf_fit_result_clear(&r);
}

static void test_sgd_separable(void **state)
{
    (void)state;
    /* rho_d, rho_s, alpha, p, f0, f1, lambda, s, k, theta0, each for r, g, b: three of
     * the published MERL materials' kinds (plastic, metal, paint) in one set. */
    const double x[30] = {0.05, 0.02, 0.01, 0.5, 1.0,  2.0,  0.02, 0.05, 0.1, 0.4, 0.6, 0.8, 1.0, 0.9, 0.8,
                          0.1,  0.3,  0.5,  1.0, 10.0, 50.0, 1.2,  1.5,  1.8, 2.0, 1.5, 3.0, 0.2, 0.3, 0.1};
    bf_samples *s = make_samples("sgd", x, 3);
    check_separable("sgd", s);
    bf_samples_free(s);
}

/* Which fits run channel by channel: sgd on several channels, and nothing else. */
static int separable(const char *spec, int C)
{
    bf_model *m = ts_model(spec, C);
    const double x[30] = {0};
    bf_samples *s = make_samples("lambert", x, C);
    bf_objective *obj = NULL;
    assert_int_equal(bf_objective_new(m, s, NULL, &obj, NULL), BF_OK);
    const int yes = bf_fit_channels_separable(obj);
    bf_objective_free(obj);
    bf_samples_free(s);
    bf_model_free(m);
    return yes;
}

static void test_which_fits(void **state)
{
    (void)state;
    assert_true(separable("sgd", 3));
    assert_true(separable("sgd", 2));
    assert_false(separable("sgd", 1));               /* one channel: nothing to split */
    assert_false(separable("sgd:mono=specular", 3)); /* free scalars tie the channels */
    assert_false(separable("lambert", 3));           /* qualifies, not declared (family.h) */
    assert_false(separable("cook_torrance", 3));
    assert_false(separable("disney", 3));
}

/* --fix on one channel reaches that channel's fit alone. */
static void test_fix_one_channel(void **state)
{
    (void)state;
    bf_samples *s = make_samples("sgd", (const double[30]){0.05, 0.02, 0.01, 0.5, 1.0, 2.0, 0.02, 0.05, 0.1, 0.4,
                                                           0.6,  0.8,  1.0,  0.9, 0.8, 0.1, 0.3,  0.5,  1.0, 10.0,
                                                           50.0, 1.2,  1.5,  1.8, 2.0, 1.5, 3.0,  0.2,  0.3, 0.1},
                                 3);
    bf_fit_options o;
    fit_options(&o);
    bf_override ov;
    assert_int_equal(bf_override_parse_fix("rho_d[1]=0.03", &ov, NULL), BF_OK);
    o.objective.overrides = &ov;
    o.objective.noverrides = 1;
    bf_fit_result r;
    bf_fit_result_init(&r);
    assert_int_equal(bf_fit_with(s, "sgd", &o, &r, NULL), BF_OK);
    assert_true(r.ok && r.x[1] == 0.03 && r.fixed[1] && r.stderr_[1] == 0.0);
    for (int k = 0; k < bf_model_nvalues(r.model); k++)
        assert_int_equal(r.fixed[k], k == 1);
    bf_fit_result_clear(&r);
    bf_samples_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sgd_separable),
        cmocka_unit_test(test_which_fits),
        cmocka_unit_test(test_fix_one_channel),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
