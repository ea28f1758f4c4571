/* The fit inside the library: the options struct every fitting path takes (built from a
 * bf_options set by run_options.c, or by the library's own callers), the accuracy
 * presets, and the fit and cross-validation entry points that take it. */
#ifndef BRDFIT_FIT_IMPL_H
#define BRDFIT_FIT_IMPL_H

#include <stddef.h>
#include <stdint.h>

#include "brdfit/fit.h"

typedef struct bf_fit_options {
    bf_objective_options objective;
    bf_solver_options solver;
    /* The search for the optimum (docs/fitting.md). starts: the starts solved to
     * convergence, the data-driven one first (1: it alone; 0: automatic, BF_FIT_STARTS to
     * BF_FIT_STARTS_MAX by the size of the screening set). screen: with more than one
     * start, the random candidates whose cost on a small subsample (the screening set)
     * chooses the other starts, which are solved there and the best then on the data; 0:
     * the other starts are drawn at random and each solved on the data (plain multistart). */
    int starts;
    int screen;
    uint64_t seed;        /* multistart (and the solver's stochastic methods) */
    const double *start;  /* NULL: data-driven; else a model vector to start from */
    int weighted_metrics; /* 1: the result's metrics use the samples' weights (a scene's
                             directions, scene.h); 0: every sample counts alike */
    /* Presolve: every start is first solved on a seeded stratified subsample of this
     * many samples, and the best of them then on all samples (the result is a solution
     * of the whole set; the presolve only saves passes over it; that last solve stops at
     * a relative cost change of 1e-9 unless solver.function_tolerance says otherwise).
     * 0: automatic (BF_FIT_PRESOLVE_SAMPLES when the data has at least
     * BF_FIT_PRESOLVE_MIN samples); < 0: never. */
    long presolve;
    /* Progress reports (brdfit/options.h; NULL: none), and what they say besides the
     * search's place: the comparison's material (index and name; -1 and NULL: none),
     * its model or the selection's candidate (-1: none), the cross-validation's fold (0:
     * the fit of all samples). bf_fit_options_init: none of them. */
    bf_progress_report_fn report;
    void *report_user;
    int material, model, fold;
    const char *material_name;
    int report_materials; /* 1: a comparison's fits set material (bf_compare_run); a
                             selection's one material is none */
} bf_fit_options;

/* The defaults every fitting command starts from (brdfit fit's): log residual, the
 * samples' own weights, Ceres, the screened search with automatic starts, automatic
 * presolve, seed 0, and a solver thread per online core (results do not depend on the
 * thread count). */
void bf_fit_options_init(bf_fit_options *o);

/* Accuracy presets (brdfit fit --accuracy): bundles of options measured with brdfit
 * tradeoff (lib/src/fit/options.c says which figures chose them). A preset fills only
 * what the caller did not set explicitly (the BF_FIT_GIVEN_* bits). */
typedef enum bf_fit_accuracy {
    BF_ACCURACY_NONE = 0, /* no preset: the options as they are */
    BF_ACCURACY_FAST,     /* a stratified subsample of BF_ACCURACY_FAST_SUBSAMPLE, Ceres, the
                             data-driven start alone */
    BF_ACCURACY_BALANCED, /* the defaults: all samples, Ceres, the screened search */
    BF_ACCURACY_BEST,     /* all samples, Ceres, BF_ACCURACY_BEST_STARTS starts screened from
                             BF_ACCURACY_BEST_SCREEN candidates, up to
                             BF_ACCURACY_BEST_ITERATIONS Ceres iterations */
} bf_fit_accuracy;

#define BF_ACCURACY_FAST_SUBSAMPLE 16000
#define BF_ACCURACY_BEST_STARTS 64
#define BF_ACCURACY_BEST_SCREEN 512
#define BF_ACCURACY_BEST_ITERATIONS 500

/* What the caller set explicitly, for bf_fit_options_apply_accuracy: bits to OR. */
enum {
    BF_FIT_GIVEN_BACKEND = 1u << 0,
    BF_FIT_GIVEN_ALGORITHM = 1u << 1,
    BF_FIT_GIVEN_STARTS = 1u << 2,
    BF_FIT_GIVEN_RESIDUAL = 1u << 3,
    BF_FIT_GIVEN_MAX_ITERATIONS = 1u << 4,
    BF_FIT_GIVEN_SUBSAMPLE = 1u << 5, /* the data's subsample count (bf_prep.subsample) */
    BF_FIT_GIVEN_SCREEN = 1u << 6,
};

/* "fast", "balanced", "best" -> *out (BF_ERR_ARG for any other name, NULL included). */
bf_status bf_fit_accuracy_parse(const char *name, bf_fit_accuracy *out, bf_error *err);
/* The preset's name; "" for BF_ACCURACY_NONE, "unknown" out of range. */
const char *bf_fit_accuracy_name(bf_fit_accuracy acc);

/* Applies preset acc to o where `given` (BF_FIT_GIVEN_*) has no bit for the setting: a
 * back end and its algorithm go together (either given keeps both); the iteration limit
 * applies to Ceres only (NLopt counts evaluations). The preset's sample count goes to
 * *subsample (the data preprocessing's bf_prep.subsample, before the data is read) when
 * subsample is not NULL, the preset has one and BF_FIT_GIVEN_SUBSAMPLE is not set.
 * BF_ACCURACY_NONE changes nothing. */
void bf_fit_options_apply_accuracy(bf_fit_options *o, bf_fit_accuracy acc, unsigned given, size_t *subsample);

/* bf_fit and bf_fit_cv with the options as a struct. */
bf_status bf_fit_with(bf_samples *s, const char *spec, const bf_fit_options *o, bf_fit_result *r, bf_error *err);
bf_status bf_fit_cv_with(bf_samples *s, const char *spec, const bf_fit_options *o, int folds, uint64_t seed,
                         bf_cv_result *out, bf_error *err);

/* The model vector x of m (configured for s's channels) judged as bf_fit_with(s, spec,
 * o) judges its solution (evaluate.c): *cost the objective it minimises, 1/2 sum
 * rho(r^2) (its solution's final_cost), and *metrics those its result reports, k the
 * free entries. x may lie outside the bounds: it is evaluated as it is. */
bf_status bf_fit_evaluate_with(bf_samples *s, const bf_model *m, const double *x, const bf_fit_options *o, double *cost,
                               bf_metrics *metrics, bf_error *err);

#endif
