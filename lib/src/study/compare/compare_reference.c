/* Published fits beside a comparison's own (compare.h, bf_compare.reference).
 *
 * Decisions:
 *  - A reference matches a fit when its material is the fit's data file's stem
 *    (bf_reference_material) and its canonical model spec is the fit's.
 *  - Both are judged by one function at their parameters (bf_fit_evaluate_with): the
 *    objective the fit minimised, so "brdfit is worse" means its search stopped above a
 *    point the published fit shows it could have reached (an optimizer miss, not a
 *    difference of metric), and the metrics the fit reports. brdfit's own objective is
 *    recomputed rather than taken from its solver, so that a reference that is brdfit's
 *    own result gives the same bits and no warning.
 *  - brdfit is worse when its objective exceeds the reference's by more than
 *    BF_COMPARE_REFERENCE_RTOL, relative; only a fit that succeeded is warned.
 *  - A reference that cannot be evaluated on the data (another channel count) is listed
 *    with the reason; a failure of memory fails the run.
 *  - The references are judged after the fits, one after another, each pass on the
 *    solver's threads: they cost a pass over the samples each, against a fit's hundreds. */
#include "brdfit/compare.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "compare/compare_impl.h"
#include "compare/compare_run.h"
#include "diagnostics.h"
#include "run_options.h"

bf_status compare_read_references(bf_compare *c, const bf_options *o, bf_error *err)
{
    bf_reference_set_free(c->references);
    c->references = NULL;
    const char *path = option_list_value(o, "reference", 0);
    if (!path)
        return BF_OK;
    bf_reference_set *s = NULL;
    bf_status rc = bf_reference_set_new(&s, err);
    for (int k = 0; rc == BF_OK && (path = option_list_value(o, "reference", k)) != NULL; k++)
        rc = bf_reference_read(s, path, err);
    if (rc != BF_OK) {
        bf_reference_set_free(s);
        return rc;
    }
    c->references = s;
    return BF_OK;
}

/* The fit of slot (i, j) when it ran, else NULL. */
static const bf_fit_result *ran(const bf_compare *c, int i, int j)
{
    const bf_compare_fit *f = &c->materials[i].fits[j];
    return (f->state == BF_CMP_OK || f->state == BF_CMP_FAILED) && f->result && f->result->model ? f->result : NULL;
}

/* The references of slot (i, j): into out (NULL: counted only); how many. */
static int matches(const bf_compare *c, int i, int j, bf_compare_reference *out)
{
    const bf_fit_result *r = ran(c, i, j);
    if (!r)
        return 0;
    char material[256];
    bf_reference_material(c->materials[i].data, material, sizeof material);
    int n = 0;
    for (int k = 0; k < c->references->n; k++) {
        const bf_reference *ref = &c->references->refs[k];
        if (!bf_reference_matches(ref, material, bf_model_spec(r->model)))
            continue;
        if (out)
            out[n] =
                (bf_compare_reference){.material = i, .model = j, .reference = ref, .cost = NAN, .brdfit_cost = NAN};
        n++;
    }
    return n;
}

/* Slot (i, j)'s references appended to c->reference, judged beside brdfit's fit on
 * samples s (room for them was made). */
static bf_status judge(bf_compare *c, int i, int j, bf_samples *s, const bf_fit_options *fo, bf_error *err)
{
    bf_compare_reference *q = c->reference + c->nreference;
    const int n = matches(c, i, j, q);
    c->nreference += n;
    if (n == 0)
        return BF_OK;
    bf_fit_result *r = c->results[(size_t)i * (size_t)c->nmodels + (size_t)j];
    double own = NAN;
    bf_metrics own_metrics;
    bf_status rc = bf_fit_evaluate_with(s, r->model, r->x, fo, &own, &own_metrics, err);
    if (rc != BF_OK)
        return rc;
    char material[256];
    bf_reference_material(c->materials[i].data, material, sizeof material);
    for (int k = 0; k < n; k++) {
        bf_error e;
        const bf_reference *ref = q[k].reference;
        q[k].brdfit_cost = own;
        rc = bf_fit_evaluate_with(s, ref->model, ref->x, fo, &q[k].cost, &q[k].metrics, &e);
        if (rc == BF_ERR_NOMEM)
            return bf_fail(err, rc, "%s", e.msg);
        if (rc != BF_OK) {
            q[k].cost = NAN;
            snprintf(q[k].message, sizeof q[k].message, "%s", e.msg);
            continue;
        }
        q[k].brdfit_worse = c->materials[i].fits[j].state == BF_CMP_OK && isfinite(q[k].cost) &&
                            own > q[k].cost * (1.0 + BF_COMPARE_REFERENCE_RTOL);
        if (q[k].brdfit_worse)
            bf_fit_warn(r, BF_WARN_REFERENCE_BETTER,
                        "%s, %s: brdfit's objective %.6g is above %.6g, the reference's (%s%s%s): the search missed "
                        "a better optimum",
                        material, c->models[j], own, q[k].cost, ref->source, ref->table ? ", " : "",
                        ref->table ? ref->table : "");
    }
    return BF_OK;
}

bf_status compare_check_references(bf_compare *c, bf_samples *const *samples, const bf_fit_options *fo, bf_error *err)
{
    free(c->reference);
    c->reference = NULL;
    c->nreference = 0;
    if (!c->references || c->references->n == 0)
        return BF_OK;
    int n = 0;
    for (int i = 0; i < c->nmaterials; i++)
        for (int j = 0; j < c->nmodels; j++)
            n += matches(c, i, j, NULL);
    if (n == 0)
        return BF_OK;
    if (!(c->reference = calloc((size_t)n, sizeof *c->reference)))
        return bf_fail(err, BF_ERR_NOMEM, "compare: out of memory for %d references", n);
    for (int i = 0; i < c->nmaterials; i++)
        for (int j = 0; j < c->nmodels; j++) {
            bf_status rc = judge(c, i, j, samples[i], fo, err);
            if (rc != BF_OK)
                return rc;
        }
    return BF_OK;
}
