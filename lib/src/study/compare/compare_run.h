/* bf_compare_run with the fit options as a struct, for the library's own callers
 * (bf_select_run): jobs fits at once, h's progress called as each ends, no new fit once
 * h's finish is set (and none, and running solves stopped, once fo's cancel is). */
#ifndef BRDFIT_COMPARE_RUN_H
#define BRDFIT_COMPARE_RUN_H

#include "brdfit/compare.h"
#include "fit_impl.h"

/* What a run calls and reads as it goes; every member may be NULL, and so may h. */
typedef struct compare_hooks {
    bf_compare_progress progress;
    void *user;                   /* progress's first argument */
    const bf_cancel_flag *finish; /* set: no new fit */
} compare_hooks;

bf_status compare_run_with(bf_compare *c, bf_samples *const *samples, const bf_fit_options *fo, int jobs,
                           const compare_hooks *h, bf_error *err);

/* c->reference once the fits have run (compare_reference.c): each fit that ran beside
 * every reference of its material and model, judged with fo as the fit judged itself;
 * the fits brdfit did worse than a reference warned (BF_WARN_REFERENCE_BETTER). */
bf_status compare_check_references(bf_compare *c, bf_samples *const *samples, const bf_fit_options *fo, bf_error *err);

#endif
