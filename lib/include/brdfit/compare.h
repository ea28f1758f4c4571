/* Comparing models across materials: rankings by an information criterion of the
 * fitted objective (BIC, AIC, AICc: metrics.h), by cross-validated error or by the
 * error itself; Pareto fronts of parameter count and of fitting work against error; the
 * simplest model within a tolerance of the best; a summary across materials; and the
 * JSON and CSV outputs.
 *
 * Everything ranked, flagged or chosen is a function of the fits' results alone (no
 * wall time enters), so the same inputs give the same outputs to the byte whatever the
 * threads and the load: fitting work is counted in sample evaluations (passes over
 * the samples times their number, the presolve's included), and wall times are written
 * only when asked (bf_compare.timing).
 *
 * bf_compare_run runs the fits (several at once, cancellable, with a progress callback)
 * and fills one bf_compare_fit per material x model; a caller may instead run the fits
 * its own way and fill them itself. bf_compare_rank derives everything else. A report
 * writer (HTML, pictures) reads the same filled structure.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_COMPARE_H
#define BRDFIT_COMPARE_H

#include <stddef.h>

#include "brdfit/error.h"
#include "brdfit/fit.h"
#include "brdfit/metrics.h"
#include "brdfit/options.h"
#include "brdfit/reference.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The error that Pareto fronts, the tolerance and the mean error use. */
typedef enum bf_compare_metric {
    BF_CMP_RMSE = 0,
    BF_CMP_RMSE_LOG,
    BF_CMP_RMSE_COS,
    BF_CMP_RMSE_REL,
} bf_compare_metric;

BF_API bf_status bf_compare_metric_parse(const char *text, bf_compare_metric *out, bf_error *err);
BF_API const char *bf_compare_metric_name(bf_compare_metric m);
BF_API double bf_compare_metric_value(const bf_metrics *m, bf_compare_metric which);

typedef enum bf_compare_state {
    BF_CMP_NOT_RUN = 0, /* never started (the run was interrupted) */
    BF_CMP_OK,          /* fitted; the only state that is ranked */
    BF_CMP_FAILED,      /* the fit ran but did not converge to a usable solution */
    BF_CMP_ERROR,       /* the fit could not run (message says why) */
} bf_compare_state;

BF_API const char *bf_compare_state_name(bf_compare_state s); /* "not_run", "ok", "failed", "error" */

/* What the models are ranked by. BIC is the default; CV needs each fit's cv_error
 * (bf_fit_cv), and then the Pareto fronts and the tolerance use it too. */
typedef enum bf_compare_rank_by {
    BF_RANK_BIC = 0,
    BF_RANK_AIC,
    BF_RANK_AICC,
    BF_RANK_CV,
    BF_RANK_ERROR, /* the error metric (bf_compare.metric) */
} bf_compare_rank_by;

BF_API bf_status bf_compare_rank_parse(const char *text, bf_compare_rank_by *out, bf_error *err);
BF_API const char *bf_compare_rank_name(bf_compare_rank_by r); /* "bic", "aic", "aicc", "cv", "error" */

/* Sample evaluations of a fit: passes over the samples times their number, presolve
 * and final pass included. Deterministic, unlike its wall time. */
BF_API double bf_compare_work(const bf_fit_result *r);

/* Frozen (docs/api.md): an array element of bf_compare_material. */
typedef struct bf_compare_fit {
    /* Filled by the caller. */
    bf_compare_state state;
    bf_metrics metrics;
    double seconds;              /* wall time: written only with bf_compare.timing */
    double work;                 /* bf_compare_work */
    double cv_error;             /* bf_fit_cv's error, or NaN when not cross-validated */
    const bf_fit_result *result; /* NULL, or the fit (not owned): parameters, standard
                                    errors and warnings for the outputs */
    char message[512];           /* BF_CMP_ERROR: why (a bf_error message) */
    /* Filled by bf_compare_rank (ranks 0 and marks 0 where the fit is not ranked). */
    double error;                               /* the error the fronts and the tolerance use: cv_error
                                    when ranked by CV, else the chosen metric (NaN unless
                                    ranked) */
    int rank;                                   /* by bf_compare.rank_by; 1 = best; equal values share
                                    the lower rank (1, 2, 2, 4) */
    int rank_bic, rank_aic, rank_aicc, rank_cv; /* by each criterion (0: not defined) */
    int pareto_k, pareto_work;                  /* 1: on the front of k (of work) against error (no other
                                    fit is at least as good in both and better in one;
                                    duplicates both stay) */
    int within_tolerance;                       /* error <= best error * (1 + tolerance) */
} bf_compare_fit;

/* Frozen (docs/api.md): an array element of bf_compare. */
typedef struct bf_compare_material {
    char *data; /* the data file, as named (owned) */
    size_t samples;
    int channels;
    bf_compare_fit *fits; /* nmodels, in model order (owned) */
    int best, simplest;   /* model indices from bf_compare_rank; -1: none ranked */
} bf_compare_material;

/* Per model, over the materials where it was ranked (NaN means when none). Frozen
 * (docs/api.md): an array element of bf_compare. */
typedef struct bf_compare_summary {
    int ranked;
    double mean_rank, mean_rank_bic, mean_rank_aic, mean_error;
    int chosen; /* materials where it is the simplest within tolerance */
} bf_compare_summary;

/* brdfit's objective is worse than a reference's when it exceeds it by more than this,
 * relative (an optimizer miss: BF_WARN_REFERENCE_BETTER). */
#define BF_COMPARE_REFERENCE_RTOL 1e-9

/* A published fit beside one of brdfit's (brdfit/reference.h): the reference's model
 * spec and material are the fit's. Frozen (docs/api.md): an array element of
 * bf_compare. */
typedef struct bf_compare_reference {
    int material, model;           /* the fit's slot */
    const bf_reference *reference; /* in bf_compare.references */
    double cost;                   /* the fit's objective at the reference's values (bf_reference_evaluate) */
    double brdfit_cost;            /* the same at brdfit's solution */
    bf_metrics metrics;            /* at the reference's values, as the fit's are computed */
    int brdfit_worse;              /* brdfit_cost > cost * (1 + BF_COMPARE_REFERENCE_RTOL) (a fit that
                                      succeeded only) */
    char message[512];             /* why it could not be evaluated ("": it was; cost NaN then) */
} bf_compare_reference;

typedef struct bf_compare {
    int nmaterials, nmodels;
    char **models;                  /* nmodels specs as the user gave them (owned) */
    bf_compare_material *materials; /* nmaterials (owned) */
    bf_compare_summary *summary;    /* nmodels (owned), from bf_compare_rank */
    bf_compare_metric metric;
    bf_compare_rank_by rank_by;
    int folds;               /* of the cross-validation (0: none ran) */
    double tolerance;        /* relative, >= 0 */
    int interrupted;         /* 1: some fits were never run */
    int timing;              /* 1: the outputs carry wall times (then they differ
                                       from run to run) */
    const char *residual;    /* the fit objective's name, for the outputs (NULL: omitted) */
    bf_fit_result **results; /* nmaterials * nmodels, slot i * nmodels + j (owned,
                                       each malloc'd and set up by bf_fit_result_init, or
                                       NULL): the fits bf_compare_run made (NULL before);
                                       a program filling a comparison itself allocates
                                       them the same way (freed by bf_compare_free) */
    /* Added at the end (docs/api.md). */
    bf_reference_set *references;    /* the options' --reference files, read by
                                        bf_compare_set_options (owned; NULL: none) */
    bf_compare_reference *reference; /* nreference (owned), from bf_compare_run: every
                                        (fit, matching reference), in slot order, then the
                                        references' order */
    int nreference;
} bf_compare;

/* A comparison of nmodels models (specs as given) across nmaterials materials (data
 * names), made by the library (read through the pointer: docs/api.md): tables zeroed,
 * every fit NOT_RUN, the names copied. */
BF_API bf_status bf_compare_new(int nmaterials, const char *const *data, int nmodels, const char *const *models,
                                bf_compare **out, bf_error *err);
/* Frees c, its tables and the fit results it holds (NULL allowed). */
BF_API void bf_compare_free(bf_compare *c);

/* Called once per fit, when it is done (whatever its state; never for a fit not run):
 * material and model index its slot, done counts the fits done so far (this one
 * included) of total. Calls come from the fitting threads, one at a time (under a
 * lock): the callback may print, and read the filled slots, without locking. */
typedef void (*bf_compare_progress)(void *user, const bf_compare *c, int material, int model, int done, int total);

/* c's ranking from the options o (brdfit/options.h, BF_TASK_COMPARE): the error metric,
 * what to rank by, the folds (only when ranking by cv), the tolerance, the timing and
 * the objective's name; and its reference files, read (bf_reference_read; a bad one is
 * its error, and c keeps no references). bf_compare_run does this itself. */
BF_API bf_status bf_compare_set_options(bf_compare *c, const bf_options *o, bf_error *err);

/* Fits every model (c->models) to every material (samples[i] for c->materials[i]) with
 * the fitting options of o, its jobs fits at once (each with threads / jobs solver
 * threads, at least 1; at most 64 at once), and fills each bf_compare_fit (state,
 * metrics, seconds, work, result, message) and each material's samples and channels.
 * progress (may be NULL) is called as each fit ends, with user. Ranked by cv, every
 * successful fit is also cross-validated (bf_fit_cv, the options' folds and seed) and
 * cv_error filled; a cross-validation that cannot run makes the fit an ERROR. A fit that
 * cannot run is an ERROR with its message; the others go on. Once the options' finish
 * flag is set no new fit starts and running ones finish; once their cancel flag is,
 * running solves stop too (bf_options_set_cancel). After either, fits never started
 * stay NOT_RUN and c->interrupted is 1.
 * The results depend neither on jobs, nor on the thread count, nor on the order the
 * fits finish in: each fit has its slot. The results are owned by c (bf_compare_free).
 * Nothing is printed and no signal handler installed: the caller does both, through
 * progress and cancel. Each sample set's geometry is computed before the threads start.
 * Returns BF_OK when the fits were run (whatever their outcome, interrupted or not);
 * BF_ERR_ARG (bad arguments, or c already run) or BF_ERR_NOMEM before any fit. Call
 * bf_compare_rank after.
 * References (the options' reference files): once the fits have run, every fit that ran
 * is set beside each reference of its material (bf_reference_material of its data name)
 * and model spec, in c->reference; a fit that succeeded with a higher objective than a
 * reference's gets a BF_WARN_REFERENCE_BETTER warning. */
BF_API bf_status bf_compare_run(bf_compare *c, bf_samples *const *samples, const bf_options *o,
                                bf_compare_progress progress, void *user, bf_error *err);

/* How many fits of c are in state s. */
BF_API int bf_compare_count(const bf_compare *c, bf_compare_state s);

/* Ranks, Pareto fronts, tolerance, best and simplest per material, and the summary.
 * A fit is ranked when it succeeded and its error and chosen criterion are finite. The
 * best is the lowest error; the simplest model is the one with the fewest free
 * parameters among those within tolerance; ties go to the lower error, then to the
 * earlier model. */
BF_API void bf_compare_rank(bf_compare *c);

/* Pareto front of points (x, y), both smaller-is-better: on[i] = 1 unless some other
 * point is <= in both and < in one. NaN points are never on it nor dominate. */
BF_API void bf_compare_pareto(int n, const double *x, const double *y, int *on);

/* Outputs through bf_outfile (no partial file on failure; path "-": stdout).
 * JSON: every key always present (null where not applicable); CSV: a header, then one
 * row per material x model in input order, with one column per fitted parameter and
 * channel (the union over the models, "name" or "name[c]"; empty where a model has no
 * such parameter) and the warnings joined by "; ". */
BF_API bf_status bf_compare_write_json(const bf_compare *c, const char *path, bf_error *err);
BF_API bf_status bf_compare_write_csv(const bf_compare *c, const char *path, bf_error *err);
/* The JSON text bf_compare_write_json writes, into *out (freed with bf_free). */
BF_API bf_status bf_compare_json(const bf_compare *c, char **out, bf_error *err);

/* The HTML report: DIR/index.html and its images and plots (relative links), built in a
 * temporary sibling folder and renamed into place, so a failure leaves nothing. An
 * existing DIR is replaced only if it holds BF_REPORT_MARKER (a previous report) or is
 * empty; otherwise BF_ERR_IO. samples: nmaterials sets (or NULL) for the overlays.
 * bf_compare_html_check says early (before fitting) whether DIR could be written. */
#define BF_REPORT_MARKER ".brdfit-report"
BF_API bf_status bf_compare_write_html(const bf_compare *c, bf_samples *const *samples, const char *dir, bf_error *err);

/* What else a report can use and say. Every field may be 0 / NULL. The caller sets it
 * up with bf_report_options_init (its size: docs/api.md). */
typedef struct bf_report_options {
    size_t size;                /* sizeof, set by bf_report_options_init */
    bf_samples *const *samples; /* nmaterials sets the models were fitted to (overlays) */
    bf_samples *const *tables;  /* nmaterials (entries may be NULL): MERL tables as read,
                                   whole, for the pictures of the measurement when the
                                   samples are a subsample of them */
    int format;                 /* bf_plot_format (render.h) of the embedded plots: PNG
                                   (0 too) or SVG; PDF embeds PNG and writes a PDF of
                                   every plot beside it, linked */
    const char *command_line;   /* the command that made the report, shown as given */
    const char *data_options;   /* how the data was read and prepared, shown */
    const char *scene;          /* the scene file the errors are over, or NULL */
} bf_report_options;
BF_API void bf_report_options_init_size(bf_report_options *o, size_t size);
static inline void bf_report_options_init(bf_report_options *o)
{
    bf_report_options_init_size(o, sizeof *o);
}
BF_API bf_status bf_compare_write_report(const bf_compare *c, const bf_report_options *o, const char *dir,
                                         bf_error *err);
BF_API bf_status bf_compare_html_check(const char *dir, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
