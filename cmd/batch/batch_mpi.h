/* brdfit batch across MPI processes (built only when CMake finds MPI: BRDFIT_HAVE_MPI).
 * Rank 0 is the coordinator: it alone opens the results database, hands out the pending
 * work items one at a time and writes each result it gets back in its own transaction,
 * as a one-process run does. The other ranks are workers: each fits the items it is
 * given (batch_run.c's fitting, one item at a time, in a child process: batch_fitter.h)
 * and sends back the item's row (batch_row_pack), or word that the item was lost. This
 * file is the messages; batch_mpi_run.c joins them to the run. docs/batch.md describes
 * the mode. */
#ifndef BRDFIT_BATCH_MPI_H
#define BRDFIT_BATCH_MPI_H

#include <signal.h>

#include "batch_rows.h"

/* Starts MPI when an MPI launcher (mpirun, srun) started this process, else nothing:
 * *rank 0 and *size 1 then, and batch runs as one process. */
void batch_mpi_start(int *rank, int *size);
/* Ends MPI if batch_mpi_start started it. */
void batch_mpi_end(void);

/* Rank 0's status (-1: go on) and manifest hash to every rank: in *status and hash. */
void batch_mpi_share(int *status, char hash[17]);
/* 1 when ok is true on every rank. */
int batch_mpi_all(int ok);

/* What the coordinator does with what the workers send. */
typedef struct batch_mpi_callbacks {
    /* A result row (its texts owned by the callee during the call only). */
    void (*done)(void *ctx, batch_row *row);
    /* The process fitting item on worker `rank` died (why: how). again: it is handed out
     * again; else it has been lost too often and is the callee's to record as an error. */
    void (*lost)(void *ctx, int item, int rank, const char *why, int again);
    void *ctx;
} batch_mpi_callbacks;

/* The coordinator (rank 0): hands out items[0..n-1] (ascending; item / nmodels is the
 * material, of weight[material], nmaterials of them) to the workers, the heaviest
 * material's first and, to a worker that holds a material, that material's next item
 * while there is one; a lost item is handed out again before any other. Once *stop is
 * set no item is handed out; the items in flight are waited for. Returns when every
 * worker has been told to stop; n = 0 only stops them. Every worker must call
 * batch_mpi_work. */
void batch_mpi_coordinate(const int *items, int n, int nmodels, const double *weight, int nmaterials,
                          const batch_mpi_callbacks *cb, const volatile sig_atomic_t *stop);

/* A worker (rank > 0): fits the items the coordinator hands out with fit(ctx, item, row,
 * &held, why, n) until told to stop. fit returns 0 with the row filled (an error row if
 * the item fails), or -1 when the item was lost (its fitting process died) with the
 * reason in why[0..n-1]; held: the material it now keeps loaded, -1 for none. */
void batch_mpi_work(int (*fit)(void *ctx, int item, batch_row *row, int *held, char *why, size_t n), void *ctx);

#endif
