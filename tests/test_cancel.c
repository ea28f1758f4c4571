/* A solve you can watch and stop (brdfit/solve.h: bf_stop, progress, cancel): fits of
 * the Cornell Garnet Red paint (as --rgb, the default search; Disney with Ceres, Walter
 * with NLopt) cancelled from the progress callback and from another thread; a cancelled
 * fit says so, holds its start, and no writer writes it; the stop reasons of an ordinary
 * fit and of one that hits its iteration limit. */
#include <math.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "brdfit/fit.h"
#include "support.h"

typedef struct watch {
    int calls;     /* progress calls */
    int cancel_at; /* the callback returns 1 at this call (0: never) */
    int signal_at; /* ... or signals the other thread at this call */
    int bad_cost;  /* a call with a cost that is not finite */
    pthread_mutex_t lock;
    pthread_cond_t cond;
    int signalled;
    volatile int flag; /* the cancel flag the other thread sets */
} watch;

static int progress(void *user, int iteration, double cost)
{
    watch *w = user;
    (void)iteration;
    w->calls++;
    w->bad_cost += !isfinite(cost);
    if (w->signal_at && w->calls == w->signal_at) {
        pthread_mutex_lock(&w->lock);
        w->signalled = 1;
        pthread_cond_signal(&w->cond);
        pthread_mutex_unlock(&w->lock);
        /* Give the other thread the time to set the flag, so that the test does not
         * depend on the scheduler: the solve must see it at a later iteration. */
        while (!w->flag)
            usleep(1000);
    }
    return w->cancel_at && w->calls >= w->cancel_at;
}

static void *canceller(void *arg)
{
    watch *w = arg;
    pthread_mutex_lock(&w->lock);
    while (!w->signalled)
        pthread_cond_wait(&w->cond, &w->lock);
    pthread_mutex_unlock(&w->lock);
    w->flag = 1;
    return NULL;
}

/* Disney with Ceres; Walter with NLopt (whose evaluations of Disney would take long). */
static void fit_watched(bf_samples *s, bf_backend backend, watch *w, bf_fit_result *r)
{
    bf_fit_options o;
    bf_fit_options_init(&o);
    o.solver.threads = 2;
    o.solver.backend = backend;
    o.solver.progress = progress;
    o.solver.progress_user = w;
    o.solver.cancel = &w->flag;
    bf_error err;
    if (bf_fit_with(s, backend == BF_BACKEND_CERES ? "disney" : "walter", &o, r, &err) != BF_OK)
        fail_msg("bf_fit: %s", err.msg);
}

/* What every cancelled fit shows: the stop reason, no fit, its start, nothing written. */
static void assert_cancelled(bf_fit_result *r)
{
    assert_int_equal(r->solution.stop, BF_STOP_CANCELLED);
    assert_string_equal(bf_stop_name(r->solution.stop), "cancelled");
    assert_false(r->ok);
    for (int k = 0; k < bf_model_nvalues(r->model); k++)
        assert_true(isfinite(r->x[k]));
    assert_true(r->nwarnings >= 1 && strstr(r->warnings[0], "cancelled"));
    const char *path = ts_tmp_path("cancelled.json");
    unlink(path);
    bf_error err;
    assert_int_equal(bf_fit_write_json(r, "garnet_red.brdf", path, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "cancelled"));
    assert_int_equal(access(path, F_OK), -1);
    const bf_fit_result *list[1] = {r};
    assert_int_equal(bf_fit_write_json_list(list, 1, "garnet_red.brdf", path, &err), BF_ERR_ARG);
    assert_int_equal(access(path, F_OK), -1);
}

static watch new_watch(void)
{
    watch w;
    memset(&w, 0, sizeof w);
    pthread_mutex_init(&w.lock, NULL);
    pthread_cond_init(&w.cond, NULL);
    return w;
}

static void test_from_the_callback(void **state)
{
    (void)state;
    bf_samples *s = ts_read_cornell_rgb("garnet_red.brdf");
    static const bf_backend backends[] = {BF_BACKEND_CERES, BF_BACKEND_NLOPT};
    for (size_t b = 0; b < sizeof backends / sizeof backends[0]; b++) {
        watch whole = new_watch(), w = new_watch();
        bf_fit_result r;
        fit_watched(s, backends[b], &whole, &r); /* the whole fit, for its count */
        assert_true(r.ok);
        assert_int_equal(r.solution.stop, BF_STOP_CONVERGED);
        assert_int_equal(whole.bad_cost, 0);
        bf_fit_result_clear(&r);
        w.cancel_at = 7;
        fit_watched(s, backends[b], &w, &r);
        assert_cancelled(&r);
        assert_int_equal(w.calls, 7); /* not one call after the cancel */
        assert_true(whole.calls > 7);
        bf_fit_result_clear(&r);
    }
    bf_samples_free(s);
}

static void test_from_another_thread(void **state)
{
    (void)state;
    bf_samples *s = ts_read_cornell_rgb("garnet_red.brdf");
    watch whole = new_watch(), w = new_watch();
    bf_fit_result r;
    fit_watched(s, BF_BACKEND_CERES, &whole, &r);
    bf_fit_result_clear(&r);
    w.signal_at = 5;
    pthread_t t;
    assert_int_equal(pthread_create(&t, NULL, canceller, &w), 0);
    fit_watched(s, BF_BACKEND_CERES, &w, &r);
    pthread_join(t, NULL);
    assert_cancelled(&r);
    /* The flag is read at every iteration: the call that saw it set is the last. */
    assert_int_equal(w.calls, 5);
    assert_true(whole.calls > 5);
    bf_fit_result_clear(&r);
    bf_samples_free(s);
}

/* Set before the fit: nothing is solved. */
static void test_cancelled_before(void **state)
{
    (void)state;
    bf_samples *s = ts_read_cornell_rgb("garnet_red.brdf");
    watch w = new_watch();
    w.flag = 1;
    bf_fit_result r;
    fit_watched(s, BF_BACKEND_CERES, &w, &r);
    assert_cancelled(&r);
    assert_int_equal(w.calls, 0);
    bf_fit_result_clear(&r);
    bf_samples_free(s);
}

/* The stop reasons of ordinary solves, and their names. */
static void test_stop_reasons(void **state)
{
    (void)state;
    assert_string_equal(bf_stop_name(BF_STOP_CONVERGED), "converged");
    assert_string_equal(bf_stop_name(BF_STOP_ITERATIONS), "iteration_limit");
    assert_string_equal(bf_stop_name(BF_STOP_TIME), "time_limit");
    assert_string_equal(bf_stop_name(BF_STOP_CANCELLED), "cancelled");
    assert_string_equal(bf_stop_name(BF_STOP_FAILED), "failed");
    assert_string_equal(bf_stop_name((bf_stop)99), "?");
    bf_samples *s = ts_read_cornell_rgb("garnet_red.brdf");
    static const bf_backend backends[] = {BF_BACKEND_CERES, BF_BACKEND_NLOPT};
    for (size_t b = 0; b < sizeof backends / sizeof backends[0]; b++) {
        bf_fit_options o;
        bf_fit_options_init(&o);
        o.starts = 1;
        o.solver.backend = backends[b];
        bf_fit_result r;
        ts_fit_ok(s, "walter", &o, &r);
        assert_int_equal(r.solution.stop, BF_STOP_CONVERGED);
        bf_fit_result_clear(&r);
        o.solver.max_iterations = 2;
        ts_fit_ok(s, "walter", &o, &r);
        assert_int_equal(r.solution.stop, BF_STOP_ITERATIONS);
        int said = 0;
        for (int k = 0; k < r.nwarnings; k++)
            said |= strstr(r.warnings[k], "stopped on its limit") != NULL;
        assert_true(said);
        bf_fit_result_clear(&r);
    }
    bf_samples_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_from_the_callback),
        cmocka_unit_test(test_from_another_thread),
        cmocka_unit_test(test_cancelled_before),
        cmocka_unit_test(test_stop_reasons),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
