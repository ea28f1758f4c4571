/* bf_compare_run with the fit options as a struct, for the library's own callers
 * (bf_select_run): jobs fits at once, progress called as each ends, no new fit once
 * finish is set (and none, and running solves stopped, once fo's cancel is). */
#ifndef BRDFIT_COMPARE_RUN_H
#define BRDFIT_COMPARE_RUN_H

#include "brdfit/compare.h"
#include "fit_impl.h"

bf_status compare_run_with(bf_compare *c, bf_samples *const *samples, const bf_fit_options *fo, int jobs,
                           bf_compare_progress progress, void *user, const bf_cancel_flag *finish, bf_error *err);

#endif
