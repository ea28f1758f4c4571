/* The library's thread pool (parallel.h): every chunk runs exactly once for any chunk and
 * thread count; calls from several threads at once and calls nested in a chunk neither
 * deadlock nor wait for one another; the pool grows with the thread count asked; a
 * forked child's loops run. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <pthread.h>
#include <signal.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>

#include "base/parallel.h"

/* ---- Counting chunks ----------------------------------------------------------------- */

typedef struct counts {
    size_t n;
    atomic_int *hits;
    double *part; /* per chunk: a value that depends on the chunk only */
} counts;

static void count_chunk(void *ctx, size_t c)
{
    counts *k = ctx;
    atomic_fetch_add(&k->hits[c], 1);
    k->part[c] = 1.0 / (double)(c + 3);
}

/* Runs a loop of n chunks on `threads` threads and checks every chunk ran once; returns
 * the partials added in chunk order. */
static double run_counted(size_t n, int threads)
{
    counts k = {n, calloc(n + 1, sizeof(atomic_int)), calloc(n + 1, sizeof(double))};
    assert_non_null(k.hits);
    assert_non_null(k.part);
    bf_parallel_for(n, threads, count_chunk, &k);
    double sum = 0.0;
    for (size_t c = 0; c < n; c++) {
        if (atomic_load(&k.hits[c]) != 1)
            fail_msg("chunk %zu of %zu ran %d times on %d threads", c, n, atomic_load(&k.hits[c]), threads);
        sum += k.part[c];
    }
    free(k.hits);
    free(k.part);
    return sum;
}

static void test_every_chunk_once(void **state)
{
    (void)state;
    static const size_t ns[] = {0, 1, 2, 3, 5, 7, 16, 64, 257, 1000};
    static const int ts[] = {-3, 0, 1, 2, 3, 4, 7, 16, 65, 300};
    for (size_t a = 0; a < sizeof ns / sizeof *ns; a++) {
        const double serial = run_counted(ns[a], 1);
        for (size_t b = 0; b < sizeof ts / sizeof *ts; b++) {
            const double s = run_counted(ns[a], ts[b]);
            assert_memory_equal(&s, &serial, sizeof s); /* the same bits for every count */
        }
    }
}

/* The pool grows when a later call asks for more threads, and still serves small calls. */
static void test_growing(void **state)
{
    (void)state;
    static const int ts[] = {2, 3, 8, 2, 16, 1, 4, 32, 2};
    for (int rep = 0; rep < 20; rep++)
        for (size_t b = 0; b < sizeof ts / sizeof *ts; b++)
            run_counted(100 + (size_t)rep, ts[b]);
}

/* ---- Concurrent callers ------------------------------------------------------------- */

static void *caller_thread(void *arg)
{
    const int id = (int)(intptr_t)arg;
    for (int rep = 0; rep < 40; rep++)
        run_counted(50 + (size_t)((rep * 7 + id) % 90), 1 + (rep + id) % 4);
    return NULL;
}

static void test_concurrent_callers(void **state)
{
    (void)state;
    enum { NT = 6 };
    pthread_t t[NT];
    for (int i = 0; i < NT; i++)
        assert_int_equal(pthread_create(&t[i], NULL, caller_thread, (void *)(intptr_t)i), 0);
    for (int i = 0; i < NT; i++)
        pthread_join(t[i], NULL);
}

/* Waits (up to a minute) until *flag is set: a loop that never sees it means the threads
 * that should run side by side did not. */
static int wait_for(atomic_int *flag)
{
    struct timespec t0, t, nap = {0, 200000};
    clock_gettime(CLOCK_MONOTONIC, &t0);
    while (!atomic_load(flag)) {
        clock_gettime(CLOCK_MONOTONIC, &t);
        if (t.tv_sec - t0.tv_sec > 60)
            return 0;
        nanosleep(&nap, NULL);
    }
    return 1;
}

/* Two callers at once: chunk 0 of each waits for the other's chunk 0. A pool
 * that ran one caller's loop after the other's would never finish. */
typedef struct meet {
    atomic_int here[2];
    atomic_int ok;
} meet;

typedef struct meet_arg {
    meet *m;
    int side;
} meet_arg;

static void meet_chunk(void *ctx, size_t c)
{
    meet_arg *a = ctx;
    if (c != 0)
        return;
    atomic_store(&a->m->here[a->side], 1);
    if (wait_for(&a->m->here[1 - a->side]))
        atomic_fetch_add(&a->m->ok, 1);
}

static void *meet_thread(void *arg)
{
    bf_parallel_for(4, 2, meet_chunk, arg);
    return NULL;
}

static void test_callers_side_by_side(void **state)
{
    (void)state;
    meet m = {0};
    meet_arg a[2] = {{&m, 0}, {&m, 1}};
    pthread_t t;
    assert_int_equal(pthread_create(&t, NULL, meet_thread, &a[1]), 0);
    bf_parallel_for(4, 2, meet_chunk, &a[0]);
    pthread_join(t, NULL);
    assert_int_equal(atomic_load(&m.ok), 2);
}

/* ---- Helpers and nesting ------------------------------------------------------------ */

/* Chunks 0 and 1 each wait for the other to start: they must run on two threads at once,
 * so the pool has to lend the caller a worker. */
typedef struct pair {
    atomic_int started[2];
    atomic_int ok;
} pair;

static void pair_chunk(void *ctx, size_t c)
{
    pair *p = ctx;
    atomic_store(&p->started[c], 1);
    if (wait_for(&p->started[1 - c]))
        atomic_fetch_add(&p->ok, 1);
}

static void test_helpers_help(void **state)
{
    (void)state;
    for (int rep = 0; rep < 20; rep++) {
        pair p = {0};
        bf_parallel_for(2, 2, pair_chunk, &p);
        assert_int_equal(atomic_load(&p.ok), 2);
    }
}

/* Nested loops: every outer chunk runs an inner loop (which itself needs two threads at
 * once), and one more level of counted loops inside that. */
typedef struct outer {
    atomic_int ok, hits[8];
} outer;

static void inner_counted(void *ctx, size_t c)
{
    (void)ctx;
    (void)c;
    run_counted(33, 3);
}

static void outer_chunk(void *ctx, size_t c)
{
    outer *o = ctx;
    atomic_fetch_add(&o->hits[c], 1);
    pair p = {0};
    bf_parallel_for(2, 2, pair_chunk, &p);
    atomic_fetch_add(&o->ok, atomic_load(&p.ok));
    bf_parallel_for(5, 2, inner_counted, NULL);
}

static void test_nested(void **state)
{
    (void)state;
    for (int threads = 1; threads <= 4; threads++) {
        outer o = {0};
        bf_parallel_for(8, threads, outer_chunk, &o);
        assert_int_equal(atomic_load(&o.ok), 16);
        for (int c = 0; c < 8; c++)
            assert_int_equal(atomic_load(&o.hits[c]), 1);
    }
}

/* ---- fork ----------------------------------------------------------------------------- */

static void test_fork_child(void **state)
{
    (void)state;
    run_counted(500, 4); /* the pool has workers before the fork */
    fflush(NULL);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        alarm(60); /* a hang ends the child with SIGALRM */
        counts k = {300, calloc(301, sizeof(atomic_int)), calloc(301, sizeof(double))};
        if (!k.hits || !k.part)
            _exit(2);
        for (int rep = 0; rep < 5; rep++)
            bf_parallel_for(300, 4, count_chunk, &k);
        for (size_t c = 0; c < 300; c++)
            if (atomic_load(&k.hits[c]) != 5)
                _exit(1);
        pair p = {0};
        bf_parallel_for(2, 2, pair_chunk, &p); /* the child's own pool lends a worker */
        _exit(atomic_load(&p.ok) == 2 ? 0 : 3);
    }
    int status = 0;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFEXITED(status));
    assert_int_equal(WEXITSTATUS(status), 0);
    run_counted(500, 4); /* and the parent's pool still works */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_chunk_once),   cmocka_unit_test(test_growing),
        cmocka_unit_test(test_concurrent_callers), cmocka_unit_test(test_callers_side_by_side),
        cmocka_unit_test(test_helpers_help),       cmocka_unit_test(test_nested),
        cmocka_unit_test(test_fork_child),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
