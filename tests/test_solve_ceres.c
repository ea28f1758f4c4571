/* The Ceres back end on small hand-made problems with known answers: exponential decay
 * y = a exp(-b t) (noiseless, so the optimum is the generating parameters) and a
 * straight line with one gross outlier (for the robust losses). No models needed. */
#include <fcntl.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "brdfit/solve.h"
#include "optim/backends.h"
#include "support.h"

#define A_TRUE 2.5
#define B_TRUE 0.7

/* Problem data and what the callbacks saw. */
typedef struct decay {
    size_t n;
    double *t, *y;
    int line;                     /* 1: residuals c0 + c1 t - y instead of the decay */
    double fail_above;            /* eval fails where x[1] > fail_above (INFINITY: never) */
    int fail_with_nan;            /* ... by writing NaN instead of returning non-zero */
    atomic_ullong residuals_done; /* residuals evaluated, all calls */
    atomic_ullong bad_ranges;     /* calls with an empty, oversized or out-of-range range */
} decay;

static int eval(void *ctx, const double *x, size_t r0, size_t r1, double *res, double *jac)
{
    decay *d = ctx;
    if (r1 <= r0 || r1 > d->n || r1 - r0 > 65536)
        atomic_fetch_add(&d->bad_ranges, 1);
    atomic_fetch_add(&d->residuals_done, r1 - r0);
    int fail = x[1] > d->fail_above;
    if (fail && !d->fail_with_nan)
        return 1;
    for (size_t r = r0; r < r1; r++) {
        size_t i = r - r0;
        double t = d->t[r];
        if (d->line) {
            res[i] = x[0] + x[1] * t - d->y[r];
            if (jac) {
                jac[i * 2] = 1.0;
                jac[i * 2 + 1] = t;
            }
        } else {
            double e = exp(-x[1] * t);
            res[i] = x[0] * e - d->y[r];
            if (jac) {
                jac[i * 2] = e;
                jac[i * 2 + 1] = -x[0] * t * e;
            }
        }
        if (fail)
            res[i] = NAN;
    }
    return 0;
}

/* n samples of a exp(-b t) on t in [0, 5). */
static decay *decay_new(size_t n)
{
    decay *d = calloc(1, sizeof *d);
    d->n = n;
    d->t = malloc(n * sizeof *d->t);
    d->y = malloc(n * sizeof *d->y);
    for (size_t i = 0; i < n; i++) {
        d->t[i] = 5.0 * (double)i / (double)n;
        d->y[i] = A_TRUE * exp(-B_TRUE * d->t[i]);
    }
    d->fail_above = INFINITY;
    atomic_init(&d->residuals_done, 0);
    atomic_init(&d->bad_ranges, 0);
    return d;
}

static void decay_free(decay *d)
{
    free(d->t);
    free(d->y);
    free(d);
}

static bf_problem problem(decay *d, const double *lo, const double *hi)
{
    bf_problem p;
    bf_problem_init(&p);
    p.nres = d->n;
    p.npar = 2;
    p.lo = lo;
    p.hi = hi;
    p.eval = eval;
    p.user = d;
    return p;
}

/* The defaults (a zeroed struct's, its size set). */
static bf_solver_options solver_options(void)
{
    bf_solver_options o;
    bf_solver_options_init(&o);
    return o;
}

static const double LO[2] = {-INFINITY, -INFINITY}, HI[2] = {INFINITY, INFINITY};

static void solve_ok(const bf_problem *p, const bf_solver_options *o, double *x, bf_solution *s)
{
    bf_error err;
    bf_error_clear(&err);
    int rc = bf_solve_ceres(p, o, x, s, &err);
    if (rc != BF_OK)
        fail_msg("bf_solve_ceres: %s", err.msg);
    assert_true(isfinite(x[0]) && isfinite(x[1]));
}

/* 1/2 sum r^2 of the decay problem at x, computed independently. */
static double decay_cost(const decay *d, const double *x)
{
    double c = 0.0;
    for (size_t i = 0; i < d->n; i++) {
        double r = x[0] * exp(-x[1] * d->t[i]) - d->y[i];
        c += 0.5 * r * r;
    }
    return c;
}

static void test_decay_recovers_parameters(void **state)
{
    (void)state;
    decay *d = decay_new(50);
    bf_problem p = problem(d, LO, HI);
    bf_solver_options o = solver_options();
    double x[2] = {0.1, 3.0}; /* far off: a 25x too small, b 4x too large */
    bf_solution s;
    solve_ok(&p, &o, x, &s);
    ts_assert_rel(x[0], A_TRUE, 1e-8, "a");
    ts_assert_rel(x[1], B_TRUE, 1e-8, "b");
    assert_int_equal(s.usable, 1);
    decay_free(d);
}

static void test_summary_filled(void **state)
{
    (void)state;
    decay *d = decay_new(50);
    bf_problem p = problem(d, LO, HI);
    bf_solver_options o = solver_options();
    double x[2] = {1.0, 2.0};
    double want_initial = decay_cost(d, x);
    bf_solution s;
    solve_ok(&p, &o, x, &s);
    assert_int_equal(s.usable, 1);
    assert_true(s.iterations > 0);
    assert_true(s.evaluations >= s.iterations);
    assert_true(s.final_cost <= s.initial_cost);
    ts_assert_rel(s.initial_cost, want_initial, 1e-12, "initial cost");
    assert_true(s.final_cost < 1e-20); /* noiseless data: the optimum has zero cost */
    assert_true(s.seconds >= 0.0);
    assert_string_equal(s.backend, "ceres");
    assert_string_equal(s.algorithm, "levenberg_marquardt");
    assert_non_null(strstr(s.termination, "CONVERGENCE"));
    assert_null(strchr(s.termination, '\n'));
    /* Every evaluation covers the whole set, in valid ranges. */
    assert_int_equal(atomic_load(&d->bad_ranges), 0);
    assert_int_equal(atomic_load(&d->residuals_done) % d->n, 0);
    decay_free(d);
}

static void test_iteration_limit(void **state)
{
    (void)state;
    decay *d = decay_new(50);
    bf_problem p = problem(d, LO, HI);
    bf_solver_options o = solver_options();
    o.max_iterations = 2;
    double x[2] = {2.0, 1.0};
    bf_solution s;
    solve_ok(&p, &o, x, &s);
    assert_int_equal(s.usable, 1); /* a limit is not a failure */
    assert_true(s.iterations >= 1 && s.iterations <= 2);
    assert_non_null(strstr(s.termination, "NO_CONVERGENCE"));
    assert_true(s.final_cost < s.initial_cost);
    ts_assert_rel(s.final_cost, decay_cost(d, x), 1e-12, "final cost at the returned x");
    decay_free(d);
}

static void test_bounds_active(void **state)
{
    (void)state;
    decay *d = decay_new(50);
    /* b capped below its true value, a floored above its best value for that cap. */
    const double lo[2] = {0.0, 0.1}, hi[2] = {10.0, 0.5};
    bf_problem p = problem(d, lo, hi);
    bf_solver_options o = solver_options();
    double x[2] = {1.0, 3.0}; /* b outside: clamped to 0.5 before the solve */
    bf_solution s;
    solve_ok(&p, &o, x, &s);
    assert_int_equal(s.usable, 1);
    assert_true(x[1] == 0.5);
    /* With b at its bound, a is the linear least-squares value sum(y e) / sum(e e). */
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < d->n; i++) {
        double e = exp(-0.5 * d->t[i]);
        num += d->y[i] * e;
        den += e * e;
    }
    ts_assert_rel(x[0], num / den, 1e-8, "a with b at its upper bound");

    /* Lower bound on a active at the solution (true a = 2.5 > 3 is excluded). */
    const double lo2[2] = {3.0, 0.0}, hi2[2] = {10.0, 5.0};
    p = problem(d, lo2, hi2);
    x[0] = 5.0;
    x[1] = 1.0;
    solve_ok(&p, &o, x, &s);
    assert_int_equal(s.usable, 1);
    assert_true(x[0] == 3.0);
    assert_true(x[1] >= 0.0 && x[1] <= 5.0);
    decay_free(d);
}

static void test_constant_parameter(void **state)
{
    (void)state;
    decay *d = decay_new(50);
    bf_problem p = problem(d, LO, HI);
    const unsigned char fixed[2] = {0, 1};
    bf_solver_options o = solver_options();
    o.constant = fixed;
    double x[2] = {0.2, 0.6};
    bf_solution s;
    solve_ok(&p, &o, x, &s);
    assert_int_equal(s.usable, 1);
    assert_true(x[1] == 0.6);
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < d->n; i++) {
        double e = exp(-0.6 * d->t[i]);
        num += d->y[i] * e;
        den += e * e;
    }
    ts_assert_rel(x[0], num / den, 1e-8, "a with b held");

    /* Everything held: x comes back as it went in. */
    const unsigned char all[2] = {1, 1};
    o.constant = all;
    x[0] = 0.2;
    x[1] = 0.6;
    solve_ok(&p, &o, x, &s);
    assert_true(x[0] == 0.2 && x[1] == 0.6);
    assert_int_equal(s.usable, 1);
    decay_free(d);
}

/* rho(s) as solve.h defines it, for the cost check. */
static double rho(bf_loss_kind k, double a, double s)
{
    switch (k) {
    case BF_LOSS_HUBER: return s <= a * a ? s : 2.0 * a * sqrt(s) - a * a;
    case BF_LOSS_CAUCHY: return a * a * log(1.0 + s / (a * a));
    case BF_LOSS_SOFT_L1: return 2.0 * a * a * (sqrt(1.0 + s / (a * a)) - 1.0);
    case BF_LOSS_ARCTAN: return a * atan(s / a);
    default: return s;
    }
}

static void test_robust_losses_ignore_outlier(void **state)
{
    (void)state;
    /* y = 1 + 2 t on 60 points, one of them 100 too high. */
    decay *d = decay_new(60);
    d->line = 1;
    for (size_t i = 0; i < d->n; i++)
        d->y[i] = 1.0 + 2.0 * d->t[i];
    d->y[17] += 100.0;
    bf_problem p = problem(d, LO, HI);
    bf_solution s;

    /* Plain least squares is pulled far off. */
    bf_solver_options o = solver_options();
    double x[2] = {0.0, 0.0};
    solve_ok(&p, &o, x, &s);
    assert_true(fabs(x[0] - 1.0) > 0.5);

    /* Each loss with scale 0.1; huber and soft_l1 keep a bounded pull (about a/n). */
    const struct {
        bf_loss_kind kind;
        double tol;
    } losses[] = {{BF_LOSS_HUBER, 2e-2}, {BF_LOSS_CAUCHY, 1e-5}, {BF_LOSS_SOFT_L1, 2e-2}, {BF_LOSS_ARCTAN, 1e-6}};
    for (size_t l = 0; l < sizeof losses / sizeof *losses; l++) {
        o.loss.kind = losses[l].kind;
        o.loss.scale = 0.1;
        x[0] = 0.0;
        x[1] = 0.0;
        solve_ok(&p, &o, x, &s);
        assert_int_equal(s.usable, 1);
        ts_assert_near(x[0], 1.0, 0.0, losses[l].tol, "intercept under a robust loss");
        ts_assert_near(x[1], 2.0, 0.0, losses[l].tol, "slope under a robust loss");
        /* The reported cost is 1/2 sum rho(r_i^2), per residual. */
        double c = 0.0;
        for (size_t i = 0; i < d->n; i++) {
            double r = x[0] + x[1] * d->t[i] - d->y[i];
            c += 0.5 * rho(losses[l].kind, 0.1, r * r);
        }
        ts_assert_rel(s.final_cost, c, 1e-9, "robust final cost");
    }
    decay_free(d);
}

static void test_algorithms_and_linear_solvers(void **state)
{
    (void)state;
    decay *d = decay_new(50);
    bf_problem p = problem(d, LO, HI);
    const char *algs[] = {"lm", "dogleg"};
    const char *lins[] = {"dense_normal_cholesky", "dense_qr", "sparse_normal_cholesky", "cgnr"};
    for (int a = 0; a < 2; a++)
        for (int l = 0; l < 4; l++) {
            bf_solver_options o = solver_options();
            o.algorithm = algs[a];
            o.linear_solver = lins[l];
            double x[2] = {0.1, 3.0};
            bf_solution s;
            if (a == 1 && strcmp(lins[l], "cgnr") == 0) { /* Ceres: dogleg needs a factorization */
                bf_error err;
                assert_int_equal(bf_solve_ceres(&p, &o, x, &s, &err), BF_ERR_ARG);
                assert_non_null(strstr(err.msg, "DOGLEG"));
                continue;
            }
            solve_ok(&p, &o, x, &s);
            assert_int_equal(s.usable, 1);
            ts_assert_rel(x[0], A_TRUE, 1e-8, lins[l]);
            ts_assert_rel(x[1], B_TRUE, 1e-8, lins[l]);
            assert_string_equal(s.algorithm, a ? "dogleg" : "levenberg_marquardt");
        }
    decay_free(d);
}

static void test_threads_same_solution(void **state)
{
    (void)state;
    /* Large enough for several blocks of the maximum size. */
    decay *d = decay_new(300000);
    for (size_t i = 0; i < d->n; i++) /* deterministic ripple so the optimum has a cost */
        d->y[i] += 1e-3 * sin(37.0 * (double)i);
    bf_problem p = problem(d, LO, HI);
    double x1[2] = {0.5, 2.0}, x4[2] = {0.5, 2.0};
    bf_solution s1, s4;
    bf_solver_options o = solver_options();
    o.threads = 1;
    solve_ok(&p, &o, x1, &s1);
    o.threads = 4;
    solve_ok(&p, &o, x4, &s4);
    assert_int_equal(s1.usable, 1);
    assert_int_equal(s4.usable, 1);
    ts_assert_rel(x4[0], x1[0], 1e-12, "a, 4 threads vs 1");
    ts_assert_rel(x4[1], x1[1], 1e-12, "b, 4 threads vs 1");
    ts_assert_rel(s4.final_cost, s1.final_cost, 1e-10, "cost, 4 threads vs 1");
    ts_assert_rel(x1[0], A_TRUE, 1e-4, "a");
    assert_int_equal(atomic_load(&d->bad_ranges), 0);
    assert_int_equal(atomic_load(&d->residuals_done) % d->n, 0);
    decay_free(d);
}

/* Two "channels" sharing a decay rate: the first half of the residuals depends on x0
 * and x2 only, the second on x1 (scaled by 1e-6, so its column is tiny) and x2. Blocks
 * inside one half have a zero Jacobian column: the block compression must handle
 * rank-deficient and badly scaled blocks exactly. */
static int eval_channels(void *ctx, const double *x, size_t r0, size_t r1, double *res, double *jac)
{
    const decay *d = ctx;
    for (size_t r = r0; r < r1; r++) {
        size_t i = r - r0;
        int c = r >= d->n / 2;
        double scale = c ? 1e-6 : 1.0, e = exp(-x[2] * d->t[r]);
        res[i] = scale * x[c] * e - d->y[r];
        if (jac) {
            jac[i * 3] = c ? 0.0 : e;
            jac[i * 3 + 1] = c ? scale * e : 0.0;
            jac[i * 3 + 2] = -scale * x[c] * d->t[r] * e;
        }
    }
    return 0;
}

static void test_block_structure(void **state)
{
    (void)state;
    decay *d = decay_new(4000);
    for (size_t i = 0; i < d->n; i++)
        d->y[i] = (i < d->n / 2 ? 2.5 : 3.0) * exp(-0.7 * d->t[i]);
    bf_problem p;
    bf_problem_init(&p);
    p.nres = d->n;
    p.npar = 3;
    p.eval = eval_channels;
    p.user = d;
    for (int threads = 1; threads <= 2; threads++) {
        bf_solver_options o = solver_options();
        o.threads = threads;
        double x[3] = {1.0, 1e6, 2.0};
        bf_solution s;
        bf_error err;
        assert_int_equal(bf_solve_ceres(&p, &o, x, &s, &err), BF_OK);
        assert_int_equal(s.usable, 1);
        ts_assert_rel(x[0], 2.5, 1e-8, "x0");
        ts_assert_rel(x[1], 3e6, 1e-8, "x1 (tiny column)");
        ts_assert_rel(x[2], 0.7, 1e-8, "shared rate");
    }
    decay_free(d);
}

static void test_failing_eval(void **state)
{
    (void)state;
    decay *d = decay_new(50);
    bf_problem p = problem(d, LO, HI);
    bf_solver_options o = solver_options();
    bf_solution s;
    for (int nan = 0; nan < 2; nan++) {
        d->fail_with_nan = nan;
        /* Fails where b > 1.2: steps from a bad start that land there are rejected and
         * the solve still reaches the optimum at b = 0.7. */
        d->fail_above = 1.2;
        double x[2] = {8.0, 0.05};
        solve_ok(&p, &o, x, &s);
        assert_int_equal(s.usable, 1);
        ts_assert_rel(x[0], A_TRUE, 1e-8, "a, with failing evaluations");
        ts_assert_rel(x[1], B_TRUE, 1e-8, "b, with failing evaluations");

        /* Fails at the start: reported unusable, x left at the start. */
        d->fail_above = 0.0;
        x[0] = 1.0;
        x[1] = 0.5;
        solve_ok(&p, &o, x, &s);
        assert_int_equal(s.usable, 0);
        assert_true(x[0] == 1.0 && x[1] == 0.5);
        assert_true(isinf(s.final_cost) && s.final_cost > 0); /* never a "best" cost */
        assert_non_null(strstr(s.termination, "FAILURE"));
    }
    decay_free(d);
}

static void test_bad_options(void **state)
{
    (void)state;
    decay *d = decay_new(10);
    bf_problem p = problem(d, LO, HI);
    double x[2] = {1.0, 1.0};
    bf_solution s;
    bf_error err;

    bf_solver_options o = solver_options();
    o.algorithm = "bfgs";
    assert_int_equal(bf_solve_ceres(&p, &o, x, &s, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "bfgs"));
    assert_non_null(strstr(err.msg, "lm"));
    assert_non_null(strstr(err.msg, "dogleg"));

    o.algorithm = NULL;
    o.linear_solver = "dense_lu";
    assert_int_equal(bf_solve_ceres(&p, &o, x, &s, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "dense_lu"));
    assert_non_null(strstr(err.msg, "dense_qr"));
    assert_non_null(strstr(err.msg, "dense_normal_cholesky"));
    assert_non_null(strstr(err.msg, "cgnr"));

    o.linear_solver = NULL;
    o.loss.kind = BF_LOSS_HUBER;
    o.loss.scale = 0.0;
    assert_int_equal(bf_solve_ceres(&p, &o, x, &s, &err), BF_ERR_ARG);
    o.loss.kind = BF_LOSS_NONE;

    const double lo[2] = {0.0, 2.0}, hi[2] = {1.0, 1.0};
    p = problem(d, lo, hi);
    assert_int_equal(bf_solve_ceres(&p, &o, x, &s, &err), BF_ERR_RANGE);
    assert_non_null(strstr(err.msg, "parameter 1"));

    p = problem(d, LO, HI);
    x[0] = NAN;
    assert_int_equal(bf_solve_ceres(&p, &o, x, &s, &err), BF_ERR_RANGE);
    assert_true(isnan(x[0]) && x[1] == 1.0); /* untouched */
    assert_null(strchr(err.msg, '\n'));
    decay_free(d);
}

static void test_prints_nothing(void **state)
{
    (void)state;
    decay *d = decay_new(2000);
    bf_problem p = problem(d, LO, HI);
    const char *path = ts_tmp_path("ceres_output.txt");
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    assert_true(fd >= 0);
    fflush(stdout);
    fflush(stderr);
    int out = dup(1), errfd = dup(2);
    dup2(fd, 1);
    dup2(fd, 2);

    /* Converging, limited, threaded, failing, constrained and rejected solves. */
    bf_solution s[6];
    int rc[6];
    bf_error err;
    double x[2] = {0.1, 3.0};
    bf_solver_options o = solver_options();
    rc[0] = bf_solve_ceres(&p, &o, x, &s[0], &err);
    o.max_iterations = 1;
    o.threads = 2;
    x[0] = 0.1;
    x[1] = 3.0;
    rc[1] = bf_solve_ceres(&p, &o, x, &s[1], &err);
    o.max_iterations = 0;
    d->fail_above = 0.0;
    rc[2] = bf_solve_ceres(&p, &o, x, &s[2], &err);
    d->fail_above = 1.2;
    x[0] = 8.0;
    x[1] = 0.05;
    o.algorithm = "dogleg";
    rc[3] = bf_solve_ceres(&p, &o, x, &s[3], &err);
    const double lo[2] = {0.0, 0.1}, hi[2] = {10.0, 0.5};
    bf_problem pb = problem(d, lo, hi);
    o.loss.kind = BF_LOSS_CAUCHY;
    o.loss.scale = 0.01;
    rc[4] = bf_solve_ceres(&pb, &o, x, &s[4], &err);
    o.linear_solver = "nope";
    rc[5] = bf_solve_ceres(&pb, &o, x, &s[5], &err);

    fflush(stdout);
    fflush(stderr);
    dup2(out, 1);
    dup2(errfd, 2);
    close(out);
    close(errfd);
    close(fd);

    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    if (st.st_size != 0)
        fail_msg("the Ceres back end printed %lld bytes (see %s)", (long long)st.st_size, path);
    for (int i = 0; i < 5; i++)
        assert_int_equal(rc[i], BF_OK);
    assert_int_equal(rc[5], BF_ERR_ARG);
    assert_int_equal(s[0].usable, 1);
    assert_int_equal(s[1].usable, 1);
    assert_int_equal(s[2].usable, 0);
    assert_int_equal(s[3].usable, 1);
    assert_int_equal(s[4].usable, 1);
    decay_free(d);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_decay_recovers_parameters),
        cmocka_unit_test(test_summary_filled),
        cmocka_unit_test(test_iteration_limit),
        cmocka_unit_test(test_bounds_active),
        cmocka_unit_test(test_constant_parameter),
        cmocka_unit_test(test_robust_losses_ignore_outlier),
        cmocka_unit_test(test_algorithms_and_linear_solvers),
        cmocka_unit_test(test_threads_same_solution),
        cmocka_unit_test(test_block_structure),
        cmocka_unit_test(test_failing_eval),
        cmocka_unit_test(test_bad_options),
        cmocka_unit_test(test_prints_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
