/* The process that fits an MPI worker's items (cmd/batch_mpi.c): a child of the worker
 * rank, so that a fit that dies (a crash, the out-of-memory killer, a kill) costs its
 * item only and not the rank, whose death would end the whole job under Open MPI 4. The
 * child lives on between items (it keeps the material it has read and its warm heap)
 * and is replaced by a fresh one when it dies. */
#ifndef BRDFIT_BATCH_FITTER_H
#define BRDFIT_BATCH_FITTER_H

#include <stddef.h>

#include "batch_rows.h"

/* What the child runs for each item: row zeroed; fit fills it (an error row if the item
 * fails) and sets *held to the material it now keeps loaded (-1 for none). */
typedef void (*batch_fit_fn)(void *ctx, int item, batch_row *row, int *held);

typedef struct batch_fitter {
    batch_fit_fn fit;
    void *ctx;
    int pid;  /* the child, 0 for none yet */
    int fd;   /* the parent's end of the socket to it */
} batch_fitter;

/* A fitter for fit(ctx, ...); no process is started until the first item. */
void batch_fitter_init(batch_fitter *f, batch_fit_fn fit, void *ctx);

/* Item fitted by the child (started first when there is none; its process name is
 * "brdfit:ITEM" while it fits ITEM), its row brought back into *row (texts malloc'd:
 * batch_row_clear) and *held set. 0 then; -1 when the child died or could not be
 * started, with why in why[0..n-1] (e.g. "killed by signal 9 (Killed)"), *row zeroed
 * and *held -1; the next item starts a fresh child. */
int batch_fitter_run(batch_fitter *f, int item, batch_row *row, int *held, char *why, size_t n);

/* Ends the child (it exits when its socket closes) and waits for it. */
void batch_fitter_clear(batch_fitter *f);

#endif
