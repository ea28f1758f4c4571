/* A set of run options (brdfit/options.h): made, copied, set and read by name through
 * the table (option_table.c), checked for what couples options, and turned into the
 * structs the readers, the preprocessing and the fit take. */
#include "run_options.h"

#include "brdfit/tool.h"

#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* ---- The table --------------------------------------------------------------------- */

int bf_option_count(void)
{
    return option_nrows;
}

const bf_option *bf_option_get(int i)
{
    return i >= 0 && i < option_nrows ? &option_rows[i].d : NULL;
}

int option_row_index(const option_row *r)
{
    return (int)(r - option_rows);
}

/* name as a keyword: "--max-theta" and "max_theta" both give "max_theta". */
static int keyword_of(const char *name, char *buf, size_t size)
{
    if (!name)
        return 0;
    if (name[0] == '-' && name[1] == '-')
        name += 2;
    size_t n = strlen(name);
    if (n == 0 || n >= size)
        return 0;
    for (size_t k = 0; k <= n; k++)
        buf[k] = name[k] == '-' ? '_' : name[k];
    return 1;
}

/* The row of that name for the task (0: the first of that name), or NULL; *named: 1
 * when a row has the name at all. */
static const option_row *find_row(const char *name, unsigned task, int *named)
{
    char key[64];
    *named = 0;
    if (!keyword_of(name, key, sizeof key))
        return NULL;
    for (int i = 0; i < option_nrows; i++)
        if (!strcmp(option_rows[i].d.name, key)) {
            *named = 1;
            if (!task || (option_rows[i].d.tasks & task))
                return &option_rows[i];
        }
    return NULL;
}

const bf_option *bf_option_find(const char *name, unsigned task)
{
    int named;
    const option_row *r = find_row(name, task, &named);
    return r ? &r->d : NULL;
}

const char *option_spelled(const bf_options *o, const char *name, char *buf, size_t size)
{
    if (o->spelling == BF_SPELL_KEYWORD) {
        snprintf(buf, size, "%s", name);
        return buf;
    }
    int n = snprintf(buf, size, "--%s", name);
    for (int k = 2; k < n && (size_t)k < size; k++)
        if (buf[k] == '_')
            buf[k] = '-';
    return buf;
}

bf_status option_keep_text(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char *copy = strdup(v);
    if (!copy)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    const int i = option_row_index(r);
    free(o->text[i]);
    o->text[i] = copy;
    return BF_OK;
}

const char *option_text(const bf_options *o, const char *name)
{
    for (int i = 0; i < option_nrows; i++)
        if (option_rows[i].d.type == BF_OPTION_TEXT && !strcmp(option_rows[i].d.name, name))
            return o->text[i];
    return NULL;
}

const char *option_list_value(const bf_options *o, const char *name, int k)
{
    for (int i = 0; i < o->nlog; i++)
        if (!strcmp(option_rows[o->log[i].row].d.name, name) && k-- == 0)
            return o->log[i].value;
    return NULL;
}

/* ---- Making and copying ------------------------------------------------------------- */

static const char *task_name(unsigned t)
{
    return t == BF_TASK_READ      ? "read"
           : t == BF_TASK_FIT     ? "fit"
           : t == BF_TASK_COMPARE ? "compare"
           : t == BF_TASK_SELECT  ? "select"
                                  : "tradeoff";
}

bf_status bf_options_new(bf_task task, bf_options **out, bf_error *err)
{
    *out = NULL;
    if (task != BF_TASK_READ && task != BF_TASK_FIT && task != BF_TASK_COMPARE && task != BF_TASK_SELECT &&
        task != BF_TASK_TRADEOFF)
        return bf_fail(err, BF_ERR_ARG, "options: unknown task %d", (int)task);
    bf_options *o = calloc(1, sizeof *o);
    if (!o)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    o->task = task;
    o->spectral_row = -1;
    /* The fit's defaults are bf_fit_options_init's; the rest the table's. */
    bf_fit_options f;
    bf_fit_options_init(&f);
    o->residual = f.objective.residual;
    o->backend = f.solver.backend;
    o->starts = f.starts;
    o->screen = f.screen;
    o->threads = f.solver.threads;
    o->presolve = f.presolve;
    o->rank_by = task == BF_TASK_SELECT ? BF_RANK_ERROR : BF_RANK_BIC;
    o->folds = 5;
    o->jobs = 1;
    o->metric = BF_CMP_RMSE_LOG;
    o->tolerance = 0.05;
    /* On noiseless data every adequate model reaches ~1e-15, where a relative tolerance
     * alone would pick whichever rounding was luckiest. */
    o->abs_tolerance = 1e-6;
    *out = o;
    return BF_OK;
}

void bf_options_free(bf_options *o)
{
    if (!o)
        return;
    for (int i = 0; i < OPTION_ROWS_MAX; i++)
        free(o->text[i]);
    for (int k = 0; k < o->nlog; k++)
        free(o->log[k].value);
    free(o->log);
    free(o->overrides);
    free(o->start);
    free(o);
}

bf_task bf_options_task(const bf_options *o)
{
    return o->task;
}

void bf_options_set_spelling(bf_options *o, bf_option_spelling spelling)
{
    o->spelling = spelling;
}

bf_status bf_options_set_start(bf_options *o, const double *x, int n, bf_error *err)
{
    if (x && o->task != BF_TASK_FIT)
        return bf_fail(err, BF_ERR_ARG, "a start is for one fit (options of BF_TASK_FIT), not %s", task_name(o->task));
    if (x && (n < 1 || n > 64 * BF_MAX_CHANNELS))
        return bf_fail(err, BF_ERR_ARG, "a start of %d values", n);
    double *copy = x ? malloc((size_t)n * sizeof *copy) : NULL;
    if (x && !copy)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    if (x)
        memcpy(copy, x, (size_t)n * sizeof *copy);
    free(o->start);
    o->start = copy;
    o->nstart = x ? n : 0;
    return BF_OK;
}

void bf_options_keep_origin(bf_options *o, int keep)
{
    o->keep_origin = keep != 0;
}

void bf_options_set_cancel(bf_options *o, const bf_cancel_flag *cancel, const bf_cancel_flag *finish)
{
    o->cancel = cancel;
    o->finish = finish;
}

void bf_options_set_progress(bf_options *o, bf_progress_fn progress, void *user)
{
    o->progress = progress;
    o->progress_user = user;
}

void bf_options_set_progress_report(bf_options *o, bf_progress_report_fn progress, void *user)
{
    o->report = progress;
    o->report_user = user;
}

/* ---- Setting and reading by name ---------------------------------------------------- */

/* The generic forms (a row without its own set): the one-line messages say the range. */
static bf_status set_generic(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64], what[96];
    void *field = (char *)o + r->at;
    option_spelled(o, r->d.name, name, sizeof name);
    switch (r->d.type) {
    case BF_OPTION_FLAG:
        if (!v || !strcmp(v, "true") || !strcmp(v, "1"))
            *(int *)field = r->flag_on;
        else if (!strcmp(v, "false") || !strcmp(v, "0"))
            *(int *)field = !r->flag_on;
        else
            return bf_fail(err, BF_ERR_ARG, "%s is on or off (true or false), got '%s'", name, v);
        return BF_OK;
    case BF_OPTION_INT: {
        long n;
        if (bf_parse_long(v, (long)r->d.lo, (long)r->d.hi, &n)) {
            *(int *)field = (int)n;
            return BF_OK;
        }
        if (!r->d.range)
            snprintf(what, sizeof what, "an integer from %ld to %ld", (long)r->d.lo, (long)r->d.hi);
        break;
    }
    case BF_OPTION_NUMBER: {
        double d;
        if (bf_parse_number(v, r->d.lo, r->d.hi, &d)) {
            *(double *)field = d;
            return BF_OK;
        }
        if (!r->d.range)
            snprintf(what, sizeof what, "a number from %g to %g", r->d.lo, r->d.hi);
        break;
    }
    case BF_OPTION_TEXT:
        if (!v)
            return bf_fail(err, BF_ERR_ARG, "%s needs a value (%s)", name, r->d.arg);
        return option_keep_text(o, r, v, err);
    default: return bf_fail(err, BF_ERR_ARG, "%s: internal error: no way to take it", name);
    }
    return bf_fail(err, BF_ERR_ARG, "%s needs %s, got '%s'", name, r->d.range ? r->d.range : what, v ? v : "");
}

bf_status bf_options_set(bf_options *o, const char *name, const char *value, bf_error *err)
{
    int named;
    const option_row *r = find_row(name, o->task, &named);
    char shown[64];
    if (!r) {
        if (!named)
            return bf_fail(err, BF_ERR_ARG, "unknown option '%s'", name ? name : "");
        char tasks[64] = "";
        for (unsigned t = BF_TASK_READ; t <= BF_TASK_TRADEOFF; t <<= 1) {
            const option_row *other = find_row(name, t, &named);
            if (other)
                snprintf(tasks + strlen(tasks), sizeof tasks - strlen(tasks), "%s%s", *tasks ? ", " : "", task_name(t));
        }
        return bf_fail(err, BF_ERR_ARG, "%s is not an option of %s (it is one of %s)",
                       option_spelled(o, find_row(name, 0, &named)->d.name, shown, sizeof shown), task_name(o->task),
                       tasks);
    }
    /* Kept first, so that a copy or a reset can set it again. */
    char *kept = value ? strdup(value) : NULL;
    option_set *log = realloc(o->log, (size_t)(o->nlog + 1) * sizeof *log);
    if ((value && !kept) || !log) {
        free(kept);
        if (log)
            o->log = log;
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    }
    o->log = log;
    bf_status rc = r->set ? r->set(o, r, value, err) : set_generic(o, r, value, err);
    if (rc != BF_OK) {
        free(kept);
        return rc;
    }
    o->log[o->nlog++] = (option_set){option_row_index(r), kept};
    o->given[option_row_index(r)] = 1;
    o->fit_given |= r->fit_given;
    return BF_OK;
}

/* o made again from its task, its hooks and the values set, but those of rows named
 * skip (NULL: none): what copying and resetting do. Values set once set again the same. */
static bf_status replay(const bf_options *o, const char *skip, bf_options **out, bf_error *err)
{
    bf_options *n = NULL;
    bf_status rc = bf_options_new(o->task, &n, err);
    if (rc != BF_OK)
        return rc;
    n->spelling = o->spelling;
    n->keep_origin = o->keep_origin;
    n->cancel = o->cancel;
    n->finish = o->finish;
    n->progress = o->progress;
    n->progress_user = o->progress_user;
    n->report = o->report;
    n->report_user = o->report_user;
    if (o->start && (rc = bf_options_set_start(n, o->start, o->nstart, err)) != BF_OK) {
        bf_options_free(n);
        return rc;
    }
    for (int k = 0; k < o->nlog && rc == BF_OK; k++) {
        const option_row *r = &option_rows[o->log[k].row];
        if (!skip || strcmp(r->d.name, skip))
            rc = bf_options_set(n, r->d.name, o->log[k].value, err);
    }
    if (rc != BF_OK) {
        bf_options_free(n);
        return rc;
    }
    *out = n;
    return BF_OK;
}

bf_status bf_options_copy(const bf_options *o, bf_options **out, bf_error *err)
{
    *out = NULL;
    return replay(o, NULL, out, err);
}

bf_status bf_options_reset(bf_options *o, const char *name, bf_error *err)
{
    int named;
    const option_row *r = find_row(name, o->task, &named);
    if (!r)
        return bf_fail(err, BF_ERR_ARG, "unknown option '%s'", name ? name : "");
    bf_options *n = NULL;
    bf_status rc = replay(o, r->d.name, &n, err);
    if (rc != BF_OK)
        return rc;
    /* n's contents into o, o's old ones freed with n's shell. */
    bf_options old = *o;
    *o = *n;
    *n = old;
    bf_options_free(n);
    return BF_OK;
}

int bf_options_given(const bf_options *o, const char *name)
{
    char key[64];
    if (!keyword_of(name, key, sizeof key))
        return 0;
    for (int i = 0; i < option_nrows; i++)
        if (o->given[i] && !strcmp(option_rows[i].d.name, key))
            return 1;
    return 0;
}

bf_status bf_options_get(const bf_options *o, const char *name, char *buf, size_t size, bf_error *err)
{
    int named;
    const option_row *r = find_row(name, o->task, &named);
    if (!r && named)
        r = find_row(name, 0, &named);
    if (!r)
        return bf_fail(err, BF_ERR_ARG, "unknown option '%s'", name ? name : "");
    if (!buf || size == 0)
        return bf_fail(err, BF_ERR_ARG, "%s: no room for its value", r->d.name);
    const void *field = (const char *)o + r->at;
    int n = 0;
    if (r->get) {
        r->get(o, r, buf, size);
        n = (int)strlen(buf);
    } else if (r->d.type == BF_OPTION_FLAG)
        n = snprintf(buf, size, "%s", *(const int *)field == r->flag_on ? "true" : "false");
    else if (r->d.type == BF_OPTION_INT)
        n = snprintf(buf, size, "%d", *(const int *)field);
    else if (r->d.type == BF_OPTION_NUMBER)
        n = snprintf(buf, size, "%.17g", *(const double *)field);
    else if (r->d.type == BF_OPTION_TEXT) {
        const char *t = o->text[option_row_index(r)];
        n = snprintf(buf, size, "%s", t ? t : "");
    } else
        buf[0] = '\0';
    if (n < 0 || (size_t)n >= size)
        return bf_fail(err, BF_ERR_ARG, "%s: its value needs more than %zu bytes", r->d.name, size - 1);
    return BF_OK;
}

/* ---- What the readers, the preprocessing and the fit take ------------------------------ */

void options_read_get(const bf_options *o, options_reading *out)
{
    memset(out, 0, sizeof *out);
    out->read.format = o->format;
    out->read.keep_origin = o->keep_origin;
    out->read.csv.radians = o->radians;
    out->read.csv.channels = option_text(o, "values");
    out->read.csv.weight_col = option_text(o, "weight");
    out->read.grid = option_text(o, "grid");
    out->read.cancel = o->cancel;
    const char *angles = option_text(o, "angles"); /* checked when set: four names */
    if (angles) {
        snprintf(out->angles, sizeof out->angles, "%s", angles);
        char *p = out->angles;
        for (int k = 0; k < 4 && p; k++) {
            char *comma = strchr(p, ',');
            out->read.csv.angle_cols[k] = p;
            if (comma)
                *comma = '\0';
            p = comma ? comma + 1 : NULL;
        }
    }
}

/* The preset's sample count, unless the user gave one (bf_fit_options_apply_accuracy). */
static size_t preset_subsample(const bf_options *o)
{
    size_t n = o->subsample;
    if (o->task != BF_TASK_READ) {
        bf_fit_options f;
        bf_fit_options_init(&f);
        bf_fit_options_apply_accuracy(&f, o->accuracy, o->fit_given, &n);
    }
    return n;
}

void options_prep_get(const bf_options *o, bf_prep *out)
{
    memset(out, 0, sizeof *out);
    out->channels = option_text(o, "channels");
    out->to_bands = o->to_bands;
    out->color = o->color;
    out->illuminant = o->illuminant;
    out->to_luminance = o->to_luminance;
    out->max_theta = o->max_theta;
    out->negative = o->negative;
    out->subsample = preset_subsample(o);
    out->seed = o->seed;
}

const char *options_scene(const bf_options *o)
{
    return option_text(o, "scene");
}

void options_fit_get(const bf_options *o, bf_fit_options *out)
{
    bf_fit_options_init(out);
    out->objective.residual = o->residual;
    out->objective.solid_angle = o->solid_angle;
    out->objective.use_weights = !o->no_weights;
    out->objective.overrides = o->overrides;
    out->objective.noverrides = o->noverrides;
    out->solver.backend = o->backend;
    out->solver.algorithm = option_text(o, "algorithm");
    out->solver.local_algorithm = option_text(o, "local");
    out->solver.max_iterations = o->max_iterations;
    out->solver.loss = o->loss;
    out->solver.threads = o->threads;
    out->solver.use_constraint = o->use_constraint;
    out->solver.progress = o->progress;
    out->solver.progress_user = o->progress_user;
    out->solver.cancel = o->cancel;
    out->report = o->report;
    out->report_user = o->report_user;
    out->start = o->start;
    out->starts = o->starts;
    out->screen = o->screen;
    out->presolve = o->presolve;
    /* One seed for everything random: the subsample and the search. */
    out->seed = o->seed;
    /* With a scene, error is reported over its directions, weighted as it weighs them. */
    out->weighted_metrics = options_scene(o) != NULL;
    bf_fit_options_apply_accuracy(out, o->accuracy, o->fit_given, NULL);
}

int options_folds(const bf_options *o)
{
    return o->rank_by == BF_RANK_CV ? o->folds : 0;
}
