/* brdfit batch under MPI (batch_run.h): rank 0 coordinates and writes the rows, the
 * other ranks fit, each item in a fitting process (batch_fitter.h); the messages between
 * them are batch_mpi.c's. Built only with MPI. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "batch_mpi.h"
#include "batch_run.h"
#include "interrupt.h"

/* The coordinator's callbacks (batch_mpi_callbacks): a worker's row written and counted;
 * a lost item told, and written as an error once it has been lost too often. */
static void coordinator_done(void *ctx, batch_row *row)
{
    batch_run *r = ctx;
    if (!r->db_failed)
        batch_run_put(r, row);
}

static void coordinator_lost(void *ctx, int item, int rank, const char *why, int again)
{
    batch_run *r = ctx;
    const int i = item / r->m->nmodels, model = item % r->m->nmodels;
    fprintf(stderr, "%s: %s, %s: the process fitting it on rank %d died (%s); %s\n", BATCH_CMD, r->m->materials[i].data,
            r->m->models[model], rank, why,
            again ? "handed out again" : "recorded as an error (--redo failed runs it again)");
    if (!again)
        batch_run_lost_twice(r, item, why);
}

/* The weight of a material is its data file's size (-1 when it cannot be read: its items
 * are errors, quick ones). */
void batch_mpi_run_coordinate(batch_run *r, const int *pending, int n)
{
    const batch_manifest *m = r->m;
    double *weight = malloc(((size_t)m->nmaterials + 1) * sizeof *weight);
    if (!weight) {
        r->db_failed = 1;
        bf_fail(&r->db_err, BF_ERR_NOMEM, "out of memory for the work queue");
        n = 0; /* the workers are stopped all the same */
    }
    for (int i = 0; weight && n > 0 && i < m->nmaterials; i++) {
        struct stat st;
        weight[i] = stat(m->materials[i].data, &st) == 0 ? (double)st.st_size : -1;
    }
    const batch_mpi_callbacks cb = {coordinator_done, coordinator_lost, r};
    batch_mpi_coordinate(pending, n, m->nmodels, weight, m->nmaterials, &cb, &interrupt_flag);
    free(weight);
}

typedef struct worker {
    batch_fitter child;
    batch_row *row; /* the item's row, taken from the fitting process */
    int got;
} worker;

/* batch_fitter_run's callback on a worker: the row kept (its texts taken). */
static void keep_row(void *ctx, batch_row *row)
{
    worker *w = ctx;
    *w->row = *row;
    row->spec = row->params = row->stderr_ = row->warnings = row->options = row->warning_kinds = NULL;
    w->got++;
}

/* batch_mpi_work's callback: the item to the fitting process and its row back. */
static int work_item(void *ctx, int item, batch_row *row, int *held, char *why, size_t n)
{
    worker *w = ctx;
    memset(row, 0, sizeof *row);
    w->row = row, w->got = 0;
    if (batch_fitter_run(&w->child, &item, 1, &(batch_sink){keep_row, w}, held, why, n) < 0)
        return -1;
    if (w->got != 1) { /* cannot happen: no SIGINT reaches the fitting process here */
        batch_row_clear(row);
        snprintf(why, n, "its process sent %d results for it", w->got);
        return -1;
    }
    return 0;
}

void batch_mpi_run_work(const batch_args *a, const batch_manifest *m)
{
    batch_fitting f;
    worker w;
    memset(&w, 0, sizeof w);
    batch_fitting_init(&f, &w.child, a, m);
    batch_mpi_work(work_item, &w);
    batch_fitter_clear(&w.child);
}
