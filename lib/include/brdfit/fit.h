/* Fitting a model to a sample set: data-driven start, seeded multistart, the chosen
 * back end, metrics and standard errors; and the result file.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_FIT_H
#define BRDFIT_FIT_H

#include <stddef.h>
#include <stdint.h>

#include "brdfit/error.h"
#include "brdfit/metrics.h"
#include "brdfit/model.h"
#include "brdfit/objective.h"
#include "brdfit/samples.h"
#include "brdfit/solve.h"

#ifdef __cplusplus
extern "C" {
#endif

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
    uint64_t seed;       /* multistart (and the solver's stochastic methods) */
    const double *start; /* NULL: data-driven; else a model vector to start from */
    int weighted_metrics; /* 1: the result's metrics use the samples' weights (a scene's
                             directions, scene.h); 0: every sample counts alike */
    /* Presolve: every start is first solved on a seeded stratified subsample of this
     * many samples, and the best of them then on all samples (the result is a solution
     * of the whole set; the presolve only saves passes over it; that last solve stops at
     * a relative cost change of 1e-9 unless solver.function_tolerance says otherwise).
     * 0: automatic (BF_FIT_PRESOLVE_SAMPLES when the data has at least
     * BF_FIT_PRESOLVE_MIN samples); < 0: never. */
    long presolve;
} bf_fit_options;

/* The search's numbers (docs/fitting.md says how they were chosen). A start is "at the
 * best" when its final cost is within BF_FIT_AT_BEST of the best one (relative; search.c
 * adds a floor for exact fits). */
#define BF_FIT_STARTS 8            /* automatic starts, at least */
#define BF_FIT_STARTS_MAX 32       /* and at most */
#define BF_FIT_SCREEN 64           /* candidates screened by default */
#define BF_FIT_SCREEN_SAMPLES 1024 /* the screening set: the data, or a subsample of this many */
#define BF_FIT_SCREEN_WORK 8192    /* automatic starts x screening samples, about */
#define BF_FIT_AT_BEST 1e-4
#define BF_FIT_PRESOLVE_SAMPLES 32768
#define BF_FIT_PRESOLVE_MIN 131072 /* 4 x the presolve: below it a presolve saves too little */

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

#define BF_FIT_MAX_WARNINGS 16
#define BF_FIT_WARNING_LEN 192

/* What the presolve did (samples 0: none ran). */
typedef struct bf_presolve_info {
    size_t samples;
    int iterations, evaluations;
    double seconds;
} bf_presolve_info;

typedef struct bf_fit_result {
    bf_model *model;        /* configured with the samples' channel count (owned) */
    double *x;              /* best parameters, bf_model_nvalues entries, always finite */
    double *stderr_;        /* standard errors (0 fixed, NaN undetermined) */
    unsigned char *fixed;   /* 1 where fixed */
    /* 1 where a free entry has no effect at the solution (its Jacobian column is zero):
     * reported once as inactive, and not counted in k (docs/criteria.md). */
    unsigned char *inactive;
    /* Per inactive entry: the parameter (bf_model_param index) whose place on a bound
     * silences it, or -1. */
    int *inactive_gate;
    bf_metrics metrics;
    bf_solution solution;   /* of the best start (the solve on all samples) */
    bf_presolve_info presolve;
    bf_presolve_info screen; /* the starts' solves on the screening set (samples 0: none) */
    int starts;             /* starts solved (bf_fit_options.starts; docs/fitting.md) */
    int starts_at_best;     /* of them, those that ended within BF_FIT_AT_BEST of the best */
    int candidates;         /* random candidates screened (0: none) */
    size_t samples;         /* samples fitted (metrics.n counts samples x channels) */
    int threads;            /* the solver's thread count, as run */
    uint64_t seed;          /* the multistart seed, as run */
    double seconds;         /* whole fit: start, solves, metrics */
    bf_residual residual;
    int ok;                 /* 1: the best start's solution is usable */
    /* What the fit should be doubted for, one line each naming the parameter and the
     * number: a parameter on a bound, one the data do not determine (no or a huge
     * standard error) or a pair correlated beyond 0.999, an albedo above 1, a lobe
     * narrower than the data's sampling near the peak, a solve stopped on its limit,
     * criteria left undefined by a robust loss. */
    int nwarnings;
    char warnings[BF_FIT_MAX_WARNINGS][BF_FIT_WARNING_LEN];
} bf_fit_result;

/* The warning of a fit whose best optimum was reached from one start of several (the
 * search may have missed a better one), as it begins. */
#define BF_FIT_WARN_ONE_START "the best optimum was reached from 1 of"
/* 1 when r has that warning (so also for a result read back from its warnings). */
int bf_fit_result_unsure(const bf_fit_result *r);

/* Fits spec ("walter", "microfacet:D=ggx,lobes=2" ...) to s. Returns BF_OK when a fit
 * ran (check r->ok: a failed fit says so in r->solution.termination, and r->x is the
 * start, never NaN); errors for bad specs, options or data. o->solver.progress sees every
 * solve's iterations and o->solver.cancel is read at each of them: a fit cancelled by
 * either stops at once, with r->ok 0, r->solution.stop BF_STOP_CANCELLED, r->x the start,
 * no metrics, and bf_fit_write_json refuses it. */
bf_status bf_fit(bf_samples *s, const char *spec, const bf_fit_options *o, bf_fit_result *r, bf_error *err);
void bf_fit_result_clear(bf_fit_result *r);

/* K-fold cross-validation: the held-out error of the fitted objective. The samples are
 * cut into `folds` seeded folds stratified over theta_h and theta_d
 * (bf_samples_folds); each is held out in turn while the rest is fitted with o (its
 * presolve, starts and seed included), and the fitted parameters' residuals, in the
 * objective's form and weights and without a robust loss, are summed over it:
 *   error = sqrt(sum w r^2 / sum w)   pooled over every held-out residual.
 * A fold whose fit fails makes the error NaN (counted in failed). */
#define BF_CV_MAX_FOLDS 20
typedef struct bf_cv_result {
    int folds;
    double error;                       /* pooled; NaN when a fold failed */
    double fold_error[BF_CV_MAX_FOLDS]; /* each fold's own */
    int failed;                         /* folds whose fit failed */
} bf_cv_result;

bf_status bf_fit_cv(bf_samples *s, const char *spec, const bf_fit_options *o, int folds, uint64_t seed, bf_cv_result *out,
              bf_error *err);

/* The largest directional albedo of model m at x, integral of f cos theta_o over the
 * outgoing hemisphere, over incidences 5 .. 85 degrees (and four azimuths for an
 * anisotropic model) and channels: the value, where (degrees) and which channel. The
 * integral runs over the half vector, dense near the mirror direction, so a narrow lobe
 * is resolved. BF_OK, or BF_ERR_NOMEM. */
bf_status bf_fit_max_albedo(const bf_model *m, const double *x, double *albedo, double *theta_deg, int *channel,
                            bf_error *err);

/* A data-driven start for any model: diffuse level from off-specular samples, lobe
 * weight and width from the samples near the specular peak, every other parameter at
 * its default, all inside the bounds. */
bf_status bf_fit_initial_guess(const bf_model *m, bf_samples *s, double *x, bf_error *err);

/* The result JSON: a parameter file (model, options, channels, params) plus data,
 * residual, metrics, optimizer summary, standard errors and timing; feeds brdfit eval. */
bf_status bf_fit_write_json(const bf_fit_result *r, const char *data_path, const char *out_path, bf_error *err);
/* Several fits of one data set as {"fits": [result, ...]} (not a parameter file). */
bf_status bf_fit_write_json_list(const bf_fit_result *const *r, int n, const char *data_path, const char *out_path,
                           bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
