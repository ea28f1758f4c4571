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
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>
#include <unistd.h>

#include "args.h"
#include "batch_db.h"
#include "batch_manifest.h"
#ifdef BRDFIT_HAVE_MPI
#include "batch_fitter.h"
#include "batch_mpi.h"
#endif
#include "cli.h"
#include "commands.h"
#include "interrupt.h"

static const char cmd[] = "brdfit batch";

static const cli_option own[] = {
    {"--output", 'o', "FILE", "the results database (SQLite; made if absent, resumed if it is this\n"
                              "manifest's)", "file"},
    {"--redo", 0, "failed|all", "run these finished items again (failed: failed and error ones)", NULL},
    {"--shard", 0, "I/N", "run only share I of N of the items (job arrays; brdfit merge joins them)", NULL},
    {"--jobs", 0, "N", "fits run at once (default 1); each gets --threads / N threads", NULL},
    {"--threads", 0, "N", "solver threads in all (default: every core; results do not depend on it)", NULL},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group};
const cli_command cli_batch = {
    "brdfit", "batch", "MANIFEST -o RESULTS.db [--redo failed|all] [--shard I/N] [--jobs N]",
    "run a manifest's fits into a resumable results database",
    "Runs every (material, model) fit a manifest lists (materials with their data options, models, and the "
    "options of brdfit compare; JSON or a plain list, one data file per line: docs/batch.md) and writes each result, as it finishes, into an SQLite database. "
    "Rerunning the same command resumes where a killed or interrupted run stopped. brdfit report ranks the results "
    "as compare does; brdfit merge joins the databases of --shard runs.",
    "file", groups, sizeof groups / sizeof groups[0],
};

typedef struct batch_args {
    cli_args args;
    const char *manifest, *output;
    int redo_failed, redo_all, shard, nshards, jobs;
    long threads; /* 0: as the manifest says */
} batch_args;

static int parse_shard(batch_args *a, const char *v)
{
    char *end;
    long i = strtol(v, &end, 10), n = *end == '/' ? strtol(end + 1, &end, 10) : 0;
    if (*end || n < 1 || n > 100000 || i < 1 || i > n) {
        fprintf(stderr, "%s: --shard needs I/N with 1 <= I <= N, got '%s'\n", cmd, v);
        return -1;
    }
    a->shard = (int)i;
    a->nshards = (int)n;
    return 0;
}

static int parse_own(batch_args *a, const char *name, const char *v)
{
    long n;
    if (!strcmp(name, "--output")) {
        a->output = v;
    } else if (!strcmp(name, "--redo")) {
        if (strcmp(v, "failed") && strcmp(v, "all")) {
            fprintf(stderr, "%s: --redo needs failed or all, got '%s'\n", cmd, v);
            return -1;
        }
        a->redo_failed = 1;
        a->redo_all = !strcmp(v, "all");
    } else if (!strcmp(name, "--shard")) {
        return parse_shard(a, v);
    } else if (!strcmp(name, "--jobs")) {
        if (!args_int(v, 1, 1024, &n)) {
            fprintf(stderr, "%s: --jobs needs an integer from 1 to 1024, got '%s'\n", cmd, v);
            return -1;
        }
        a->jobs = (int)n;
    } else { /* --threads */
        if (!args_int(v, 1, FIT_OPTIONS_MAX_THREADS, &a->threads)) {
            fprintf(stderr, "%s: --threads needs an integer from 1 to %d, got '%s'\n", cmd, FIT_OPTIONS_MAX_THREADS, v);
            return -1;
        }
    }
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
    for (int i = 0; i < a->args.n; i++) {
        const char *name = a->args.v[i].name, *v = a->args.v[i].value;
        if (!name) {
            if (a->manifest) {
                fprintf(stderr, "%s: one manifest only (got '%s' and '%s')\n", cmd, a->manifest, v);
                return 2;
            }
            a->manifest = v;
        } else if (parse_own(a, name, v) < 0) {
            return 2;
        }
    }
    if (!a->manifest || !a->output) {
        fprintf(stderr, "%s: %s (see brdfit batch --help)\n", cmd,
                !a->manifest ? "a manifest is required" : "-o RESULTS.db is required");
        return 2;
    }
    return -1;
}

/* ---- The run ------------------------------------------------------------------------- */

typedef struct run {
    const batch_args *a;
    const batch_manifest *m;
    batch_db *db;        /* the writer (the one process, or the MPI coordinator); NULL in a
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
    unsigned char sent[128];
} run;

static void show_progress(const run *r)
{
    if (!r->tty || cli_quiet())
        return;
    double el = args_now() - r->t0, eta = r->done ? el / r->done * (r->total - r->done) : NAN;
    fprintf(stderr, "\r%s: %d/%d items, %d failed", cmd, r->done, r->total, r->bad);
    if (isfinite(eta))
        fprintf(stderr, ", ETA %.0f s", eta);
    fputs("    ", stderr);
    if (r->done == r->total)
        fputc('\n', stderr);
    fflush(stderr);
}

/* The run cannot go on (a database failure, no memory): no new fit starts. In a fitting
 * process the items of the call become error rows instead (fit_items). */
static void fail(run *r, const bf_error *err)
{
    r->db_failed = 1;
    r->db_err = *err;
    if (r->db)
        interrupt_raise();
}

/* A finished item's row written (its own transaction) and counted. */
static void put_row(run *r, const batch_row *row)
{
    if (batch_db_put(r->db, row, &r->db_err) != BF_OK) {
        r->db_failed = 1;
        interrupt_raise();
        return;
    }
    r->done++;
    if (!row->pending && row->state == BF_CMP_OK)
        r->ok++;
    else
        r->bad++;
    show_progress(r);
}

/* The item's row written, or, in a fitting process, sent to its parent. */
static void record(run *r, batch_row *row)
{
    if (r->db_failed)
        return;
    row->material = r->material;
    row->item = r->material * r->m->nmodels + row->model;
    if (r->out) {
        batch_fitter_emit(r->out, row, r->held);
        r->sent[row->model] = 1;
    } else {
        put_row(r, row);
    }
}

/* bf_compare_progress: one fit finished (calls never overlap). */
static void fit_done(void *ctx, const bf_compare *c, int material, int j, int done, int total)
{
    (void)material, (void)done, (void)total;
    run *r = ctx;
    batch_row row = {0};
    bf_error err;
    if (batch_row_from_fit(&row, c, j, &err) != BF_OK) {
        fail(r, &err);
        return;
    }
    row.model = r->model_of[j];
    record(r, &row);
    batch_row_clear(&row);
}

/* Every model of models[0..n-1] an error on the current material (why: reason). */
static void data_error(run *r, const int *models, int n, const char *reason)
{
    for (int k = 0; k < n; k++) {
        batch_row row = {.model = models[k], .state = BF_CMP_ERROR, .seconds = NAN, .cv = NAN, .work = NAN};
        snprintf(row.message, sizeof row.message, "%s", reason);
        record(r, &row);
    }
}

/* A material read and prepared for fitting: s NULL when it could not be (why: reason). */
typedef struct material {
    int i;
    bf_samples *s;
    fit_options fopt;
    char reason[512];
} material;

static void material_load(const run *r, int i, material *mt)
{
    const batch_manifest *m = r->m;
    data_options dopt;
    mt->i = i;
    mt->s = NULL;
    if (batch_manifest_data_options(m, i, &dopt, cmd) < 0) { /* checked when read: cannot fail */
        snprintf(mt->reason, sizeof mt->reason, "its data options do not parse");
        return;
    }
    mt->fopt = m->fopt;
    if (r->a->threads > 0)
        mt->fopt.fit.solver.threads = (int)r->a->threads;
    fit_options_finish(&mt->fopt, &dopt);
    if (!(mt->s = data_options_load(&dopt, m->materials[i].data, NULL, cmd)))
        data_options_load_reason(&dopt, m->materials[i].data, mt->reason, sizeof mt->reason);
}

static void material_release(material *mt)
{
    bf_samples_free(mt->s);
    mt->s = NULL;
    mt->i = -1;
}

/* The models models[0..n-1] (manifest indices) of a loaded material fitted, each row
 * recorded as it finishes. */
static void material_fit(run *r, material *mt, const int *models, int n)
{
    const batch_manifest *m = r->m;
    r->material = mt->i;
    r->model_of = models;
    if (!mt->s) {
        data_error(r, models, n, mt->reason);
        return;
    }
    const char *specs[128], *data = m->materials[mt->i].data;
    for (int k = 0; k < n; k++)
        specs[k] = m->models[models[k]];
    bf_compare c;
    bf_error err;
    memset(&c, 0, sizeof c);
    if (bf_compare_init(&c, 1, &data, n, specs, &err) != BF_OK) {
        fail(r, &err);
    } else {
        c.folds = m->ro.rank_by == BF_RANK_CV ? m->ro.folds : 0;
        bf_compare_run_options ro = {.jobs = r->a->jobs, .progress = fit_done, .ctx = r, .cancel = &interrupt_flag};
        if (bf_compare_run(&c, &mt->s, &mt->fopt.fit, &ro, &err) != BF_OK)
            fail(r, &err); /* only before any fit: bad arguments or no memory */
    }
    bf_compare_clear(&c);
}

/* ---- The fitting process (batch_fitter.h) ---------------------------------------------- */

/* Its state: a run of its own (no database; rows go to its parent) and the material it
 * holds. Made by the parent before the fork; only the child's copy is used. */
typedef struct fitting {
    run r;
    material mt;
} fitting;

/* batch_fit_fn: one material's items fitted, the material loaded unless held (and kept
 * for the next call). Whatever stops the fits (no memory, a bad spec) makes the items
 * without a row error rows; items not started after a SIGINT get none (pending). */
static void fit_items(void *ctx, const int *items, int n, batch_fitter_out *out)
{
    fitting *w = ctx;
    const int nm = w->r.m->nmodels, i = items[0] / nm;
    int models[128];
    for (int k = 0; k < n && k < 128; k++)
        models[k] = items[k] % nm;
    if (w->mt.i != i) {
        material_release(&w->mt);
        material_load(&w->r, i, &w->mt);
    }
    w->r.out = out;
    w->r.held = w->mt.s ? i : -1;
    w->r.db_failed = 0;
    memset(w->r.sent, 0, sizeof w->r.sent);
    material_fit(&w->r, &w->mt, models, n);
    if (w->r.db_failed) {
        w->r.db_failed = 0;
        for (int k = 0; k < n; k++)
            if (!w->r.sent[models[k]])
                data_error(&w->r, &models[k], 1, w->r.db_err.msg);
    }
}

static void fitting_init(fitting *w, batch_fitter *f, const batch_args *a, const batch_manifest *m)
{
    memset(w, 0, sizeof *w);
    w->r.a = a, w->r.m = m;
    w->mt.i = -1;
    batch_fitter_init(f, fit_items, w);
}

/* An item whose fitting process died both times it ran (one process or MPI): an error
 * row saying so, with the last reason. */
static void lost_twice(run *r, int item, const char *why)
{
    const int model = item % r->m->nmodels;
    char reason[sizeof ((batch_row *)0)->message];
    snprintf(reason, sizeof reason, "the process fitting it died each of the 2 times it ran; the last time: %.400s",
             why);
    r->material = item / r->m->nmodels;
    data_error(r, &model, 1, reason);
}

/* ---- One process ---------------------------------------------------------------------- */

/* batch_fitter_run's callback in the one process: a row written, its model marked. */
static void got_row(void *ctx, batch_row *row)
{
    run *r = ctx;
    r->sent[row->model] = 1;
    if (!r->db_failed)
        put_row(r, row);
}

/* One material's items (items[0..n-1]) through the fitting process. When that dies, each
 * item without a row runs again alone; one that dies alone too is an error row. */
static void run_material(run *r, batch_fitter *f, const int *items, int n)
{
    const int nm = r->m->nmodels, i = items[0] / nm;
    char why[512], why2[512];
    int held;
    memset(r->sent, 0, sizeof r->sent);
    if (batch_fitter_run(f, items, n, got_row, r, &held, why, sizeof why) == 0 || interrupt_flag)
        return;
    int left = 0;
    for (int k = 0; k < n; k++)
        left += !r->sent[items[k] % nm];
    fprintf(stderr, "%s: %s: the process fitting it died (%s); %s\n", cmd, r->m->materials[i].data, why,
            left == 1 ? "its unfinished fit runs again" : "its unfinished fits run again, one at a time");
    for (int k = 0; k < n && !interrupt_flag; k++) {
        const int model = items[k] % nm;
        if (r->sent[model] || batch_fitter_run(f, &items[k], 1, got_row, r, &held, why2, sizeof why2) == 0 ||
            interrupt_flag)
            continue;
        fprintf(stderr, "%s: %s, %s: the process fitting it died again (%s); recorded as an error (--redo failed "
                "runs it again)\n", cmd, r->m->materials[i].data, r->m->models[model], why2);
        lost_twice(r, items[k], why2);
    }
}

/* The pending items, material by material, in one fitting process. */
static void run_items(run *r, const int *items, int n)
{
    fitting w;
    batch_fitter f;
    fitting_init(&w, &f, r->a, r->m);
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

#ifdef BRDFIT_HAVE_MPI
/* ---- MPI (batch_mpi.h) ----------------------------------------------------------------- */

/* The coordinator's callbacks (batch_mpi_callbacks): a worker's row written and counted;
 * a lost item told, and written as an error once it has been lost too often. */
static void coordinator_done(void *ctx, batch_row *row)
{
    run *r = ctx;
    if (!r->db_failed)
        put_row(r, row);
}

static void coordinator_lost(void *ctx, int item, int rank, const char *why, int again)
{
    run *r = ctx;
    const int i = item / r->m->nmodels, model = item % r->m->nmodels;
    fprintf(stderr, "%s: %s, %s: the process fitting it on rank %d died (%s); %s\n", cmd, r->m->materials[i].data,
            r->m->models[model], rank, why,
            again ? "handed out again" : "recorded as an error (--redo failed runs it again)");
    if (!again)
        lost_twice(r, item, why);
}

/* The items of r (pending[0..n-1]) handed out to the workers; the weight of a material
 * is its data file's size (-1 when it cannot be read: its items are errors, quick ones). */
static void coordinate(run *r, const int *pending, int n)
{
    const batch_manifest *m = r->m;
    double *weight = malloc(((size_t)m->nmaterials + 1) * sizeof *weight);
    if (!weight) {
        r->db_failed = 1;
        bf_fail(&r->db_err, BF_ERR_NOMEM, "out of memory for the work queue");
        n = 0; /* the workers are stopped all the same */
    }
    for (int i = 0; weight && i < m->nmaterials; i++) {
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
    row->spec = row->params = row->stderr_ = row->warnings = row->options = NULL;
    w->got++;
}

/* batch_mpi_work's callback: the item to the fitting process and its row back. */
static int work_item(void *ctx, int item, batch_row *row, int *held, char *why, size_t n)
{
    worker *w = ctx;
    memset(row, 0, sizeof *row);
    w->row = row, w->got = 0;
    if (batch_fitter_run(&w->child, &item, 1, keep_row, w, held, why, n) < 0)
        return -1;
    if (w->got != 1) { /* cannot happen: no SIGINT reaches the fitting process here */
        batch_row_clear(row);
        snprintf(why, n, "its process sent %d results for it", w->got);
        return -1;
    }
    return 0;
}

static void work(const batch_args *a, const batch_manifest *m)
{
    fitting f;
    worker w;
    memset(&w, 0, sizeof w);
    fitting_init(&f, &w.child, a, m);
    batch_mpi_work(work_item, &w);
    batch_fitter_clear(&w.child);
}
#endif

/* One process, or the coordinator of several (nproc > 1): its workers are stopped on
 * every path. */
static int batch(const batch_args *a, const batch_manifest *m, int nproc)
{
    batch_db *db;
    bf_error err;
    int *items = NULL, n = 0, status = -1;
    run r = {.a = a, .m = m, .tty = isatty(STDERR_FILENO)};
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
        if (nproc > 1) {
            const batch_mpi_callbacks cb = {coordinator_done, coordinator_lost, &r};
            batch_mpi_coordinate(NULL, 0, m->nmodels, NULL, 0, &cb, &interrupt_flag);
        }
#endif
        batch_db_close(db);
        return status;
    }
    r.db = db, r.total = n, r.t0 = args_now();
    struct sigaction old;
    interrupt_catch(&old); /* SIGINT, or a database failure (interrupt_raise): no new fit */
    cli_note(cmd, "%d items to run into %s", n, a->output);
#ifdef BRDFIT_HAVE_MPI
    if (nproc > 1)
        coordinate(&r, items, n);
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
        fprintf(stderr, "%s: %d of %d items failed (brdfit report lists them; --redo failed reruns them)\n", cmd,
                r.bad, r.total);
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
            work(&a, &m);
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
