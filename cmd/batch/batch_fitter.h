/* The process that fits brdfit batch's items: a child of the process that runs the batch
 * (the one-process run, or an MPI worker rank: cmd/batch_mpi.c), so that a fit that dies
 * (a crash, the out-of-memory killer, a kill) costs its items and not the run, whose
 * death would end a one-process batch or, under Open MPI 4, the whole MPI job. The child
 * lives on between calls (it keeps the material it has read and its warm heap) and is
 * replaced by a fresh one when it dies. */
#ifndef BRDFIT_BATCH_FITTER_H
#define BRDFIT_BATCH_FITTER_H

#include <signal.h>
#include <stddef.h>

#include "batch_rows.h"

/* In the child: where its rows go (batch_fitter_emit). */
typedef struct batch_fitter_out batch_fitter_out;

/* What the child runs for a call: items[0..n-1], all of one material, fitted; each row
 * handed to batch_fitter_emit as it finishes (an error row for an item that fails; none
 * for an item not run because of an interrupt). */
typedef void (*batch_fit_fn)(void *ctx, const int *items, int n, batch_fitter_out *out);

/* In the child: a finished row sent to the parent, with the material the child now holds
 * (-1 for none). Calls must not overlap. */
void batch_fitter_emit(batch_fitter_out *out, const batch_row *row, int held);

typedef struct batch_fitter {
    batch_fit_fn fit;
    void *ctx;
    /* When this flag (the parent's SIGINT flag) is set during a call, SIGINT is passed on
     * to the child, once: it then starts no new fit. The child has a process group of its
     * own, so a terminal's ^C reaches it only this way. NULL: never. */
    const volatile sig_atomic_t *interrupt;
    int pid;       /* the child, 0 for none yet */
    int fd;        /* the parent's end of the socket to it */
    int forwarded; /* SIGINT passed on to this child */
} batch_fitter;

/* A fitter for fit(ctx, ...); no process is started until the first call. */
void batch_fitter_init(batch_fitter *f, batch_fit_fn fit, void *ctx);

/* Where the rows of a call go: got(user, row) as each arrives (got may take the row's
 * texts, setting them to NULL). */
typedef struct batch_sink {
    void (*got)(void *user, batch_row *row);
    void *user;
} batch_sink;

/* items[0..n-1] (one material's) fitted by the child, started first when there is none;
 * its process name is "brdfit:ITEM" (the first item, then "+" when there are more). Each
 * row goes to the sink as it arrives; *held: the material the child holds. 0 when the child finished the call (every
 * item has a row, or was not run after an interrupt); -1 when it died or could not be
 * started, with why in why[0..n-1] (e.g. "killed by signal 9 (Killed)") and *held -1: the
 * rows received before still went to the sink, and the next call starts a fresh child. */
int batch_fitter_run(batch_fitter *f, const int *items, int n, const batch_sink *sink, int *held, char *why,
                     size_t whylen);

/* Ends the child (it exits when its socket closes) and waits for it. */
void batch_fitter_clear(batch_fitter *f);

#endif
