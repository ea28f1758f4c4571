/* Parameter files (JSON, via cJSON): model, options, channels and named values. */
#include "brdfit/io.h"
#include "json_keys.h"
#include "json_pos.h"
#include "params_json.h"
#include "read_text.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Line of the first occurrence of "key" in the text from where the entry starts: good
 * enough to point a user at the offending entry, since cJSON keeps no positions. */
static size_t line_of_key(const bf_params_src *s, const char *key)
{
    char pat[96];
    snprintf(pat, sizeof pat, "\"%s\"", key);
    const char *from = s->from ? s->from : s->text;
    const char *p = strstr(from, pat);
    return (size_t)bf_json_line(s->text, p ? p : from);
}

/* Builds "model:k=v,..." from the model string and the options object; every piece is
 * measured before it is copied. */
static bf_status build_spec(const bf_params_src *s, const cJSON *model, const cJSON *options, char *spec, size_t size,
                            bf_error *err)
{
    if (!cJSON_IsString(model) || !*model->valuestring)
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: \"model\" must be a non-empty string", s->path,
                       model ? line_of_key(s, "model") : 1);
    size_t n = strlen(model->valuestring);
    if (n >= size)
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: \"model\" is too long (%zu characters, at most %zu)", s->path,
                       line_of_key(s, "model"), n, size - 1);
    memcpy(spec, model->valuestring, n + 1);
    if (!options)
        return BF_OK;
    if (!cJSON_IsObject(options))
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: \"options\" must be an object", s->path, line_of_key(s, "options"));
    int first = strchr(spec, ':') == NULL;
    const cJSON *o;
    cJSON_ArrayForEach(o, options)
    {
        char num[32];
        const char *val = num;
        /* An integer only after a range check: converting 1e30 to int is undefined. */
        if (cJSON_IsString(o))
            val = o->valuestring;
        else if (cJSON_IsNumber(o) && fabs(o->valuedouble) <= 1e9 && o->valuedouble == floor(o->valuedouble))
            snprintf(num, sizeof num, "%d", (int)o->valuedouble);
        else
            return bf_fail(err, BF_ERR_PARSE, "%s:%zu: option \"%s\" must be a string or an integer", s->path,
                           line_of_key(s, o->string), o->string);
        /* A comma or '=' would smuggle in another option ("fresnel": "schlick,mono=all"). */
        if (!*o->string || strpbrk(o->string, ",=") || strchr(val, ','))
            return bf_fail(err, BF_ERR_PARSE,
                           "%s:%zu: option \"%s\": names and values cannot be empty or hold ','"
                           " (names not '=' either)",
                           s->path, line_of_key(s, o->string), o->string);
        int k = snprintf(spec + n, size - n, "%c%s=%s", first ? ':' : ',', o->string, val);
        if (k < 0 || (size_t)k >= size - n)
            return bf_fail(err, BF_ERR_PARSE, "%s:%zu: model and options too long (at most %zu characters)", s->path,
                           line_of_key(s, o->string), size - 1);
        n += (size_t)k;
        first = 0;
    }
    return BF_OK;
}

/* Channel count: "channels" if given, else the length of the first colour array, else 1. */
static bf_status channel_count(const bf_params_src *s, const cJSON *root, const cJSON *params, int *C, bf_error *err)
{
    const cJSON *ch = cJSON_GetObjectItemCaseSensitive(root, "channels");
    if (ch) {
        /* Range first, then the conversion (1e30 has no int). */
        if (!cJSON_IsNumber(ch) || !(ch->valuedouble >= 1.0 && ch->valuedouble <= BF_MAX_CHANNELS) ||
            ch->valuedouble != floor(ch->valuedouble))
            return bf_fail(err, BF_ERR_PARSE, "%s:%zu: \"channels\" must be an integer from 1 to %d", s->path,
                           line_of_key(s, "channels"), BF_MAX_CHANNELS);
        *C = (int)ch->valuedouble;
        return BF_OK;
    }
    *C = 1;
    const cJSON *p;
    cJSON_ArrayForEach(p, params)
    {
        if (cJSON_IsArray(p)) {
            *C = cJSON_GetArraySize(p);
            break;
        }
    }
    if (*C < 1 || *C > BF_MAX_CHANNELS)
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: %s array: a parameter has 1 to %d values, one per channel", s->path,
                       line_of_key(s, p->string), *C < 1 ? "empty" : "too long", BF_MAX_CHANNELS);
    return BF_OK;
}

static bf_status read_value(const bf_params_src *s, const cJSON *v, const char *name, double *out, bf_error *err)
{
    if (!cJSON_IsNumber(v))
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: parameter %s: expected a number", s->path, line_of_key(s, name),
                       name);
    if (!isfinite(v->valuedouble))
        return bf_fail(err, BF_ERR_RANGE, "%s:%zu: parameter %s is not finite", s->path, line_of_key(s, name), name);
    *out = v->valuedouble;
    return BF_OK;
}

static bf_status fill_params(const bf_params_src *s, const cJSON *params, const bf_model *m, double *x,
                             int check_bounds, bf_error *err)
{
    int C = bf_model_channels(m), rc;
    const cJSON *p;
    cJSON_ArrayForEach(p, params)
    {
        if (bf_model_find_param(m, p->string) < 0)
            return bf_fail(err, BF_ERR_PARSE, "%s:%zu: model %s has no parameter \"%s\"", s->path,
                           line_of_key(s, p->string), bf_model_spec(m), p->string);
        for (const cJSON *q = params->child; q != p; q = q->next)
            if (strcmp(q->string, p->string) == 0)
                return bf_fail(err, BF_ERR_PARSE, "%s:%zu: parameter \"%s\" given twice", s->path,
                               line_of_key(s, p->string), p->string);
    }
    for (int i = 0; i < bf_model_nparams(m); i++) {
        const bf_param_info *pi = bf_model_param(m, i);
        double *dst = x + bf_model_param_offset(m, i);
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(params, pi->name);
        if (!v)
            return bf_fail(err, BF_ERR_PARSE, "%s:%zu: missing parameter \"%s\" of model %s", s->path,
                           line_of_key(s, "params"), pi->name, bf_model_spec(m));
        if (pi->color && cJSON_IsArray(v)) {
            if (cJSON_GetArraySize(v) != C)
                return bf_fail(err, BF_ERR_PARSE, "%s:%zu: colour parameter %s has %d values for %d channels", s->path,
                               line_of_key(s, pi->name), pi->name, cJSON_GetArraySize(v), C);
            int c = 0;
            const cJSON *e;
            cJSON_ArrayForEach(e, v)
            {
                if ((rc = read_value(s, e, pi->name, dst + c++, err)) != BF_OK)
                    return rc;
            }
        } else if (pi->color && C > 1) {
            return bf_fail(err, BF_ERR_PARSE, "%s:%zu: colour parameter %s needs an array of %d values", s->path,
                           line_of_key(s, pi->name), pi->name, C);
        } else if ((rc = read_value(s, v, pi->name, dst, err)) != BF_OK) {
            return rc;
        }
    }
    bf_error e2;
    if (check_bounds && bf_model_check(m, x, &e2) != BF_OK) {
        /* Name the line of the offending parameter: its name leads the message. */
        char name[64] = "";
        sscanf(e2.msg, "parameter %63[^[ ]", name);
        return bf_fail(err, e2.code, "%s:%zu: %s", s->path, line_of_key(s, name), e2.msg);
    }
    return BF_OK;
}

bf_status bf_params_read(const char *path, bf_model **model, double **x, bf_error *err)
{
    *model = NULL;
    *x = NULL;
    size_t len;
    char *text;
    bf_status rc = bf_read_text(path, &text, &len, err);
    if (rc != BF_OK)
        return rc;
    rc = bf_params_parse(text, path, model, x, err);
    free(text);
    return rc;
}

bf_status bf_params_from_json(const bf_params_src *s, const cJSON *root, int check_bounds, bf_model **model, double **x,
                              bf_error *err)
{
    *model = NULL;
    *x = NULL;
    if (!cJSON_IsObject(root))
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: expected a JSON object", s->path,
                       (size_t)bf_json_line(s->text, s->from ? s->from : s->text));
    const char *key;
    int repeated = bf_json_repeated_key(root, &key);
    if (repeated)
        return repeated < 0
                   ? bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", s->path)
                   : bf_fail(err, BF_ERR_PARSE, "%s:%zu: \"%s\" given twice", s->path, line_of_key(s, key), key);
    const cJSON *params = cJSON_GetObjectItemCaseSensitive(root, "params");
    if (!cJSON_IsObject(params))
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: \"params\" object missing", s->path,
                       params ? line_of_key(s, "params") : (size_t)bf_json_line(s->text, s->from ? s->from : s->text));
    char spec[256];
    int C = 1;
    bf_status rc;
    if ((rc = build_spec(s, cJSON_GetObjectItemCaseSensitive(root, "model"),
                         cJSON_GetObjectItemCaseSensitive(root, "options"), spec, sizeof spec, err)) != BF_OK ||
        (rc = channel_count(s, root, params, &C, err)) != BF_OK)
        return rc;
    bf_error e2;
    bf_model *m = NULL;
    if (bf_model_new(spec, C, &m, &e2) != BF_OK)
        return bf_fail(err, e2.code, "%s:%zu: %s", s->path, line_of_key(s, "model"), e2.msg);
    double *v = malloc((size_t)bf_model_nvalues(m) * sizeof *v + 1);
    if (!v)
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", s->path);
    else
        rc = fill_params(s, params, m, v, check_bounds, err);
    if (rc != BF_OK) {
        bf_model_free(m);
        free(v);
        return rc;
    }
    *model = m;
    *x = v;
    return BF_OK;
}

bf_status bf_params_parse(const char *text, const char *name, bf_model **model, double **x, bf_error *err)
{
    *model = NULL;
    *x = NULL;
    const char *path = name ? name : "parameters"; /* what messages call the text */
    if (!text)
        return bf_fail(err, BF_ERR_ARG, "%s: no text", path);
    const size_t len = strlen(text);
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, len + 1, &end, 1) /* length counts the NUL */;
    if (!root)
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: malformed JSON", path, (size_t)bf_json_line(text, end ? end : text));
    if (!cJSON_IsObject(root)) {
        cJSON_Delete(root);
        return bf_fail(err, BF_ERR_PARSE, "%s:1: expected a JSON object", path);
    }
    const bf_params_src s = {path, text, NULL};
    bf_status rc = bf_params_from_json(&s, root, 1, model, x, err);
    cJSON_Delete(root);
    return rc;
}
