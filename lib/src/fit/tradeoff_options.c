/* The tradeoff's own run options (tradeoff_options.h): kept as given when set, read back
 * with their defaults, and the four lists split, parsed and checked.
 *
 * Decisions:
 *  - The lists are checked once every option is in (bf_options_check), not when set:
 *    their defaults follow the base setting (--backend, --residual, --starts), and a
 *    method is checked with the base's other settings (its constraint, its local method).
 *  - The values are kept as the text given and parsed where used, so that the table's
 *    default is the one place a default is written. */
#include "tradeoff_options.h"

#include "brdfit/tool.h"
#include "brdfit/tradeoff.h"
#include "run_options.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The option's name as the set's messages spell it ("--samples" or "samples"). */
#define SPELL(o, name, buf) option_spelled((o), (name), (buf), sizeof(buf))

static const char *const list_names[TRADEOFF_NLISTS] = {"samples", "methods", "residuals", "starts_list"};

/* ---- Methods ------------------------------------------------------------------------ */

bf_status bf_tradeoff_method_apply(const char *text, bf_solver_options *so, bf_error *err)
{
    bf_backend backend;
    const bf_method_info *m;
    if (bf_method_parse(text, &backend, &m, err) != BF_OK)
        return BF_ERR_ARG;
    bf_solver_options o = *so;
    o.backend = backend;
    o.algorithm = m->name;
    if (bf_solver_options_check(&o, err) != BF_OK)
        return bf_fail(err, BF_ERR_ARG, "method \"%s\": %s", text, err ? err->msg : "");
    *so = o;
    return BF_OK;
}

/* The base setting as a methods item: "ceres" for its default, "ceres:dogleg", or the
 * NLopt method's name. */
static void method_of(bf_backend backend, const char *algorithm, char *buf, size_t size)
{
    const bf_method_info *m = bf_method_find(backend, algorithm);
    if (!m) /* an unknown algorithm is bf_options_check's to report */
        m = bf_method_default(backend);
    if (backend == BF_BACKEND_CERES && (m->caps & BF_METHOD_DEFAULT))
        snprintf(buf, size, "ceres");
    else if (backend == BF_BACKEND_CERES)
        snprintf(buf, size, "ceres:%s", m->name);
    else
        snprintf(buf, size, "%s", m->name);
}

/* ---- Taking and giving values -------------------------------------------------------- */

int options_tradeoff_count(const char *s, long hi, long *out)
{
    char buf[32];
    size_t len = strlen(s);
    long mul = 1, v;
    if (len > 1 && len < sizeof buf && (s[len - 1] == 'k' || s[len - 1] == 'K')) {
        memcpy(buf, s, len - 1);
        buf[len - 1] = '\0';
        s = buf;
        mul = 1000;
    }
    if (!bf_parse_long(s, 1, hi / mul, &v))
        return 0;
    *out = v * mul;
    return 1;
}

bf_status options_tradeoff_set_number(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    long n;
    double d;
    int ok = v && (r->d.type == BF_OPTION_INT ? options_tradeoff_count(v, (long)r->d.hi, &n) && n >= (long)r->d.lo
                                              : bf_parse_number(v, r->d.lo, r->d.hi, &d));
    if (!ok)
        return bf_fail(err, BF_ERR_ARG, "%s needs %s, got '%s'", SPELL(o, r->d.name, name), r->d.range, v ? v : "");
    return option_keep_text(o, r, v, err);
}

bf_status options_tradeoff_set_cost(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    if (!v || (strcmp(v, "work") && strcmp(v, "seconds")))
        return bf_fail(err, BF_ERR_ARG, "%s needs work or seconds, got '%s'", SPELL(o, r->d.name, name), v ? v : "");
    return option_keep_text(o, r, v, err);
}

/* "WxH", each side an integer in the row's range. */
static int plot_size(const option_row *r, const char *v, int *w, int *h)
{
    char buf[32];
    const char *x = v ? strchr(v, 'x') : NULL;
    long a, b;
    if (!x || (size_t)(x - v) >= sizeof buf)
        return 0;
    memcpy(buf, v, (size_t)(x - v));
    buf[x - v] = '\0';
    if (!bf_parse_long(buf, (long)r->d.lo, (long)r->d.hi, &a) ||
        !bf_parse_long(x + 1, (long)r->d.lo, (long)r->d.hi, &b))
        return 0;
    *w = (int)a;
    *h = (int)b;
    return 1;
}

bf_status options_tradeoff_set_plot_size(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    int w, h;
    if (!plot_size(r, v, &w, &h))
        return bf_fail(err, BF_ERR_ARG, "%s needs %s, got '%s'", SPELL(o, r->d.name, name), r->d.range, v ? v : "");
    return option_keep_text(o, r, v, err);
}

void options_tradeoff_get_kept(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    const char *t = o->text[option_row_index(r)];
    snprintf(buf, size, "%s", t ? t : r->d.def ? r->d.def : "");
}

void options_tradeoff_get_list(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    const char *t = o->text[option_row_index(r)];
    if (t || r->d.def) {
        snprintf(buf, size, "%s", t ? t : r->d.def);
        return;
    }
    bf_fit_options f;
    options_fit_get(o, &f);
    if (!strcmp(r->d.name, "methods")) {
        const char *algorithm = f.solver.algorithm && *f.solver.algorithm ? f.solver.algorithm : NULL;
        if (f.solver.backend != BF_BACKEND_CERES || algorithm)
            method_of(f.solver.backend, algorithm, buf, size);
        else
            snprintf(buf, size, "ceres,LD_LBFGS");
    } else if (!strcmp(r->d.name, "residuals"))
        snprintf(buf, size, "%s", bf_residual_name(f.objective.residual));
    else if (f.starts > 0)
        snprintf(buf, size, "%d", f.starts);
    else
        snprintf(buf, size, "auto");
}

/* ---- The lists ------------------------------------------------------------------------ */

void options_tradeoff_clear(options_tradeoff *t)
{
    for (int l = 0; l < TRADEOFF_NLISTS; l++)
        free(t->text[l]);
    memset(t, 0, sizeof *t);
}

/* The row of a tradeoff option (a bf_option is its row's first member). */
static const option_row *row_of(const char *name)
{
    return (const option_row *)bf_option_find(name, BF_TASK_TRADEOFF);
}

/* A list of o as given, or its default; copied (NULL when out of memory). */
static char *list_of(const bf_options *o, const char *name)
{
    const option_row *r = row_of(name);
    const char *t = o->text[option_row_index(r)];
    char buf[256];
    if (!t) {
        options_tradeoff_get_list(o, r, buf, sizeof buf);
        t = buf;
    }
    return strdup(t);
}

/* List l split into items (in place): BF_ERR_ARG naming the list for an empty item or
 * too many. */
static bf_status split(const bf_options *o, options_tradeoff *t, int l, bf_error *err)
{
    char name[64];
    int n = 0;
    for (char *p = t->text[l];;) {
        char *comma = strchr(p, ',');
        if (comma)
            *comma = '\0';
        if (!*p)
            return bf_fail(err, BF_ERR_ARG, "%s: empty item in the list", SPELL(o, list_names[l], name));
        if (n >= OPTIONS_TRADEOFF_MAX_LIST)
            return bf_fail(err, BF_ERR_ARG, "%s: more than %d items", SPELL(o, list_names[l], name),
                           OPTIONS_TRADEOFF_MAX_LIST);
        t->items[l][n++] = p;
        t->n[l] = n;
        if (!comma)
            return BF_OK;
        p = comma + 1;
    }
}

/* The items as counts, methods, residual forms and start counts. */
static bf_status parse(const bf_options *o, options_tradeoff *t, bf_error *err)
{
    char name[64];
    bf_error e;
    long n;
    for (int k = 0; k < t->n[TRADEOFF_SAMPLES]; k++) {
        const char *item = t->items[TRADEOFF_SAMPLES][k];
        if (!strcmp(item, "all"))
            t->counts[k] = 0;
        else if (options_tradeoff_count(item, 1000000000L, &n))
            t->counts[k] = (size_t)n;
        else
            return bf_fail(err, BF_ERR_ARG, "%s: '%s' is not a positive count or 'all'",
                           SPELL(o, list_names[TRADEOFF_SAMPLES], name), item);
    }
    bf_fit_options base;
    options_fit_get(o, &base);
    for (int k = 0; k < t->n[TRADEOFF_METHODS]; k++) {
        bf_solver_options so = base.solver;
        if (bf_tradeoff_method_apply(t->items[TRADEOFF_METHODS][k], &so, &e) != BF_OK)
            return bf_fail(err, BF_ERR_ARG, "%s: %s", SPELL(o, list_names[TRADEOFF_METHODS], name), e.msg);
    }
    for (int k = 0; k < t->n[TRADEOFF_RESIDUALS]; k++)
        if (bf_residual_parse(t->items[TRADEOFF_RESIDUALS][k], &t->residuals[k], &e) != BF_OK)
            return bf_fail(err, BF_ERR_ARG, "%s: %s", SPELL(o, list_names[TRADEOFF_RESIDUALS], name), e.msg);
    for (int k = 0; k < t->n[TRADEOFF_STARTS]; k++) {
        const char *item = t->items[TRADEOFF_STARTS][k];
        if (!strcmp(item, "auto"))
            n = 0; /* brdfit fit's automatic starts */
        else if (!options_tradeoff_count(item, 100000, &n))
            return bf_fail(err, BF_ERR_ARG, "%s: '%s' is not a positive integer or auto",
                           SPELL(o, list_names[TRADEOFF_STARTS], name), item);
        t->starts[k] = (int)n;
    }
    /* The sample counts may still merge (bf_tradeoff_new); the product is the most there
     * can be. */
    double settings = (double)t->n[0] * t->n[1] * t->n[2] * t->n[3];
    if (settings > BF_TRADEOFF_MAX_ROWS)
        return bf_fail(err, BF_ERR_ARG, "%.0f settings is too many (at most %d): shorten the lists", settings,
                       BF_TRADEOFF_MAX_ROWS);
    return BF_OK;
}

/* The other values, checked when set: their text (or default) read. */
static void values(const bf_options *o, options_tradeoff *t)
{
    char buf[64];
    bf_options_get(o, "test_fraction", buf, sizeof buf, NULL);
    t->test_fraction = strtod(buf, NULL);
    bf_options_get(o, "repeats", buf, sizeof buf, NULL);
    long n = 1;
    options_tradeoff_count(buf, (long)row_of("repeats")->d.hi, &n);
    t->repeats = (int)n;
    bf_options_get(o, "cost", buf, sizeof buf, NULL);
    t->cost_seconds = !strcmp(buf, "seconds");
    bf_options_get(o, "plot_size", buf, sizeof buf, NULL);
    plot_size(row_of("plot_size"), buf, &t->plot_width, &t->plot_height);
}

bf_status options_tradeoff_get(const bf_options *o, options_tradeoff *out, bf_error *err)
{
    memset(out, 0, sizeof *out);
    if (o->task != BF_TASK_TRADEOFF)
        return bf_fail(err, BF_ERR_ARG, "tradeoff: options of another task (make them for BF_TASK_TRADEOFF)");
    /* Each list split before any is parsed: a list's form is wrong before its items. */
    bf_status rc = BF_OK;
    for (int l = 0; l < TRADEOFF_NLISTS && rc == BF_OK; l++) {
        if (!(out->text[l] = list_of(o, list_names[l])))
            rc = bf_fail(err, BF_ERR_NOMEM, "out of memory");
        else
            rc = split(o, out, l, err);
    }
    if (rc == BF_OK)
        rc = parse(o, out, err);
    if (rc != BF_OK) {
        options_tradeoff_clear(out);
        return rc;
    }
    values(o, out);
    return BF_OK;
}

bf_status options_tradeoff_check(const bf_options *o, bf_error *err)
{
    options_tradeoff t;
    bf_status rc = options_tradeoff_get(o, &t, err);
    if (rc == BF_OK)
        options_tradeoff_clear(&t);
    return rc;
}
