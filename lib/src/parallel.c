#include "parallel.h"

#include <pthread.h>
#include <stdatomic.h>

typedef struct job {
    atomic_size_t next;
    size_t nchunks;
    void (*fn)(void *ctx, size_t chunk);
    void *ctx;
} job;

static void *worker(void *arg)
{
    job *j = arg;
    for (size_t c; (c = atomic_fetch_add(&j->next, 1)) < j->nchunks;)
        j->fn(j->ctx, c);
    return NULL;
}

void bf_parallel_for(size_t nchunks, int threads, void (*fn)(void *ctx, size_t chunk), void *ctx)
{
    enum { MAX_THREADS = 64 };
    job j = {.nchunks = nchunks, .fn = fn, .ctx = ctx};
    atomic_init(&j.next, 0);
    if (threads > MAX_THREADS)
        threads = MAX_THREADS;
    if ((size_t)threads > nchunks)
        threads = (int)nchunks;
    pthread_t tid[MAX_THREADS];
    int started = 0;
    for (int t = 1; t < threads; t++)
        if (pthread_create(&tid[started], NULL, worker, &j) == 0)
            started++;
    worker(&j);
    for (int t = 0; t < started; t++)
        pthread_join(tid[t], NULL);
}
