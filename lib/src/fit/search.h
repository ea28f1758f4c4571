/* Internal: the search for a fit's optimum, from the data-driven start and others
 * (search.c; docs/fitting.md says how and what it costs). The fit driver (fit.c) gives
 * it the problem its starts are solved on (the data's, or the presolve's subsample's) and
 * takes the best point to the whole data. */
#ifndef BF_FIT_SEARCH_H
#define BF_FIT_SEARCH_H

#include "brdfit/fit.h"
#include "fit_impl.h"
#include "objective_state.h"

typedef struct bf_search {
    /* In. */
    bf_samples *samples; /* the samples of prob: the data, or the presolve's
                                       subsample (the screening set is drawn from them) */
    const bf_fit_options *options;
    const bf_objective_options *objective_options;
    const bf_objective *objective; /* the objective of prob (its kidx, model) */
    const bf_problem *prob;        /* where the chosen starts are solved */
    int presolved;                 /* 1: prob is the presolve's subsample of the data */
    const double *z0;              /* the data-driven (or the caller's) start, internal */
    struct bf_fit_watch *watch;    /* the fit's progress reports (progress.h; NULL: none) */
    /* Out. */
    double *z;          /* the best point on prob (nz, allocated by the caller) */
    bf_solution best;   /* its solution on prob */
    bf_solution first;  /* the first start's, for the reason of a failed fit */
    uint64_t best_seed; /* the solver seed that gave it */
    int have_best;
    int cancelled; /* 1: a solve was cancelled (bf_solver_options.cancel or
                                       .progress); the search stopped there */
    int starts, starts_at_best, candidates;
    bf_presolve_info on_prob; /* the solves on prob, summed */
    bf_presolve_info screen;  /* the solves on the screening subsample (samples 0: none) */
    /* The screening subsample's objective and samples when one was drawn (else NULL):
     * owned, freed by bf_fit_search_clear. */
    bf_objective *screen_objective;
    bf_samples *screen_samples;
} bf_search;

/* Runs the search (s->z, best, ...): the data-driven start alone when options->starts is 1;
 * with options->screen 0, the data-driven start and starts-1 random ones, each solved on
 * prob; otherwise the screened search of docs/fitting.md. Errors: bad options, a back end
 * that cannot run, out of memory. */
bf_status bf_fit_search(bf_search *s, bf_error *err);
/* Hands the best point z (on prob) over to the whole data: entries within 1e-4 of their
 * range of a bound go onto it when the data cannot tell (the cost rises by less than one
 * unit of chi-square: a lobe whose weight crept to 1e-7 is off), and the entries that have no effect there are flagged in hold
 * (nz), to be held constant in the solve on all samples: a dead lobe's width and Fresnel
 * would only send Levenberg-Marquardt along a valley it cannot leave (a MERL table's
 * second Walter lobe: 16 passes over 3.3 M residuals). Returns how many are held. */
int bf_fit_search_handover(const bf_search *s, double *z, unsigned char *hold);

/* Frees what the search kept (the screening objective), also after an error. */
void bf_fit_search_clear(bf_search *s);

/* A subsample of the data and its objective: the presolve's, the screening set's. The
 * caller frees both, also after an error (either may be NULL). */
typedef struct bf_subsample {
    bf_samples *samples;
    bf_objective *objective;
} bf_subsample;

/* A seeded stratified subsample of n of s's samples and its objective for model m and
 * options oo, into *out (zeroed by the caller). */
bf_status bf_fit_subsample_objective(bf_samples *s, size_t n, uint64_t seed, const bf_model *m,
                                     const bf_objective_options *oo, bf_subsample *out, bf_error *err);

/* The starts the screened search solves for options o on a screening set of n samples
 * (o->starts, or when it is 0 (automatic) BF_FIT_STARTS to BF_FIT_STARTS_MAX: more for a
 * small screening set). */
int bf_fit_search_starts(const bf_fit_options *o, size_t n);

#endif
