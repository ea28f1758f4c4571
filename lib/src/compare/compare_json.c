/* The comparison as JSON. Keys are stable: every key is written for every fit, with
 * null where it does not apply (unranked fits, NaN metrics, no parameters), so that
 * scripts and the report can index without checking. */
#include "brdfit/compare.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>

#include "brdfit/io.h"

static cJSON *number(double v) { return isfinite(v) ? cJSON_CreateNumber(v) : cJSON_CreateNull(); }
static void add_number(cJSON *o, const char *key, double v) { cJSON_AddItemToObject(o, key, number(v)); }
static void add_rank(cJSON *o, const char *key, int r)
{
    cJSON_AddItemToObject(o, key, r > 0 ? cJSON_CreateNumber(r) : cJSON_CreateNull());
}
static void add_string(cJSON *o, const char *key, const char *s)
{
    cJSON_AddItemToObject(o, key, s ? cJSON_CreateString(s) : cJSON_CreateNull());
}

/* The fitted parameters by name (colour parameters as arrays), as in a parameter file. */
static cJSON *params_json(const bf_fit_result *r)
{
    if (!r || !r->model || !r->x)
        return cJSON_CreateNull();
    cJSON *o = cJSON_CreateObject();
    int C = bf_model_channels(r->model);
    for (int i = 0; i < bf_model_nparams(r->model); i++) {
        const bf_param_info *p = bf_model_param(r->model, i);
        const double *v = r->x + bf_model_param_offset(r->model, i);
        if (p->colour) {
            cJSON *a = cJSON_CreateArray();
            for (int c = 0; c < C; c++)
                cJSON_AddItemToArray(a, number(v[c]));
            cJSON_AddItemToObject(o, p->name, a);
        } else {
            add_number(o, p->name, v[0]);
        }
    }
    return o;
}

static cJSON *fit_json(const bf_compare *c, int j, const bf_compare_fit *f)
{
    cJSON *o = cJSON_CreateObject();
    int ran = f->state == BF_CMP_OK || f->state == BF_CMP_FAILED;
    add_string(o, "model", c->models[j]);
    add_string(o, "spec", f->result && f->result->model ? bf_model_spec(f->result->model) : NULL);
    add_string(o, "status", bf_compare_state_name(f->state));
    cJSON_AddBoolToObject(o, "ok", f->state == BF_CMP_OK);
    add_string(o, "message", f->state == BF_CMP_ERROR ? f->message : NULL);
    add_number(o, "k", ran ? f->metrics.k : NAN);
    add_number(o, "n", ran ? (double)f->metrics.n : NAN);
    add_number(o, "error", f->error);
    add_number(o, "rmse", ran ? f->metrics.rmse : NAN);
    add_number(o, "rmse_log", ran ? f->metrics.rmse_log : NAN);
    add_number(o, "rmse_cos", ran ? f->metrics.rmse_cos : NAN);
    add_number(o, "rmse_rel", ran ? f->metrics.rmse_rel : NAN);
    add_number(o, "max_err", ran ? f->metrics.max_err : NAN);
    add_number(o, "aic", ran ? f->metrics.aic : NAN);
    add_number(o, "bic", ran ? f->metrics.bic : NAN);
    add_number(o, "seconds", ran ? f->seconds : NAN);
    add_rank(o, "rank_bic", f->rank_bic);
    add_rank(o, "rank_aic", f->rank_aic);
    cJSON_AddBoolToObject(o, "pareto_k", f->pareto_k);
    cJSON_AddBoolToObject(o, "pareto_time", f->pareto_time);
    cJSON_AddBoolToObject(o, "within_tolerance", f->within_tolerance);
    cJSON_AddItemToObject(o, "params", params_json(ran ? f->result : NULL));
    return o;
}

static cJSON *compare_json(const bf_compare *c)
{
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "version", 1);
    add_string(root, "error", bf_compare_metric_name(c->metric));
    cJSON_AddNumberToObject(root, "tolerance", c->tolerance);
    add_string(root, "residual", c->residual);
    cJSON_AddBoolToObject(root, "interrupted", c->interrupted);
    cJSON *models = cJSON_AddArrayToObject(root, "models");
    for (int j = 0; j < c->nmodels; j++)
        cJSON_AddItemToArray(models, cJSON_CreateString(c->models[j]));
    cJSON *mats = cJSON_AddArrayToObject(root, "materials");
    for (int i = 0; i < c->nmaterials; i++) {
        const bf_compare_material *m = &c->materials[i];
        cJSON *mo = cJSON_CreateObject();
        add_string(mo, "data", m->data);
        cJSON_AddNumberToObject(mo, "samples", (double)m->samples);
        cJSON_AddNumberToObject(mo, "channels", m->channels);
        add_string(mo, "best", m->best >= 0 ? c->models[m->best] : NULL);
        add_string(mo, "simplest", m->simplest >= 0 ? c->models[m->simplest] : NULL);
        cJSON *fits = cJSON_AddArrayToObject(mo, "fits");
        for (int j = 0; j < c->nmodels; j++)
            cJSON_AddItemToArray(fits, fit_json(c, j, &m->fits[j]));
        cJSON_AddItemToArray(mats, mo);
    }
    cJSON *sum = cJSON_AddArrayToObject(root, "summary");
    for (int j = 0; j < c->nmodels; j++) {
        const bf_compare_summary *s = &c->summary[j];
        cJSON *so = cJSON_CreateObject();
        add_string(so, "model", c->models[j]);
        cJSON_AddNumberToObject(so, "materials", s->ranked);
        add_number(so, "mean_rank_bic", s->mean_rank_bic);
        add_number(so, "mean_rank_aic", s->mean_rank_aic);
        add_number(so, "mean_error", s->mean_error);
        cJSON_AddNumberToObject(so, "chosen_simplest", s->chosen);
        cJSON_AddItemToArray(sum, so);
    }
    return root;
}

int bf_compare_write_json(const bf_compare *c, const char *path, bf_error *err)
{
    const char *name = path ? path : "-";
    cJSON *root = compare_json(c);
    char *text = root ? cJSON_Print(root) : NULL;
    cJSON_Delete(root);
    if (!text)
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory writing the comparison", name);
    bf_outfile f;
    int rc = bf_outfile_open(&f, path, err);
    if (rc == BF_OK) {
        if (fputs(text, f.fp) < 0 || fputc('\n', f.fp) == EOF) {
            bf_outfile_abort(&f);
            rc = bf_fail(err, BF_ERR_IO, "%s: write failed", name);
        } else {
            rc = bf_outfile_commit(&f, err);
        }
    }
    cJSON_free(text);
    return rc;
}
