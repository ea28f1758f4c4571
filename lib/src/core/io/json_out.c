/* Shared JSON output helpers (see json_out.h). */
#include "json_out.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/formats.h"
#include "brdfit/io.h"
#include "brdfit/version.h"

/* The text itself (bf_format_double, which reads back exactly): cJSON prints %1.15g
 * whenever that reads back within a relative DBL_EPSILON, which loses the last bit of
 * about one double in five (found by fuzz/fuzz_params.c: a result file read back). */
cJSON *bf_json_number(double v)
{
    char buf[40];
    return isfinite(v) ? cJSON_CreateRaw(bf_format_double(v, buf, sizeof buf)) : cJSON_CreateNull();
}

void bf_json_add_number(cJSON *o, const char *key, double v)
{
    cJSON_AddItemToObject(o, key, bf_json_number(v));
}

void bf_json_add_string(cJSON *o, const char *key, const char *s)
{
    cJSON_AddItemToObject(o, key, s ? cJSON_CreateString(s) : cJSON_CreateNull());
}

void bf_json_add_version(cJSON *o)
{
    bf_json_add_string(o, "brdfit_version", bf_version());
}

cJSON *bf_json_params(const bf_model *m, const double *x)
{
    if (!m || !x)
        return cJSON_CreateNull();
    cJSON *o = cJSON_CreateObject();
    int C = bf_model_channels(m);
    for (int i = 0; i < bf_model_nparams(m); i++) {
        const bf_param_info *p = bf_model_param(m, i);
        const double *v = x + bf_model_param_offset(m, i);
        if (p->color) {
            cJSON *a = cJSON_CreateArray();
            for (int c = 0; c < C; c++)
                cJSON_AddItemToArray(a, bf_json_number(v[c]));
            cJSON_AddItemToObject(o, p->name, a);
        } else {
            bf_json_add_number(o, p->name, v[0]);
        }
    }
    return o;
}

bf_status bf_json_text(cJSON *root, const char *what, char **out, bf_error *err)
{
    char *text = root ? cJSON_Print(root) : NULL;
    cJSON_Delete(root);
    *out = NULL;
    size_t n = text ? strlen(text) : 0;
    char *s = text ? malloc(n + 2) : NULL; /* plain malloc: the caller frees with bf_free */
    if (s) {
        memcpy(s, text, n);
        s[n] = '\n';
        s[n + 1] = '\0';
    }
    cJSON_free(text);
    if (!s)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory writing %s", what);
    *out = s;
    return BF_OK;
}

bf_status bf_json_write(cJSON *root, const char *path, const char *what, bf_error *err)
{
    const char *name = path ? path : "-";
    char *text;
    if (bf_json_text(root, what, &text, NULL) != BF_OK)
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory writing %s", name, what);
    bf_outfile f;
    bf_status rc = bf_outfile_open(&f, path, err);
    if (rc == BF_OK) {
        fputs(text, f.fp);
        rc = bf_outfile_commit(&f, err); /* checks every write */
    }
    free(text);
    return rc;
}
