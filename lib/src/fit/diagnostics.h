/* Internal: the warnings of a fit (diagnostics.c), for the fit driver. */
#ifndef BF_FIT_DIAGNOSTICS_H
#define BF_FIT_DIAGNOSTICS_H

#include "brdfit/fit.h"
#include "fit_impl.h"
#include "objective_state.h"

/* Adds one warning of the given kind (printf style; cut at the slot's size; past
 * BF_FIT_MAX_WARNINGS the last slot says that more were left out, kind
 * BF_WARN_TRUNCATED). */
void bf_fit_warn(bf_fit_result *r, bf_warning_kind kind, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* Every check of diagnostics.c on a finished fit: o its objective, s its samples, corr
 * the free entries' correlations (bf_obj_final; NULL: none). */
void bf_fit_diagnose(const bf_objective *o, bf_samples *s, const bf_fit_options *opt, const double *corr,
                     bf_fit_result *r);
/* The same without the search's warnings (failed, solver limit, one start): what the
 * fit's point and figures say, for a fit run channel by channel (fit_channels.h) whose
 * channels say those themselves. */
void bf_fit_diagnose_model(const bf_objective *o, bf_samples *s, const bf_fit_options *opt, const double *corr,
                           bf_fit_result *r);

#endif
