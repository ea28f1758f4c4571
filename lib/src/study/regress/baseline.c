/* Reading a regression baseline: structure and type checks with the file's line in
 * every message, relative paths, tolerance resolution.
 *
 * cJSON keeps no positions, so messages find the line of a value by walking the text
 * (already known to be valid JSON) along the value's path: "cases/2/options/5". */
#include "brdfit/regress.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/json_keys.h"
#include "io/json_pos.h"
#include "io/read_text.h"
#include "regress/regress_impl.h"

const char *const bf_regress_metric_names[] = {"rmse", "rmse_cos", "rmse_log", "rmse_rel", "max_err", "aic",
                                               "aicc", "bic",      "loglik",   "n",        "k"};
const int bf_regress_nmetric_names = (int)(sizeof bf_regress_metric_names / sizeof bf_regress_metric_names[0]);

int bf_regress_metric(const bf_metrics *m, const char *name, double *out)
{
    const double v[] = {m->rmse, m->rmse_cos, m->rmse_log, m->rmse_rel,  m->max_err,  m->aic,
                        m->aicc, m->bic,      m->loglik,   (double)m->n, (double)m->k};
    for (int i = 0; i < bf_regress_nmetric_names; i++)
        if (!strcmp(name, bf_regress_metric_names[i])) {
            *out = v[i];
            return 1;
        }
    return 0;
}

int bf_regress_addf(char ***lines, int *n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int len = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    char *s = len >= 0 ? malloc((size_t)len + 1) : NULL;
    char **grown = s ? realloc(*lines, (size_t)(*n + 1) * sizeof *grown) : NULL;
    if (!grown) {
        free(s);
        return -1;
    }
    va_start(ap, fmt);
    vsnprintf(s, (size_t)len + 1, fmt, ap);
    va_end(ap);
    *lines = grown;
    grown[(*n)++] = s;
    return 0;
}

/* ---- positions in the text ---------------------------------------------------------- */

int bf_regress_line(const bf_regress_baseline *b, const char *fmt, ...)
{
    char path[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(path, sizeof path, fmt, ap);
    va_end(ap);
    return bf_json_line_of_path(b->text, path);
}

/* ---- paths and tolerances --------------------------------------------------------------- */

char *bf_regress_resolve(const bf_regress_baseline *b, const char *path)
{
    if (path[0] == '/' || !strcmp(b->dir, "."))
        return strdup(path);
    size_t n = strlen(b->dir) + strlen(path) + 2;
    char *s = malloc(n);
    if (s)
        snprintf(s, n, "%s/%s", b->dir, path);
    return s;
}

static void apply(bf_tolerance *t, const cJSON *o)
{
    const cJSON *rel = cJSON_GetObjectItemCaseSensitive(o, "rel");
    const cJSON *abs_ = cJSON_GetObjectItemCaseSensitive(o, "abs");
    if (cJSON_IsNumber(rel))
        t->rel = rel->valuedouble;
    if (cJSON_IsNumber(abs_))
        t->abs = abs_->valuedouble;
}

/* The group's own rel/abs, then the entry for name. */
static void apply_layer(bf_tolerance *t, const cJSON *tolerance, const char *group, const char *name)
{
    const cJSON *g = cJSON_GetObjectItemCaseSensitive(tolerance, group);
    if (!cJSON_IsObject(g))
        return;
    apply(t, g);
    const cJSON *entry = name ? cJSON_GetObjectItemCaseSensitive(g, name) : NULL;
    if (cJSON_IsObject(entry))
        apply(t, entry);
}

bf_tolerance bf_regress_tolerance(const bf_regress_baseline *b, int c, const char *group, const char *name)
{
    int params = !strcmp(group, "params");
    bf_tolerance t = {params ? BF_REGRESS_PARAMS_REL : BF_REGRESS_METRICS_REL,
                      params ? BF_REGRESS_PARAMS_ABS : BF_REGRESS_METRICS_ABS};
    apply_layer(&t, cJSON_GetObjectItemCaseSensitive(b->doc, "tolerance"), group, name);
    const cJSON *cases = cJSON_GetObjectItemCaseSensitive(b->doc, "cases");
    const cJSON *cs = cJSON_GetArrayItem(cases, c);
    apply_layer(&t, cJSON_GetObjectItemCaseSensitive(cs, "tolerance"), group, name);
    return t;
}

/* ---- checks ------------------------------------------------------------------------------ */

typedef struct parser {
    bf_regress_baseline *b;
    bf_error *err;
} parser;

#define FAIL(P, PATH, ...)                                                                                             \
    bf_fail((P)->err, BF_ERR_PARSE, "%s:%d: %s", (P)->b->path, bf_json_line_of_path((P)->b->text, PATH),               \
            (snprintf(msg, sizeof msg, __VA_ARGS__), msg))

/* No key of object o twice (cJSON keeps both; lookups and rewrites disagree on them). */
static bf_status no_repeats(parser *p, const cJSON *o, const char *path)
{
    char msg[400], sub[600];
    const char *key;
    int found = bf_json_repeated_key(o, &key);
    if (found < 0)
        return bf_fail(p->err, BF_ERR_NOMEM, "%s: out of memory", p->b->path);
    if (found == 0)
        return BF_OK;
    snprintf(sub, sizeof sub, "%s%s%s", path, *path ? "/" : "", key);
    return FAIL(p, sub, "key \"%s\" appears twice in the same object", key);
}

static bf_status only_keys(parser *p, const cJSON *o, const char *path, const char *const *keys, const char *what)
{
    char msg[400], sub[600];
    if (no_repeats(p, o, path) != BF_OK)
        return p->err->code;
    for (const cJSON *it = o->child; it; it = it->next) {
        int known = 0;
        for (const char *const *k = keys; *k; k++)
            known |= !strcmp(it->string, *k);
        if (!known) {
            snprintf(sub, sizeof sub, "%s%s%s", path, *path ? "/" : "", it->string);
            return FAIL(p, sub, "unknown key \"%s\" in %s", it->string, what);
        }
    }
    return BF_OK;
}

static int is_param_of(const char *spec, const char *name)
{
    bf_model *m = NULL;
    bf_model_new(spec, 1, &m, NULL);
    int found = m && bf_model_find_param(m, name) >= 0;
    bf_model_free(m);
    return found;
}

static int is_metric(const char *name)
{
    for (int i = 0; i < bf_regress_nmetric_names; i++)
        if (!strcmp(name, bf_regress_metric_names[i]))
            return 1;
    return 0;
}

/* {"rel": x, "abs": y} with x, y >= 0 and finite; "entry" allows nothing else. */
static bf_status check_tol_numbers(parser *p, const cJSON *o, const char *path)
{
    char msg[400], sub[1200];
    static const char *const keys[] = {"rel", "abs", NULL};
    if (!cJSON_IsObject(o))
        return FAIL(p, path, "a tolerance must be an object like {\"rel\": 1e-6, \"abs\": 1e-9}");
    if (only_keys(p, o, path, keys, "a tolerance (rel, abs)") != BF_OK)
        return p->err->code;
    for (const cJSON *it = o->child; it; it = it->next)
        if (!cJSON_IsNumber(it) || !(it->valuedouble >= 0.0) || !isfinite(it->valuedouble)) {
            snprintf(sub, sizeof sub, "%s/%s", path, it->string);
            return FAIL(p, sub, "tolerance %s must be a number >= 0", it->string);
        }
    return BF_OK;
}

/* {"params": {"rel", "abs", NAME: {...}}, "metrics": {...}}; specs: the models whose
 * parameter names are allowed (one for a case, every case's for the file). */
static bf_status check_tolerance(parser *p, const cJSON *t, const char *path, char *const *specs, int nspecs)
{
    char msg[400], sub[600];
    static const char *const groups[] = {"params", "metrics", NULL};
    if (!cJSON_IsObject(t))
        return FAIL(p, path, "\"tolerance\" must be an object with \"params\" and/or \"metrics\"");
    if (only_keys(p, t, path, groups, "\"tolerance\" (params, metrics)") != BF_OK)
        return p->err->code;
    for (const cJSON *g = t->child; g; g = g->next) {
        snprintf(sub, sizeof sub, "%s/%s", path, g->string);
        if (!cJSON_IsObject(g))
            return FAIL(p, sub, "\"tolerance\".\"%s\" must be an object", g->string);
        if (no_repeats(p, g, sub) != BF_OK)
            return p->err->code;
        int params = !strcmp(g->string, "params");
        for (const cJSON *e = g->child; e; e = e->next) {
            char epath[700];
            snprintf(epath, sizeof epath, "%s/%s", sub, e->string);
            if (!strcmp(e->string, "rel") || !strcmp(e->string, "abs")) {
                if (!cJSON_IsNumber(e) || !(e->valuedouble >= 0.0) || !isfinite(e->valuedouble))
                    return FAIL(p, epath, "tolerance %s must be a number >= 0", e->string);
                continue;
            }
            int known = 0;
            for (int k = 0; params && k < nspecs; k++)
                known |= is_param_of(specs[k], e->string);
            if (!params)
                known = is_metric(e->string);
            if (!known)
                return FAIL(p, epath, "tolerance for unknown %s \"%s\"%s%s", params ? "parameter" : "metric", e->string,
                            params && nspecs == 1 ? " of " : "", params && nspecs == 1 ? specs[0] : "");
            if (check_tol_numbers(p, e, epath) != BF_OK)
                return p->err->code;
        }
    }
    return BF_OK;
}

static char *dup_or_fail(parser *p, const char *s)
{
    char *d = strdup(s);
    if (!d)
        bf_fail(p->err, BF_ERR_NOMEM, "%s: out of memory", p->b->path);
    return d;
}

/* Expected values of one group: NAME: number | null | [number | null, ...]. */
static bf_status read_values(parser *p, const cJSON *g, const char *path, int metrics, bf_regress_value **out, int *n)
{
    char msg[400], sub[600];
    if (!cJSON_IsObject(g))
        return FAIL(p, path, "\"%s\" must be an object of named values", metrics ? "metrics" : "params");
    if (no_repeats(p, g, path) != BF_OK)
        return p->err->code;
    int count = cJSON_GetArraySize(g);
    *out = calloc((size_t)(count > 0 ? count : 1), sizeof **out);
    if (!*out)
        return bf_fail(p->err, BF_ERR_NOMEM, "%s: out of memory", p->b->path);
    for (const cJSON *e = g->child; e; e = e->next) {
        snprintf(sub, sizeof sub, "%s/%s", path, e->string);
        if (metrics && !is_metric(e->string))
            return FAIL(
                p, sub,
                "unknown metric \"%s\" (rmse, rmse_cos, rmse_log, rmse_rel, max_err, aic, aicc, bic, loglik, n, k)",
                e->string);
        bf_regress_value *v = &(*out)[(*n)++];
        v->line = bf_json_line_of_path(p->b->text, sub);
        if (!(v->name = dup_or_fail(p, e->string)))
            return p->err->code;
        v->array = cJSON_IsArray(e);
        v->n = v->array ? cJSON_GetArraySize(e) : 1;
        if ((v->array && (metrics || v->n == 0)) || (!v->array && !cJSON_IsNumber(e) && !cJSON_IsNull(e)))
            return FAIL(p, sub, "\"%s\" must be a number%s", e->string,
                        metrics ? "" : " or a non-empty array of numbers (one per channel)");
        if (!(v->v = calloc((size_t)v->n, sizeof *v->v)))
            return bf_fail(p->err, BF_ERR_NOMEM, "%s: out of memory", p->b->path);
        for (int k = 0; k < v->n; k++) {
            const cJSON *x = v->array ? cJSON_GetArrayItem(e, k) : e;
            if (!cJSON_IsNumber(x) && !cJSON_IsNull(x))
                return FAIL(p, sub, "\"%s\" must hold numbers", e->string);
            v->v[k] = cJSON_IsNumber(x) ? x->valuedouble : NAN;
        }
    }
    return BF_OK;
}

static bf_status read_case(parser *p, const cJSON *o, int i, bf_regress_case *c)
{
    char msg[400], path[64], sub[128];
    static const char *const keys[] = {"name", "data", "model", "options", "tolerance", "expected", "comment", NULL};
    snprintf(path, sizeof path, "cases/%d", i);
    c->line = bf_json_line_of_path(p->b->text, path);
    c->expect_ok = 1;
    if (!cJSON_IsObject(o))
        return FAIL(p, path, "case %d must be an object", i + 1);
    if (only_keys(p, o, path, keys, "a case (name, data, model, options, tolerance, expected, comment)") != BF_OK)
        return p->err->code;

    const char *const required[] = {"name", "data", "model"};
    for (int k = 0; k < 3; k++) {
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, required[k]);
        snprintf(sub, sizeof sub, "%s/%s", path, required[k]);
        if (!v)
            return FAIL(p, path, "case %d has no \"%s\"", i + 1, required[k]);
        if (!cJSON_IsString(v) || !v->valuestring[0])
            return FAIL(p, sub, "\"%s\" must be a non-empty string", required[k]);
    }
    c->name = dup_or_fail(p, cJSON_GetObjectItemCaseSensitive(o, "name")->valuestring);
    c->data = c->name ? dup_or_fail(p, cJSON_GetObjectItemCaseSensitive(o, "data")->valuestring) : NULL;
    c->model = c->data ? dup_or_fail(p, cJSON_GetObjectItemCaseSensitive(o, "model")->valuestring) : NULL;
    if (!c->model)
        return p->err->code;
    if (!(c->data_path = bf_regress_resolve(p->b, c->data)))
        return bf_fail(p->err, BF_ERR_NOMEM, "%s: out of memory", p->b->path);
    c->data_line = bf_regress_line(p->b, "%s/data", path);
    c->model_line = bf_regress_line(p->b, "%s/model", path);

    bf_error merr;
    bf_model *m = NULL;
    if (bf_model_new(c->model, 1, &m, &merr) != BF_OK) {
        snprintf(sub, sizeof sub, "%s/model", path);
        return FAIL(p, sub, "case '%.60s': %.300s", c->name, merr.msg);
    }
    bf_model_free(m);

    const cJSON *opts = cJSON_GetObjectItemCaseSensitive(o, "options");
    snprintf(sub, sizeof sub, "%s/options", path);
    c->options_line = bf_json_line_of_path(p->b->text, sub);
    if (opts) {
        if (!cJSON_IsArray(opts))
            return FAIL(p, sub, "\"options\" must be an array of strings (brdfit fit's options)");
        int n = cJSON_GetArraySize(opts);
        c->options = calloc((size_t)n + 1, sizeof *c->options);
        c->option_lines = calloc((size_t)n + 1, sizeof *c->option_lines);
        if (!c->options || !c->option_lines)
            return bf_fail(p->err, BF_ERR_NOMEM, "%s: out of memory", p->b->path);
        for (int k = 0; k < n; k++) {
            const cJSON *s = cJSON_GetArrayItem(opts, k);
            char opath[160];
            snprintf(opath, sizeof opath, "%s/%d", sub, k);
            if (!cJSON_IsString(s))
                return FAIL(p, opath, "option %d must be a string", k + 1);
            if (!(c->options[k] = dup_or_fail(p, s->valuestring)))
                return p->err->code;
            c->option_lines[k] = bf_json_line_of_path(p->b->text, opath);
            c->noptions++;
        }
    }

    const cJSON *tol = cJSON_GetObjectItemCaseSensitive(o, "tolerance");
    snprintf(sub, sizeof sub, "%s/tolerance", path);
    if (tol && check_tolerance(p, tol, sub, &c->model, 1) != BF_OK)
        return p->err->code;

    const cJSON *exp = cJSON_GetObjectItemCaseSensitive(o, "expected");
    snprintf(sub, sizeof sub, "%s/expected", path);
    if (!exp)
        return BF_OK; /* checks ok only; brdfit regress --update fills it in */
    static const char *const ekeys[] = {"ok", "params", "metrics", NULL};
    if (!cJSON_IsObject(exp))
        return FAIL(p, sub, "\"expected\" must be an object");
    if (only_keys(p, exp, sub, ekeys, "\"expected\" (ok, params, metrics)") != BF_OK)
        return p->err->code;
    const cJSON *ok = cJSON_GetObjectItemCaseSensitive(exp, "ok");
    if (ok && !cJSON_IsBool(ok)) {
        snprintf(sub, sizeof sub, "%s/expected/ok", path);
        return FAIL(p, sub, "\"ok\" must be true or false");
    }
    c->expect_ok = !ok || cJSON_IsTrue(ok);
    const cJSON *g = cJSON_GetObjectItemCaseSensitive(exp, "params");
    snprintf(sub, sizeof sub, "%s/expected/params", path);
    if (g && read_values(p, g, sub, 0, &c->params, &c->nparams) != BF_OK)
        return p->err->code;
    g = cJSON_GetObjectItemCaseSensitive(exp, "metrics");
    snprintf(sub, sizeof sub, "%s/expected/metrics", path);
    if (g && read_values(p, g, sub, 1, &c->metrics, &c->nmetrics) != BF_OK)
        return p->err->code;
    return BF_OK;
}

/* 1 when s prints as it is (bf_printable changes nothing), 0 if not, -1 out of memory. */
static int printable(const char *s)
{
    char *shown = bf_printable_dup(s);
    int same = shown ? !strcmp(shown, s) : -1;
    free(shown);
    return same;
}

static bf_status unprintable(parser *p, const char *path, const char *text)
{
    char msg[400];
    return FAIL(p, path, "'%s' holds control characters or invalid UTF-8", text);
}

/* Names, paths, models, options and keys reach terminals, logs and JUnit as they are:
 * none may hold control characters or invalid UTF-8. Comments are never shown. */
static bf_status check_text(parser *p, const cJSON *x, const char *path)
{
    char sub[600];
    int k = 0;
    for (const cJSON *e = x->child; e; e = e->next, k++) {
        if (e->string && !strcmp(e->string, "comment"))
            continue;
        if (e->string)
            snprintf(sub, sizeof sub, "%s%s%s", path, *path ? "/" : "", e->string);
        else
            snprintf(sub, sizeof sub, "%s%s%d", path, *path ? "/" : "", k);
        const char *texts[2] = {e->string, cJSON_IsString(e) ? e->valuestring : NULL};
        for (int t = 0; t < 2; t++) {
            bf_status rc = texts[t] ? printable(texts[t]) : 1;
            if (rc < 0)
                return bf_fail(p->err, BF_ERR_NOMEM, "%s: out of memory", p->b->path);
            if (rc == 0)
                return unprintable(p, sub, texts[t]);
        }
        if ((cJSON_IsObject(e) || cJSON_IsArray(e)) && check_text(p, e, sub) != BF_OK)
            return p->err->code;
    }
    return BF_OK;
}

static bf_status parse_doc(parser *p)
{
    char msg[400];
    bf_regress_baseline *b = p->b;
    const char *end = NULL;
    b->doc = cJSON_ParseWithOpts(b->text, &end, 1);
    if (!b->doc) {
        if (!end)
            return bf_fail(p->err, BF_ERR_NOMEM, "%s: out of memory", b->path);
        if (!*end)
            return bf_fail(p->err, BF_ERR_PARSE, "%s:%d: malformed JSON: the text ends inside a value", b->path,
                           bf_json_line(b->text, end));
        return bf_fail(p->err, BF_ERR_PARSE, "%s:%d: malformed JSON near '%.*s'", b->path, bf_json_line(b->text, end),
                       (int)(strcspn(end, "\r\n") < 20 ? strcspn(end, "\r\n") : 20), end);
    }
    if (!cJSON_IsObject(b->doc))
        return FAIL(p, "", "a baseline is a JSON object with \"brdfit_baseline\": 1 and \"cases\"");
    if (check_text(p, b->doc, "") != BF_OK)
        return p->err->code;
    /* brdfit_version: the build that last wrote the file (--update); not checked. */
    static const char *const keys[] = {"brdfit_baseline", "brdfit_version", "tolerance", "cases", "comment", NULL};
    if (only_keys(p, b->doc, "", keys, "the baseline (brdfit_baseline, brdfit_version, tolerance, cases, comment)") !=
        BF_OK)
        return p->err->code;
    const cJSON *version = cJSON_GetObjectItemCaseSensitive(b->doc, "brdfit_baseline");
    if (!version)
        return FAIL(p, "", "not a brdfit baseline: no \"brdfit_baseline\": 1");
    if (!cJSON_IsNumber(version) || version->valuedouble != 1.0)
        return FAIL(p, "brdfit_baseline", "unsupported baseline version (this brdfit reads version 1)");

    const cJSON *cases = cJSON_GetObjectItemCaseSensitive(b->doc, "cases");
    if (!cJSON_IsArray(cases) || cJSON_GetArraySize(cases) == 0)
        return FAIL(p, cases ? "cases" : "", "\"cases\" must be a non-empty array of cases");
    int n = cJSON_GetArraySize(cases);
    if (!(b->cases = calloc((size_t)n, sizeof *b->cases)))
        return bf_fail(p->err, BF_ERR_NOMEM, "%s: out of memory", b->path);
    int i = 0;
    for (const cJSON *o = cases->child; o; o = o->next, i++) {
        b->ncases++;
        if (read_case(p, o, i, &b->cases[i]) != BF_OK)
            return p->err->code;
        for (int k = 0; k < i; k++)
            if (!strcmp(b->cases[k].name, b->cases[i].name)) {
                char path[64];
                snprintf(path, sizeof path, "cases/%d/name", i);
                return FAIL(p, path, "case name '%s' is used twice (also line %d)", b->cases[i].name, b->cases[k].line);
            }
    }
    const cJSON *tol = cJSON_GetObjectItemCaseSensitive(b->doc, "tolerance");
    if (tol) {
        char **specs = malloc((size_t)n * sizeof *specs);
        if (!specs)
            return bf_fail(p->err, BF_ERR_NOMEM, "%s: out of memory", b->path);
        for (int k = 0; k < n; k++)
            specs[k] = b->cases[k].model;
        bf_status rc = check_tolerance(p, tol, "tolerance", specs, n);
        free(specs);
        if (rc != BF_OK)
            return rc;
    }
    return BF_OK;
}

bf_status bf_regress_parse(const char *text, const char *path, bf_regress_baseline **out, bf_error *err)
{
    *out = NULL;
    bf_regress_baseline *b = calloc(1, sizeof *b);
    if (!b || !(b->text = strdup(text)) || !(b->path = strdup(path))) {
        bf_regress_baseline_free(b);
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
    }
    const char *slash = strrchr(path, '/');
    b->dir = slash ? strndup(path, slash == path ? 1 : (size_t)(slash - path)) : strdup(".");
    if (!b->dir) {
        bf_regress_baseline_free(b);
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
    }
    parser p = {b, err};
    bf_status rc = parse_doc(&p);
    if (rc != BF_OK) {
        bf_regress_baseline_free(b);
        return rc;
    }
    *out = b;
    return BF_OK;
}

bf_status bf_regress_load(const char *path, bf_regress_baseline **out, bf_error *err)
{
    *out = NULL;
    size_t len;
    char *text;
    bf_status rc = bf_read_text(path, &text, &len, err);
    if (rc != BF_OK)
        return rc;
    rc = bf_regress_parse(text, path, out, err);
    free(text);
    return rc;
}

static void free_values(bf_regress_value *v, int n)
{
    for (int i = 0; v && i < n; i++) {
        free(v[i].name);
        free(v[i].v);
    }
    free(v);
}

void bf_regress_baseline_free(bf_regress_baseline *b)
{
    if (!b)
        return;
    for (int i = 0; i < b->ncases; i++) {
        bf_regress_case *c = &b->cases[i];
        free(c->name);
        free(c->data);
        free(c->data_path);
        free(c->model);
        for (int k = 0; k < c->noptions; k++)
            free(c->options[k]);
        free(c->options);
        free(c->option_lines);
        free_values(c->params, c->nparams);
        free_values(c->metrics, c->nmetrics);
    }
    free(b->cases);
    cJSON_Delete(b->doc);
    free(b->text);
    free(b->path);
    free(b->dir);
    free(b);
}
