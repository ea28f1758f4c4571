/* The NLopt back end through bf_solve, on hand-made problems with known answers:
 * exponential decay (exact data), a multimodal 1-D cost, a straight line with an
 * outlier, plus bounds, constants, a constraint, threads, seeds and the errors. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/solve.h"
#include "optim/backends.h"
#include "support.h"

/* y_i = A exp(-k t_i) (+ outlier), parameters (A, k) or, with `line`, y = a + b t. */
typedef struct curve {
    size_t n;
    double *t, *y;
    int line;
    double fail_k;  /* eval fails (returns 1) where k > fail_k (0: never) */
    int nan_always; /* residuals are NaN */
    int passes;     /* calls with r0 == 0: whole-set passes (single writer) */
} curve;

static int curve_eval(void *ctx, const double *x, size_t r0, size_t r1, double *res, double *jac)
{
    curve *c = ctx;
    if (r0 == 0)
        c->passes++;
    if (c->fail_k > 0 && x[1] > c->fail_k)
        return 1;
    for (size_t i = r0; i < r1; i++) {
        const double t = c->t[i];
        double f, d0, d1;
        if (c->line) {
            f = x[0] + x[1] * t;
            d0 = 1.0;
            d1 = t;
        } else {
            const double e = exp(-x[1] * t);
            f = x[0] * e;
            d0 = e;
            d1 = -x[0] * t * e;
        }
        res[i - r0] = c->nan_always ? NAN : f - c->y[i];
        if (jac) {
            jac[(i - r0) * 2] = d0;
            jac[(i - r0) * 2 + 1] = d1;
        }
    }
    return 0;
}

static const double A_TRUE = 2.5, K_TRUE = 1.3;

static curve make_decay(size_t n)
{
    curve c = {0};
    c.n = n;
    c.t = malloc(n * sizeof *c.t);
    c.y = malloc(n * sizeof *c.y);
    for (size_t i = 0; i < n; i++) {
        c.t[i] = 4.0 * (double)i / (double)(n - 1);
        c.y[i] = A_TRUE * exp(-K_TRUE * c.t[i]);
    }
    return c;
}

static void free_curve(curve *c)
{
    free(c->t);
    free(c->y);
}

static double LO[2] = {0.0, 0.0}, HI[2] = {10.0, 10.0};

static bf_problem problem_of(curve *c)
{
    bf_problem p;
    bf_problem_init(&p);
    p.nres = c->n;
    p.npar = 2;
    p.lo = LO;
    p.hi = HI;
    p.eval = curve_eval;
    p.user = c;
    return p;
}

static bf_solver_options nlopt_opts(const char *alg)
{
    bf_solver_options o;
    bf_solver_options_init(&o);
    o.backend = BF_BACKEND_NLOPT;
    o.algorithm = alg;
    return o;
}

/* 1/2 sum r^2 at x, by hand. */
static double cost_at(curve *c, const double *x)
{
    double *r = malloc(c->n * sizeof *r), sum = 0;
    curve_eval(c, x, 0, c->n, r, NULL);
    c->passes--;
    for (size_t i = 0; i < c->n; i++)
        sum += r[i] * r[i];
    free(r);
    return 0.5 * sum;
}

static void check_decay_recovered(const char *alg)
{
    curve c = make_decay(200);
    bf_problem p = problem_of(&c);
    bf_solver_options o = nlopt_opts(alg);
    double x[2] = {1.0, 0.5};
    const double c0 = cost_at(&c, x);
    bf_solution s;
    bf_error err = {0};
    assert_int_equal(bf_solve(&p, &o, x, &s, &err), BF_OK);
    assert_true(s.usable);
    ts_assert_rel(x[0], A_TRUE, 1e-6, alg);
    ts_assert_rel(x[1], K_TRUE, 1e-6, alg);
    assert_string_equal(s.backend, "nlopt");
    assert_string_equal(s.algorithm, alg);
    ts_assert_rel(s.initial_cost, c0, 1e-14, "initial cost");
    ts_assert_rel(s.final_cost, cost_at(&c, x), 1e-12, "final cost");
    assert_true(s.final_cost < 1e-12 * c0);
    /* counts: the start's evaluation plus one per NLopt call, each a whole-set pass */
    assert_int_equal(s.evaluations, s.iterations + 1);
    assert_int_equal(s.evaluations, c.passes);
    assert_true(s.seconds >= 0.0);
    assert_true(strncmp(s.termination, "NLOPT_", 6) == 0);
    free_curve(&c);
}

static void test_decay_lbfgs(void **state)
{
    (void)state;
    check_decay_recovered("LD_LBFGS");
}
static void test_decay_bobyqa(void **state)
{
    (void)state;
    check_decay_recovered("LN_BOBYQA");
}
static void test_decay_others(void **state)
{
    (void)state;
    check_decay_recovered("LD_SLSQP");
    check_decay_recovered("LD_MMA");
}

/* Default algorithm (NULL) is LD_LBFGS. */
static void test_default_algorithm(void **state)
{
    (void)state;
    curve c = make_decay(50);
    bf_problem p = problem_of(&c);
    bf_solver_options o = nlopt_opts(NULL);
    double x[2] = {1.0, 0.5};
    bf_solution s;
    assert_int_equal(bf_solve(&p, &o, x, &s, NULL), BF_OK);
    assert_string_equal(s.algorithm, "LD_LBFGS");
    free_curve(&c);
}

/* F(x) = 1/2 (0.09 (x - 4)^2 + 2 sin^2 x): minima near every k pi, the global one near pi. */
static int multi_eval(void *ctx, const double *x, size_t r0, size_t r1, double *res, double *jac)
{
    (void)ctx;
    for (size_t i = r0; i < r1; i++) {
        const double v = i == 0 ? 0.3 * (x[0] - 4.0) : sqrt(2.0) * sin(x[0]);
        const double d = i == 0 ? 0.3 : sqrt(2.0) * cos(x[0]);
        res[i - r0] = v;
        if (jac)
            jac[i - r0] = d;
    }
    return 0;
}

/* The global minimiser: F'(x) = 0.09 (x - 4) + sin 2x = 0 on [2.8, 3.5], by bisection. */
static double multi_global(void)
{
    double a = 2.8, b = 3.5;
    for (int i = 0; i < 200; i++) {
        const double m = 0.5 * (a + b);
        const double fm = 0.09 * (m - 4) + sin(2 * m);
        if (fm > 0)
            b = m;
        else
            a = m;
    }
    return 0.5 * (a + b);
}

static double MLO[1] = {-5.0}, MHI[1] = {10.0};

static bf_problem multi_problem(void)
{
    bf_problem p;
    bf_problem_init(&p);
    p.nres = 2;
    p.npar = 1;
    p.lo = MLO;
    p.hi = MHI;
    p.eval = multi_eval;
    return p;
}

static void test_multimodal(void **state)
{
    (void)state;
    const double xg = multi_global();
    bf_problem p = multi_problem();
    bf_solution s;
    /* a local method from 0.3 stays in the basin near 0 */
    bf_solver_options o = nlopt_opts("LD_LBFGS");
    double x = 0.3;
    assert_int_equal(bf_solve(&p, &o, &x, &s, NULL), BF_OK);
    assert_true(s.usable);
    assert_true(fabs(x) < 0.5);
    const double local_cost = s.final_cost;

    o = nlopt_opts("GN_DIRECT_L");
    x = 0.3;
    assert_int_equal(bf_solve(&p, &o, &x, &s, NULL), BF_OK);
    assert_true(s.usable);
    ts_assert_rel(x, xg, 1e-4, "GN_DIRECT_L minimiser");
    assert_true(s.final_cost < 0.2 * local_cost);
    assert_true(s.iterations <= 20000);

    o = nlopt_opts("G_MLSL_LDS");
    o.max_iterations = 3000;
    x = 0.3;
    assert_int_equal(bf_solve(&p, &o, &x, &s, NULL), BF_OK);
    assert_true(s.usable);
    ts_assert_rel(x, xg, 1e-6, "G_MLSL_LDS minimiser");
    assert_string_equal(s.algorithm, "G_MLSL_LDS+LD_LBFGS");
    assert_int_equal(s.iterations, 3000); /* MLSL runs to its evaluation limit */
    assert_non_null(strstr(s.termination, "MAXEVAL_REACHED"));

    o.local_algorithm = "LN_BOBYQA";
    x = 0.3;
    assert_int_equal(bf_solve(&p, &o, &x, &s, NULL), BF_OK);
    ts_assert_rel(x, xg, 1e-5, "G_MLSL_LDS+LN_BOBYQA minimiser");
}

/* Stochastic methods: the same seed gives the same answer, bit for bit. */
static void test_seeded(void **state)
{
    (void)state;
    const double xg = multi_global();
    bf_problem p = multi_problem();
    const char *algs[] = {"GN_CRS2_LM", "GN_ISRES"};
    for (int a = 0; a < 2; a++) {
        double got[3];
        const uint64_t seeds[3] = {42, 42, 7};
        for (int r = 0; r < 3; r++) {
            bf_solver_options o = nlopt_opts(algs[a]);
            o.seed = seeds[r];
            o.max_iterations = 3000;
            got[r] = 0.3;
            bf_solution s;
            assert_int_equal(bf_solve(&p, &o, &got[r], &s, NULL), BF_OK);
            assert_true(s.usable);
            ts_assert_near(got[r], xg, 0, 0.05, algs[a]);
        }
        assert_true(got[0] == got[1]);
        (void)got[2]; /* another seed may or may not land on the same bits */
    }
}

static void test_bounds_respected(void **state)
{
    (void)state;
    const char *algs[] = {"LD_LBFGS", "LD_SLSQP", "LD_MMA", "LN_BOBYQA", "LN_SBPLX", "LN_NELDERMEAD", "LN_COBYLA"};
    for (size_t a = 0; a < sizeof algs / sizeof algs[0]; a++) {
        curve c = make_decay(100);
        double lo[2] = {0.5, 0.0}, hi[2] = {2.0, 10.0}; /* A's optimum (2.5) is outside */
        bf_problem p = problem_of(&c);
        p.lo = lo;
        p.hi = hi;
        bf_solver_options o = nlopt_opts(algs[a]);
        o.max_iterations = 20000;
        double x[2] = {1.0, 0.5};
        bf_solution s;
        assert_int_equal(bf_solve(&p, &o, x, &s, NULL), BF_OK);
        assert_true(s.usable);
        assert_true(x[0] >= lo[0] && x[0] <= hi[0]);
        assert_true(x[1] >= lo[1] && x[1] <= hi[1]);
        ts_assert_rel(x[0], 2.0, 1e-5, algs[a]);
        free_curve(&c);
    }
    /* a start outside the bounds is clamped (a constant parameter shows it exactly) */
    curve c = make_decay(100);
    bf_problem p = problem_of(&c);
    bf_solver_options o = nlopt_opts("LD_LBFGS");
    unsigned char constant[2] = {0, 1};
    o.constant = constant;
    double x[2] = {1.0, 12.0};
    bf_solution s;
    assert_int_equal(bf_solve(&p, &o, x, &s, NULL), BF_OK);
    assert_true(x[1] == 10.0);
    free_curve(&c);
}

static void test_constant_parameter(void **state)
{
    (void)state;
    const char *algs[] = {"LD_LBFGS", "LN_BOBYQA", "GN_DIRECT_L"};
    for (int a = 0; a < 3; a++) {
        curve c = make_decay(100);
        bf_problem p = problem_of(&c);
        bf_solver_options o = nlopt_opts(algs[a]);
        unsigned char constant[2] = {0, 1};
        o.constant = constant;
        double x[2] = {1.0, 1.0};
        bf_solution s;
        assert_int_equal(bf_solve(&p, &o, x, &s, NULL), BF_OK);
        assert_true(s.usable);
        assert_true(x[1] == 1.0);
        /* with k held, the best A is linear least squares: sum y e / sum e^2 */
        double num = 0, den = 0;
        for (size_t i = 0; i < c.n; i++) {
            const double e = exp(-c.t[i]);
            num += c.y[i] * e;
            den += e * e;
        }
        ts_assert_rel(x[0], num / den, a == 2 ? 1e-4 : 1e-6, algs[a]);
        free_curve(&c);
    }
    /* every parameter constant: nothing to do, the cost is reported */
    curve c = make_decay(10);
    bf_problem p = problem_of(&c);
    bf_solver_options o = nlopt_opts("LD_LBFGS");
    unsigned char all[2] = {1, 1};
    o.constant = all;
    double x[2] = {1.0, 1.0};
    bf_solution s;
    assert_int_equal(bf_solve(&p, &o, x, &s, NULL), BF_OK);
    assert_true(s.usable);
    assert_true(x[0] == 1.0 && x[1] == 1.0);
    ts_assert_rel(s.final_cost, cost_at(&c, x), 1e-14, "cost with no free parameter");
    free_curve(&c);
}

/* Constraint A + k <= 3 (the unconstrained optimum has 3.8). */
static double sum_constraint(void *ctx, const double *x, double *grad)
{
    (void)ctx;
    if (grad) {
        grad[0] = 1.0;
        grad[1] = 1.0;
    }
    return x[0] + x[1] - 3.0;
}

static void test_constraint(void **state)
{
    (void)state;
    const char *algs[] = {"LD_SLSQP", "LD_MMA", "LN_COBYLA"};
    for (int a = 0; a < 3; a++) {
        curve c = make_decay(100);
        bf_problem p = problem_of(&c);
        p.constraint = sum_constraint;
        bf_solver_options o = nlopt_opts(algs[a]);
        o.use_constraint = 1;
        o.max_iterations = 20000;
        double x[2] = {1.0, 0.5};
        bf_solution s;
        bf_error err = {0};
        assert_int_equal(bf_solve(&p, &o, x, &s, &err), BF_OK);
        assert_true(s.usable);
        ts_assert_near(x[0] + x[1], 3.0, 0, 1e-6, algs[a]); /* on the constraint */
        /* and optimal on it: the gradient J^T r is normal to the constraint (gA = gk) */
        double *r = malloc(c.n * sizeof *r), *J = malloc(2 * c.n * sizeof *J), g[2] = {0, 0};
        curve_eval(&c, x, 0, c.n, r, J);
        for (size_t i = 0; i < c.n; i++) {
            g[0] += J[2 * i] * r[i];
            g[1] += J[2 * i + 1] * r[i];
        }
        assert_true(g[0] < 0); /* the cost wants to leave through the constraint */
        ts_assert_near(g[1], g[0], a == 2 ? 1e-3 : 1e-5, 0, algs[a]);
        free(r);
        free(J);
        free_curve(&c);
    }
    /* GN_ISRES takes the constraint too: its answer is feasible */
    curve c = make_decay(100);
    bf_problem p = problem_of(&c);
    p.constraint = sum_constraint;
    bf_solver_options o = nlopt_opts("GN_ISRES");
    o.use_constraint = 1;
    o.seed = 3;
    o.max_iterations = 4000;
    double x[2] = {1.0, 0.5};
    bf_solution s;
    assert_int_equal(bf_solve(&p, &o, x, &s, NULL), BF_OK);
    assert_true(s.usable);
    assert_true(x[0] + x[1] <= 3.0 + 1e-9);
    free_curve(&c);
}

static void expect_error(const bf_problem *p, const bf_solver_options *o, int code, const char *f1, const char *f2)
{
    double x[2] = {1.0, 0.5};
    bf_solution s;
    bf_error err = {0};
    assert_int_equal(bf_solve(p, o, x, &s, &err), code);
    assert_int_equal(err.code, code);
    if (!strstr(err.msg, f1) || (f2 && !strstr(err.msg, f2)))
        fail_msg("message \"%s\" should contain \"%s\"%s%s", err.msg, f1, f2 ? " and " : "", f2 ? f2 : "");
    assert_null(strchr(err.msg, '\n'));
    assert_true(x[0] == 1.0 && x[1] == 0.5); /* x untouched, finite */
    assert_int_equal(s.usable, 0);
}

static void test_errors(void **state)
{
    (void)state;
    curve c = make_decay(20);
    bf_problem p = problem_of(&c);
    p.constraint = sum_constraint;
    bf_solver_options o = nlopt_opts("LN_BOBYQA");
    o.use_constraint = 1;
    expect_error(&p, &o, BF_ERR_ARG, "LN_BOBYQA does not take constraints", "LD_SLSQP");

    o = nlopt_opts("LD_FOO");
    expect_error(&p, &o, BF_ERR_ARG, "unknown nlopt method \"LD_FOO\"", "G_MLSL_LDS");
    o = nlopt_opts("G_MLSL_LDS");
    o.local_algorithm = "GN_DIRECT_L";
    expect_error(&p, &o, BF_ERR_ARG, "not a local NLopt method", "LN_SBPLX");

    /* global methods need finite bounds */
    double lo[2] = {0, 0}, hi[2] = {10, INFINITY};
    bf_problem q = p;
    q.lo = lo;
    q.hi = hi;
    o = nlopt_opts("GN_DIRECT_L");
    expect_error(&q, &o, BF_ERR_ARG, "needs finite bounds", "parameter 1");

    /* bf_solve's own checks */
    o = nlopt_opts("LD_LBFGS");
    q = p;
    q.npar = 0;
    expect_error(&q, &o, BF_ERR_ARG, "parameters", NULL);
    q = p;
    q.nres = 0;
    expect_error(&q, &o, BF_ERR_ARG, "no residuals", NULL);
    double blo[2] = {0, 5}, bhi[2] = {10, 4};
    q = p;
    q.lo = blo;
    q.hi = bhi;
    expect_error(&q, &o, BF_ERR_RANGE, "parameter 1 has bounds", NULL);
    o.threads = -2;
    expect_error(&p, &o, BF_ERR_ARG, "thread", NULL);

    double x[2] = {NAN, 0.5};
    bf_error err = {0};
    o = nlopt_opts("LD_LBFGS");
    assert_int_equal(bf_solve(&p, &o, x, NULL, &err), BF_ERR_RANGE);
    assert_non_null(strstr(err.msg, "NaN"));
    free_curve(&c);
}

/* Threads: the sums are taken in chunk order whatever the thread count, so the solve is
 * bit-for-bit the same for 1, 2, 3 and 8 threads (30000 residuals: 4 chunks). */
static void test_threads_agree(void **state)
{
    (void)state;
    const char *algs[] = {"LD_LBFGS", "LN_BOBYQA"};
    for (int a = 0; a < 2; a++) {
        double ref[2] = {0, 0}, refcost = 0;
        int refevals = 0;
        const int threads[] = {1, 2, 3, 8};
        for (int t = 0; t < 4; t++) {
            curve c = make_decay(30000);
            c.y[123] += 0.5; /* not an exact fit, so the cost is not ~0 */
            bf_problem p = problem_of(&c);
            bf_solver_options o = nlopt_opts(algs[a]);
            o.threads = threads[t];
            o.loss.kind = BF_LOSS_SOFT_L1;
            o.loss.scale = 0.1;
            double x[2] = {1.0, 0.5};
            bf_solution s;
            assert_int_equal(bf_solve(&p, &o, x, &s, NULL), BF_OK);
            assert_true(s.usable);
            if (t == 0) {
                memcpy(ref, x, sizeof ref);
                refcost = s.final_cost;
                refevals = s.evaluations;
                ts_assert_rel(x[1], K_TRUE, 1e-4, "k with an outlier and soft_l1");
            } else {
                if (x[0] != ref[0] || x[1] != ref[1] || s.final_cost != refcost)
                    fail_msg("%s with %d threads: (%.17g, %.17g) cost %.17g, one thread (%.17g, %.17g) "
                             "cost %.17g",
                             algs[a], threads[t], x[0], x[1], s.final_cost, ref[0], ref[1], refcost);
                assert_int_equal(s.evaluations, refevals);
            }
            free_curve(&c);
        }
    }
}

/* A robust loss lets an outlier pull far less: line y = 1 + 2 t with one point off by 50. */
static void test_robust_loss(void **state)
{
    (void)state;
    curve c = {0};
    c.n = 41;
    c.line = 1;
    c.t = malloc(c.n * sizeof *c.t);
    c.y = malloc(c.n * sizeof *c.y);
    for (size_t i = 0; i < c.n; i++) {
        c.t[i] = 0.1 * (double)i;
        c.y[i] = 1.0 + 2.0 * c.t[i];
    }
    c.y[20] += 50.0;
    double lo[2] = {-100, -100}, hi[2] = {100, 100};
    bf_problem p = problem_of(&c);
    p.lo = lo;
    p.hi = hi;
    bf_solver_options o = nlopt_opts("LD_LBFGS");
    double plain[2] = {0, 0};
    bf_solution s;
    assert_int_equal(bf_solve(&p, &o, plain, &s, NULL), BF_OK);
    /* least squares: the outlier moves the intercept by 50/41 (it sits at the mean t) */
    ts_assert_rel(plain[0], 1.0 + 50.0 / 41.0, 1e-6, "least-squares intercept");

    const char *losses[] = {"huber:0.1", "cauchy:0.1", "soft_l1:0.1", "arctan:0.1"};
    for (int l = 0; l < 4; l++) {
        o = nlopt_opts("LD_LBFGS");
        assert_int_equal(bf_loss_parse(losses[l], &o.loss, NULL), BF_OK);
        double x[2] = {0, 0};
        assert_int_equal(bf_solve(&p, &o, x, &s, NULL), BF_OK);
        assert_true(s.usable);
        if (!(fabs(x[0] - 1.0) < 0.05 * fabs(plain[0] - 1.0)))
            fail_msg("%s: intercept %g, least squares %g, truth 1", losses[l], x[0], plain[0]);
        ts_assert_near(x[1], 2.0, 0, 0.05, losses[l]);
        /* the reported cost is 1/2 sum rho(r^2) */
        double r[41], sum = 0;
        curve_eval(&c, x, 0, c.n, r, NULL);
        for (size_t i = 0; i < c.n; i++)
            sum += bf_loss_eval(&o.loss, r[i] * r[i], NULL);
        ts_assert_rel(s.final_cost, 0.5 * sum, 1e-12, "robust cost");
    }
    free_curve(&c);
}

/* Evaluation limits and failing evaluations: never NaN, the start kept when nothing works. */
static void test_limits_and_failures(void **state)
{
    (void)state;
    curve c = make_decay(100);
    bf_problem p = problem_of(&c);
    bf_solver_options o = nlopt_opts("LN_BOBYQA");
    o.max_iterations = 7;
    double x[2] = {1.0, 0.5};
    bf_solution s;
    assert_int_equal(bf_solve(&p, &o, x, &s, NULL), BF_OK);
    assert_int_equal(s.iterations, 7);
    assert_int_equal(s.evaluations, 8);
    assert_true(strncmp(s.termination, "NLOPT_MAXEVAL_REACHED", 21) == 0);
    assert_true(s.usable);
    assert_true(s.final_cost < s.initial_cost);

    /* evaluations fail where k > 2: the solver steers around them */
    c.fail_k = 2.0;
    o = nlopt_opts("LN_BOBYQA");
    x[0] = 1.0;
    x[1] = 0.5;
    assert_int_equal(bf_solve(&p, &o, x, &s, NULL), BF_OK);
    assert_true(s.usable);
    ts_assert_rel(x[1], K_TRUE, 1e-5, "k with failing evaluations");

    /* the start itself fails: BF_OK, not usable, start kept, said so */
    x[0] = 1.0;
    x[1] = 3.0;
    o = nlopt_opts("LD_LBFGS");
    assert_int_equal(bf_solve(&p, &o, x, &s, NULL), BF_OK);
    assert_int_equal(s.usable, 0);
    assert_true(x[0] == 1.0 && x[1] == 3.0);
    assert_non_null(strstr(s.termination, "not finite"));
    assert_false(isnan(s.final_cost));

    /* NaN everywhere */
    c.fail_k = 0;
    c.nan_always = 1;
    o = nlopt_opts("LN_NELDERMEAD");
    x[0] = 1.0;
    x[1] = 0.5;
    assert_int_equal(bf_solve(&p, &o, x, &s, NULL), BF_OK);
    assert_int_equal(s.usable, 0);
    assert_true(x[0] == 1.0 && x[1] == 0.5);
    free_curve(&c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_decay_lbfgs),         cmocka_unit_test(test_decay_bobyqa),
        cmocka_unit_test(test_decay_others),        cmocka_unit_test(test_default_algorithm),
        cmocka_unit_test(test_multimodal),          cmocka_unit_test(test_seeded),
        cmocka_unit_test(test_bounds_respected),    cmocka_unit_test(test_constant_parameter),
        cmocka_unit_test(test_constraint),          cmocka_unit_test(test_errors),
        cmocka_unit_test(test_threads_agree),       cmocka_unit_test(test_robust_loss),
        cmocka_unit_test(test_limits_and_failures),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
