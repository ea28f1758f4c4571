/* Internal: the warnings of a fit (diagnostics.c), for the fit driver. */
#ifndef BF_FIT_DIAGNOSTICS_H
#define BF_FIT_DIAGNOSTICS_H

#include "brdfit/fit.h"
#include "fit_impl.h"
#include "objective_impl.h"

/* Adds one warning (printf style; cut at the slot's size; past BF_FIT_MAX_WARNINGS the
 * last slot says that more were left out). */
void bf_fit_warn(bf_fit_result *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Every check of diagnostics.c on a finished fit: o its objective, s its samples, corr
 * the free entries' correlations (bf_obj_final; NULL: none). */
void bf_fit_diagnose(const bf_objective *o, bf_samples *s, const bf_fit_options *opt, const double *corr,
                     bf_fit_result *r);

#endif
