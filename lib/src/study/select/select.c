/* Model selection: the smallest candidate within tolerance of the best (see select.h). */
#include "brdfit/select.h"

#include "compare/compare_impl.h"
#include "compare/compare_run.h"
#include "select/select_run.h"
#include "fit_impl.h"
#include "run_options.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/json_out.h"
#include "metrics_json.h"

/* In order of complexity; the mono variants are added after each coloured model. */
static const char *const default_specs[] = {
    "lambert",        "oren_nayar",   "blinn_phong",           "ward_iso",
    "cook_torrance",  "walter",       "ashikhmin_shirley_iso", "lafortune",
    "ward",           "walter_aniso", "ashikhmin_shirley",     "cook_torrance:lobes=2",
    "walter:lobes=2",
};
static const char *const default_mono_specs[] = {
    "lambert",
    "oren_nayar",
    "blinn_phong:mono=specular",
    "ward_iso:mono=specular",
    "cook_torrance:mono=specular",
    "walter:mono=specular",
    "ashikhmin_shirley_iso:mono=specular",
    "lafortune:mono=specular",
    "ward:mono=specular",
    "walter_aniso:mono=specular",
    "ashikhmin_shirley:mono=specular",
    "cook_torrance:lobes=2,mono=specular",
    "walter:lobes=2,mono=specular",
};
enum { NDEFAULT = sizeof default_specs / sizeof default_specs[0] };

int bf_select_default_candidates(int channels, const char ***specs)
{
    const char **out = malloc(2 * NDEFAULT * sizeof *out);
    int n = 0;
    if (!out) {
        *specs = NULL;
        return -1;
    }
    for (int i = 0; i < NDEFAULT; i++) {
        out[n++] = default_specs[i];
        if (channels > 1 && strcmp(default_specs[i], default_mono_specs[i]))
            out[n++] = default_mono_specs[i];
    }
    *specs = (const char **)out;
    return n;
}

/* A colour parameter besides the first (the diffuse colour) makes the highlight
 * coloured; with one channel there is no colour to speak of. */
static int colored_specular(const bf_model *m)
{
    int colors = 0;
    for (int i = 0; i < bf_model_nparams(m); i++)
        colors += bf_model_param(m, i)->color;
    return bf_model_channels(m) > 1 && colors > 1;
}

bf_status bf_select_init(bf_select *s, int n, const char *const *specs, int channels, const bf_options *o,
                         bf_error *err)
{
    memset(s, 0, sizeof *s);
    s->best = s->chosen = -1;
    if (n < 1)
        return bf_fail(err, BF_ERR_ARG, "select: no candidate models");
    if (!o)
        return bf_fail(err, BF_ERR_ARG, "select: no options");
    if (!(s->c = calloc((size_t)n, sizeof *s->c)))
        return bf_fail(err, BF_ERR_NOMEM, "select: out of memory");
    s->n = n;
    s->metric = o->metric;
    s->rank_by = o->rank_by;
    s->folds = o->folds;
    s->timing = o->timing;
    s->tolerance = o->tolerance;
    s->abs_tolerance = o->abs_tolerance;
    for (int i = 0; i < n; i++) {
        bf_select_candidate *c = &s->c[i];
        if (strlen(specs[i]) >= sizeof c->spec) {
            bf_select_clear(s);
            return bf_fail(err, BF_ERR_ARG, "model spec '%.40s...' is too long", specs[i]);
        }
        snprintf(c->spec, sizeof c->spec, "%s", specs[i]);
        bf_model *m = NULL;
        if (bf_model_new(specs[i], channels, &m, err) != BF_OK) {
            bf_select_clear(s);
            return BF_ERR_ARG;
        }
        c->k = bf_model_nvalues(m);
        c->anisotropic = bf_model_family(m)->anisotropic;
        c->lobes = bf_model_lobes(m);
        c->colored_specular = colored_specular(m);
        c->error = c->criterion = c->cv_error = NAN;
        bf_model_free(m);
    }
    return BF_OK;
}

void bf_select_clear(bf_select *s)
{
    if (!s)
        return;
    for (int i = 0; i < s->n && s->c; i++)
        if (s->c[i].result) {
            bf_fit_result_clear(s->c[i].result);
            free(s->c[i].result);
        }
    free(s->c);
    memset(s, 0, sizeof *s);
    s->best = s->chosen = -1;
}

bf_status bf_select_new(int n, const char *const *specs, int channels, const bf_options *o, bf_select **out,
                        bf_error *err)
{
    bf_select *s = malloc(sizeof *s);
    *out = NULL;
    if (!s)
        return bf_fail(err, BF_ERR_NOMEM, "select: out of memory");
    bf_status rc = bf_select_init(s, n, specs, channels, o, err);
    if (rc != BF_OK) {
        free(s);
        return rc;
    }
    *out = s;
    return BF_OK;
}

void bf_select_free(bf_select *s)
{
    if (!s)
        return;
    bf_select_clear(s);
    free(s);
}

/* bf_compare_run's progress: the finished fit moved into its candidate (the table keeps
 * a zeroed slot), then the caller's progress. Calls never overlap. */
typedef struct select_run {
    bf_select *s;
    select_hooks h;
} select_run;

static void candidate_done(void *user, const bf_compare *c, int material, int j, int done, int total)
{
    (void)material, (void)total;
    select_run *r = user;
    bf_select_candidate *cand = &r->s->c[j];
    const bf_compare_fit *f = &c->materials[0].fits[j];
    cand->state = f->state;
    if (f->state == BF_CMP_ERROR) {
        snprintf(cand->message, sizeof cand->message, "%s", f->message);
    } else {
        cand->result = c->results[j]; /* material 0's slot j, taken over */
        c->results[j] = NULL;
        cand->seconds = cand->result->seconds;
        cand->work = f->work;
        cand->k = cand->result->metrics.k; /* fixed parameters (--fix) do not count */
        cand->cv_error = f->cv_error;
    }
    if (r->h.progress)
        r->h.progress(r->h.user, r->s, j, done);
}

bf_status bf_select_run(bf_select *s, bf_samples *data, const bf_options *o, bf_select_progress progress, void *user,
                        bf_error *err)
{
    if (!o)
        return bf_fail(err, BF_ERR_ARG, "select: no options");
    bf_status rc = bf_options_check(o, err);
    if (rc != BF_OK)
        return rc;
    bf_fit_options fo;
    options_fit_get(o, &fo);
    const select_hooks h = {progress, user, o->finish};
    return select_run_with(s, data, &fo, o->jobs, &h, err);
}

bf_status select_run_with(bf_select *s, bf_samples *data, const bf_fit_options *o, int jobs, const select_hooks *h,
                          bf_error *err)
{
    const char **specs = malloc((size_t)s->n * sizeof *specs);
    if (!specs)
        return bf_fail(err, BF_ERR_NOMEM, "select: out of memory");
    for (int i = 0; i < s->n; i++)
        specs[i] = s->c[i].spec;
    const char *name = "data";
    bf_compare c;
    bf_status rc = bf_compare_init(&c, 1, &name, s->n, specs, err);
    free(specs);
    if (rc != BF_OK)
        return rc;
    c.folds = s->rank_by == BF_RANK_CV ? s->folds : 0;
    select_run r = {s, h ? *h : (select_hooks){0}};
    const compare_hooks ch = {candidate_done, &r, r.h.finish};
    rc = compare_run_with(&c, &data, o, jobs, &ch, err);
    bf_compare_clear(&c);
    if (rc == BF_OK)
        bf_select_choose(s);
    return rc;
}

/* The order of preference between two candidates (negative: a first). */
static int prefer(const bf_select *s, int a, int b)
{
    const bf_select_candidate *x = &s->c[a], *y = &s->c[b];
    if (x->k != y->k)
        return x->k - y->k;
    if (x->anisotropic != y->anisotropic)
        return x->anisotropic - y->anisotropic;
    if (x->lobes != y->lobes)
        return x->lobes - y->lobes;
    if (x->colored_specular != y->colored_specular)
        return x->colored_specular - y->colored_specular;
    /* Unfitted candidates (NaN error) after fitted ones. */
    int nx = isnan(x->error), ny = isnan(y->error);
    if (nx != ny)
        return nx - ny;
    if (!nx && x->error != y->error)
        return x->error < y->error ? -1 : 1;
    return a - b;
}

/* What rank_by orders the candidates by. */
static double criterion(const bf_select *s, const bf_select_candidate *c)
{
    const bf_metrics *m = &c->result->metrics;
    switch (s->rank_by) {
    case BF_RANK_BIC: return m->bic;
    case BF_RANK_AIC: return m->aic;
    case BF_RANK_AICC: return m->aicc;
    case BF_RANK_CV: return c->cv_error;
    case BF_RANK_ERROR: return bf_compare_metric_value(m, s->metric);
    }
    return NAN;
}

void bf_select_choose(bf_select *s)
{
    const int by_error = s->rank_by == BF_RANK_ERROR || s->rank_by == BF_RANK_CV;
    s->best = s->chosen = -1;
    for (int i = 0; i < s->n; i++) {
        bf_select_candidate *c = &s->c[i];
        c->within = c->rank = 0;
        c->error = c->criterion = NAN;
        if (c->state != BF_CMP_OK)
            continue;
        double e = s->rank_by == BF_RANK_CV ? c->cv_error : bf_compare_metric_value(&c->result->metrics, s->metric);
        double v = criterion(s, c);
        if (!isfinite(e) || !isfinite(v))
            continue;
        c->error = e;
        c->criterion = v;
        if (s->best < 0 || c->error < s->c[s->best].error)
            s->best = i;
    }
    for (int i = 0; i < s->n; i++) /* competition ranks: ties share the lower */
        if (isfinite(s->c[i].criterion)) {
            s->c[i].rank = 1;
            for (int j = 0; j < s->n; j++)
                s->c[i].rank += isfinite(s->c[j].criterion) && s->c[j].criterion < s->c[i].criterion;
        }
    if (s->best < 0)
        return;
    double limit = s->c[s->best].error * (1.0 + s->tolerance) + s->abs_tolerance;
    for (int i = 0; i < s->n; i++) {
        bf_select_candidate *c = &s->c[i];
        c->within = by_error ? c->error <= limit : c->rank == 1;
        if (c->within && (s->chosen < 0 || prefer(s, i, s->chosen) < 0))
            s->chosen = i;
    }
}

void bf_select_order(const bf_select *s, int *order)
{
    for (int i = 0; i < s->n; i++)
        order[i] = i;
    /* Insertion sort: the list is short, and qsort has no context argument in C11. */
    for (int i = 1; i < s->n; i++)
        for (int j = i; j > 0 && prefer(s, order[j - 1], order[j]) > 0; j--) {
            int t = order[j];
            order[j] = order[j - 1];
            order[j - 1] = t;
        }
}

static cJSON *select_json(const bf_select *s, const char *data)
{
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "version", 2);
    bf_json_add_version(root);
    bf_json_add_string(root, "data", data);
    bf_json_add_string(root, "rank_by", bf_compare_rank_name(s->rank_by));
    bf_json_add_number(root, "folds", s->rank_by == BF_RANK_CV ? s->folds : NAN);
    bf_json_add_string(root, "error", s->rank_by == BF_RANK_CV ? "cv" : bf_compare_metric_name(s->metric));
    bf_json_add_string(root, "work", "sample evaluations: passes over the samples times their number");
    cJSON_AddBoolToObject(root, "timing", s->timing);
    cJSON_AddNumberToObject(root, "tolerance", s->tolerance);
    cJSON_AddNumberToObject(root, "abs_tolerance", s->abs_tolerance);
    bf_json_add_string(root, "best", s->best >= 0 ? s->c[s->best].spec : NULL);
    bf_json_add_string(root, "chosen", s->chosen >= 0 ? s->c[s->chosen].spec : NULL);
    cJSON *list = cJSON_AddArrayToObject(root, "candidates");
    for (int i = 0; i < s->n; i++) {
        const bf_select_candidate *c = &s->c[i];
        int ran = c->state == BF_CMP_OK || c->state == BF_CMP_FAILED;
        cJSON *o = cJSON_CreateObject();
        bf_json_add_string(o, "model", c->spec);
        bf_json_add_string(o, "spec", ran ? bf_model_spec(c->result->model) : NULL);
        cJSON_AddNumberToObject(o, "k", c->k);
        cJSON_AddBoolToObject(o, "anisotropic", c->anisotropic);
        cJSON_AddNumberToObject(o, "lobes", c->lobes);
        cJSON_AddBoolToObject(o, "coloured_specular", c->colored_specular);
        bf_json_add_string(o, "status", bf_compare_state_name(c->state));
        bf_json_add_string(o, "message", c->state == BF_CMP_ERROR ? c->message : NULL);
        bf_json_add_number(o, "error", c->error);
        bf_json_add_number(o, "criterion", c->criterion);
        bf_json_add_number(o, "cv", c->cv_error);
        cJSON_AddItemToObject(o, "rank", c->rank > 0 ? cJSON_CreateNumber(c->rank) : cJSON_CreateNull());
        cJSON_AddBoolToObject(o, "within_tolerance", c->within);
        cJSON_AddBoolToObject(o, "chosen", i == s->chosen);
        bf_json_add_number(o, "work", ran ? c->work : NAN);
        if (s->timing)
            bf_json_add_number(o, "seconds", ran ? c->seconds : NAN);
        cJSON_AddItemToObject(o, "metrics", ran ? bf_json_metrics(&c->result->metrics) : cJSON_CreateNull());
        cJSON_AddItemToObject(o, "params", ran ? bf_json_params(c->result->model, c->result->x) : cJSON_CreateNull());
        cJSON_AddItemToObject(o, "stderr",
                              ran ? bf_json_params(c->result->model, c->result->stderr_) : cJSON_CreateNull());
        cJSON *w = cJSON_AddArrayToObject(o, "warnings");
        for (int k = 0; ran && k < c->result->nwarnings; k++)
            cJSON_AddItemToArray(w, cJSON_CreateString(c->result->warnings[k]));
        cJSON_AddItemToArray(list, o);
    }
    return root;
}

bf_status bf_select_write_json(const bf_select *s, const char *data, const char *path, bf_error *err)
{
    return bf_json_write(select_json(s, data), path, "the selection", err);
}

bf_status bf_select_json(const bf_select *s, const char *data, char **out, bf_error *err)
{
    return bf_json_text(select_json(s, data), "the selection", out, err);
}
