/* bf_parallel_for on one persistent pool of worker threads for the whole library.
 *
 * Decisions:
 *  - The pool is created on first use (pthread_once) and grows, never shrinks: a call
 *    that wants h helpers (min(threads, nchunks) - 1) while fewer than h workers are idle
 *    and unclaimed starts the difference, so the pool holds at most as many workers as
 *    were ever wanted at once (the largest thread count asked, minus 1, for one caller;
 *    the sum of the helpers wanted by the calls running at the same moment when several
 *    run at once, e.g. compare's fits), and never more than MAX_WORKERS.
 *  - A call is a job on the caller's stack, put on the pool's list of open jobs. The
 *    calling thread always works on its own job's chunks, from the job's shared counter,
 *    until none are left; idle workers help whichever open job (oldest first) has chunks
 *    left and fewer helpers than it asked for. A worker that joins a job runs its chunks
 *    until the counter runs out and only then looks for another, so a job's caller,
 *    once its counter is out, waits only for helpers finishing its last chunks. Nested
 *    calls (a chunk that calls bf_parallel_for, as compare's fits do) make a job of
 *    their own that their thread works through, helped or not: nothing ever waits for a
 *    worker to become free, so nested and concurrent calls cannot deadlock, and calls
 *    from several threads proceed side by side instead of one after another.
 *  - Workers sleep on a condition variable between jobs. At exit (atexit) the workers
 *    are stopped and joined when no job is running; when one is (exit from a chunk, or
 *    from one thread while another is in a loop) they are left as they are: joining
 *    could wait for a whole fit, and the process ends anyway. After that every call runs
 *    on the calling thread alone.
 *  - fork: the child has the forking thread only. pthread_atfork holds the pool's lock
 *    across the fork (so its state is consistent) and the child starts from an empty
 *    pool that grows again on demand; a forked child's loops therefore run, and do not
 *    wait for workers that do not exist. (Forking from inside a chunk while helpers run
 *    that job is not supported: their chunks would never finish in the child.)
 *  - One thread, or one chunk: the loop runs on the calling thread without the pool. */
#include "parallel.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>

enum { MAX_WORKERS = 256 };

typedef struct job {
    atomic_size_t next; /* the next chunk to hand out */
    size_t nchunks;
    void (*fn)(void *ctx, size_t chunk);
    void *ctx;
    int want;   /* helpers wanted (pool lock) */
    int active; /* helpers working on it now (pool lock) */
    int listed; /* on the open list (pool lock) */
    struct job *prev, *nxt;
} job;

static struct {
    pthread_mutex_t lock;
    pthread_cond_t work;         /* a job was posted, or shutdown */
    pthread_cond_t done;         /* some job's last helper left */
    job *head, *tail;            /* open jobs, oldest first */
    pthread_t *tid;              /* started workers (joinable) */
    int nworkers, idle, claimed; /* claimed: idle workers signalled, not yet awake */
    int running;                 /* calls in progress that use the pool */
    int shutdown;                /* workers to exit */
    int closed;                  /* torn down: every call runs on the calling thread */
} pool = {.lock = PTHREAD_MUTEX_INITIALIZER, .work = PTHREAD_COND_INITIALIZER, .done = PTHREAD_COND_INITIALIZER};

static pthread_once_t pool_once = PTHREAD_ONCE_INIT;

static void run_chunks(job *j)
{
    for (size_t c; (c = atomic_fetch_add_explicit(&j->next, 1, memory_order_relaxed)) < j->nchunks;)
        j->fn(j->ctx, c);
}

static void unlink_job(job *j)
{
    if (!j->listed)
        return;
    if (j->prev)
        j->prev->nxt = j->nxt;
    else
        pool.head = j->nxt;
    if (j->nxt)
        j->nxt->prev = j->prev;
    else
        pool.tail = j->prev;
    j->prev = j->nxt = NULL;
    j->listed = 0;
}

/* The oldest open job that has chunks left and wants another helper (pool lock held). */
static job *pick_job(void)
{
    for (job *j = pool.head; j;) {
        job *nx = j->nxt;
        if (atomic_load_explicit(&j->next, memory_order_relaxed) >= j->nchunks)
            unlink_job(j); /* nothing left to hand out: no one else needs to look at it */
        else if (j->active < j->want)
            return j;
        j = nx;
    }
    return NULL;
}

static void *worker(void *arg)
{
    (void)arg;
    pthread_mutex_lock(&pool.lock);
    for (;;) {
        job *j;
        while (!pool.shutdown && !(j = pick_job())) {
            pool.idle++;
            pthread_cond_wait(&pool.work, &pool.lock);
            pool.idle--;
            if (pool.claimed > 0)
                pool.claimed--;
        }
        if (pool.shutdown)
            break;
        j->active++;
        pthread_mutex_unlock(&pool.lock);
        run_chunks(j);
        pthread_mutex_lock(&pool.lock);
        /* The counter is out: the job's caller may be waiting for its helpers. */
        unlink_job(j);
        if (--j->active == 0)
            pthread_cond_broadcast(&pool.done);
    }
    pthread_mutex_unlock(&pool.lock);
    return NULL;
}

/* At exit: stop and join the workers if no loop is running (see the decisions). */
static void pool_teardown(void)
{
    pthread_mutex_lock(&pool.lock);
    pool.closed = 1;
    if (pool.running > 0) {
        pthread_mutex_unlock(&pool.lock);
        return;
    }
    pool.shutdown = 1;
    pthread_cond_broadcast(&pool.work);
    int n = pool.nworkers;
    pthread_t *tid = pool.tid;
    pool.nworkers = 0;
    pool.tid = NULL;
    pthread_mutex_unlock(&pool.lock);
    for (int i = 0; i < n; i++)
        pthread_join(tid[i], NULL);
    free(tid);
}

static void before_fork(void)
{
    pthread_mutex_lock(&pool.lock);
}
static void after_fork_parent(void)
{
    pthread_mutex_unlock(&pool.lock);
}

/* The child: no workers, no jobs (the parent's belong to threads the child does not
 * have); fresh lock and conditions (the old ones may hold waiters that do not exist). */
static void after_fork_child(void)
{
    free(pool.tid);
    pool.tid = NULL;
    pool.nworkers = pool.idle = pool.claimed = pool.running = 0;
    pool.head = pool.tail = NULL;
    pthread_mutex_init(&pool.lock, NULL);
    pthread_cond_init(&pool.work, NULL);
    pthread_cond_init(&pool.done, NULL);
}

static void pool_init(void)
{
    pthread_atfork(before_fork, after_fork_parent, after_fork_child);
    atexit(pool_teardown);
}

/* Makes sure `want` idle, unclaimed workers exist, as far as the limit and
 * pthread_create allow, and wakes that many (pool lock held). */
static void provide_workers(int want)
{
    int avail = pool.idle - pool.claimed;
    if (avail < 0)
        avail = 0;
    if (avail < want && pool.nworkers < MAX_WORKERS) {
        if (!pool.tid && !(pool.tid = malloc(MAX_WORKERS * sizeof *pool.tid)))
            return;
        /* New workers look at the open list as soon as they start: no signal needed. */
        for (int k = avail; k < want && pool.nworkers < MAX_WORKERS; k++) {
            if (pthread_create(&pool.tid[pool.nworkers], NULL, worker, NULL) != 0)
                break;
            pool.nworkers++;
        }
    }
    int wake = avail < want ? avail : want;
    for (int k = 0; k < wake; k++)
        pthread_cond_signal(&pool.work);
    pool.claimed += wake;
}

void bf_parallel_for(size_t nchunks, int threads, void (*fn)(void *ctx, size_t chunk), void *ctx)
{
    if (nchunks == 0)
        return;
    size_t t = threads < 1 ? 1 : (size_t)threads;
    if (t > nchunks)
        t = nchunks;
    if (t > MAX_WORKERS + 1)
        t = MAX_WORKERS + 1;
    job j = {.nchunks = nchunks, .fn = fn, .ctx = ctx, .want = (int)t - 1};
    atomic_init(&j.next, 0);
    if (t > 1) {
        pthread_once(&pool_once, pool_init);
        pthread_mutex_lock(&pool.lock);
        if (pool.closed) {
            pthread_mutex_unlock(&pool.lock);
            t = 1;
        } else {
            pool.running++;
            j.listed = 1;
            j.prev = pool.tail;
            if (pool.tail)
                pool.tail->nxt = &j;
            else
                pool.head = &j;
            pool.tail = &j;
            provide_workers(j.want);
            pthread_mutex_unlock(&pool.lock);
        }
    }
    run_chunks(&j);
    if (t <= 1)
        return;
    /* Every chunk is handed out: no one may join now; wait for the helpers' last ones
     * (their writes are seen after the lock they release when leaving). */
    pthread_mutex_lock(&pool.lock);
    unlink_job(&j);
    while (j.active > 0)
        pthread_cond_wait(&pool.done, &pool.lock);
    pool.running--;
    pthread_mutex_unlock(&pool.lock);
}
