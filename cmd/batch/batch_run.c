/* The parts of a brdfit batch run (batch_run.h) that record rows, and the fitting
 * process's side: a material loaded and kept between calls, its items fitted through
 * bf_compare_run exactly as brdfit compare fits them, each row sent to the parent as it
 * finishes. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "args.h"
#include "brdfit/clock.h"
#include "batch_db.h"
#include "batch_run.h"
#include "interrupt.h"

static void show_progress(const batch_run *r)
{
    if (!r->tty || cli_quiet())
        return;
    double el = bf_now_seconds() - r->t0, eta = r->done ? el / r->done * (r->total - r->done) : NAN;
    fprintf(stderr, "\r%s: %d/%d items, %d failed", BATCH_CMD, r->done, r->total, r->bad);
    if (isfinite(eta))
        fprintf(stderr, ", ETA %.0f s", eta);
    fputs("    ", stderr);
    if (r->done == r->total)
        fputc('\n', stderr);
    fflush(stderr);
}

/* The run cannot go on (a database failure, no memory): no new fit starts. In a fitting
 * process the items of the call become error rows instead (fit_items). */
static void fail(batch_run *r, const bf_error *err)
{
    r->db_failed = 1;
    r->db_err = *err;
    if (r->db)
        interrupt_raise();
}

void batch_run_put(batch_run *r, const batch_row *row)
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
static void record(batch_run *r, batch_row *row)
{
    if (r->db_failed)
        return;
    row->material = r->material;
    row->item = r->material * r->m->nmodels + row->model;
    if (r->out) {
        batch_fitter_emit(r->out, row, r->held);
        r->sent[row->model] = 1;
    } else {
        batch_run_put(r, row);
    }
}

/* bf_compare_progress: one fit finished (calls never overlap). */
static void fit_done(void *ctx, const bf_compare *c, int material, int j, int done, int total)
{
    (void)material, (void)done, (void)total;
    batch_run *r = ctx;
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

void batch_run_error_rows(batch_run *r, const int *models, int n, const char *reason)
{
    for (int k = 0; k < n; k++) {
        batch_row row = {.model = models[k], .state = BF_CMP_ERROR, .seconds = NAN, .cv = NAN, .work = NAN};
        snprintf(row.message, sizeof row.message, "%s", reason);
        record(r, &row);
    }
}

static void material_load(const batch_run *r, int i, batch_loaded *mt)
{
    const batch_manifest *m = r->m;
    mt->i = i;
    mt->s = NULL;
    if (batch_manifest_options(m, i, &mt->o, BATCH_CMD) < 0) { /* checked when read: cannot fail */
        snprintf(mt->reason, sizeof mt->reason, "its data options do not parse");
        return;
    }
    char threads[32];
    snprintf(threads, sizeof threads, "%ld", (long)r->a->threads);
    bf_error err;
    if (r->a->threads > 0 && bf_options_set(mt->o, "threads", threads, &err) != BF_OK)
        snprintf(mt->reason, sizeof mt->reason, "%s", err.msg);
    else if (!(mt->s = data_options_load(mt->o, m->materials[i].data, NULL, &err, BATCH_CMD)))
        snprintf(mt->reason, sizeof mt->reason, "%s", err.msg);
}

static void material_release(batch_loaded *mt)
{
    bf_samples_free(mt->s);
    bf_options_free(mt->o);
    mt->s = NULL;
    mt->o = NULL;
    mt->i = -1;
}

/* The models models[0..n-1] (manifest indices) of a loaded material fitted, each row
 * recorded as it finishes. */
static void material_fit(batch_run *r, batch_loaded *mt, const int *models, int n)
{
    const batch_manifest *m = r->m;
    r->material = mt->i;
    r->model_of = models;
    if (!mt->s) {
        batch_run_error_rows(r, models, n, mt->reason);
        return;
    }
    const char *specs[BATCH_MAX_MODELS], *data = m->materials[mt->i].data;
    for (int k = 0; k < n; k++)
        specs[k] = m->models[models[k]];
    bf_compare *c = NULL;
    bf_error err;
    if (bf_compare_new(1, &data, n, specs, &c, &err) != BF_OK) {
        fail(r, &err);
    } else {
        char jobs[32];
        snprintf(jobs, sizeof jobs, "%d", r->a->jobs);
        bf_options_set_cancel(mt->o, NULL, &interrupt_flag);
        if (bf_options_set(mt->o, "jobs", jobs, &err) != BF_OK ||
            bf_compare_run(c, &mt->s, mt->o, fit_done, r, &err) != BF_OK)
            fail(r, &err); /* only before any fit: bad arguments or no memory */
    }
    bf_compare_free(c);
}

/* batch_fit_fn: one material's items fitted, the material loaded unless held (and kept
 * for the next call). Whatever stops the fits (no memory, a bad spec) makes the items
 * without a row error rows; items not started after a SIGINT get none (pending). */
static void fit_items(void *ctx, const int *items, int n, batch_fitter_out *out)
{
    batch_fitting *w = ctx;
    const int nm = w->r.m->nmodels, i = items[0] / nm;
    int models[BATCH_MAX_MODELS];
    for (int k = 0; k < n && k < BATCH_MAX_MODELS; k++)
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
                batch_run_error_rows(&w->r, &models[k], 1, w->r.db_err.msg);
    }
}

void batch_fitting_init(batch_fitting *w, batch_fitter *f, const batch_args *a, const batch_manifest *m)
{
    memset(w, 0, sizeof *w);
    w->r.a = a, w->r.m = m;
    w->mt.i = -1;
    batch_fitter_init(f, fit_items, w);
}

void batch_run_lost_twice(batch_run *r, int item, const char *why)
{
    const int model = item % r->m->nmodels;
    char reason[sizeof((batch_row *)0)->message];
    snprintf(reason, sizeof reason, "the process fitting it died each of the 2 times it ran; the last time: %.400s",
             why);
    r->material = item / r->m->nmodels;
    batch_run_error_rows(r, &model, 1, reason);
}
