/* Comparing models across materials: rankings by BIC and AIC, Pareto fronts of
 * parameter count and fitting time against error, the simplest model within a
 * tolerance of the best, a summary across materials, and the JSON and CSV outputs.
 *
 * The caller runs the fits (how, and how many at once, is its business) and fills one
 * bf_compare_fit per material x model; bf_compare_rank derives everything else. A report
 * writer (HTML, pictures) reads the same filled structure. */
#ifndef BRDFIT_COMPARE_H
#define BRDFIT_COMPARE_H

#include <stddef.h>

#include "brdfit/error.h"
#include "brdfit/fit.h"
#include "brdfit/metrics.h"

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

int bf_compare_metric_parse(const char *text, bf_compare_metric *out, bf_error *err);
const char *bf_compare_metric_name(bf_compare_metric m);
double bf_compare_metric_value(const bf_metrics *m, bf_compare_metric which);

typedef enum bf_compare_state {
    BF_CMP_NOT_RUN = 0, /* never started (the run was interrupted) */
    BF_CMP_OK,          /* fitted; the only state that is ranked */
    BF_CMP_FAILED,      /* the fit ran but did not converge to a usable solution */
    BF_CMP_ERROR,       /* the fit could not run (message says why) */
} bf_compare_state;

const char *bf_compare_state_name(bf_compare_state s); /* "not_run", "ok", "failed", "error" */

typedef struct bf_compare_fit {
    /* Filled by the caller. */
    bf_compare_state state;
    bf_metrics metrics;
    double seconds;
    const bf_fit_result *result; /* NULL, or the fit (not owned): parameters for the JSON */
    char message[512];           /* BF_CMP_ERROR: why (a bf_error message) */
    /* Filled by bf_compare_rank (ranks 0 and marks 0 where the fit is not ranked). */
    double error;                /* the chosen metric (NaN unless ranked) */
    int rank_bic, rank_aic;      /* 1 = best; equal values share the lower rank (1, 2, 2, 4) */
    int pareto_k, pareto_time;   /* 1: on the front (no other fit is at least as good in
                                    both and better in one; duplicates both stay) */
    int within_tolerance;        /* error <= best error * (1 + tolerance) */
} bf_compare_fit;

typedef struct bf_compare_material {
    char *data;            /* the data file, as named (owned) */
    size_t samples;
    int channels;
    bf_compare_fit *fits;  /* nmodels, in model order (owned) */
    int best, simplest;    /* model indices from bf_compare_rank; -1: none ranked */
} bf_compare_material;

/* Per model, over the materials where it was ranked (NaN means when none). */
typedef struct bf_compare_summary {
    int ranked;
    double mean_rank_bic, mean_rank_aic, mean_error;
    int chosen;            /* materials where it is the simplest within tolerance */
} bf_compare_summary;

typedef struct bf_compare {
    int nmaterials, nmodels;
    char **models;                  /* nmodels specs as the user gave them (owned) */
    bf_compare_material *materials; /* nmaterials (owned) */
    bf_compare_summary *summary;    /* nmodels (owned), from bf_compare_rank */
    bf_compare_metric metric;
    double tolerance;               /* relative, >= 0 */
    int interrupted;                /* 1: some fits were never run */
    const char *residual;           /* the fit objective's name, for the outputs (NULL: omitted) */
} bf_compare;

/* Allocates the tables (fits zeroed, state NOT_RUN) and copies the names. */
int bf_compare_init(bf_compare *c, int nmaterials, const char *const *data, int nmodels,
                    const char *const *models, bf_error *err);
void bf_compare_free(bf_compare *c);

/* Ranks, Pareto fronts, tolerance, best and simplest per material, and the summary.
 * The simplest model is the one with the fewest free parameters among those within
 * tolerance; ties go to the lower error, then to the earlier model. */
void bf_compare_rank(bf_compare *c);

/* Pareto front of points (x, y), both smaller-is-better: on[i] = 1 unless some other
 * point is <= in both and < in one. NaN points are never on it nor dominate. */
void bf_compare_pareto(int n, const double *x, const double *y, int *on);

/* Outputs through bf_outfile (no partial file on failure; path "-": stdout).
 * JSON: every key always present (null where not applicable); CSV: a header, then one
 * row per material x model in input order. */
int bf_compare_write_json(const bf_compare *c, const char *path, bf_error *err);
int bf_compare_write_csv(const bf_compare *c, const char *path, bf_error *err);

/* The HTML report: DIR/index.html and its PNG images (relative links), built in a
 * temporary sibling folder and renamed into place, so a failure leaves nothing. An
 * existing DIR is replaced only if it holds BF_REPORT_MARKER (a previous report) or is
 * empty; otherwise BF_ERR_IO. samples: nmaterials sets (or NULL) for the overlays.
 * bf_compare_html_check says early (before fitting) whether DIR could be written. */
#define BF_REPORT_MARKER ".brdfit-report"
int bf_compare_write_html(const bf_compare *c, bf_samples *const *samples, const char *dir, bf_error *err);
int bf_compare_html_check(const char *dir, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
