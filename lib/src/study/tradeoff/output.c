/* The tradeoff table as JSON and CSV (the plot is report/tradeoff/tradeoff_plot.c).
 * JSON keys are stable: every key is written for every row, null where it does not
 * apply (a row that did not run, NaN metrics); wall times only with t->timing, so that
 * by default two runs write the same bytes. */
#include "brdfit/tradeoff.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/io.h"
#include "brdfit/tool.h"
#include "io/json_out.h"
#include "metrics_json.h"

static const char *row_status(const bf_tradeoff_row *r)
{
    return r->ran ? (r->ok ? "ok" : "failed") : (r->message[0] ? "error" : "not_run");
}

/* A metrics object as in a result file (null for a row that did not run). */
static cJSON *metrics_json(const bf_metrics *m, int ran)
{
    return ran ? bf_json_metrics(m) : cJSON_CreateNull();
}

static cJSON *tradeoff_json(const bf_tradeoff *t)
{
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "version", 2);
    bf_json_add_version(root);
    cJSON_AddStringToObject(root, "data", t->data);
    cJSON_AddStringToObject(root, "model", t->model);
    cJSON_AddNumberToObject(root, "samples", (double)t->total);
    cJSON_AddNumberToObject(root, "train_samples", (double)t->train_n);
    cJSON_AddNumberToObject(root, "test_samples", (double)t->test_n);
    cJSON_AddNumberToObject(root, "channels", t->channels);
    cJSON_AddNumberToObject(root, "test_fraction", t->test_fraction);
    cJSON_AddNumberToObject(root, "seed", (double)t->seed);
    cJSON_AddNumberToObject(root, "repeats", t->repeats);
    cJSON_AddStringToObject(root, "error", bf_compare_metric_name(t->metric));
    cJSON_AddNumberToObject(root, "tolerance", t->tolerance);
    cJSON_AddStringToObject(root, "cost", bf_tradeoff_cost_name(t->cost));
    cJSON_AddStringToObject(root, "work", "sample evaluations: passes over the samples times their number");
    cJSON_AddBoolToObject(root, "timing", t->timing);
    cJSON_AddItemToObject(root, "best", t->best >= 0 ? cJSON_CreateNumber(t->best) : cJSON_CreateNull());
    cJSON_AddItemToObject(root, "recommended",
                          t->recommended >= 0 ? cJSON_CreateNumber(t->recommended) : cJSON_CreateNull());
    cJSON *rows = cJSON_AddArrayToObject(root, "rows");
    for (int i = 0; i < t->nrows; i++) {
        const bf_tradeoff_row *r = &t->rows[i];
        cJSON *o = cJSON_CreateObject();
        cJSON_AddNumberToObject(o, "index", i);
        cJSON_AddNumberToObject(o, "samples", (double)r->samples);
        cJSON_AddBoolToObject(o, "all", r->all);
        cJSON_AddStringToObject(o, "method", r->method ? r->method : "");
        cJSON_AddStringToObject(o, "residual", bf_residual_name(r->residual));
        cJSON_AddNumberToObject(o, "starts", r->starts);
        cJSON_AddStringToObject(o, "status", row_status(r));
        cJSON_AddBoolToObject(o, "ok", r->ran && r->ok);
        cJSON_AddItemToObject(o, "message", r->message[0] ? cJSON_CreateString(r->message) : cJSON_CreateNull());
        if (t->timing)
            bf_json_add_number(o, "seconds", r->ran ? r->seconds : NAN);
        bf_json_add_number(o, "work", r->ran ? r->work : NAN);
        bf_json_add_number(o, "iterations", r->ran ? r->iterations : NAN);
        bf_json_add_number(o, "error", r->error);
        cJSON_AddItemToObject(o, "train", metrics_json(&r->train, r->ran));
        cJSON_AddItemToObject(o, "test", metrics_json(&r->test, r->ran));
        cJSON_AddBoolToObject(o, "on_front", r->on_front);
        cJSON_AddBoolToObject(o, "within_tolerance", r->within_tolerance);
        cJSON_AddBoolToObject(o, "best", i == t->best);
        cJSON_AddBoolToObject(o, "recommended", i == t->recommended);
        cJSON *w = cJSON_AddArrayToObject(o, "warnings");
        for (int k = 0; k < r->nwarnings; k++)
            cJSON_AddItemToArray(w, cJSON_CreateString(r->warnings[k]));
        cJSON_AddItemToArray(rows, o);
    }
    return root;
}

bf_status bf_tradeoff_write_json(const bf_tradeoff *t, const char *path, bf_error *err)
{
    return bf_json_write(tradeoff_json(t), path, "the tradeoff table", err);
}

bf_status bf_tradeoff_json(const bf_tradeoff *t, char **out, bf_error *err)
{
    *out = NULL;
    return bf_json_text(tradeoff_json(t), "the tradeoff table", out, err);
}

static void put_metrics(FILE *fp, const bf_metrics *m, int ran)
{
    bf_csv_put_number(fp, ran ? m->rmse : NAN);
    bf_csv_put_number(fp, ran ? m->rmse_log : NAN);
    bf_csv_put_number(fp, ran ? m->rmse_cos : NAN);
    bf_csv_put_number(fp, ran ? m->rmse_rel : NAN);
    bf_csv_put_number(fp, ran ? m->max_err : NAN);
}

bf_status bf_tradeoff_write_csv(const bf_tradeoff *t, const char *path, bf_error *err)
{
    bf_outfile f;
    bf_status rc = bf_outfile_open(&f, path, err);
    if (rc != BF_OK)
        return rc;
    FILE *fp = f.fp;
    fprintf(fp,
            "samples,all,method,residual,starts,status,work,iterations,error,"
            "train_rmse,train_rmse_log,train_rmse_cos,train_rmse_rel,train_max_err,"
            "test_rmse,test_rmse_log,test_rmse_cos,test_rmse_rel,test_max_err,"
            "on_front,within_tolerance,best,recommended,warnings%s\n",
            t->timing ? ",seconds" : "");
    for (int i = 0; i < t->nrows; i++) {
        const bf_tradeoff_row *r = &t->rows[i];
        fprintf(fp, "%zu,%d,", r->samples, r->all);
        bf_csv_put_text(fp, r->method ? r->method : "");
        fprintf(fp, ",%s,%d,%s", bf_residual_name(r->residual), r->starts, row_status(r));
        bf_csv_put_number(fp, r->ran ? r->work : NAN);
        bf_csv_put_number(fp, r->ran ? (double)r->iterations : NAN);
        bf_csv_put_number(fp, r->error);
        put_metrics(fp, &r->train, r->ran);
        put_metrics(fp, &r->test, r->ran);
        fprintf(fp, ",%d,%d,%d,%d", r->on_front, r->within_tolerance, i == t->best, i == t->recommended);
        if (r->warnings)
            bf_csv_put_list(fp, r->warnings[0], sizeof r->warnings[0], r->nwarnings);
        else
            fputc(',', fp);
        if (t->timing)
            bf_csv_put_number(fp, r->ran ? r->seconds : NAN);
        fputc('\n', fp);
    }
    return bf_outfile_commit(&f, err); /* checks every write */
}
