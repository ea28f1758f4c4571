/* bf_select_run with the fit options as a struct, for the library's own callers. */
#ifndef BRDFIT_SELECT_RUN_H
#define BRDFIT_SELECT_RUN_H

#include "brdfit/select.h"
#include "fit_impl.h"

bf_status select_run_with(bf_select *s, bf_samples *data, const bf_fit_options *o, int jobs,
                          bf_select_progress progress, void *user, const bf_cancel_flag *finish, bf_error *err);

#endif
