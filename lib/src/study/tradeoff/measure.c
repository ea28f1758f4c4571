/* The whole tradeoff from a set of options (bf_tradeoff_run): checks, the train/test
 * split, the grid, every row in order, the ranking; and a row's setting as a brdfit fit
 * command line (bf_tradeoff_fit_command).
 *
 * Decisions:
 *  - The data options (reading, preprocessing, even the subsample) apply to the data as
 *    read; then the test fraction of what is left is held out (seeded uniform random),
 *    and the sample counts apply to the rest: each a seeded stratified subsample, as
 *    `brdfit fit --subsample N` draws it.
 *  - The fit options are the base setting; the lists replace their part of it.
 *  - Rows run one at a time (each with the options' threads), so that their times
 *    compare.
 *  - The recommended command repeats the data and base fit options in the order they
 *    were set, so that `brdfit fit` reads and fits the data as the tradeoff did. */
#include "brdfit/tradeoff.h"

#include "base/cancel.h"
#include "run_options.h"
#include "tradeoff/tradeoff_impl.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A flag a signal handler or another thread may set (as compare_run.c reads it). */
/* ---- Command lines ------------------------------------------------------------------- */

/* A growing text; failed is set (and the text kept as it was) when out of memory. */
typedef struct text {
    char *s;
    size_t len, cap;
    int failed;
} text;

static void add(text *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void add(text *t, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    if (n < 0 || t->failed) {
        t->failed = 1;
        return;
    }
    if (t->len + (size_t)n + 1 > t->cap) {
        size_t cap = 2 * (t->len + (size_t)n + 1);
        char *s = realloc(t->s, cap);
        if (!s) {
            t->failed = 1;
            return;
        }
        t->s = s;
        t->cap = cap;
    }
    va_start(ap, fmt);
    vsnprintf(t->s + t->len, t->cap - t->len, fmt, ap);
    va_end(ap);
    t->len += (size_t)n;
}

/* " ARG", in single quotes when a shell would split or expand it (a quote inside closed,
 * escaped and reopened). */
static void add_arg(text *t, const char *arg)
{
    if (*arg && !strpbrk(arg, " \t\n'\"\\$`*?[]{}()<>|&;#~!")) {
        add(t, " %s", arg);
        return;
    }
    add(t, " '");
    for (const char *c = arg; *c; c++)
        add(t, *c == '\'' ? "'\\''" : "%c", *c);
    add(t, "'");
}

/* The fit options each row sets itself, left out of the repeated base ones. */
static int row_sets(const char *name)
{
    return !strcmp(name, "backend") || !strcmp(name, "algorithm") || !strcmp(name, "residual") ||
           !strcmp(name, "starts");
}

/* The data and base fit options of o as set, in order, as brdfit fit's options: each
 * " --name value" (a flag turned on: its name alone; turned off: nothing). */
static char *base_options(const bf_options *o)
{
    text t = {0};
    add(&t, "%s", "");
    for (int k = 0; k < o->nlog; k++) {
        const option_row *r = &option_rows[o->log[k].row];
        const char *v = o->log[k].value;
        if (!strcmp(r->d.group, "tradeoff") || row_sets(r->d.name))
            continue;
        if (r->d.type == BF_OPTION_FLAG && v && (!strcmp(v, "false") || !strcmp(v, "0")))
            continue;
        char name[64];
        snprintf(name, sizeof name, "--%s", r->d.name);
        for (char *c = name + 2; *c; c++)
            if (*c == '_')
                *c = '-';
        add(&t, " %s", name);
        if (v && !(r->d.type == BF_OPTION_FLAG && (!strcmp(v, "true") || !strcmp(v, "1"))))
            add_arg(&t, v);
    }
    if (t.failed) {
        free(t.s);
        return NULL;
    }
    return t.s;
}

bf_status bf_tradeoff_fit_command(const bf_tradeoff *t, int i, char **out, bf_error *err)
{
    *out = NULL;
    if (!t || i < 0 || i >= t->nrows)
        return bf_fail(err, BF_ERR_ARG, "tradeoff: no row %d", i);
    const bf_tradeoff_row *r = &t->rows[i];
    text c = {0};
    add(&c, "brdfit fit %s%s -m %s ", t->data, t->fit_options ? t->fit_options : "", t->model);
    if (!r->all)
        add(&c, "--subsample %zu ", r->samples);
    bf_backend b = BF_BACKEND_CERES;
    const bf_method_info *m = NULL;
    if (bf_method_parse(r->method, &b, &m, NULL) != BF_OK || (b == BF_BACKEND_CERES && (m->caps & BF_METHOD_DEFAULT)))
        add(&c, "--backend %s", bf_backend_name(b));
    else
        add(&c, "--backend %s --algorithm %s", bf_backend_name(b), m->name);
    add(&c, " --residual %s", bf_residual_name(r->residual));
    if (r->starts > 0) /* automatic starts (0) are brdfit fit's default: no option */
        add(&c, " --starts %d", r->starts);
    if (c.failed) {
        free(c.s);
        return bf_fail(err, BF_ERR_NOMEM, "tradeoff: out of memory");
    }
    *out = c.s;
    return BF_OK;
}

/* ---- The measurement ----------------------------------------------------------------- */

/* What bf_tradeoff_run holds between its phases. */
typedef struct measure {
    const bf_samples *data;
    const char *name, *model;
    const bf_options *o;
    options_tradeoff l; /* the lists, until the table holds copies */
    bf_samples *train, *test;
    bf_tradeoff *t;
} measure;

/* The table for the split data, with the options' values, into m->t: BF_OK, or the error. */
static bf_status make_table(measure *m, bf_error *err)
{
    const options_tradeoff *l = &m->l;
    bf_tradeoff_grid g;
    bf_tradeoff_grid_init(&g);
    g.ncounts = l->n[TRADEOFF_SAMPLES];
    g.counts = l->counts;
    g.nmethods = l->n[TRADEOFF_METHODS];
    g.methods = l->items[TRADEOFF_METHODS];
    g.nresiduals = l->n[TRADEOFF_RESIDUALS];
    g.residuals = l->residuals;
    g.nstarts = l->n[TRADEOFF_STARTS];
    g.starts = l->starts;
    bf_tradeoff *t = NULL;
    bf_status rc = bf_tradeoff_new_grid(m->name, m->model, m->train->n, &g, &t, err);
    if (rc != BF_OK)
        return rc;
    const bf_options *o = m->o;
    t->total = m->data->n;
    t->test_n = m->test->n;
    t->channels = m->data->channels;
    t->test_fraction = l->test_fraction;
    t->seed = o->seed;
    t->repeats = l->repeats;
    t->metric = o->metric;
    t->tolerance = o->tolerance;
    t->cost = l->cost_seconds ? BF_TRADEOFF_COST_SECONDS : BF_TRADEOFF_COST_WORK;
    t->timing = o->timing || l->cost_seconds; /* a cost in seconds is shown */
    t->plot_width = l->plot_width;
    t->plot_height = l->plot_height;
    if (!(t->fit_options = base_options(o))) {
        bf_tradeoff_free(t);
        return bf_fail(err, BF_ERR_NOMEM, "tradeoff: out of memory");
    }
    m->t = t;
    return BF_OK;
}

/* Every row in order, until the cancel or finish flag: BF_OK, or running out of memory. */
static bf_status run_rows(measure *m, bf_tradeoff_progress progress, void *user, bf_error *err)
{
    bf_tradeoff *t = m->t;
    bf_error e;
    for (int i = 0; i < t->nrows; i++) {
        if (bf_cancel_is_set(m->o->cancel) || bf_cancel_is_set(m->o->finish))
            break;
        /* A row that cannot run says so in its message; running out of memory stops all. */
        if (bf_tradeoff_run_row(t, i, m->train, m->test, m->o, &e) == BF_ERR_NOMEM)
            return bf_fail(err, BF_ERR_NOMEM, "%s", e.msg);
        if (progress)
            progress(user, t, i);
    }
    return BF_OK;
}

/* Positional as bf_compare_run and bf_select_run are: the settings are in o, the rest is data and the callback. */
bf_status bf_tradeoff_run(const bf_samples *data, const char *name, const char *model, const bf_options *o,
                          bf_tradeoff_progress progress, void *user, bf_tradeoff **out, bf_error *err)
{
    bf_error local;
    if (!err)
        err = &local;
    *out = NULL;
    if (!data || !model || !o)
        return bf_fail(err, BF_ERR_ARG, "tradeoff: needs data, a model and options");
    /* Bad usage first, before any work. */
    measure m = {.data = data, .name = name, .model = model, .o = o};
    bf_status rc = bf_options_check_models(o, &model, 1, err);
    if (rc == BF_OK)
        rc = bf_options_check(o, err);
    if (rc == BF_OK)
        rc = options_tradeoff_get(o, &m.l, err);
    if (rc != BF_OK)
        return rc;
    bf_error e;
    if ((rc = bf_tradeoff_split(data, m.l.test_fraction, o->seed, &m.train, &m.test, &e)) != BF_OK) {
        options_tradeoff_clear(&m.l);
        return name ? bf_fail(err, rc, "%s: %s", name, e.msg) : bf_fail(err, rc, "%s", e.msg);
    }
    rc = make_table(&m, err);
    options_tradeoff_clear(&m.l); /* the table holds copies of the methods */
    if (rc == BF_OK)
        rc = run_rows(&m, progress, user, err);
    bf_samples_free(m.train);
    bf_samples_free(m.test);
    if (rc != BF_OK) {
        bf_tradeoff_free(m.t);
        return rc;
    }
    bf_tradeoff_rank(m.t);
    *out = m.t;
    return BF_OK;
}
