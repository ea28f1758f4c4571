/* Internal: the scratch of an objective's passes (objective.c, objective_normal.c), apart
 * from the objective so that both files use it without using each other. */
#ifndef BF_OBJECTIVE_WS_H
#define BF_OBJECTIVE_WS_H

#include <pthread.h>
#include <stddef.h>

/* The scratch of the objective's passes, allocated once per objective (on first use,
 * grown when a pass needs more) and kept until bf_objective_free, instead of at every
 * evaluation. A pass takes a workspace for its own sums and every chunk of it takes one
 * while it runs, from the objective's free list under a lock (chunks run on any thread
 * of the pool, several at once): a workspace is used by one thread at a time, and there
 * are never more than the threads that ever worked at once on the objective's passes,
 * plus their callers. Contents are not kept between uses. */
enum {
    BF_WS_VALS,
    BF_WS_GRAD,
    BF_WS_G,
    BF_WS_S,
    BF_WS_JC,
    BF_WS_COLS,
    BF_WS_USED, /* a chunk's blocks */
    BF_WS_TR,
    BF_WS_TJ,
    BF_WS_COL,  /* a chunk's lobe sums */
    BF_WS_MBUF, /* a chunk's metric values */
    BF_WS_PART,
    BF_WS_SUM,
    BF_WS_FTR,
    BF_WS_FTJ,
    BF_WS_MSUM, /* a pass's sums */
    BF_WS_NBUF
};
typedef struct bf_obj_ws {
    struct bf_obj_ws *next_free, *next_all;
    void *buf[BF_WS_NBUF];
    size_t cap[BF_WS_NBUF]; /* bytes */
} bf_obj_ws;

typedef struct bf_obj_ws_list {
    pthread_mutex_t lock;
    bf_obj_ws *free_list, *all;
} bf_obj_ws_list;

/* An objective's list of workspaces (NULL when out of memory), and its end with every
 * workspace it made. */
bf_obj_ws_list *bf_obj_ws_list_new(void);
void bf_obj_ws_list_free(bf_obj_ws_list *l);
/* A workspace for the calling thread (NULL when out of memory); bf_obj_ws_put returns
 * it. The list is the one thing an objective's passes change (they take it const). */
bf_obj_ws *bf_obj_ws_get(bf_obj_ws_list *l);
void bf_obj_ws_put(bf_obj_ws_list *l, bf_obj_ws *w);
/* Buffer k of w with room for `bytes` (contents undefined), NULL when out of memory. */
void *bf_obj_ws_buf(bf_obj_ws *w, int k, size_t bytes);

#endif
