/* A work item as a database row and back (batch_rows.h).
 *
 * Decisions:
 *  - Parameters and standard errors are JSON objects of the model's entry names
 *    ("rho_d[0]": 0.6), readable in the sqlite3 shell; numbers are written with 17
 *    significant digits so that reading them back gives the same doubles, and a
 *    compare-style output from the database is the same to the byte. JSON has no NaN
 *    or infinity: those are the strings "nan", "inf", "-inf".
 *  - Entries are read back by position, after checking their count against the model
 *    rebuilt from the canonical spec: the names are for people.
 *  - Each warning's kind is stored by name (bf_warning_kind_name) in a JSON array of its
 *    own, beside the texts, so the texts stay the array of strings they always were and
 *    a report decides on the kinds (bf_fit_result_unsure) without reading the texts; only
 *    rows stored before kinds were fall back on their texts (legacy_kind). */
#include "batch_rows.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static cJSON *number(double v)
{
    if (isfinite(v)) {
        char buf[40];
        snprintf(buf, sizeof buf, "%.17g", v);
        return cJSON_CreateRaw(buf);
    }
    return cJSON_CreateString(isnan(v) ? "nan" : v > 0 ? "inf" : "-inf");
}

static double number_of(const cJSON *e)
{
    if (cJSON_IsNumber(e))
        return e->valuedouble;
    if (cJSON_IsString(e) && !strcmp(e->valuestring, "inf"))
        return INFINITY;
    if (cJSON_IsString(e) && !strcmp(e->valuestring, "-inf"))
        return -INFINITY;
    return NAN;
}

/* The model's entries with values v as a JSON object text (malloc'd; NULL: no memory). */
static char *entries_json(const bf_model *m, const double *v)
{
    cJSON *o = cJSON_CreateObject();
    for (int k = 0; o && k < bf_model_nvalues(m); k++) {
        char name[64];
        cJSON_AddItemToObject(o, bf_model_entry_name(m, k, name, sizeof name), number(v[k]));
    }
    char *s = o ? cJSON_PrintUnformatted(o) : NULL;
    cJSON_Delete(o);
    return s;
}

/* The warnings' texts, or with kinds 1 their kinds' names, as a JSON array text
 * (malloc'd; NULL: no memory). */
static char *warnings_json(const bf_fit_result *r, int kinds)
{
    cJSON *a = cJSON_CreateArray();
    for (int w = 0; a && w < r->nwarnings; w++)
        cJSON_AddItemToArray(a, cJSON_CreateString(kinds ? bf_warning_kind_name(r->warning_kind[w]) : r->warnings[w]));
    char *s = a ? cJSON_PrintUnformatted(a) : NULL;
    cJSON_Delete(a);
    return s;
}

void batch_row_clear(batch_row *r)
{
    free(r->spec);
    free(r->params);
    free(r->stderr_);
    free(r->warnings);
    free(r->options);
    free(r->warning_kinds);
    r->spec = r->params = r->stderr_ = r->warnings = r->options = r->warning_kinds = NULL;
}

bf_status batch_row_from_fit(batch_row *r, const bf_compare *c, int j, bf_error *err)
{
    const bf_compare_material *mat = &c->materials[0];
    const bf_compare_fit *f = &mat->fits[j];
    r->pending = 0;
    r->state = f->state;
    r->samples = mat->samples;
    r->channels = mat->channels;
    r->metrics = f->metrics;
    r->cv = f->cv_error;
    r->work = f->work;
    r->seconds = f->seconds;
    snprintf(r->message, sizeof r->message, "%s", f->state == BF_CMP_ERROR ? f->message : "");
    const bf_fit_result *res = f->state == BF_CMP_ERROR ? NULL : f->result;
    if (!res || !res->model)
        return BF_OK;
    if (!(r->spec = strdup(bf_model_spec(res->model))) || !(r->params = entries_json(res->model, res->x)) ||
        !(r->stderr_ = entries_json(res->model, res->stderr_)) || !(r->warnings = warnings_json(res, 0)) ||
        !(r->warning_kinds = warnings_json(res, 1))) {
        batch_row_clear(r);
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for a result row");
    }
    return BF_OK;
}

/* n values of the JSON object text into v; -1 when it is not one of n entries. */
static int entries_read(const char *text, double *v, int n)
{
    cJSON *o = text ? cJSON_Parse(text) : NULL;
    int k = 0;
    for (const cJSON *e = cJSON_IsObject(o) ? o->child : NULL; e; e = e->next, k++)
        if (k < n)
            v[k] = number_of(e);
    cJSON_Delete(o);
    return o && k == n ? 0 : -1;
}

/* How the one-start warning began in rows stored without kinds (schema 1), frozen here:
 * the wording brdfit writes today may change, old databases keep theirs. */
#define LEGACY_ONE_START "the best optimum was reached from 1 of"

/* The kind of a warning stored without one. Only BF_WARN_ONE_START decides anything a
 * report shows (bf_fit_result_unsure: compare's "?"), so it alone is recognised, by its
 * old text, and an old database reports as it did; every other warning is BF_WARN_OTHER,
 * which loses its kind (at a bound, undetermined ...) but nothing the report decides. */
static bf_warning_kind legacy_kind(const char *text)
{
    return strncmp(text, LEGACY_ONE_START, sizeof LEGACY_ONE_START - 1) ? BF_WARN_OTHER : BF_WARN_ONE_START;
}

/* The texts, and their kinds: one name per text in kinds (an unknown name, from a later
 * brdfit, is BF_WARN_OTHER), or, for a row stored before kinds were (kinds NULL),
 * legacy_kind. -1 when either is not such an array. */
static int warnings_read(const char *text, const char *kinds, bf_fit_result *res)
{
    cJSON *a = text ? cJSON_Parse(text) : NULL, *k = kinds ? cJSON_Parse(kinds) : NULL;
    int ok = cJSON_IsArray(a) && (!kinds || (cJSON_IsArray(k) && cJSON_GetArraySize(k) == cJSON_GetArraySize(a)));
    const cJSON *kn = ok && k ? k->child : NULL;
    for (const cJSON *e = ok ? a->child : NULL; e && res->nwarnings < BF_FIT_MAX_WARNINGS; e = e->next) {
        bf_warning_kind kind = BF_WARN_OTHER;
        if (kinds) { /* the kind at the text's position */
            if (!cJSON_IsString(kn)) {
                ok = 0;
                break;
            }
            if (bf_warning_kind_parse(kn->valuestring, &kind, NULL) != BF_OK)
                kind = BF_WARN_OTHER;
            kn = kn->next;
        }
        if (!cJSON_IsString(e))
            continue;
        res->warning_kind[res->nwarnings] = kinds ? kind : legacy_kind(e->valuestring);
        snprintf(res->warnings[res->nwarnings++], BF_FIT_WARNING_LEN, "%s", e->valuestring);
    }
    cJSON_Delete(a);
    cJSON_Delete(k);
    return ok ? 0 : -1;
}

bf_status batch_row_to_fit(const batch_row *r, bf_compare_fit *f, bf_fit_result *res, bf_error *err)
{
    bf_fit_result_clear(res);
    f->state = r->pending ? BF_CMP_NOT_RUN : r->state;
    f->metrics = r->metrics;
    f->cv_error = r->cv;
    f->work = r->work;
    f->seconds = r->seconds;
    snprintf(f->message, sizeof f->message, "%s", r->message);
    f->result = NULL;
    if (r->pending || r->state == BF_CMP_ERROR || !r->spec)
        return BF_OK;
    bf_status rc = bf_model_new(r->spec, r->channels, &res->model, err);
    if (rc != BF_OK)
        return rc;
    const int n = bf_model_nvalues(res->model);
    res->x = calloc((size_t)n + 1, sizeof *res->x);
    res->stderr_ = calloc((size_t)n + 1, sizeof *res->stderr_);
    res->fixed = calloc((size_t)n + 1, 1);
    if (!res->x || !res->stderr_ || !res->fixed) {
        bf_fit_result_clear(res);
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for item %d's result", r->item);
    }
    if (entries_read(r->params, res->x, n) < 0 || entries_read(r->stderr_, res->stderr_, n) < 0 ||
        warnings_read(r->warnings, r->warning_kinds, res) < 0) {
        bf_fit_result_clear(res);
        return bf_fail(err, BF_ERR_PARSE, "item %d: its parameters or warnings cannot be read back", r->item);
    }
    res->metrics = r->metrics;
    res->samples = r->samples;
    res->ok = r->state == BF_CMP_OK;
    f->result = res;
    return BF_OK;
}

/* ---- Bytes (batch_row_pack) ------------------------------------------------------------ */

typedef struct packer {
    unsigned char *p; /* NULL: only counting */
    size_t n;
} packer;

static void put(packer *k, const void *v, size_t n)
{
    if (k->p && n) /* an empty string or array may come as NULL, which memcpy may not take */
        memcpy(k->p + k->n, v, n);
    k->n += n;
}

static void put_i64(packer *k, int64_t v)
{
    put(k, &v, sizeof v);
}
static void put_f64(packer *k, double v)
{
    put(k, &v, sizeof v);
}

/* A text as its length + 1 (0: absent) and its bytes. */
static void put_text(packer *k, const char *s)
{
    const size_t n = s ? strlen(s) : 0;
    put_i64(k, s ? (int64_t)n + 1 : 0);
    put(k, s, n);
}

static void put_row(packer *k, const batch_row *r)
{
    const bf_metrics *m = &r->metrics;
    const int64_t ints[] = {r->item,     r->material,   r->model, r->pending,  r->state,          (int64_t)r->samples,
                            r->channels, (int64_t)m->n, m->k,     m->weighted, (int64_t)m->crit_n};
    const double reals[] = {m->rmse, m->rmse_cos, m->rmse_log, m->rmse_rel, m->max_err, m->loglik,
                            m->aic,  m->aicc,     m->bic,      r->cv,       r->work,    r->seconds};
    for (size_t i = 0; i < sizeof ints / sizeof ints[0]; i++)
        put_i64(k, ints[i]);
    for (size_t i = 0; i < sizeof reals / sizeof reals[0]; i++)
        put_f64(k, reals[i]);
    put_text(k, r->message);
    const char *texts[] = {r->spec, r->params, r->stderr_, r->warnings, r->options, r->warning_kinds};
    for (size_t i = 0; i < sizeof texts / sizeof texts[0]; i++)
        put_text(k, texts[i]);
}

bf_status batch_row_pack(const batch_row *r, unsigned char **buf, size_t *len, bf_error *err)
{
    packer k = {NULL, 0};
    put_row(&k, r); /* the size first, then the bytes */
    if (!(k.p = malloc(k.n)))
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for item %d's result", r->item);
    *len = k.n;
    k.n = 0;
    put_row(&k, r);
    *buf = k.p;
    return BF_OK;
}

typedef struct unpacker {
    const unsigned char *p;
    size_t n, at;
    int bad;
} unpacker;

static void get(unpacker *u, void *v, size_t n)
{
    if (u->bad || u->n - u->at < n) {
        u->bad = 1;
        memset(v, 0, n);
        return;
    }
    memcpy(v, u->p + u->at, n);
    u->at += n;
}

static int64_t get_i64(unpacker *u)
{
    int64_t v;
    get(u, &v, sizeof v);
    return v;
}

static double get_f64(unpacker *u)
{
    double v;
    get(u, &v, sizeof v);
    return v;
}

/* A text into buf (size cap) when buf is given, else malloc'd (NULL when absent). */
static char *get_text(unpacker *u, char *buf, size_t cap)
{
    const int64_t n1 = get_i64(u);
    if (u->bad || n1 <= 0)
        return NULL;
    const size_t n = (size_t)(n1 - 1);
    if (n > u->n - u->at || (buf && n >= cap)) {
        u->bad = 1;
        return NULL;
    }
    char *s = buf ? buf : malloc(n + 1);
    if (!s) {
        u->bad = 2;
        return NULL;
    }
    get(u, s, n);
    s[n] = 0;
    return s;
}

bf_status batch_row_unpack(const unsigned char *buf, size_t len, batch_row *r, bf_error *err)
{
    unpacker u = {buf, len, 0, 0};
    bf_metrics *m = &r->metrics;
    memset(r, 0, sizeof *r);
    r->item = (int)get_i64(&u), r->material = (int)get_i64(&u), r->model = (int)get_i64(&u);
    r->pending = (int)get_i64(&u), r->state = (bf_compare_state)get_i64(&u);
    r->samples = (size_t)get_i64(&u), r->channels = (int)get_i64(&u);
    m->n = (size_t)get_i64(&u), m->k = (int)get_i64(&u), m->weighted = (int)get_i64(&u);
    m->crit_n = (size_t)get_i64(&u);
    double *reals[] = {&m->rmse, &m->rmse_cos, &m->rmse_log, &m->rmse_rel, &m->max_err, &m->loglik,
                       &m->aic,  &m->aicc,     &m->bic,      &r->cv,       &r->work,    &r->seconds};
    for (size_t i = 0; i < sizeof reals / sizeof reals[0]; i++)
        *reals[i] = get_f64(&u);
    get_text(&u, r->message, sizeof r->message);
    char **texts[] = {&r->spec, &r->params, &r->stderr_, &r->warnings, &r->options, &r->warning_kinds};
    for (size_t i = 0; i < sizeof texts / sizeof texts[0]; i++)
        *texts[i] = get_text(&u, NULL, 0);
    if (u.bad || u.at != len) {
        batch_row_clear(r);
        return u.bad == 2 ? bf_fail(err, BF_ERR_NOMEM, "out of memory for a result row")
                          : bf_fail(err, BF_ERR_PARSE, "a result row of %zu bytes that is not one", len);
    }
    return BF_OK;
}
