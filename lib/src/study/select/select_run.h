/* bf_select_run with the fit options as a struct, for the library's own callers. */
#ifndef BRDFIT_SELECT_RUN_H
#define BRDFIT_SELECT_RUN_H

#include "brdfit/select.h"
#include "fit_impl.h"

/* What a run calls and reads as it goes; every member may be NULL, and so may h. */
typedef struct select_hooks {
    bf_select_progress progress;
    void *user;                   /* progress's first argument */
    const bf_cancel_flag *finish; /* set: no new fit */
} select_hooks;

/* jobs candidates fitted at once (bf_compare_run's rules). */
bf_status select_run_with(bf_select *s, bf_samples *data, const bf_fit_options *o, int jobs, const select_hooks *h,
                          bf_error *err);

#endif
