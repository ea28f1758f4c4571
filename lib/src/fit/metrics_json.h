/* Internal: a fit's metrics as the JSON object every result document writes (the fit
 * result, select's candidates, tradeoff's rows). */
#ifndef BF_METRICS_JSON_H
#define BF_METRICS_JSON_H

#include <cjson/cJSON.h>

#include "brdfit/metrics.h"

/* {rmse, rmse_cos, rmse_log, rmse_rel, max_err, n, k, weighted, loglik, aic, aicc, bic,
 * criteria_n}; numbers that are not finite are null. */
cJSON *bf_json_metrics(const bf_metrics *m);

#endif
