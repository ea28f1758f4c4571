/* The comparison as JSON. Keys are stable: every key is written for every fit, with
 * null where it does not apply (unranked fits, NaN metrics, no parameters), so that
 * scripts and the report can index without checking. Wall times appear only when the
 * comparison asks for them (bf_compare.timing); everything else is a function of the
 * fits, so two runs give the same bytes. */
#include "brdfit/compare.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/json_out.h"

static void add_rank(cJSON *o, const char *key, int r)
{
    cJSON_AddItemToObject(o, key, r > 0 ? cJSON_CreateNumber(r) : cJSON_CreateNull());
}

/* The entries outside the bounds, as a list of names (", "-separated in the reference). */
static cJSON *outside_json(const char *outside)
{
    cJSON *a = cJSON_CreateArray();
    for (const char *p = outside; *p;) {
        const char *e = strstr(p, ", ");
        const size_t n = e ? (size_t)(e - p) : strlen(p);
        char name[BF_REFERENCE_OUTSIDE_LEN];
        snprintf(name, sizeof name, "%.*s", (int)n, p);
        cJSON_AddItemToArray(a, cJSON_CreateString(name));
        p += n + (e ? 2 : 0);
    }
    return a;
}

/* A published fit beside brdfit's (compare.h, bf_compare_reference). */
static cJSON *reference_json(const bf_compare *c, const bf_compare_reference *q)
{
    const bf_reference *r = q->reference;
    const int ok = !q->message[0];
    cJSON *o = cJSON_CreateObject();
    bf_json_add_string(o, "source", r->source);
    bf_json_add_string(o, "table", r->table);
    bf_json_add_string(o, "file", r->file);
    cJSON_AddNumberToObject(o, "line", r->line);
    bf_json_add_string(o, "material", r->material);
    bf_json_add_string(o, "spec", bf_model_spec(r->model));
    bf_json_add_number(o, "cost", q->cost);
    bf_json_add_number(o, "brdfit_cost", q->brdfit_cost);
    bf_json_add_number(o, "error", ok ? bf_compare_metric_value(&q->metrics, c->metric) : NAN);
    bf_json_add_number(o, "rmse", ok ? q->metrics.rmse : NAN);
    bf_json_add_number(o, "rmse_log", ok ? q->metrics.rmse_log : NAN);
    bf_json_add_number(o, "rmse_cos", ok ? q->metrics.rmse_cos : NAN);
    bf_json_add_number(o, "rmse_rel", ok ? q->metrics.rmse_rel : NAN);
    bf_json_add_number(o, "max_err", ok ? q->metrics.max_err : NAN);
    cJSON_AddBoolToObject(o, "outside_bounds", r->outside[0] != '\0');
    cJSON_AddItemToObject(o, "outside", outside_json(r->outside));
    cJSON_AddBoolToObject(o, "brdfit_worse", q->brdfit_worse);
    bf_json_add_string(o, "message", ok ? NULL : q->message);
    cJSON_AddItemToObject(o, "params", bf_json_params(r->model, r->x));
    return o;
}

static cJSON *fit_json(const bf_compare *c, int i, int j, const bf_compare_fit *f)
{
    cJSON *o = cJSON_CreateObject();
    const int ran = f->state == BF_CMP_OK || f->state == BF_CMP_FAILED;
    const bf_fit_result *r = ran ? f->result : NULL;
    bf_json_add_string(o, "model", c->models[j]);
    bf_json_add_string(o, "spec", f->result && f->result->model ? bf_model_spec(f->result->model) : NULL);
    bf_json_add_string(o, "status", bf_compare_state_name(f->state));
    cJSON_AddBoolToObject(o, "ok", f->state == BF_CMP_OK);
    bf_json_add_string(o, "message", f->state == BF_CMP_ERROR ? f->message : NULL);
    bf_json_add_number(o, "k", ran ? f->metrics.k : NAN);
    bf_json_add_number(o, "n", ran ? (double)f->metrics.n : NAN);
    bf_json_add_number(o, "error", f->error);
    bf_json_add_number(o, "rmse", ran ? f->metrics.rmse : NAN);
    bf_json_add_number(o, "rmse_log", ran ? f->metrics.rmse_log : NAN);
    bf_json_add_number(o, "rmse_cos", ran ? f->metrics.rmse_cos : NAN);
    bf_json_add_number(o, "rmse_rel", ran ? f->metrics.rmse_rel : NAN);
    bf_json_add_number(o, "max_err", ran ? f->metrics.max_err : NAN);
    bf_json_add_number(o, "loglik", ran ? f->metrics.loglik : NAN);
    bf_json_add_number(o, "aic", ran ? f->metrics.aic : NAN);
    bf_json_add_number(o, "aicc", ran ? f->metrics.aicc : NAN);
    bf_json_add_number(o, "bic", ran ? f->metrics.bic : NAN);
    bf_json_add_number(o, "cv", ran ? f->cv_error : NAN);
    bf_json_add_number(o, "work", ran ? f->work : NAN);
    if (c->timing)
        bf_json_add_number(o, "seconds", ran ? f->seconds : NAN);
    add_rank(o, "rank", f->rank);
    add_rank(o, "rank_bic", f->rank_bic);
    add_rank(o, "rank_aic", f->rank_aic);
    add_rank(o, "rank_aicc", f->rank_aicc);
    add_rank(o, "rank_cv", f->rank_cv);
    cJSON_AddBoolToObject(o, "pareto_k", f->pareto_k);
    cJSON_AddBoolToObject(o, "pareto_work", f->pareto_work);
    cJSON_AddBoolToObject(o, "within_tolerance", f->within_tolerance);
    cJSON_AddItemToObject(o, "params", r ? bf_json_params(r->model, r->x) : cJSON_CreateNull());
    cJSON_AddItemToObject(o, "stderr", r ? bf_json_params(r->model, r->stderr_) : cJSON_CreateNull());
    cJSON *w = cJSON_AddArrayToObject(o, "warnings");
    for (int k = 0; r && k < r->nwarnings; k++)
        cJSON_AddItemToArray(w, cJSON_CreateString(r->warnings[k]));
    cJSON *refs = cJSON_AddArrayToObject(o, "references");
    for (int k = 0; k < c->nreference; k++)
        if (c->reference[k].material == i && c->reference[k].model == j)
            cJSON_AddItemToArray(refs, reference_json(c, &c->reference[k]));
    return o;
}

static cJSON *compare_json(const bf_compare *c)
{
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "version", 2);
    bf_json_add_version(root);
    bf_json_add_string(root, "rank_by", bf_compare_rank_name(c->rank_by));
    /* The error of the fronts and the tolerance: cross-validated when ranked by it. */
    bf_json_add_string(root, "error", c->rank_by == BF_RANK_CV ? "cv" : bf_compare_metric_name(c->metric));
    bf_json_add_number(root, "folds", c->folds > 0 ? c->folds : NAN);
    cJSON_AddNumberToObject(root, "tolerance", c->tolerance);
    bf_json_add_string(root, "residual", c->residual);
    bf_json_add_string(root, "work", "sample evaluations: passes over the samples times their number");
    cJSON_AddBoolToObject(root, "timing", c->timing);
    cJSON_AddBoolToObject(root, "interrupted", c->interrupted);
    cJSON *models = cJSON_AddArrayToObject(root, "models");
    for (int j = 0; j < c->nmodels; j++)
        cJSON_AddItemToArray(models, cJSON_CreateString(c->models[j]));
    cJSON *mats = cJSON_AddArrayToObject(root, "materials");
    for (int i = 0; i < c->nmaterials; i++) {
        const bf_compare_material *m = &c->materials[i];
        cJSON *mo = cJSON_CreateObject();
        bf_json_add_string(mo, "data", m->data);
        cJSON_AddNumberToObject(mo, "samples", (double)m->samples);
        cJSON_AddNumberToObject(mo, "channels", m->channels);
        bf_json_add_string(mo, "best", m->best >= 0 ? c->models[m->best] : NULL);
        bf_json_add_string(mo, "simplest", m->simplest >= 0 ? c->models[m->simplest] : NULL);
        cJSON *fits = cJSON_AddArrayToObject(mo, "fits");
        for (int j = 0; j < c->nmodels; j++)
            cJSON_AddItemToArray(fits, fit_json(c, i, j, &m->fits[j]));
        cJSON_AddItemToArray(mats, mo);
    }
    cJSON *sum = cJSON_AddArrayToObject(root, "summary");
    for (int j = 0; j < c->nmodels; j++) {
        const bf_compare_summary *s = &c->summary[j];
        cJSON *so = cJSON_CreateObject();
        bf_json_add_string(so, "model", c->models[j]);
        cJSON_AddNumberToObject(so, "materials", s->ranked);
        bf_json_add_number(so, "mean_rank", s->mean_rank);
        bf_json_add_number(so, "mean_rank_bic", s->mean_rank_bic);
        bf_json_add_number(so, "mean_rank_aic", s->mean_rank_aic);
        bf_json_add_number(so, "mean_error", s->mean_error);
        cJSON_AddNumberToObject(so, "chosen_simplest", s->chosen);
        cJSON_AddItemToArray(sum, so);
    }
    return root;
}

bf_status bf_compare_write_json(const bf_compare *c, const char *path, bf_error *err)
{
    return bf_json_write(compare_json(c), path, "the comparison", err);
}

bf_status bf_compare_json(const bf_compare *c, char **out, bf_error *err)
{
    return bf_json_text(compare_json(c), "the comparison", out, err);
}
