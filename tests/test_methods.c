/* The method registry (solve.h): its invariants, parsing as tradeoff and the command
 * line write methods, the checks made before any work, and every method running on a
 * one-parameter problem through its back end (so no registry entry lacks a back-end
 * mapping). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "brdfit/solve.h"

static void test_registry(void **state)
{
    (void)state;
    int defaults[2] = {0, 0};
    for (int i = 0; i < bf_method_count(); i++) {
        const bf_method_info *m = bf_method_get(i);
        assert_non_null(m->name);
        assert_non_null(m->summary);
        defaults[m->backend] += (m->caps & BF_METHOD_DEFAULT) != 0;
        assert_true(m->caps & BF_METHOD_BOUNDS);
        for (int j = 0; j < i; j++) /* names unique within a back end */
            assert_false(bf_method_get(j)->backend == m->backend && !strcmp(bf_method_get(j)->name, m->name));
        assert_ptr_equal(bf_method_find(m->backend, m->name), m);
        /* A global method is never a local one. */
        assert_false((m->caps & BF_METHOD_GLOBAL) && (m->caps & BF_METHOD_LOCAL));
    }
    assert_int_equal(defaults[BF_BACKEND_CERES], 1);
    assert_int_equal(defaults[BF_BACKEND_NLOPT], 1);
    assert_null(bf_method_get(bf_method_count()));
    assert_string_equal(bf_method_default(BF_BACKEND_CERES)->name, "lm");
    assert_string_equal(bf_method_default(BF_BACKEND_NLOPT)->name, "LD_LBFGS");
    assert_string_equal(bf_method_find(BF_BACKEND_CERES, "levenberg_marquardt")->name, "lm");
    assert_string_equal(bf_method_find(BF_BACKEND_NLOPT, "ln_bobyqa")->name, "LN_BOBYQA");
    assert_null(bf_method_find(BF_BACKEND_CERES, "LD_LBFGS"));
    char list[256];
    bf_method_list(BF_BACKEND_NLOPT, BF_METHOD_CONSTRAINTS, 0, list, sizeof list);
    assert_string_equal(list, "LD_SLSQP, LD_MMA, LN_COBYLA, GN_ISRES");
}

static void test_parse(void **state)
{
    (void)state;
    static const struct {
        const char *text, *name;
        bf_backend backend;
    } ok[] = {
        {"ceres", "lm", BF_BACKEND_CERES},
        {"ceres:dogleg", "dogleg", BF_BACKEND_CERES},
        {"dogleg", "dogleg", BF_BACKEND_CERES},
        {"lm", "lm", BF_BACKEND_CERES},
        {"nlopt", "LD_LBFGS", BF_BACKEND_NLOPT},
        {"nlopt:LN_BOBYQA", "LN_BOBYQA", BF_BACKEND_NLOPT},
        {"LN_COBYLA", "LN_COBYLA", BF_BACKEND_NLOPT},
        {"gn_isres", "GN_ISRES", BF_BACKEND_NLOPT},
    };
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++) {
        bf_backend b;
        const bf_method_info *m;
        bf_error err;
        assert_int_equal(bf_method_parse(ok[i].text, &b, &m, &err), BF_OK);
        assert_int_equal(b, ok[i].backend);
        assert_string_equal(m->name, ok[i].name);
    }
    const char *bad[] = {"", "ceres:LD_LBFGS", "nlopt:lm", "LX_NOPE", "gpu:lm"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        bf_backend b;
        const bf_method_info *m;
        bf_error err;
        assert_int_equal(bf_method_parse(bad[i], &b, &m, &err), BF_ERR_ARG);
    }
}

static void test_check(void **state)
{
    (void)state;
    bf_error err;
    bf_solver_options o;
    bf_solver_options_init(&o);
    assert_int_equal(bf_solver_options_check(&o, &err), BF_OK); /* ceres, its default */
    o.use_constraint = 1;
    assert_int_equal(bf_solver_options_check(&o, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "ceres method lm does not take constraints (those that do: LD_SLSQP"));
    o.backend = BF_BACKEND_NLOPT;
    o.algorithm = "LD_SLSQP";
    assert_int_equal(bf_solver_options_check(&o, &err), BF_OK);
    o.use_constraint = 0;
    o.algorithm = "G_MLSL_LDS";
    o.local_algorithm = "GN_DIRECT_L";
    assert_int_equal(bf_solver_options_check(&o, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "is not a local NLopt method"));
    o.local_algorithm = "LN_SBPLX";
    assert_int_equal(bf_solver_options_check(&o, &err), BF_OK);
    o.algorithm = "dogleg";
    assert_int_equal(bf_solver_options_check(&o, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "unknown nlopt method \"dogleg\""));
}

static int quadratic(void *ctx, const double *x, size_t r0, size_t r1, double *res, double *jac)
{
    (void)ctx;
    for (size_t r = r0; r < r1; r++) {
        res[r - r0] = x[0] - 0.25 * (double)(r + 1);
        if (jac)
            jac[r - r0] = 1.0;
    }
    return 0;
}

/* Every registered method solves min sum (x - r/4)^2 over [-10, 10]: x = 0.5 for r = 1..3. */
static void test_every_method_runs(void **state)
{
    (void)state;
    for (int i = 0; i < bf_method_count(); i++) {
        const bf_method_info *m = bf_method_get(i);
        double lo = -10.0, hi = 10.0, x = 3.0;
        bf_problem p;
        bf_problem_init(&p);
        p.nres = 3;
        p.npar = 1;
        p.lo = &lo;
        p.hi = &hi;
        p.eval = quadratic;
        bf_solver_options o;
        bf_solver_options_init(&o);
        o.backend = m->backend;
        o.algorithm = m->name;
        o.max_iterations = m->caps & BF_METHOD_GLOBAL ? 4000 : 0;
        bf_solution sol;
        bf_error err;
        int rc = bf_solve(&p, &o, &x, &sol, &err);
        if (rc != BF_OK)
            fail_msg("%s: %s", m->name, err.msg);
        if (!(fabs(x - 0.5) < 1e-2))
            fail_msg("%s: x = %g, expected 0.5", m->name, x);
    }
}

/* The solver options and the problem carry their sizes (docs/api.md): init's defaults (a
 * zeroed struct's), and a struct not set up by its init refused with one line. */
static void test_sizes(void **state)
{
    (void)state;
    bf_solver_options o;
    memset(&o, 0xff, sizeof o); /* every field set, not left from a zeroed frame */
    bf_solver_options_init(&o);
    assert_int_equal(o.size, sizeof o);
    assert_int_equal(o.backend, BF_BACKEND_CERES);
    assert_null(o.algorithm);
    assert_int_equal(o.max_iterations, 0);
    assert_int_equal(o.loss.kind, BF_LOSS_NONE);
    assert_null(o.cancel);
    bf_problem p;
    memset(&p, 0xff, sizeof p);
    bf_problem_init(&p);
    assert_int_equal(p.size, sizeof p);
    assert_null(p.eval);
    assert_null(p.normal);

    double lo = -10.0, hi = 10.0, x = 3.0;
    p.nres = 3;
    p.npar = 1;
    p.lo = &lo;
    p.hi = &hi;
    p.eval = quadratic;
    bf_solution sol;
    bf_error err;
    assert_int_equal(bf_solve(&p, NULL, &x, &sol, &err), BF_OK); /* NULL: init's defaults */
    assert_true(fabs(x - 0.5) < 1e-8);

    o.size = 0;
    assert_int_equal(bf_solver_options_check(&o, &err), BF_ERR_ARG);
    assert_string_equal(err.msg,
                        "bf_solver_options: size 0 is not that of a bf_solver_options (set it with its init function)");
    x = 3.0;
    assert_int_equal(bf_solve(&p, &o, &x, &sol, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "bf_solver_options: size 0"));
    assert_true(x == 3.0); /* nothing ran */
    o.size = sizeof o;
    p.size = sizeof p - 1;
    assert_int_equal(bf_solve(&p, &o, &x, &sol, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "bf_problem: size"));
    assert_non_null(strstr(err.msg, "(set it with its init function)"));
    p.size = sizeof p;
    assert_int_equal(bf_solve(&p, &o, &x, &sol, &err), BF_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_registry),          cmocka_unit_test(test_parse), cmocka_unit_test(test_check),
        cmocka_unit_test(test_every_method_runs), cmocka_unit_test(test_sizes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
