/* One run of brdfit batch (cmd_batch.c): its arguments, its state, and what records its
 * rows, shared by the one-process loop (cmd_batch.c), the fitting process (batch_run.c)
 * and the MPI coordinator and workers (batch_mpi_run.c). */
#ifndef BRDFIT_BATCH_RUN_H
#define BRDFIT_BATCH_RUN_H

#include "batch_fitter.h"
#include "batch_manifest.h"
#include "batch_rows.h"
#include "cli.h"

#define BATCH_CMD "brdfit batch" /* the prefix of its messages */

typedef struct batch_db batch_db;

typedef struct batch_args {
    cli_args args;
    const char *manifest, *output;
    int redo_failed, redo_all, shard, nshards, jobs;
    long threads; /* 0: as the manifest says */
} batch_args;

typedef struct batch_run {
    const batch_args *a;
    const batch_manifest *m;
    batch_db *db; /* the writer (the one process, or the MPI coordinator); NULL in a
                            fitting process */
    int material;
    const int *model_of; /* the comparison's model j -> the manifest's */
    int done, total, ok, bad;
    int tty;
    double t0;
    int db_failed;
    bf_error db_err;
    /* A fitting process (batch_fitter.h): where its rows go, the material it holds, and
     * which models of the current call have a row. */
    batch_fitter_out *out;
    int held;
    unsigned char sent[BATCH_MAX_MODELS];
} batch_run;

/* A finished item's row written to r's database (its own transaction) and counted; a
 * database failure stops the run (no new fit starts). */
void batch_run_put(batch_run *r, const batch_row *row);

/* Every model of models[0..n-1] an error row of the current material (why: reason). */
void batch_run_error_rows(batch_run *r, const int *models, int n, const char *reason);

/* An item whose fitting process died both times it ran (one process or MPI): an error
 * row saying so, with the last reason. */
void batch_run_lost_twice(batch_run *r, int item, const char *why);

/* A material read and prepared for fitting: s NULL when it could not be (why: reason). */
typedef struct batch_loaded {
    int i;
    bf_samples *s;
    bf_options *o; /* the material's options (owned) */
    char reason[512];
} batch_loaded;

/* The fitting process's state: a run of its own (no database; rows go to its parent)
 * and the material it holds. Made by the parent before the fork; only the child's copy
 * is used. */
typedef struct batch_fitting {
    batch_run r;
    batch_loaded mt;
} batch_fitting;

/* f set up to fit the items of a's run of m in a child process (batch_fitter.h) whose
 * state is w's copy. */
void batch_fitting_init(batch_fitting *w, batch_fitter *f, const batch_args *a, const batch_manifest *m);

#ifdef BRDFIT_HAVE_MPI
/* The coordinator (rank 0): r's pending items (pending[0..n-1]) handed out to the
 * workers, largest material first, each row written as it comes back; n = 0 only stops
 * the workers (batch_mpi_run.c). */
void batch_mpi_run_coordinate(batch_run *r, const int *pending, int n);
/* A worker (rank > 0): the items the coordinator hands out, fitted one at a time in a
 * fitting process, until told to stop. */
void batch_mpi_run_work(const batch_args *a, const batch_manifest *m);
#endif

#endif
