/* The spec option mono: colour parameters tied across channels. A tied model must
 * equal the untied one with the value repeated per channel, its gradient must match
 * finite differences, and a fit must recover a white highlight with fewer parameters. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/fit.h"
#include "support.h"

/* Above eval_mono's chunk (16384 / (C P) samples: 682 for walter on RGB), so several
 * chunks, and ranges that do not start at 0, are checked. */
enum { NDIRS = 1500 };

static bf_geometry *random_geometry(ts_rng *r)
{
    double ti[NDIRS], pi_[NDIRS], to[NDIRS], po[NDIRS];
    ts_random_dirs(r, NDIRS, ti, pi_, to, po);
    bf_error err;
    bf_geometry *g = NULL;
    bf_geometry_from_angles(NDIRS, ti, pi_, to, po, &g, &err);
    assert_non_null(g);
    return g;
}

static void test_table_and_spec(void **state)
{
    (void)state;
    bf_model *m = ts_model("walter:mono=rho_s", 3);
    /* rho_d 3 + rho_s 1 + alpha + f0 */
    assert_int_equal(bf_model_nvalues(m), 6);
    int i = bf_model_find_param(m, "rho_s");
    assert_true(i >= 0);
    assert_int_equal(bf_model_param(m, i)->color, 0);
    assert_int_equal(bf_model_param(m, i)->mono, 1);
    assert_int_equal(bf_model_param(m, bf_model_find_param(m, "rho_d"))->color, 1);
    /* rho_s is walter's "specular" set, so the canonical spec says so, and reads back. */
    assert_string_equal(bf_model_option(m, "mono"), "specular");
    assert_non_null(strstr(bf_model_spec(m), "mono=specular"));
    bf_model *again = ts_model(bf_model_spec(m), 3);
    assert_string_equal(bf_model_spec(again), bf_model_spec(m));
    assert_int_equal(bf_model_nvalues(again), 6);
    bf_model_free(again);
    bf_model_free(m);

    m = ts_model("cook_torrance:lobes=2,mono=rho_s_2", 3);
    assert_string_equal(bf_model_option(m, "mono"), "rho_s_2");
    assert_int_equal(bf_model_nvalues(m), 3 + 3 + 1 + 1 + 1 + 1 + 1);
    bf_model_free(m);

    m = ts_model("lambert:mono=all", 3);
    assert_int_equal(bf_model_nvalues(m), 1);
    bf_model_free(m);

    /* One channel: nothing to tie, same layout. */
    m = ts_model("walter:mono=specular", 1);
    assert_int_equal(bf_model_nvalues(m), 4);
    bf_model_free(m);

    /* Untied models say no mono. */
    m = ts_model("walter", 3);
    assert_null(bf_model_option(m, "mono"));
    assert_int_equal(bf_model_param(m, bf_model_find_param(m, "rho_s"))->mono, 0);
    bf_model_free(m);
}

static void test_bad_specs(void **state)
{
    (void)state;
    static const struct {
        const char *spec, *fragment;
    } bad[] = {
        {"lambert:mono=specular", "ties nothing"},
        {"walter:mono=alpha", "not a colour parameter"},
        {"walter:mono=rho_q", "not one of its parameters"},
        {"walter:mono=rho_s,mono=rho_d", "given twice"},
        {"walter:mono=", "not key=value"},
        {"walter:mono=rho_s+", "ends with"},
        {"disney:mono=specular", "ties nothing"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        bf_error err;
        bf_model *m = NULL;
        bf_model_new(bad[k].spec, 3, &m, &err);
        if (m || !strstr(err.msg, bad[k].fragment))
            fail_msg("%s: expected an error with '%s', got %s", bad[k].spec, bad[k].fragment, m ? "a model" : err.msg);
    }
}

/* Values equal the untied model with the tied value in every channel; the Jacobian
 * matches central differences. */
static void check_against_untied(const char *untied_spec, const char *mono_spec, int C, ts_rng *r)
{
    bf_model *mu = ts_model(untied_spec, C), *mm = ts_model(mono_spec, C);
    const int Pu = bf_model_nvalues(mu), Pm = bf_model_nvalues(mm), np = bf_model_nparams(mm);
    assert_int_equal(bf_model_nparams(mu), np);
    assert_true(Pm < Pu);
    bf_geometry *g = random_geometry(r);
    double *xm = malloc((size_t)Pm * sizeof *xm), *xu = malloc((size_t)Pu * sizeof *xu);
    ts_random_params(mm, r, TS_PARAMS_MODERATE, xm);
    for (int i = 0; i < np; i++) {
        const bf_param_info *p = bf_model_param(mm, i);
        for (int c = 0; c < C; c++)
            if (bf_model_param(mu, i)->color || c == 0)
                xu[bf_model_param_offset(mu, i) + c] = xm[bf_model_param_offset(mm, i) + (p->color ? c : 0)];
    }
    size_t nv = (size_t)NDIRS * (size_t)C;
    double *vm = malloc(nv * sizeof *vm), *vu = malloc(nv * sizeof *vu);
    double *grad = malloc(nv * (size_t)Pm * sizeof *grad);
    bf_model_eval(mu, xu, g, vu, NULL);
    bf_model_eval(mm, xm, g, vm, grad);
    for (size_t k = 0; k < nv; k++)
        ts_assert_near(vm[k], vu[k], 1e-14, 1e-300, mono_spec);
    /* Values alone (no gradient) take the same path to the same numbers. */
    double *v2 = malloc(nv * sizeof *v2);
    bf_model_eval(mm, xm, g, v2, NULL);
    for (size_t k = 0; k < nv; k++)
        assert_true(v2[k] == vm[k]);
    for (int k = 0; k < Pm; k++) {
        double x0 = xm[k], h = 1e-6 * (fabs(x0) > 1e-3 ? fabs(x0) : 1e-3);
        xm[k] = x0 + h;
        double *a = ts_eval(mm, xm, g);
        xm[k] = x0 - h;
        double *b = ts_eval(mm, xm, g);
        xm[k] = x0;
        for (size_t q = 0; q < nv; q++) {
            double fd = (a[q] - b[q]) / (2.0 * h);
            /* Relative agreement, plus the rounding of the difference quotient (about
             * 1e-16 |value| / h) and a floor for derivatives near 0. */
            double g = grad[q * (size_t)Pm + (size_t)k];
            double tol = 1e-5 * (fabs(fd) + fabs(g)) + 1e-14 * fabs(vm[q]) / h + 1e-9 * (fabs(vm[q]) + 1.0);
            if (fabs(g - fd) > tol)
                fail_msg("%s: d value[%zu] / d x[%d] = %.10g, finite difference %.10g", mono_spec, q, k,
                         grad[q * (size_t)Pm + (size_t)k], fd);
        }
        free(a);
        free(b);
    }
    /* A range not starting at 0 gives the same values and Jacobian rows. */
    const size_t i0 = 700, i1 = NDIRS;
    double *gr = malloc((i1 - i0) * (size_t)C * (size_t)Pm * sizeof *gr);
    bf_model_eval_range(mm, xm, g, i0, i1, v2, gr);
    for (size_t q = 0; q < (i1 - i0) * (size_t)C; q++) {
        assert_true(v2[q] == vm[i0 * (size_t)C + q]);
        for (int k = 0; k < Pm; k++)
            assert_true(gr[q * (size_t)Pm + (size_t)k] == grad[(i0 * (size_t)C + q) * (size_t)Pm + (size_t)k]);
    }
    free(gr);
    free(v2);
    free(vm);
    free(vu);
    free(grad);
    free(xm);
    free(xu);
    bf_geometry_free(g);
    bf_model_free(mu);
    bf_model_free(mm);
}

static void test_values_and_gradient(void **state)
{
    (void)state;
    ts_rng r = {0x6d6f6e6fULL};
    check_against_untied("walter", "walter:mono=specular", 3, &r);
    check_against_untied("ashikhmin_shirley", "ashikhmin_shirley:mono=rho_s", 3, &r);
    check_against_untied("cook_torrance:lobes=2", "cook_torrance:lobes=2,mono=specular", 3, &r);
    check_against_untied("lafortune:lobes=2", "lafortune:lobes=2,mono=rho_s_1", 4, &r);
    check_against_untied("oren_nayar", "oren_nayar:mono=all", 3, &r);
    check_against_untied("disney", "disney:mono=all", 3, &r);
    check_against_untied("ward", "ward:mono=specular", 5, &r);
}

/* A white highlight on coloured data: the tied model fits it exactly with 6 parameters
 * instead of 8, and its rho_s is the one value every channel had. */
static void test_fit_recovers_white_highlight(void **state)
{
    (void)state;
    enum { N = 3000 };
    bf_error err;
    bf_samples *s = NULL;
    bf_samples_new(N, 3, &s, &err);
    assert_non_null(s);
    ts_rng r = {12345};
    for (size_t i = 0; i < N; i++)
        ts_random_pair_deg(&r, i % 3 == 0, &s->theta_i[i], &s->phi_i[i], &s->theta_o[i], &s->phi_o[i]);
    bf_model *truth = ts_model("walter", 3);
    const double xt[] = {0.6, 0.3, 0.1, 0.4, 0.4, 0.4, 0.15, 0.05};
    const bf_geometry *g = NULL;
    bf_samples_geometry(s, &g, &err);
    assert_non_null(g);
    bf_model_eval(truth, xt, g, s->value, NULL);

    bf_fit_options o;
    memset(&o, 0, sizeof o);
    bf_objective_options_init(&o.objective); /* the embedded structs carry their sizes */
    bf_solver_options_init(&o.solver);
    o.objective.residual = BF_RESIDUAL_LOG;
    o.solver.backend = BF_BACKEND_CERES;
    o.starts = 1;
    bf_fit_result res;
    assert_int_equal(bf_fit_with(s, "walter:mono=specular", &o, &res, &err), BF_OK);
    assert_true(res.ok);
    assert_int_equal(res.metrics.k, 6);
    const bf_model *m = res.model;
    ts_assert_rel(res.x[bf_model_param_offset(m, bf_model_find_param(m, "rho_s"))], 0.4, 1e-6, "rho_s");
    ts_assert_rel(res.x[bf_model_param_offset(m, bf_model_find_param(m, "alpha"))], 0.15, 1e-6, "alpha");
    for (int c = 0; c < 3; c++)
        ts_assert_rel(res.x[bf_model_param_offset(m, bf_model_find_param(m, "rho_d")) + c], xt[c], 1e-6, "rho_d");
    assert_true(res.metrics.rmse < 1e-8);
    bf_fit_result_clear(&res);
    bf_model_free(truth);
    bf_samples_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table_and_spec),
        cmocka_unit_test(test_bad_specs),
        cmocka_unit_test(test_values_and_gradient),
        cmocka_unit_test(test_fit_recovers_white_highlight),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
