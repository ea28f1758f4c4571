/* A fit's metrics as JSON (metrics_json.h). */
#include "metrics_json.h"

#include "io/json_out.h"

cJSON *bf_json_metrics(const bf_metrics *m)
{
    cJSON *o = cJSON_CreateObject();
    bf_json_add_number(o, "rmse", m->rmse);
    bf_json_add_number(o, "rmse_cos", m->rmse_cos);
    bf_json_add_number(o, "rmse_log", m->rmse_log);
    bf_json_add_number(o, "rmse_rel", m->rmse_rel);
    bf_json_add_number(o, "max_err", m->max_err);
    cJSON_AddNumberToObject(o, "n", (double)m->n);
    cJSON_AddNumberToObject(o, "k", m->k);
    cJSON_AddBoolToObject(o, "weighted", m->weighted);
    /* The criteria of the fit's own likelihood (metrics.h); null where undefined. */
    bf_json_add_number(o, "loglik", m->loglik);
    bf_json_add_number(o, "aic", m->aic);
    bf_json_add_number(o, "aicc", m->aicc);
    bf_json_add_number(o, "bic", m->bic);
    cJSON_AddNumberToObject(o, "criteria_n", (double)m->crit_n);
    return o;
}
