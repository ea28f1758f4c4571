/* The comparison as CSV: one row per material x model, in input order. Empty fields
 * where a value does not apply (unranked, not run); model specs hold commas, so text
 * fields are quoted whenever they need it (RFC 4180). */
#include "brdfit/compare.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "brdfit/io.h"

static void put_int(FILE *fp, int v, int present)
{
    fputc(',', fp);
    if (present)
        fprintf(fp, "%d", v);
}

int bf_compare_write_csv(const bf_compare *c, const char *path, bf_error *err)
{
    const char *name = path ? path : "-";
    bf_outfile f;
    int rc = bf_outfile_open(&f, path, err);
    if (rc != BF_OK)
        return rc;
    FILE *fp = f.fp;
    fprintf(fp, "material,model,status,k,n,error,rmse,rmse_log,rmse_cos,rmse_rel,max_err,aic,bic,seconds,"
                "rank_bic,rank_aic,pareto_k,pareto_time,within_tolerance,simplest\n");
    for (int i = 0; i < c->nmaterials; i++) {
        const bf_compare_material *m = &c->materials[i];
        for (int j = 0; j < c->nmodels; j++) {
            const bf_compare_fit *x = &m->fits[j];
            const bf_metrics *q = &x->metrics;
            int ran = x->state == BF_CMP_OK || x->state == BF_CMP_FAILED, ranked = x->rank_bic > 0;
            bf_csv_put_text(fp, m->data);
            fputc(',', fp);
            bf_csv_put_text(fp, c->models[j]);
            fprintf(fp, ",%s", bf_compare_state_name(x->state));
            put_int(fp, q->k, ran);
            bf_csv_put_number(fp, ran ? (double)q->n : NAN);
            bf_csv_put_number(fp, x->error);
            bf_csv_put_number(fp, ran ? q->rmse : NAN);
            bf_csv_put_number(fp, ran ? q->rmse_log : NAN);
            bf_csv_put_number(fp, ran ? q->rmse_cos : NAN);
            bf_csv_put_number(fp, ran ? q->rmse_rel : NAN);
            bf_csv_put_number(fp, ran ? q->max_err : NAN);
            bf_csv_put_number(fp, ran ? q->aic : NAN);
            bf_csv_put_number(fp, ran ? q->bic : NAN);
            bf_csv_put_number(fp, ran ? x->seconds : NAN);
            put_int(fp, x->rank_bic, ranked);
            put_int(fp, x->rank_aic, ranked);
            put_int(fp, x->pareto_k, 1);
            put_int(fp, x->pareto_time, 1);
            put_int(fp, x->within_tolerance, 1);
            put_int(fp, m->simplest == j, 1);
            fputc('\n', fp);
        }
    }
    if (ferror(fp)) {
        bf_outfile_abort(&f);
        return bf_fail(err, BF_ERR_IO, "%s: write failed", name);
    }
    return bf_outfile_commit(&f, err);
}
