/* Ranking fits of several models to several materials: ranks by criterion, Pareto
 * fronts, the simplest model within tolerance, and the summary across materials. */
#include "brdfit/compare.h"

#include "compare/compare_impl.h"
#include "run_options.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

double bf_compare_work(const bf_fit_result *r)
{
    return (double)r->screen.evaluations * (double)r->screen.samples +
           (double)r->presolve.evaluations * (double)r->presolve.samples +
           ((double)r->solution.evaluations + 1.0) * (double)r->samples;
}

const char *bf_compare_state_name(bf_compare_state s)
{
    switch (s) {
    case BF_CMP_NOT_RUN: return "not_run";
    case BF_CMP_OK: return "ok";
    case BF_CMP_FAILED: return "failed";
    case BF_CMP_ERROR: return "error";
    }
    return "?";
}

/* The ranking's options, as a run's options hold them (beside the table they fill: bf_compare_init
 * applies the defaults, bf_compare_run a run's own). */
bf_status bf_compare_set_options(bf_compare *c, const bf_options *o, bf_error *err)
{
    if (!c || !o)
        return bf_fail(err, BF_ERR_ARG, "compare: no table or no options");
    c->metric = o->metric;
    c->rank_by = o->rank_by;
    /* Folds only when ranking by the cross-validated error: K more fits per model. */
    c->folds = options_folds(o);
    c->timing = o->timing;
    c->tolerance = o->tolerance;
    c->residual = bf_residual_name(o->residual);
    return compare_read_references(c, o, err);
}

bf_status bf_compare_init(bf_compare *c, int nmaterials, const char *const *data, int nmodels,
                          const char *const *models, bf_error *err)
{
    memset(c, 0, sizeof *c);
    /* The ranking's defaults are the options' (bf_compare_run applies a run's own). */
    bf_options *defaults = NULL;
    bf_status rc = bf_options_new(BF_TASK_COMPARE, &defaults, err);
    if (rc == BF_OK)
        rc = bf_compare_set_options(c, defaults, err);
    bf_options_free(defaults);
    if (rc != BF_OK)
        return rc;
    if (nmaterials < 1 || nmodels < 1)
        return bf_fail(err, BF_ERR_ARG, "a comparison needs at least one material and one model");
    c->nmaterials = nmaterials;
    c->nmodels = nmodels;
    c->models = calloc((size_t)nmodels, sizeof *c->models);
    c->materials = calloc((size_t)nmaterials, sizeof *c->materials);
    c->summary = calloc((size_t)nmodels, sizeof *c->summary);
    int ok = c->models && c->materials && c->summary;
    for (int j = 0; ok && j < nmodels; j++)
        ok = (c->models[j] = strdup(models[j])) != NULL;
    for (int i = 0; ok && i < nmaterials; i++) {
        bf_compare_material *m = &c->materials[i];
        m->best = m->simplest = -1;
        ok = (m->data = strdup(data[i])) && (m->fits = calloc((size_t)nmodels, sizeof *m->fits));
    }
    if (!ok) {
        bf_compare_clear(c);
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for a comparison table");
    }
    return BF_OK;
}

void bf_compare_clear(bf_compare *c)
{
    if (c->results)
        for (size_t k = 0; k < (size_t)c->nmaterials * (size_t)c->nmodels; k++) {
            bf_fit_result_clear(c->results[k]);
            free(c->results[k]);
        }
    free(c->results);
    if (c->models)
        for (int j = 0; j < c->nmodels; j++)
            free(c->models[j]);
    if (c->materials)
        for (int i = 0; i < c->nmaterials; i++) {
            free(c->materials[i].data);
            free(c->materials[i].fits);
        }
    free(c->models);
    free(c->materials);
    free(c->summary);
    bf_reference_set_free(c->references);
    free(c->reference);
    memset(c, 0, sizeof *c);
}

bf_status bf_compare_new(int nmaterials, const char *const *data, int nmodels, const char *const *models,
                         bf_compare **out, bf_error *err)
{
    bf_compare *c = malloc(sizeof *c);
    *out = NULL;
    if (!c)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for a comparison table");
    bf_status rc = bf_compare_init(c, nmaterials, data, nmodels, models, err);
    if (rc != BF_OK) {
        free(c);
        return rc;
    }
    *out = c;
    return BF_OK;
}

void bf_compare_free(bf_compare *c)
{
    if (!c)
        return;
    bf_compare_clear(c);
    free(c);
}

void bf_compare_pareto(int n, const double *x, const double *y, int *on)
{
    for (int i = 0; i < n; i++) {
        on[i] = !isnan(x[i]) && !isnan(y[i]);
        for (int j = 0; on[i] && j < n; j++) {
            if (j == i || isnan(x[j]) || isnan(y[j]))
                continue;
            if (x[j] <= x[i] && y[j] <= y[i] && (x[j] < x[i] || y[j] < y[i]))
                on[i] = 0;
        }
    }
}

/* Competition ranks of v over the flagged entries: 1 + how many are strictly smaller,
 * so exact ties share a rank. O(n^2): n is a handful of models. */
static void rank_values(int n, const double *v, const int *use, int *rank)
{
    for (int i = 0; i < n; i++) {
        rank[i] = 0;
        if (!use[i])
            continue;
        rank[i] = 1;
        for (int j = 0; j < n; j++)
            if (use[j] && v[j] < v[i])
                rank[i]++;
    }
}

/* The criterion a fit is ranked by under rank_by (NaN where undefined). */
static double criterion(const bf_compare *c, const bf_compare_fit *f, bf_compare_rank_by by)
{
    switch (by) {
    case BF_RANK_BIC: return f->metrics.bic;
    case BF_RANK_AIC: return f->metrics.aic;
    case BF_RANK_AICC: return f->metrics.aicc;
    case BF_RANK_CV: return f->cv_error;
    case BF_RANK_ERROR: return bf_compare_metric_value(&f->metrics, c->metric);
    }
    return NAN;
}

static void rank_material(bf_compare *c, bf_compare_material *m)
{
    const int n = c->nmodels;
    int *use = calloc((size_t)n * 4, sizeof *use);
    double *v = calloc((size_t)n * 4, sizeof *v);
    if (!use || !v) { /* nothing ranked rather than a crash; the outputs show nulls */
        free(use);
        free(v);
        return;
    }
    int *r = use + n, *on_k = use + 2 * n, *on_w = use + 3 * n;
    double *val = v, *err = v + n, *kk = v + 2 * n, *work = v + 3 * n;
    m->best = m->simplest = -1;
    for (int j = 0; j < n; j++) {
        bf_compare_fit *f = &m->fits[j];
        f->rank = f->rank_bic = f->rank_aic = f->rank_aicc = f->rank_cv = 0;
        f->pareto_k = f->pareto_work = f->within_tolerance = 0;
        f->error = NAN;
        /* A fit with a non-finite error or criterion cannot be placed: left unranked. */
        double e = c->rank_by == BF_RANK_CV ? f->cv_error : bf_compare_metric_value(&f->metrics, c->metric);
        use[j] = f->state == BF_CMP_OK && isfinite(e) && isfinite(criterion(c, f, c->rank_by));
        if (use[j])
            f->error = e;
        err[j] = f->error;
        kk[j] = use[j] ? f->metrics.k : NAN;
        work[j] = use[j] ? f->work : NAN;
        if (use[j] && (m->best < 0 || e < m->fits[m->best].error))
            m->best = j;
    }
    /* The chosen criterion's rank, and each criterion's over the fits where it is
     * defined (among the ranked ones). */
    static const bf_compare_rank_by all[] = {BF_RANK_BIC, BF_RANK_AIC, BF_RANK_AICC, BF_RANK_CV};
    int *avail = calloc((size_t)n, sizeof *avail);
    for (int a = -1; avail && a < 4; a++) {
        const bf_compare_rank_by by = a < 0 ? c->rank_by : all[a];
        for (int j = 0; j < n; j++) {
            val[j] = criterion(c, &m->fits[j], by);
            avail[j] = use[j] && isfinite(val[j]);
        }
        rank_values(n, val, avail, r);
        for (int j = 0; j < n; j++) {
            bf_compare_fit *f = &m->fits[j];
            int *dst = a < 0                ? &f->rank
                       : by == BF_RANK_BIC  ? &f->rank_bic
                       : by == BF_RANK_AIC  ? &f->rank_aic
                       : by == BF_RANK_AICC ? &f->rank_aicc
                                            : &f->rank_cv;
            *dst = r[j];
        }
    }
    free(avail);
    bf_compare_pareto(n, kk, err, on_k);
    bf_compare_pareto(n, work, err, on_w);
    for (int j = 0; j < n; j++) {
        m->fits[j].pareto_k = on_k[j];
        m->fits[j].pareto_work = on_w[j];
    }
    if (m->best >= 0) {
        double limit = m->fits[m->best].error * (1.0 + c->tolerance);
        for (int j = 0; j < n; j++) {
            bf_compare_fit *f = &m->fits[j];
            if (!use[j] || !(f->error <= limit))
                continue;
            f->within_tolerance = 1;
            if (m->simplest < 0) {
                m->simplest = j;
                continue;
            }
            const bf_compare_fit *s = &m->fits[m->simplest];
            if (f->metrics.k < s->metrics.k || (f->metrics.k == s->metrics.k && f->error < s->error))
                m->simplest = j;
        }
    }
    free(use);
    free(v);
}

void bf_compare_rank(bf_compare *c)
{
    for (int i = 0; i < c->nmaterials; i++)
        rank_material(c, &c->materials[i]);
    for (int j = 0; j < c->nmodels; j++) {
        bf_compare_summary *s = &c->summary[j];
        double rk = 0, rb = 0, ra = 0, e = 0;
        int nb = 0, na = 0;
        memset(s, 0, sizeof *s);
        for (int i = 0; i < c->nmaterials; i++) {
            const bf_compare_material *m = &c->materials[i];
            const bf_compare_fit *f = &m->fits[j];
            if (!f->rank)
                continue;
            s->ranked++;
            rk += f->rank;
            if (f->rank_bic)
                rb += f->rank_bic, nb++;
            if (f->rank_aic)
                ra += f->rank_aic, na++;
            e += f->error;
            s->chosen += m->simplest == j;
        }
        s->mean_rank = s->ranked ? rk / s->ranked : NAN;
        s->mean_rank_bic = nb ? rb / nb : NAN;
        s->mean_rank_aic = na ? ra / na : NAN;
        s->mean_error = s->ranked ? e / s->ranked : NAN;
    }
}
