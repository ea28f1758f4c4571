/* Fitting cost against accuracy on one data set: a grid of training sample counts,
 * optimizer methods, residual forms and multistart counts, each fitted on a seeded
 * training set and judged on a disjoint held-out test set; the Pareto front of cost
 * against test error and the cheapest setting within a tolerance of the best.
 *
 * The cost is fitting work by default: sample evaluations (passes over the samples,
 * with or without derivatives, times their number: bf_compare_work), the same on every
 * machine and load, so the outputs are reproducible to the byte. BF_TRADEOFF_COST_SECONDS
 * uses the measured wall time instead (then the front and the recommendation vary from
 * run to run, and the outputs say so).
 *
 * bf_tradeoff_run makes the whole measurement from a set of options (BF_TASK_TRADEOFF,
 * brdfit/options.h: the lists, the test fraction, the cost, the tolerance ...), as
 * `brdfit tradeoff` does. Or the caller builds the grid (bf_tradeoff_new_grid), runs each row
 * (bf_tradeoff_run_row, in any order, one at a time, since rows are timed) and ranks
 * (bf_tradeoff_rank). The writers read the filled table.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_TRADEOFF_H
#define BRDFIT_TRADEOFF_H

#include <stddef.h>
#include <stdint.h>

#include "brdfit/compare.h"
#include "brdfit/error.h"
#include "brdfit/fit.h"
#include "brdfit/metrics.h"
#include "brdfit/options.h"
#include "brdfit/render.h"
#include "brdfit/samples.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A method as the command line names it (bf_method_parse: "ceres", "ceres:dogleg",
 * "dogleg", "nlopt", "nlopt:LN_BOBYQA", "LN_BOBYQA" ...), checked against the method
 * registry with the other settings of the options base (bf_solver_options_check).
 * Unknown names and methods that do not suit are BF_ERR_ARG. */
BF_API bf_status bf_tradeoff_method_check(const char *text, const bf_options *base, bf_error *err);

/* Splits s into a training and a test set, disjoint, together every sample: the test set
 * is a seeded uniform random subset of exactly round(n * fraction) samples (at least 1,
 * and at least 1 left for training), both in the original order. fraction in (0, 1).
 * Weights and channel names are copied; the MERL origin is not (neither set is a table). */
BF_API bf_status bf_tradeoff_split(const bf_samples *s, double fraction, uint64_t seed, bf_samples **train,
                                   bf_samples **test, bf_error *err);

/* Frozen (docs/api.md): an array element of bf_tradeoff. */
typedef struct bf_tradeoff_row {
    /* The setting (bf_tradeoff_new_grid). */
    size_t samples;     /* training samples fitted (the whole training set when all) */
    int all;            /* 1: the whole training set, no subsampling */
    const char *method; /* as given (a copy the table owns) */
    bf_residual residual;
    int starts;
    /* Filled by bf_tradeoff_run_row. */
    int ran; /* 1: a fit ran (ok or not); 0: not run or an error (message) */
    int ok;
    double seconds; /* bf_fit_result.seconds, minimum over the repeats */
    double work;    /* sample evaluations of the fit (bf_compare_work) */
    int iterations;
    int nwarnings;
    char (*warnings)[BF_FIT_WARNING_LEN]; /* the fit's warnings (owned), or NULL */
    bf_metrics train, test;
    char message[512]; /* why the fit could not run (a bf_error message) */
    /* Filled by bf_tradeoff_rank (0 / NaN for rows not ok). */
    double error; /* the chosen metric on the test set */
    int on_front; /* Pareto front of cost against error */
    int within_tolerance;
} bf_tradeoff_row;

typedef enum bf_tradeoff_cost {
    BF_TRADEOFF_COST_WORK = 0, /* sample evaluations: reproducible */
    BF_TRADEOFF_COST_SECONDS,  /* wall time: varies with the machine and its load */
} bf_tradeoff_cost;

typedef struct bf_tradeoff {
    char *data, *model; /* owned copies */
    size_t total, train_n, test_n;
    int channels;
    double test_fraction;
    uint64_t seed;
    int repeats;
    bf_compare_metric metric;
    double tolerance;
    bf_tradeoff_cost cost;
    int timing; /* 1: the outputs carry wall times (always with cost seconds) */
    int nrows;
    bf_tradeoff_row *rows; /* owned */
    int best, recommended; /* row indices from bf_tradeoff_rank; -1: none ok */
    /* From the options of bf_tradeoff_run (bf_tradeoff_new_grid: 0 and NULL). */
    int plot_width, plot_height; /* plot_size, for bf_tradeoff_write_plot */
    char *fit_options;           /* owned: the data and base fit options as set, as brdfit fit's
                                    options (bf_tradeoff_fit_command), or NULL */
    char *names;                 /* owned: the methods' names, which the rows point into */
} bf_tradeoff;

/* The most settings a grid may hold (the product of the list lengths). */
#define BF_TRADEOFF_MAX_ROWS 100000

/* The grid's lists, each a count and an array the caller keeps: training sample counts
 * (0 meaning all), methods as the command line names them, residual forms and multistart
 * counts (0: automatic). Set up by bf_tradeoff_grid_init (its size: docs/api.md; every
 * list empty). */
typedef struct bf_tradeoff_grid {
    size_t size; /* sizeof, set by bf_tradeoff_grid_init */
    int ncounts;
    const size_t *counts;
    int nmethods;
    const char *const *methods;
    int nresiduals;
    const bf_residual *residuals;
    int nstarts;
    const int *starts;
} bf_tradeoff_grid;
BF_API void bf_tradeoff_grid_init_size(bf_tradeoff_grid *g, size_t size);
static inline void bf_tradeoff_grid_init(bf_tradeoff_grid *g)
{
    bf_tradeoff_grid_init_size(g, sizeof *g);
}

/* The table of a grid: the full product of its lists, sample counts outermost. Counts
 * >= train_n become "all", and the counts are sorted ascending and deduplicated, so rows
 * run in ascending sample count. Then methods (copied), residuals, starts, in the order
 * given. Every list must be non-empty. Made by the library (read through the pointer:
 * docs/api.md); freed with bf_tradeoff_free. */
BF_API bf_status bf_tradeoff_new_grid(const char *data, const char *model, size_t train_n, const bf_tradeoff_grid *grid,
                                      bf_tradeoff **out, bf_error *err);
/* bf_tradeoff_new_grid with the lists as arguments, for programs written against it. */
BF_API BF_DEPRECATED("use bf_tradeoff_new_grid") bf_status
    bf_tradeoff_new(const char *data, const char *model, size_t train_n, int ncounts, const size_t *counts,
                    int nmethods, const char *const *methods, int nresiduals, const bf_residual *residuals, int nstarts,
                    const int *starts, bf_tradeoff **out, bf_error *err);
BF_API void bf_tradeoff_free(bf_tradeoff *t);

/* Runs row i: subsamples train (seeded stratified, bf_prep with t->seed) unless the row is
 * all, fits t->model with base overridden by the row's method, residual and starts,
 * t->repeats times (same seed each time: the same fit, so the minimum time is the
 * fit's time with the least interference), and measures the best fit on train and test
 * (every metric). Returns BF_OK when the row was filled (a fit that could not run says so
 * in row->message and returns its error code too). */
BF_API bf_status bf_tradeoff_run_row(bf_tradeoff *t, int i, bf_samples *train, bf_samples *test, const bf_options *base,
                                     bf_error *err);

/* Called after each row of bf_tradeoff_run (i its index), from the calling thread, for
 * progress output. */
typedef void (*bf_tradeoff_progress)(void *user, const bf_tradeoff *t, int i);

/* The whole measurement, as `brdfit tradeoff` makes it, from the options o
 * (BF_TASK_TRADEOFF): model and o checked (bf_options_check_models, bf_options_check:
 * the lists too, BF_ERR_ARG with the command line's messages); data (prepared already:
 * bf_samples_load or bf_samples_prepare) split by the options' test_fraction and seed
 * (bf_tradeoff_split; a set too small to split is BF_ERR_ARG, its message led by name);
 * the grid made from the lists (bf_tradeoff_new_grid; the methods default to the base
 * setting's method or ceres,LD_LBFGS, the residuals and start counts to the base's);
 * every row run in that order, one at a time (bf_tradeoff_run_row with o as the base: a
 * row that cannot run is marked and the others go on), progress (may be NULL) called
 * after each with user; then ranked (bf_tradeoff_rank). The table carries the options'
 * values (test fraction, seed, repeats, error, tolerance, cost, timing, plot size) and
 * the base options for bf_tradeoff_fit_command. o's cancel and finish flags
 * (bf_options_set_cancel) stop it before the next row (the rows left are not run).
 * name (may be NULL) names the data in the outputs. *out: the table (bf_tradeoff_free),
 * NULL on failure. Returns BF_OK when the rows were run, whatever their outcome. */
BF_API bf_status bf_tradeoff_run(const bf_samples *data, const char *name, const char *model, const bf_options *o,
                                 bf_tradeoff_progress progress, void *user, bf_tradeoff **out, bf_error *err);

/* error from t->metric on the test set, the Pareto front of (cost, error) over the ok
 * rows, best (lowest error; ties to the cheaper, then the earlier row), within tolerance
 * (error <= best * (1 + tolerance)) and recommended: the cheapest row within tolerance
 * (ties to the lower error, then the earlier row). */
BF_API void bf_tradeoff_rank(bf_tradeoff *t);

/* A row's cost under t->cost (NaN for a row that did not run). */
BF_API double bf_tradeoff_row_cost(const bf_tradeoff *t, const bf_tradeoff_row *r);
BF_API const char *bf_tradeoff_cost_name(bf_tradeoff_cost c); /* "work", "seconds" */

/* Row i's setting as a `brdfit fit` command line, into *out (freed with bf_free):
 * "brdfit fit DATA OPTIONS -m MODEL SETTING", OPTIONS the data and base fit options of
 * bf_tradeoff_run as they were set, in order (shell-quoted where needed; none for a
 * table of bf_tradeoff_new_grid), SETTING the row's: --subsample N (unless all), --backend
 * (and --algorithm unless Ceres's default), --residual and --starts (unless automatic).
 * The recommendation is row t->recommended. */
BF_API bf_status bf_tradeoff_fit_command(const bf_tradeoff *t, int i, char **out, bf_error *err);

/* Outputs through bf_outfile (no partial file on failure; "-": stdout). JSON: every key
 * always present (null where not applicable), seconds only with t->timing; CSV: a header
 * and one row per grid row, a seconds column only with t->timing. */
BF_API bf_status bf_tradeoff_write_json(const bf_tradeoff *t, const char *path, bf_error *err);
/* The JSON's text, into *out (freed with bf_free). */
BF_API bf_status bf_tradeoff_json(const bf_tradeoff *t, char **out, bf_error *err);
BF_API bf_status bf_tradeoff_write_csv(const bf_tradeoff *t, const char *path, bf_error *err);

/* Test error (log axis unless some error is 0) against the cost (log axis): every
 * setting, the Pareto front drawn and named, its points labelled #N (the row's number,
 * from 1), the recommended setting ringed; a plot (render.h) of width x height in format
 * (BF_PLOT_BY_NAME: by the extension .png, .svg or .pdf). axes (may be NULL; set up by
 * bf_plot_axes_init): what the axes span. */
BF_API bf_status bf_tradeoff_write_plot(const bf_tradeoff *t, const char *path, int format, int width, int height,
                                        bf_plot_axes *axes, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
