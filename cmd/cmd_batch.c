/* brdfit batch MANIFEST -o RESULTS.db: every model of a manifest fitted to every
 * material of it (batch_manifest.h), each (material, model) fit a work item whose
 * result is a row of an SQLite database (batch_db.h, docs/batch.md).
 *
 * Decisions:
 *  - Materials are read one at a time, when one of their items is to run, and released
 *    after their last fit: memory is that of the largest material, not of all.
 *  - A material's pending models run through bf_compare_run (--jobs at once, the
 *    --threads budget shared), exactly as brdfit compare runs them, so the rows hold
 *    compare's results; each finished fit is written in its own transaction as it
 *    arrives, so a killed run loses only the fits in flight.
 *  - The fits run in a child process (batch_fitter.h) that sends their rows back: one
 *    whose fit crashes or is killed costs that material's unfinished items, which run
 *    again one at a time in a fresh process; an item that dies alone too is an error
 *    row (--redo failed reruns it). A crash in one model on one material then cannot end
 *    a library run, nor stop every rerun at the same item.
 *  - Rerunning resumes: only pending items run. --redo failed makes failed and error
 *    items pending again first, --redo all every item. A database of another manifest,
 *    version or shard is refused (batch_db_setup), never mixed.
 *  - --shard I/N runs items with item % N == I - 1 (item = material x models + model)
 *    into its own database; brdfit merge combines the shards.
 *  - Data that cannot be read or prepared makes each of its items an error with the
 *    reason as its message (printed on stderr too); the other materials go on.
 *  - --threads here overrides a manifest's: results do not depend on it (fit.h), and the
 *    machine that runs a batch is not part of what the manifest asks.
 *  - Progress (items done, failures, ETA) on a terminal; nothing when stderr is not one.
 *    SIGINT: no new fit starts, running fits finish and are written, exit 130; the
 *    database is resumable. A second SIGINT ends the process at once.
 *  - Exit: 0 every item of the shard ok; 1 some item failed or errored, or the database
 *    could not be used; 2 bad usage or manifest; 130 interrupted. */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "args.h"
#include "brdfit/clock.h"
#include "batch/batch_db.h"
#include "batch/batch_manifest.h"
#ifdef BRDFIT_HAVE_MPI
#include "batch/batch_mpi.h"
#endif
#include "batch/batch_run.h"
#include "cli.h"
#include "commands.h"
#include "interrupt.h"

static const char cmd[] = BATCH_CMD;

static int take_redo(void *target, const cli_option *o, const char *v, const char *c)
{
    batch_args *a = target;
    (void)o;
    if (strcmp(v, "failed") && strcmp(v, "all")) {
        fprintf(stderr, "%s: --redo needs failed or all, got '%s'\n", c, v);
        return -1;
    }
    a->redo_failed = 1;
    a->redo_all = !strcmp(v, "all");
    return 0;
}

static int take_shard(void *target, const cli_option *o, const char *v, const char *c)
{
    batch_args *a = target;
    char *end;
    (void)o;
    long i = strtol(v, &end, 10), n = *end == '/' ? strtol(end + 1, &end, 10) : 0;
    if (*end || n < 1 || n > 100000 || i < 1 || i > n) {
        fprintf(stderr, "%s: --shard needs I/N with 1 <= I <= N, got '%s'\n", c, v);
        return -1;
    }
    a->shard = (int)i;
    a->nshards = (int)n;
    return 0;
}

static int take_jobs(void *target, const cli_option *o, const char *v, const char *c)
{
    (void)o;
    return args_jobs(c, v, &((batch_args *)target)->jobs);
}

/* --threads: a long (0 stands for "as the manifest says"), so not CLI_INT_AT's int; its
 * range is the fit option's. */
static int take_threads(void *target, const cli_option *o, const char *v, const char *c)
{
    (void)o;
    const bf_option *d = bf_option_find("threads", BF_TASK_COMPARE);
    if (!args_int(v, (long)d->lo, (long)d->hi, &((batch_args *)target)->threads)) {
        fprintf(stderr, "%s: --threads needs %s, got '%s'\n", c, d->range ? d->range : "an integer from 1 to 1024", v);
        return -1;
    }
    return 0;
}

static const cli_option own[] = {
    {"--output", 'o', "FILE",
     "the results database (SQLite; made if absent, resumed if it is this\n"
     "manifest's)",
     "file", CLI_STRING_AT(batch_args, output)},
    {"--redo", 0, "failed|all", "run these finished items again (failed: failed and error ones)", NULL,
     CLI_CALLS(take_redo)},
    {"--shard", 0, "I/N", "run only share I of N of the items (job arrays; brdfit merge joins them)", NULL,
     CLI_CALLS(take_shard)},
    {"--jobs", 0, "N", "fits run at once (default 1); each gets --threads / N threads", NULL, CLI_CALLS(take_jobs)},
    {"--threads", 0, "N", "solver threads in all (default: every core; results do not depend on it)", NULL,
     CLI_CALLS(take_threads)},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group};
const cli_command cli_batch = {
    "brdfit",
    "batch",
    "MANIFEST -o RESULTS.db [--redo failed|all] [--shard I/N] [--jobs N]",
    "run a manifest's fits into a resumable results database",
    "Runs every (material, model) fit a manifest lists (materials with their data options, models, and the "
    "options of brdfit compare; JSON or a plain list, one data file per line: docs/batch.md) and writes each result, "
    "as it finishes, into an SQLite database. "
    "Rerunning the same command resumes where a killed or interrupted run stopped. brdfit report ranks the results "
    "as compare does; brdfit merge joins the databases of --shard runs.",
    "file",
    groups,
    sizeof groups / sizeof groups[0],
};

static int take_manifest(void *ctx, const char *v, const char *c)
{
    batch_args *a = ctx;
    if (a->manifest) {
        fprintf(stderr, "%s: one manifest only (got '%s' and '%s')\n", c, a->manifest, v);
        return -1;
    }
    a->manifest = v;
    return 0;
}

/* -1 to go on, else the exit status. */
static int parse(batch_args *a, int argc, char **argv)
{
    memset(a, 0, sizeof *a);
    a->shard = a->nshards = a->jobs = 1;
    int p = cli_parse(&cli_batch, argc, argv, &a->args);
    if (p != CLI_OK)
        return p == CLI_EXIT ? 0 : 2;
    void *const targets[] = {a};
    if (cli_take(&cli_batch, targets, CLI_COUNT(targets), &a->args, take_manifest, a, cmd) < 0)
        return 2;
    if (!a->manifest || !a->output) {
        fprintf(stderr, "%s: %s (see brdfit batch --help)\n", cmd,
                !a->manifest ? "a manifest is required" : "-o RESULTS.db is required");
        return 2;
    }
    return -1;
}

/* ---- One process ---------------------------------------------------------------------- */

/* batch_fitter_run's callback in the one process: a row written, its model marked. */
static void got_row(void *ctx, batch_row *row)
{
    batch_run *r = ctx;
    r->sent[row->model] = 1;
    if (!r->db_failed)
        batch_run_put(r, row);
}

/* One material's items (items[0..n-1]) through the fitting process. When that dies, each
 * item without a row runs again alone; one that dies alone too is an error row. */
static void run_material(batch_run *r, batch_fitter *f, const int *items, int n)
{
    const int nm = r->m->nmodels, i = items[0] / nm;
    char why[512], why2[512];
    int held;
    memset(r->sent, 0, sizeof r->sent);
    if (batch_fitter_run(f, items, n, &(batch_sink){got_row, r}, &held, why, sizeof why) == 0 || interrupt_flag)
        return;
    int left = 0;
    for (int k = 0; k < n; k++)
        left += !r->sent[items[k] % nm];
    fprintf(stderr, "%s: %s: the process fitting it died (%s); %s\n", cmd, r->m->materials[i].data, why,
            left == 1 ? "its unfinished fit runs again" : "its unfinished fits run again, one at a time");
    for (int k = 0; k < n && !interrupt_flag; k++) {
        const int model = items[k] % nm;
        if (r->sent[model] ||
            batch_fitter_run(f, &items[k], 1, &(batch_sink){got_row, r}, &held, why2, sizeof why2) == 0 ||
            interrupt_flag)
            continue;
        fprintf(stderr,
                "%s: %s, %s: the process fitting it died again (%s); recorded as an error (--redo failed "
                "runs it again)\n",
                cmd, r->m->materials[i].data, r->m->models[model], why2);
        batch_run_lost_twice(r, items[k], why2);
    }
}

/* The pending items, material by material, in one fitting process. */
static void run_items(batch_run *r, const int *items, int n)
{
    batch_fitting w;
    batch_fitter f;
    batch_fitting_init(&w, &f, r->a, r->m);
    f.interrupt = &interrupt_flag;
    for (int k = 0; k < n && !interrupt_flag;) {
        const int i = items[k] / r->m->nmodels;
        int j = k;
        while (j < n && items[j] / r->m->nmodels == i)
            j++;
        run_material(r, &f, items + k, j - k);
        k = j;
    }
    batch_fitter_clear(&f);
}

/* One process, or the coordinator of several (nproc > 1): its workers are stopped on
 * every path. */
static int batch(const batch_args *a, const batch_manifest *m, int nproc)
{
    batch_db *db;
    bf_error err;
    int *items = NULL, n = 0, status = -1;
    batch_run r = {.a = a, .m = m, .tty = isatty(STDERR_FILENO)};
    if (batch_db_open(a->output, BATCH_DB_WRITE, &db, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        db = NULL, status = 1;
    } else if (batch_db_setup(db, m, a->shard, a->nshards, &err) != BF_OK ||
               batch_db_redo(db, a->redo_failed, a->redo_all, &err) != BF_OK ||
               batch_db_pending(db, &items, &n, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        status = err.code == BF_ERR_ARG ? 2 : 1;
    }
    if (status >= 0) {
#ifdef BRDFIT_HAVE_MPI
        if (nproc > 1)
            batch_mpi_run_coordinate(&r, NULL, 0);
#endif
        batch_db_close(db);
        return status;
    }
    r.db = db, r.total = n, r.t0 = bf_now_seconds();
    struct sigaction old;
    interrupt_catch(&old); /* SIGINT, or a database failure (interrupt_raise): no new fit */
    cli_note(cmd, "%d items to run into %s", n, a->output);
#ifdef BRDFIT_HAVE_MPI
    if (nproc > 1)
        batch_mpi_run_coordinate(&r, items, n);
    else
#endif
        run_items(&r, items, n);
    (void)nproc;
    interrupt_release(&old);
    free(items);
    batch_db_close(db);
    if (r.tty && !cli_quiet() && r.done < r.total)
        fputc('\n', stderr);
    if (r.db_failed) {
        fprintf(stderr, "%s: %s\n", cmd, r.db_err.msg);
        return 1;
    }
    if (r.done < r.total) {
        fprintf(stderr, "%s: interrupted after %d of %d items; the same command resumes\n", cmd, r.done, r.total);
        return 130;
    }
    if (r.bad) {
        fprintf(stderr, "%s: %d of %d items failed (brdfit report lists them; --redo failed reruns them)\n", cmd, r.bad,
                r.total);
        return 1;
    }
    return 0;
}

int cmd_batch(int argc, char **argv)
{
    batch_args a;
    batch_manifest m = {0};
    int status = parse(&a, argc, argv), rank = 0, nproc = 1;
#ifdef BRDFIT_HAVE_MPI
    if (status < 0)
        batch_mpi_start(&rank, &nproc);
#endif
    if (status < 0 && rank == 0)
        status = batch_manifest_read(a.manifest, NULL, &m, cmd) < 0 ? 2 : -1;
#ifdef BRDFIT_HAVE_MPI
    if (nproc > 1) {
        /* Every rank reads the manifest (the workers after rank 0 could) and checks that
         * it is rank 0's: a file that differs on another machine would fit other items. */
        char hash[17];
        memcpy(hash, m.hash, sizeof hash);
        batch_mpi_share(&status, hash);
        if (status < 0 && rank > 0) {
            if (batch_manifest_read(a.manifest, NULL, &m, cmd) < 0) {
                status = 2;
            } else if (memcmp(hash, m.hash, sizeof hash)) {
                fprintf(stderr, "%s: %s: not the manifest rank 0 read (the file differs here)\n", cmd, a.manifest);
                status = 2;
            }
        }
        if (!batch_mpi_all(status < 0) && status < 0)
            status = 2;
        if (status < 0 && rank > 0) {
            batch_mpi_run_work(&a, &m);
            status = 0;
        }
    }
#endif
    if (status < 0)
        status = batch(&a, &m, nproc);
#ifdef BRDFIT_HAVE_MPI
    batch_mpi_end();
#endif
    batch_manifest_clear(&m);
    cli_args_free(&a.args);
    return status;
}
