/* Rewriting a baseline with new results (brdfit regress --update): names, data,
 * options, tolerances and key order stay as they were; the expected values change. The
 * file is printed by hand (2-space indent, small objects and arrays of scalars on one
 * line) so it stays readable in review; numbers use the shortest text that reads back
 * exactly, strings cJSON's escaping. */
#include "brdfit/formats.h"
#include "brdfit/regress.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/io.h"
#include "brdfit/version.h"
#include "regress/regress_impl.h"

typedef struct updater {
    char ***changes;
    int *nchanges;
    int nomem;
} updater;

static cJSON *number(double v)
{
    return isfinite(v) ? cJSON_CreateNumber(v) : cJSON_CreateNull();
}

static double value_of(const cJSON *x)
{
    return cJSON_IsNumber(x) ? x->valuedouble : NAN;
}

static int same(double a, double b)
{
    return (isnan(a) && isnan(b)) || a == b;
}

static const char *text(double v, char *buf)
{
    return isfinite(v) ? bf_format_double(v, buf, 32) : "null";
}

/* old (NULL: absent) against the n new values; one change line per difference. */
static void note(updater *u, const char *group, const char *name, const cJSON *old, const double *v, int n, int array)
{
    char a[32], b[32];
    int oldn = !old ? 0 : cJSON_IsArray(old) ? cJSON_GetArraySize(old) : 1;
    if (!old) {
        u->nomem |= bf_regress_addf(u->changes, u->nchanges, "  %s.%s: added", group, name) != 0;
        return;
    }
    if (oldn != n || cJSON_IsArray(old) != array) {
        u->nomem |= bf_regress_addf(u->changes, u->nchanges, "  %s.%s: %d value%s -> %d value%s", group, name, oldn,
                                    oldn == 1 ? "" : "s", n, n == 1 ? "" : "s") != 0;
        return;
    }
    for (int k = 0; k < n; k++) {
        double was = value_of(array ? cJSON_GetArrayItem(old, k) : old);
        if (same(was, v[k]))
            continue;
        if (array)
            u->nomem |= bf_regress_addf(u->changes, u->nchanges, "  %s.%s[%d]: %s -> %s", group, name, k, text(was, a),
                                        text(v[k], b)) != 0;
        else
            u->nomem |= bf_regress_addf(u->changes, u->nchanges, "  %s.%s: %s -> %s", group, name, text(was, a),
                                        text(v[k], b)) != 0;
    }
}

/* Sets g[name] to the n values (an array when array), noting the change. */
static void set(updater *u, cJSON *g, const char *group, const char *name, const double *v, int n, int array)
{
    cJSON *old = cJSON_GetObjectItemCaseSensitive(g, name);
    note(u, group, name, old, v, n, array);
    cJSON *item = array ? cJSON_CreateArray() : number(v[0]);
    for (int k = 0; array && item && k < n; k++) {
        cJSON *x = number(v[k]);
        if (!x || !cJSON_AddItemToArray(item, x)) {
            cJSON_Delete(x);
            u->nomem = 1;
        }
    }
    if (!item)
        u->nomem = 1;
    else if (old)
        cJSON_ReplaceItemInObjectCaseSensitive(g, name, item); /* names the new item too */
    else if (!cJSON_AddItemToObject(g, name, item)) {
        cJSON_Delete(item);
        u->nomem = 1;
    }
}

static cJSON *object_member(updater *u, cJSON *o, const char *key)
{
    cJSON *g = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!g && !(g = cJSON_AddObjectToObject(o, key)))
        u->nomem = 1;
    return g;
}

static void update_params(updater *u, cJSON *g, const bf_fit_result *r)
{
    const bf_model *m = r->model;
    int C = bf_model_channels(m);
    int pinned = g->child != NULL;
    /* Pinned names the model does not have go; the rest take the new values. */
    for (cJSON *e = g->child, *next; e; e = next) {
        next = e->next;
        if (bf_model_find_param(m, e->string) < 0) {
            u->nomem |= bf_regress_addf(u->changes, u->nchanges, "  params.%s: removed (not a parameter of %s)",
                                        e->string, bf_model_spec(m)) != 0;
            cJSON_Delete(cJSON_DetachItemViaPointer(g, e));
        }
    }
    for (int i = 0; i < bf_model_nparams(m); i++) {
        const bf_param_info *pi = bf_model_param(m, i);
        if (pinned && !cJSON_GetObjectItemCaseSensitive(g, pi->name))
            continue;
        set(u, g, "params", pi->name, r->x + bf_model_param_offset(m, i), pi->color ? C : 1, pi->color);
    }
}

static void update_metrics(updater *u, cJSON *g, const bf_fit_result *r)
{
    int pinned = g->child != NULL;
    for (int i = 0; i < bf_regress_nmetric_names; i++) {
        const char *name = bf_regress_metric_names[i];
        if (pinned && !cJSON_GetObjectItemCaseSensitive(g, name))
            continue;
        double v = NAN;
        bf_regress_metric(&r->metrics, name, &v);
        set(u, g, "metrics", name, &v, 1, 0);
    }
}

bf_status bf_regress_update(bf_regress_baseline *b, int c, const bf_fit_result *r, char ***changes, int *nchanges,
                            bf_error *err)
{
    updater u = {changes, nchanges, 0};
    cJSON *cs = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(b->doc, "cases"), c);
    cJSON *exp = cs ? object_member(&u, cs, "expected") : NULL;
    if (!exp)
        return bf_fail(err, u.nomem ? BF_ERR_NOMEM : BF_ERR_ARG, "%s: no case %d to update", b->path, c + 1);
    cJSON *ok = cJSON_GetObjectItemCaseSensitive(exp, "ok");
    int was = !ok || cJSON_IsTrue(ok);
    if (was != r->ok)
        u.nomem |=
            bf_regress_addf(changes, nchanges, "  ok: %s -> %s", was ? "true" : "false", r->ok ? "true" : "false") != 0;
    if (ok)
        cJSON_ReplaceItemInObjectCaseSensitive(exp, "ok", cJSON_CreateBool(r->ok));
    else
        cJSON_AddBoolToObject(exp, "ok", r->ok);
    b->cases[c].expect_ok = r->ok;
    /* A failed fit's values are its start: nothing to pin. */
    if (r->ok) {
        cJSON *g = object_member(&u, exp, "params");
        if (g)
            update_params(&u, g, r);
        if ((g = object_member(&u, exp, "metrics")))
            update_metrics(&u, g, r);
    }
    if (u.nomem)
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory updating case '%s'", b->path, b->cases[c].name);
    return BF_OK;
}

/* ---- printing ------------------------------------------------------------------------ */

static int scalar(const cJSON *x)
{
    return !cJSON_IsArray(x) && !cJSON_IsObject(x);
}

static int put_string(FILE *f, const char *s)
{
    cJSON *tmp = cJSON_CreateString(s);
    char *t = tmp ? cJSON_PrintUnformatted(tmp) : NULL;
    cJSON_Delete(tmp);
    if (!t)
        return -1;
    fputs(t, f);
    free(t);
    return 0;
}

static int put(FILE *f, const cJSON *x, int indent)
{
    char buf[32];
    if (cJSON_IsNumber(x)) {
        fputs(text(x->valuedouble, buf), f);
        return 0;
    }
    if (cJSON_IsString(x))
        return put_string(f, x->valuestring);
    if (cJSON_IsBool(x) || cJSON_IsNull(x)) {
        fputs(cJSON_IsNull(x) ? "null" : cJSON_IsTrue(x) ? "true" : "false", f);
        return 0;
    }
    int object = cJSON_IsObject(x), n = 0, all_scalar = 1;
    for (const cJSON *e = x->child; e; e = e->next, n++)
        all_scalar &= scalar(e);
    /* Arrays of scalars and objects of up to three scalars stay on one line. */
    int inline_ = all_scalar && (!object || n <= 3);
    fputc(object ? '{' : '[', f);
    for (const cJSON *e = x->child; e; e = e->next) {
        if (inline_)
            fputs(e == x->child ? "" : ", ", f);
        else
            fprintf(f, "\n%*s", indent + 2, "");
        if (object) {
            if (put_string(f, e->string) != 0)
                return -1;
            fputs(": ", f);
        }
        if (put(f, e, indent + 2) != 0)
            return -1;
        if (!inline_ && e->next)
            fputc(',', f);
    }
    if (!inline_ && n > 0)
        fprintf(f, "\n%*s", indent, "");
    fputc(object ? '}' : ']', f);
    return 0;
}

/* Sets "brdfit_version" to this build, in place or else right after "brdfit_baseline"
 * (the file's first lines say what it is and what wrote it); -1 out of memory. */
static int stamp_version(cJSON *doc)
{
    cJSON *v = cJSON_CreateString(bf_version());
    if (!v)
        return -1;
    if (cJSON_GetObjectItemCaseSensitive(doc, "brdfit_version"))
        return cJSON_ReplaceItemInObjectCaseSensitive(doc, "brdfit_version", v) ? 0 : (cJSON_Delete(v), -1);
    if (!cJSON_AddItemToObject(doc, "brdfit_version", v)) {
        cJSON_Delete(v);
        return -1;
    }
    /* Added last: the members after "brdfit_baseline" move behind it, in their order
     * (re-appending keeps their keys; cJSON 1.7.15 refuses to insert into an object). */
    cJSON *e = doc->child;
    while (e && e->string && strcmp(e->string, "brdfit_baseline"))
        e = e->next;
    for (cJSON *next = e ? e->next : NULL; (e = next) && e != v;) {
        next = e->next;
        cJSON_AddItemToArray(doc, cJSON_DetachItemViaPointer(doc, e));
    }
    return 0;
}

bf_status bf_regress_write(const bf_regress_baseline *b, const char *path, bf_error *err)
{
    if (stamp_version(b->doc) != 0)
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory writing the baseline", path);
    bf_outfile f;
    bf_status rc = bf_outfile_open(&f, path, err);
    if (rc != BF_OK)
        return rc;
    if (put(f.fp, b->doc, 0) != 0) {
        bf_outfile_abort(&f);
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory writing the baseline", path);
    }
    fputc('\n', f.fp);
    return bf_outfile_commit(&f, err);
}
