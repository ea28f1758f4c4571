/* The comparison as CSV: one row per material x model, in input order. Empty fields
 * where a value does not apply (unranked, not run); model specs hold commas, so text
 * fields are quoted whenever they need it (RFC 4180). After the fixed columns, one
 * column per fitted parameter and channel: the union of every fit's entry names, in
 * the order they first appear (model order, then each model's parameter order). */
#include "brdfit/compare.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/io.h"
#include "brdfit/tool.h"

#define NAME_LEN 64

static void put_int(FILE *fp, int v, int present)
{
    fputc(',', fp);
    if (present)
        fprintf(fp, "%d", v);
}

/* The fit's result when it ran (parameters, warnings), else NULL. */
static const bf_fit_result *ran_result(const bf_compare_fit *f)
{
    return (f->state == BF_CMP_OK || f->state == BF_CMP_FAILED) ? f->result : NULL;
}

/* The union of the entry names of every fit, in order of first appearance. */
static char (*param_columns(const bf_compare *c, int *count))[NAME_LEN]
{
    int cap = 64, n = 0;
    char(*names)[NAME_LEN] = malloc((size_t)cap * NAME_LEN);
    for (int j = 0; names && j < c->nmodels; j++)
        for (int i = 0; names && i < c->nmaterials; i++) {
            const bf_fit_result *r = ran_result(&c->materials[i].fits[j]);
            for (int k = 0; r && names && k < bf_model_nvalues(r->model); k++) {
                char name[NAME_LEN];
                bf_model_entry_name(r->model, k, name, sizeof name);
                int seen = 0;
                for (int q = 0; q < n && !seen; q++)
                    seen = !strcmp(names[q], name);
                if (seen)
                    continue;
                if (n == cap) {
                    char(*more)[NAME_LEN] = realloc(names, (size_t)(cap *= 2) * NAME_LEN);
                    if (!more) {
                        free(names);
                        names = NULL;
                        break;
                    }
                    names = more;
                }
                memcpy(names[n++], name, NAME_LEN);
            }
        }
    *count = n;
    return names;
}

/* The fit's value of the entry called name, NaN if it has none. */
static double param_value(const bf_fit_result *r, const char *name)
{
    char e[NAME_LEN];
    for (int k = 0; r && k < bf_model_nvalues(r->model); k++)
        if (!strcmp(bf_model_entry_name(r->model, k, e, sizeof e), name))
            return r->x[k];
    return NAN;
}

/* Slot (i, j)'s references, each column a field of "; "-joined values in the references'
 * order: who published them ("source (table)"), their objective and rmse_log (empty
 * where not evaluated), 1 where outside the bounds, 1 where brdfit did worse. */
static void put_references(FILE *fp, const bf_compare *c, int i, int j)
{
    enum { COLS = 5, ITEM = 160 };
    int n = 0;
    for (int k = 0; k < c->nreference; k++)
        n += c->reference[k].material == i && c->reference[k].model == j;
    char *items = n ? calloc((size_t)n * COLS, ITEM) : NULL;
    if (!items) {
        fputs(",,,,,", fp);
        return;
    }
    int q = 0;
    for (int k = 0; k < c->nreference; k++) {
        const bf_compare_reference *x = &c->reference[k];
        if (x->material != i || x->model != j)
            continue;
        char *row[COLS];
        for (int col = 0; col < COLS; col++)
            row[col] = items + ((size_t)col * (size_t)n + (size_t)q) * ITEM;
        snprintf(row[0], ITEM, "%s%s%s%s", x->reference->source, x->reference->table ? " (" : "",
                 x->reference->table ? x->reference->table : "", x->reference->table ? ")" : "");
        if (isfinite(x->cost))
            bf_format_double(x->cost, row[1], ITEM);
        if (!x->message[0] && isfinite(x->metrics.rmse_log))
            bf_format_double(x->metrics.rmse_log, row[2], ITEM);
        snprintf(row[3], ITEM, "%d", x->reference->outside[0] != '\0');
        snprintf(row[4], ITEM, "%d", x->brdfit_worse);
        q++;
    }
    for (int col = 0; col < COLS; col++)
        bf_csv_put_list(fp, items + (size_t)col * (size_t)n * ITEM, ITEM, n);
    free(items);
}

bf_status bf_compare_write_csv(const bf_compare *c, const char *path, bf_error *err)
{
    const char *name = path ? path : "-";
    int ncols = 0;
    char(*cols)[NAME_LEN] = param_columns(c, &ncols);
    if (!cols)
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory for the parameter columns", name);
    bf_outfile f;
    bf_status rc = bf_outfile_open(&f, path, err);
    if (rc != BF_OK) {
        free(cols);
        return rc;
    }
    FILE *fp = f.fp;
    fprintf(fp,
            "material,model,status,k,n,error,rmse,rmse_log,rmse_cos,rmse_rel,max_err,loglik,aic,aicc,bic,cv,"
            "work,rank,rank_bic,rank_aic,rank_aicc,rank_cv,pareto_k,pareto_work,within_tolerance,simplest,"
            "warnings%s",
            c->timing ? ",seconds" : "");
    if (c->references) /* only then: the table is otherwise as it was */
        fputs(",references,reference_cost,reference_rmse_log,reference_outside_bounds,brdfit_worse", fp);
    for (int q = 0; q < ncols; q++) {
        fputc(',', fp);
        bf_csv_put_text(fp, cols[q]);
    }
    fputc('\n', fp);
    for (int i = 0; i < c->nmaterials; i++) {
        const bf_compare_material *m = &c->materials[i];
        for (int j = 0; j < c->nmodels; j++) {
            const bf_compare_fit *x = &m->fits[j];
            const bf_metrics *q = &x->metrics;
            const bf_fit_result *r = ran_result(x);
            const int ran = x->state == BF_CMP_OK || x->state == BF_CMP_FAILED;
            bf_csv_put_text(fp, m->data);
            fputc(',', fp);
            bf_csv_put_text(fp, c->models[j]);
            fprintf(fp, ",%s", bf_compare_state_name(x->state));
            put_int(fp, q->k, ran);
            bf_csv_put_number(fp, ran ? (double)q->n : NAN);
            bf_csv_put_number(fp, x->error);
            const double v[] = {q->rmse, q->rmse_log, q->rmse_cos, q->rmse_rel, q->max_err, q->loglik,
                                q->aic,  q->aicc,     q->bic,      x->cv_error, x->work};
            for (size_t k = 0; k < sizeof v / sizeof v[0]; k++)
                bf_csv_put_number(fp, ran ? v[k] : NAN);
            put_int(fp, x->rank, x->rank > 0);
            put_int(fp, x->rank_bic, x->rank_bic > 0);
            put_int(fp, x->rank_aic, x->rank_aic > 0);
            put_int(fp, x->rank_aicc, x->rank_aicc > 0);
            put_int(fp, x->rank_cv, x->rank_cv > 0);
            put_int(fp, x->pareto_k, 1);
            put_int(fp, x->pareto_work, 1);
            put_int(fp, x->within_tolerance, 1);
            put_int(fp, m->simplest == j, 1);
            if (r)
                bf_csv_put_list(fp, r->warnings[0], sizeof r->warnings[0], r->nwarnings);
            else
                fputc(',', fp);
            if (c->timing)
                bf_csv_put_number(fp, ran ? x->seconds : NAN);
            if (c->references)
                put_references(fp, c, i, j);
            for (int k = 0; k < ncols; k++)
                bf_csv_put_number(fp, param_value(r, cols[k]));
            fputc('\n', fp);
        }
    }
    free(cols);
    return bf_outfile_commit(&f, err); /* checks every write */
}
