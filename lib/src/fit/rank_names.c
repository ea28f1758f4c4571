/* The names of the error metrics and rankings (brdfit/compare.h): below the comparison,
 * since the run options (run_options.c) take them. */
#include "brdfit/compare.h"

#include <math.h>
#include <string.h>

static const char *const metric_names[] = {"rmse", "rmse_log", "rmse_cos", "rmse_rel"};

bf_status bf_compare_metric_parse(const char *text, bf_compare_metric *out, bf_error *err)
{
    for (int i = 0; i < (int)(sizeof metric_names / sizeof metric_names[0]); i++)
        if (text && !strcmp(text, metric_names[i])) {
            *out = (bf_compare_metric)i;
            return BF_OK;
        }
    return bf_fail(err, BF_ERR_ARG, "unknown error metric '%s' (rmse, rmse_log, rmse_cos, rmse_rel)", text ? text : "");
}

const char *bf_compare_metric_name(bf_compare_metric m)
{
    return (unsigned)m < sizeof metric_names / sizeof metric_names[0] ? metric_names[m] : "?";
}

double bf_compare_metric_value(const bf_metrics *m, bf_compare_metric which)
{
    switch (which) {
    case BF_CMP_RMSE: return m->rmse;
    case BF_CMP_RMSE_LOG: return m->rmse_log;
    case BF_CMP_RMSE_COS: return m->rmse_cos;
    case BF_CMP_RMSE_REL: return m->rmse_rel;
    }
    return NAN;
}

static const char *const rank_names[] = {"bic", "aic", "aicc", "cv", "error"};

bf_status bf_compare_rank_parse(const char *text, bf_compare_rank_by *out, bf_error *err)
{
    for (int i = 0; i < (int)(sizeof rank_names / sizeof rank_names[0]); i++)
        if (text && !strcmp(text, rank_names[i])) {
            *out = (bf_compare_rank_by)i;
            return BF_OK;
        }
    return bf_fail(err, BF_ERR_ARG, "unknown ranking '%s' (bic, aic, aicc, cv, error)", text ? text : "");
}

const char *bf_compare_rank_name(bf_compare_rank_by r)
{
    return (unsigned)r < sizeof rank_names / sizeof rank_names[0] ? rank_names[r] : "?";
}
