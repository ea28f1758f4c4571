/* The fit result file: a parameter file (model, options, channels, params: what
 * bf_params_read reads) plus data, residual, metrics, standard errors, fixed
 * parameters, the optimizer summary and timing. Colour parameters are arrays of one
 * value per channel (also for one channel), scalars plain numbers. Numbers round-trip
 * (bf_json_number: the shortest text that reads back exactly).
 * NaN and Inf (an undetermined standard error, metrics of a failed fit) are null. */
#include "brdfit/fit.h"
#include "brdfit/io.h"
#include "io/json_out.h"
#include "metrics_json.h"
#include "models/terms.h"

#include <cjson/cJSON.h>
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* "walter:fresnel=schlick,lobes=2" -> {"fresnel": "schlick", "lobes": 2}. */
static cJSON *options_json(const bf_model *m)
{
    cJSON *o = cJSON_CreateObject();
    const char *p = strchr(bf_model_spec(m), ':');
    while (o && p && *p) {
        p++;
        const char *eq = strchr(p, '='), *comma = strchr(p, ',');
        const char *end = comma ? comma : p + strlen(p);
        if (eq && eq < end) {
            char key[64], val[64];
            snprintf(key, sizeof key, "%.*s", (int)(eq - p), p);
            snprintf(val, sizeof val, "%.*s", (int)(end - eq - 1), eq + 1);
            int digits = val[0] != '\0';
            for (const char *c = val; *c; c++)
                digits &= isdigit((unsigned char)*c) != 0;
            cJSON_AddItemToObject(o, key, digits ? cJSON_CreateNumber(atof(val)) : cJSON_CreateString(val));
        }
        p = end;
    }
    return o;
}

/* Names of fixed entries: a colour parameter fixed on every channel is its name, one
 * fixed on some channels only lists NAME[c] for those. */
/* The parameters whose every entry flags says (a name), or the flagged entries alone
 * ("rho_d[1]"): the fixed ones, the inactive ones. */
static cJSON *flagged_names(const bf_fit_result *r, const unsigned char *flags)
{
    const bf_model *m = r->model;
    int C = bf_model_channels(m);
    cJSON *a = cJSON_CreateArray();
    for (int i = 0; a && flags && i < bf_model_nparams(m); i++) {
        const bf_param_info *p = bf_model_param(m, i);
        const unsigned char *f = flags + bf_model_param_offset(m, i);
        int nc = p->color ? C : 1, nf = 0;
        for (int c = 0; c < nc; c++)
            nf += f[c] != 0;
        if (nf == nc) {
            cJSON_AddItemToArray(a, cJSON_CreateString(p->name));
        } else {
            for (int c = 0; c < nc; c++) {
                if (!f[c])
                    continue;
                char buf[80];
                snprintf(buf, sizeof buf, "%s[%d]", p->name, c);
                cJSON_AddItemToArray(a, cJSON_CreateString(buf));
            }
        }
    }
    return a;
}

/* The complex index n + ik of each conductor Fresnel term (Gulbrandsen's mapping of its
 * r and g: a renderer that takes n and k, as pbrt's and Mitsuba's conductors do, reads
 * them here): {"n": [...], "k": [...]}, "n_2"/"k_2" for lobe 2. NULL without one. */
static cJSON *conductor_json(const bf_model *m, const double *x)
{
    cJSON *o = NULL;
    const int C = bf_model_channels(m);
    for (int i = 1; i < bf_model_nparams(m); i++) {
        const bf_param_info *g = bf_model_param(m, i), *r = bf_model_param(m, i - 1);
        if (g->role != BF_ROLE_EDGE_TINT || (!o && !(o = cJSON_CreateObject())))
            continue;
        const int K = g->color ? C : 1; /* mono ties r and g to one value */
        cJSON *na = cJSON_CreateArray(), *ka = cJSON_CreateArray();
        for (int c = 0; c < K; c++) {
            double n, k;
            bf_conductor_nk(x[bf_model_param_offset(m, i - 1) + (r->color ? c : 0)], x[bf_model_param_offset(m, i) + c],
                            &n, &k, NULL);
            cJSON_AddItemToArray(na, cJSON_CreateNumber(n));
            cJSON_AddItemToArray(ka, cJSON_CreateNumber(k));
        }
        char key[40];
        snprintf(key, sizeof key, "n%s", g->name + 1); /* g, g_2 -> n, n_2 */
        cJSON_AddItemToObject(o, key, na);
        key[0] = 'k';
        cJSON_AddItemToObject(o, key, ka);
    }
    return o;
}

/* top: the whole document (a single result), which names the version first. */
static cJSON *result_json(const bf_fit_result *r, const char *data_path, int top)
{
    const bf_model *m = r->model;
    cJSON *o = cJSON_CreateObject();
    if (!o)
        return NULL;
    if (top)
        bf_json_add_version(o);
    cJSON_AddStringToObject(o, "model", bf_model_name(m));
    cJSON_AddItemToObject(o, "options", options_json(m));
    cJSON_AddNumberToObject(o, "channels", bf_model_channels(m));
    cJSON_AddItemToObject(o, "params", bf_json_params(m, r->x));
    cJSON *nk = conductor_json(m, r->x);
    if (nk)
        cJSON_AddItemToObject(o, "conductor", nk);
    if (data_path)
        cJSON_AddStringToObject(o, "data", data_path);
    else
        cJSON_AddNullToObject(o, "data");
    cJSON_AddNumberToObject(o, "samples", (double)r->samples);
    cJSON_AddStringToObject(o, "residual", bf_residual_name(r->residual));

    cJSON_AddItemToObject(o, "metrics", bf_json_metrics(&r->metrics));

    cJSON_AddItemToObject(o, "stderr", bf_json_params(m, r->stderr_));
    cJSON_AddItemToObject(o, "fixed", flagged_names(r, r->fixed));
    /* Entries without effect at the solution (not counted in k; the warnings say why). */
    cJSON_AddItemToObject(o, "inactive", flagged_names(r, r->inactive));
    cJSON *warn = cJSON_AddArrayToObject(o, "warnings");
    for (int w = 0; w < r->nwarnings; w++)
        cJSON_AddItemToArray(warn, cJSON_CreateString(r->warnings[w]));

    const bf_solution *s = &r->solution;
    cJSON *op = cJSON_AddObjectToObject(o, "optimizer");
    cJSON_AddStringToObject(op, "backend", s->backend);
    cJSON_AddStringToObject(op, "algorithm", s->algorithm);
    cJSON_AddNumberToObject(op, "iterations", s->iterations);
    cJSON_AddNumberToObject(op, "evaluations", s->evaluations);
    bf_json_add_number(op, "initial_cost", s->initial_cost);
    bf_json_add_number(op, "final_cost", s->final_cost);
    cJSON_AddStringToObject(op, "termination", s->termination);
    bf_json_add_number(op, "seconds", s->seconds);
    cJSON_AddNumberToObject(op, "threads", r->threads);
    cJSON_AddNumberToObject(op, "starts", r->starts);
    cJSON_AddNumberToObject(op, "starts_at_best", r->starts_at_best);
    if (r->candidates > 0)
        cJSON_AddNumberToObject(op, "candidates", r->candidates);
    if (r->screen.samples > 0) { /* the starts' solves on the screening set (fit.h) */
        cJSON *sc = cJSON_AddObjectToObject(op, "screen");
        cJSON_AddNumberToObject(sc, "samples", (double)r->screen.samples);
        cJSON_AddNumberToObject(sc, "iterations", r->screen.iterations);
        cJSON_AddNumberToObject(sc, "evaluations", r->screen.evaluations);
        bf_json_add_number(sc, "seconds", r->screen.seconds);
    }
    if (r->presolve.samples > 0) { /* the starts' solves on a subsample (fit.h) */
        cJSON *pre = cJSON_AddObjectToObject(op, "presolve");
        cJSON_AddNumberToObject(pre, "samples", (double)r->presolve.samples);
        cJSON_AddNumberToObject(pre, "iterations", r->presolve.iterations);
        cJSON_AddNumberToObject(pre, "evaluations", r->presolve.evaluations);
        bf_json_add_number(pre, "seconds", r->presolve.seconds);
    }
    /* A seed above 2^53 would not survive a JSON number: write it as a string then. */
    if (r->seed <= (1ull << 53))
        cJSON_AddNumberToObject(op, "seed", (double)r->seed);
    else {
        char buf[24];
        snprintf(buf, sizeof buf, "%llu", (unsigned long long)r->seed);
        cJSON_AddStringToObject(op, "seed", buf);
    }
    cJSON_AddBoolToObject(o, "ok", r->ok);
    bf_json_add_number(o, "seconds", r->seconds);
    return o;
}

bf_status bf_fit_write_json(const bf_fit_result *r, const char *data_path, const char *out_path, bf_error *err)
{
    if (!r || !r->model || !r->x)
        return bf_fail(err, BF_ERR_ARG, "no fit result to write");
    if (r->solution.stop == BF_STOP_CANCELLED)
        return bf_fail(err, BF_ERR_ARG, "the fit was cancelled: no result to write");
    return bf_json_write(result_json(r, data_path, 1), out_path, "the result", err);
}

bf_status bf_fit_result_json(const bf_fit_result *r, const char *data_path, char **out, bf_error *err)
{
    *out = NULL;
    if (!r || !r->model || !r->x)
        return bf_fail(err, BF_ERR_ARG, "no fit result to write");
    if (r->solution.stop == BF_STOP_CANCELLED)
        return bf_fail(err, BF_ERR_ARG, "the fit was cancelled: no result to write");
    return bf_json_text(result_json(r, data_path, 1), "the result", out, err);
}

bf_status bf_fit_write_json_list(const bf_fit_result *const *r, int n, const char *data_path, const char *out_path,
                                 bf_error *err)
{
    cJSON *root = cJSON_CreateObject();
    if (root)
        bf_json_add_version(root);
    cJSON *fits = root ? cJSON_AddArrayToObject(root, "fits") : NULL;
    for (int i = 0; fits && i < n; i++) {
        if (!r[i] || !r[i]->model || !r[i]->x) {
            cJSON_Delete(root);
            return bf_fail(err, BF_ERR_ARG, "no fit result to write");
        }
        if (r[i]->solution.stop == BF_STOP_CANCELLED) {
            cJSON_Delete(root);
            return bf_fail(err, BF_ERR_ARG, "fit %d was cancelled: no results to write", i + 1);
        }
        cJSON_AddItemToArray(fits, result_json(r[i], data_path, 0));
    }
    return bf_json_write(root, out_path, "the results", err);
}
