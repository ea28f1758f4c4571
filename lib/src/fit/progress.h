/* Internal: a fit's progress reports (brdfit/options.h, bf_progress_report). The fit
 * driver and the search say which phase they are in before its solves; each solve's
 * iterations then reach the caller's report callback through a relay installed in that
 * solve's own solver options, so the solvers know nothing of phases. */
#ifndef BF_FIT_PROGRESS_H
#define BF_FIT_PROGRESS_H

#include "brdfit/solve.h"
#include "fit_impl.h"

typedef struct bf_fit_watch {
    const bf_fit_options *o;
    bf_progress_report r; /* where the fit is */
    int next;             /* the phase's next solve */
} bf_fit_watch;

/* w for a fit of spec with options o (material, model, fold from o). */
void bf_fit_watch_init(bf_fit_watch *w, const bf_fit_options *o, const char *spec);
/* A new phase: its solves (or candidates) number from 0, at most starts of them, on a set
 * of samples samples. */
void bf_fit_watch_phase(bf_fit_watch *w, bf_fit_phase phase, int starts, size_t samples);
/* so (a copy of the fit's solver options) set up for the phase's next solve: its
 * progress relayed to the report callback, the fit's own progress callback kept. Nothing
 * changes when there is no report callback (w NULL included). */
void bf_fit_watch_solve(bf_fit_watch *w, bf_solver_options *so);
/* Reports candidate j of the phase and its cost; non-zero: the caller asks to stop. */
int bf_fit_watch_candidate(bf_fit_watch *w, int j, double cost);
/* Reports the end of the fit: its solution (sol) on samples samples. */
void bf_fit_watch_done(bf_fit_watch *w, const bf_solution *sol, size_t samples);

#endif
