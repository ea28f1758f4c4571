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
#include "brdfit/options.h"
#include "brdfit/samples.h"
#include "brdfit/solve.h"

#ifdef __cplusplus
extern "C" {
#endif

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

#define BF_FIT_MAX_WARNINGS 16
#define BF_FIT_WARNING_LEN 192

/* What kind of doubt a warning of bf_fit_result says: callers decide on the kind (is the
 * fit unsure? is a parameter at a bound?), never on the text, which is for people and may
 * be reworded. Each kind has a stable snake_case name (bf_warning_kind_name) for files
 * that store kinds; a name never changes meaning, new kinds are added at the end. */
typedef enum bf_warning_kind {
    BF_WARN_OTHER = 0,        /* "other": none of these (or a warning read back without a kind) */
    BF_WARN_AT_BOUND,         /* "at_bound": a free parameter on a bound of its range */
    BF_WARN_UNDETERMINED,     /* "undetermined": no standard error, or a huge one */
    BF_WARN_CORRELATED,       /* "correlated": parameters correlated beyond 0.999 */
    BF_WARN_INACTIVE,         /* "inactive": parameters without effect (not counted in k) */
    BF_WARN_ALBEDO,           /* "albedo_above_one": the fitted BRDF reflects more than it receives */
    BF_WARN_NARROW_LOBE,      /* "narrow_lobe": a lobe narrower than the data's sampling */
    BF_WARN_ONE_START,        /* "one_start": the best optimum reached from 1 of several starts */
    BF_WARN_SOLVER_LIMIT,     /* "solver_limit": the solve stopped on its iteration or time limit */
    BF_WARN_FAILED,           /* "failed": the fit failed (r->ok 0) */
    BF_WARN_CANCELLED,        /* "cancelled": the fit was cancelled by its caller */
    BF_WARN_NO_CRITERIA,      /* "criteria_undefined": AIC, AICc, BIC undefined under a robust loss */
    BF_WARN_TRUNCATED,        /* "truncated": the list was cut at BF_FIT_MAX_WARNINGS */
    BF_WARN_REFERENCE_BETTER, /* "reference_better": a published fit of the same model has a
                                 lower objective on this data (brdfit compare --reference):
                                 the search missed a better optimum */
    BF_WARN_KINDS             /* the count, not a kind */
} bf_warning_kind;

/* The kind's stable name ("at_bound"; "unknown" for a value out of range). */
BF_API const char *bf_warning_kind_name(bf_warning_kind k);
/* The kind of a name bf_warning_kind_name gives; BF_ERR_ARG (listing the names) for
 * any other. */
BF_API bf_status bf_warning_kind_parse(const char *name, bf_warning_kind *out, bf_error *err);

/* What the presolve did (samples 0: none ran). Frozen (docs/api.md): embedded in bf_fit_result. */
typedef struct bf_presolve_info {
    size_t samples;
    int iterations, evaluations;
    double seconds;
} bf_presolve_info;

/* A fit. The caller sets it up with bf_fit_result_init (its size: docs/api.md), bf_fit
 * fills it, bf_fit_result_clear frees what it holds (and keeps it ready for another). */
typedef struct bf_fit_result {
    size_t size;          /* sizeof, set by bf_fit_result_init */
    bf_model *model;      /* configured with the samples' channel count (owned) */
    double *x;            /* best parameters, bf_model_nvalues entries, always finite */
    double *stderr_;      /* standard errors (0 fixed, NaN undetermined) */
    unsigned char *fixed; /* 1 where fixed */
    /* 1 where a free entry has no effect at the solution (its Jacobian column is zero):
     * reported once as inactive, and not counted in k (docs/criteria.md). */
    unsigned char *inactive;
    /* Per inactive entry: the parameter (bf_model_param index) whose place on a bound
     * silences it, or -1. */
    int *inactive_gate;
    bf_metrics metrics;
    bf_solution solution; /* of the best start (the solve on all samples) */
    bf_presolve_info presolve;
    bf_presolve_info screen; /* the starts' solves on the screening set (samples 0: none) */
    int starts;              /* starts solved (the option starts; docs/fitting.md) */
    int starts_at_best;      /* of them, those that ended within BF_FIT_AT_BEST of the best */
    int candidates;          /* random candidates screened (0: none) */
    size_t samples;          /* samples fitted (metrics.n counts samples x channels) */
    int threads;             /* the solver's thread count, as run */
    uint64_t seed;           /* the multistart seed, as run */
    double seconds;          /* whole fit: start, solves, metrics */
    bf_residual residual;
    int ok; /* 1: the best start's solution is usable */
    /* What the fit should be doubted for, one line each naming the parameter and the
     * number: a parameter on a bound, one the data do not determine (no or a huge
     * standard error) or a pair correlated beyond 0.999, an albedo above 1, a lobe
     * narrower than the data's sampling near the peak, a solve stopped on its limit,
     * criteria left undefined by a robust loss. */
    int nwarnings;
    char warnings[BF_FIT_MAX_WARNINGS][BF_FIT_WARNING_LEN];
    /* The kind of warnings[i] (at the end, so the fields above keep their offsets). */
    bf_warning_kind warning_kind[BF_FIT_MAX_WARNINGS];
    /* The parameters' covariance, bf_model_nvalues squared, row-major in the model's order
     * (owned): s^2 (J^T J)^+ at the solution, from the pass that gives stderr_ (its
     * diagonal is stderr_ squared), NaN in the row and column of an entry without a
     * standard error, 0 in a fixed entry's. NULL for a cancelled fit and a result the
     * program made (read back from a file). */
    double *covariance;
} bf_fit_result;

/* 1 when r has a BF_WARN_ONE_START warning: its best optimum was reached from one start
 * of several, so the search may have missed a better one (also for a result read back
 * with its kinds). */
BF_API int bf_fit_result_unsure(const bf_fit_result *r);

/* Fits spec ("walter", "microfacet:D=ggx,lobes=2" ...) to s with the fitting options of
 * o (brdfit/options.h; any task but BF_TASK_READ). Returns BF_OK when a fit ran (check
 * r->ok: a failed fit says so in r->solution.termination, and r->x is the start, never
 * NaN); errors for bad specs, options or data. The options' progress callback sees
 * every solve's iterations and their cancel flag is read at each of them: a fit
 * cancelled by either stops at once, with r->ok 0, r->solution.stop BF_STOP_CANCELLED,
 * r->x the start, no metrics, and bf_fit_write_json refuses it. */
BF_API bf_status bf_fit(bf_samples *s, const char *spec, const bf_options *o, bf_fit_result *r, bf_error *err);
/* An empty result with its size set, for bf_fit (or for a program's own fit, as brdfit
 * report fills them from a database). */
BF_API void bf_fit_result_init_size(bf_fit_result *r, size_t size);
static inline void bf_fit_result_init(bf_fit_result *r)
{
    bf_fit_result_init_size(r, sizeof *r);
}
BF_API void bf_fit_result_clear(bf_fit_result *r);

/* K-fold cross-validation: the held-out error of the fitted objective. The samples are
 * cut into `folds` seeded folds (the options' seed) stratified over theta_h and theta_d
 * (bf_samples_folds); each is held out in turn while the rest is fitted with o (its
 * presolve, starts and seed included), and the fitted parameters' residuals, in the
 * objective's form and weights and without a robust loss, are summed over it:
 *   error = sqrt(sum w r^2 / sum w)   pooled over every held-out residual.
 * A fold whose fit fails makes the error NaN (counted in failed). */
#define BF_CV_MAX_FOLDS 20
typedef struct bf_cv_result {
    size_t size; /* sizeof, set by bf_cv_result_init (docs/api.md) */
    int folds;
    double error;                       /* pooled; NaN when a fold failed */
    double fold_error[BF_CV_MAX_FOLDS]; /* each fold's own */
    int failed;                         /* folds whose fit failed */
} bf_cv_result;

BF_API bf_status bf_fit_cv(bf_samples *s, const char *spec, const bf_options *o, int folds, bf_cv_result *out,
                           bf_error *err);
BF_API void bf_cv_result_init_size(bf_cv_result *r, size_t size);
static inline void bf_cv_result_init(bf_cv_result *r)
{
    bf_cv_result_init_size(r, sizeof *r);
}

/* The largest directional albedo of model m at x, integral of f cos theta_o over the
 * outgoing hemisphere, over incidences 5 .. 85 degrees (and four azimuths for an
 * anisotropic model) and channels: the value, where (degrees) and which channel. The
 * integral runs over the half vector, dense near the mirror direction, so a narrow lobe
 * is resolved. BF_OK, or BF_ERR_NOMEM. */
BF_API bf_status bf_fit_max_albedo(const bf_model *m, const double *x, double *albedo, double *theta_deg, int *channel,
                                   bf_error *err);

/* A data-driven start for any model: diffuse level from off-specular samples, lobe
 * weight and width from the samples near the specular peak, every other parameter at
 * its default, all inside the bounds. */
BF_API bf_status bf_fit_initial_guess(const bf_model *m, bf_samples *s, double *x, bf_error *err);

/* The result JSON: a parameter file (model, options, channels, params) plus data,
 * residual, metrics, optimizer summary, standard errors and timing; feeds brdfit eval. */
BF_API bf_status bf_fit_write_json(const bf_fit_result *r, const char *data_path, const char *out_path, bf_error *err);
/* The same text, into *out (freed with bf_free): what a program keeps or parses instead
 * of a file. */
BF_API bf_status bf_fit_result_json(const bf_fit_result *r, const char *data_path, char **out, bf_error *err);
/* Several fits of one data set as {"fits": [result, ...]} (not a parameter file). */
BF_API bf_status bf_fit_write_json_list(const bf_fit_result *const *r, int n, const char *data_path,
                                        const char *out_path, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
