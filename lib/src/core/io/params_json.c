/* Parameter files (JSON, via cJSON): model, options, channels and named values. */
#include "brdfit/io.h"
#include "json_keys.h"
#include "json_pos.h"
#include "read_text.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Line of the first occurrence of "key" in the text: good enough to point a user at
 * the offending entry, since cJSON keeps no positions. */
static size_t line_of_key(const char *text, const char *key)
{
    char pat[96];
    snprintf(pat, sizeof pat, "\"%s\"", key);
    const char *p = strstr(text, pat);
    return p ? (size_t)bf_json_line(text, p) : 1;
}

/* Builds "model:k=v,..." from the model string and the options object; every piece is
 * measured before it is copied. */
static bf_status build_spec(const char *path, const char *text, const cJSON *model, const cJSON *options, char *spec,
                            size_t size, bf_error *err)
{
    if (!cJSON_IsString(model) || !*model->valuestring)
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: \"model\" must be a non-empty string", path,
                       model ? line_of_key(text, "model") : 1);
    size_t n = strlen(model->valuestring);
    if (n >= size)
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: \"model\" is too long (%zu characters, at most %zu)", path,
                       line_of_key(text, "model"), n, size - 1);
    memcpy(spec, model->valuestring, n + 1);
    if (!options)
        return BF_OK;
    if (!cJSON_IsObject(options))
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: \"options\" must be an object", path, line_of_key(text, "options"));
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
            return bf_fail(err, BF_ERR_PARSE, "%s:%zu: option \"%s\" must be a string or an integer", path,
                           line_of_key(text, o->string), o->string);
        /* A comma or '=' would smuggle in another option ("fresnel": "schlick,mono=all"). */
        if (!*o->string || strpbrk(o->string, ",=") || strchr(val, ','))
            return bf_fail(err, BF_ERR_PARSE,
                           "%s:%zu: option \"%s\": names and values cannot be empty or hold ','"
                           " (names not '=' either)",
                           path, line_of_key(text, o->string), o->string);
        int k = snprintf(spec + n, size - n, "%c%s=%s", first ? ':' : ',', o->string, val);
        if (k < 0 || (size_t)k >= size - n)
            return bf_fail(err, BF_ERR_PARSE, "%s:%zu: model and options too long (at most %zu characters)", path,
                           line_of_key(text, o->string), size - 1);
        n += (size_t)k;
        first = 0;
    }
    return BF_OK;
}

/* Channel count: "channels" if given, else the length of the first colour array, else 1. */
static bf_status channel_count(const char *path, const char *text, const cJSON *root, const cJSON *params, int *C,
                               bf_error *err)
{
    const cJSON *ch = cJSON_GetObjectItemCaseSensitive(root, "channels");
    if (ch) {
        /* Range first, then the conversion (1e30 has no int). */
        if (!cJSON_IsNumber(ch) || !(ch->valuedouble >= 1.0 && ch->valuedouble <= BF_MAX_CHANNELS) ||
            ch->valuedouble != floor(ch->valuedouble))
            return bf_fail(err, BF_ERR_PARSE, "%s:%zu: \"channels\" must be an integer from 1 to %d", path,
                           line_of_key(text, "channels"), BF_MAX_CHANNELS);
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
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: %s array: a parameter has 1 to %d values, one per channel", path,
                       line_of_key(text, p->string), *C < 1 ? "empty" : "too long", BF_MAX_CHANNELS);
    return BF_OK;
}

static bf_status read_value(const char *path, const char *text, const cJSON *v, const char *name, double *out,
                            bf_error *err)
{
    if (!cJSON_IsNumber(v))
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: parameter %s: expected a number", path, line_of_key(text, name),
                       name);
    if (!isfinite(v->valuedouble))
        return bf_fail(err, BF_ERR_RANGE, "%s:%zu: parameter %s is not finite", path, line_of_key(text, name), name);
    *out = v->valuedouble;
    return BF_OK;
}

static bf_status fill_params(const char *path, const char *text, const cJSON *params, const bf_model *m, double *x,
                             bf_error *err)
{
    int C = bf_model_channels(m), rc;
    const cJSON *p;
    cJSON_ArrayForEach(p, params)
    {
        if (bf_model_find_param(m, p->string) < 0)
            return bf_fail(err, BF_ERR_PARSE, "%s:%zu: model %s has no parameter \"%s\"", path,
                           line_of_key(text, p->string), bf_model_spec(m), p->string);
        for (const cJSON *q = params->child; q != p; q = q->next)
            if (strcmp(q->string, p->string) == 0)
                return bf_fail(err, BF_ERR_PARSE, "%s:%zu: parameter \"%s\" given twice", path,
                               line_of_key(text, p->string), p->string);
    }
    for (int i = 0; i < bf_model_nparams(m); i++) {
        const bf_param_info *pi = bf_model_param(m, i);
        double *dst = x + bf_model_param_offset(m, i);
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(params, pi->name);
        if (!v)
            return bf_fail(err, BF_ERR_PARSE, "%s:%zu: missing parameter \"%s\" of model %s", path,
                           line_of_key(text, "params"), pi->name, bf_model_spec(m));
        if (pi->color && cJSON_IsArray(v)) {
            if (cJSON_GetArraySize(v) != C)
                return bf_fail(err, BF_ERR_PARSE, "%s:%zu: colour parameter %s has %d values for %d channels", path,
                               line_of_key(text, pi->name), pi->name, cJSON_GetArraySize(v), C);
            int c = 0;
            const cJSON *e;
            cJSON_ArrayForEach(e, v)
            {
                if ((rc = read_value(path, text, e, pi->name, dst + c++, err)) != BF_OK)
                    return rc;
            }
        } else if (pi->color && C > 1) {
            return bf_fail(err, BF_ERR_PARSE, "%s:%zu: colour parameter %s needs an array of %d values", path,
                           line_of_key(text, pi->name), pi->name, C);
        } else if ((rc = read_value(path, text, v, pi->name, dst, err)) != BF_OK) {
            return rc;
        }
    }
    bf_error e2;
    if (bf_model_check(m, x, &e2) != BF_OK) {
        /* Name the line of the offending parameter: its name leads the message. */
        char name[64] = "";
        sscanf(e2.msg, "parameter %63[^[ ]", name);
        return bf_fail(err, e2.code, "%s:%zu: %s", path, line_of_key(text, name), e2.msg);
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

bf_status bf_params_parse(const char *text, const char *name, bf_model **model, double **x, bf_error *err)
{
    *model = NULL;
    *x = NULL;
    const char *path = name ? name : "parameters"; /* what messages call the text */
    const size_t len = text ? strlen(text) : 0;
    bf_status rc;
    if (!text)
        return bf_fail(err, BF_ERR_ARG, "%s: no text", path);
    bf_model *m = NULL;
    double *v = NULL;
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, len + 1, &end, 1) /* length counts the NUL */;
    if (!root) {
        rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: malformed JSON", path, (size_t)bf_json_line(text, end ? end : text));
        goto done;
    }
    if (!cJSON_IsObject(root)) {
        rc = bf_fail(err, BF_ERR_PARSE, "%s:1: expected a JSON object", path);
        goto done;
    }
    const char *key;
    int repeated = bf_json_repeated_key(root, &key);
    if (repeated) {
        rc = repeated < 0 ? bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path)
                          : bf_fail(err, BF_ERR_PARSE, "%s:%zu: \"%s\" given twice", path, line_of_key(text, key), key);
        goto done;
    }
    const cJSON *params = cJSON_GetObjectItemCaseSensitive(root, "params");
    if (!cJSON_IsObject(params)) {
        rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: \"params\" object missing", path,
                     params ? line_of_key(text, "params") : 1);
        goto done;
    }
    char spec[256];
    int C = 1;
    if ((rc = build_spec(path, text, cJSON_GetObjectItemCaseSensitive(root, "model"),
                         cJSON_GetObjectItemCaseSensitive(root, "options"), spec, sizeof spec, err)) != BF_OK ||
        (rc = channel_count(path, text, root, params, &C, err)) != BF_OK)
        goto done;
    bf_error e2;
    if (bf_model_new(spec, C, &m, &e2) != BF_OK) {
        rc = bf_fail(err, e2.code, "%s:%zu: %s", path, line_of_key(text, "model"), e2.msg);
        goto done;
    }
    if (!(v = malloc((size_t)bf_model_nvalues(m) * sizeof *v + 1))) {
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
        goto done;
    }
    rc = fill_params(path, text, params, m, v, err);
done:
    cJSON_Delete(root);
    if (rc != BF_OK) {
        bf_model_free(m);
        free(v);
        return rc;
    }
    *model = m;
    *x = v;
    return BF_OK;
}
