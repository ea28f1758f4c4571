/* Internal: a parallel loop over fixed chunks. Callers keep one partial result per
 * chunk and combine them in chunk order, so results do not depend on the thread count. */
#ifndef BF_PARALLEL_H
#define BF_PARALLEL_H

#include <stddef.h>

/* Calls fn(ctx, c) for every chunk c in [0, nchunks) on up to `threads` threads (the
 * calling thread is one of them, helped by the library's persistent pool: see
 * parallel.c) and returns when all are done. Chunks are handed out in order from a
 * shared counter: fn must not depend on which thread runs a chunk. Calls may come from
 * several threads at once and from inside a chunk (nested): each makes progress on its
 * own. If threads cannot be started, the calling thread does the rest. */
void bf_parallel_for(size_t nchunks, int threads, void (*fn)(void *ctx, size_t chunk), void *ctx);

#endif
