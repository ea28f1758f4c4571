/* Choosing the smallest model that serves: fit candidates to one data set (restricted
 * to a scene's directions beforehand, if the user has one) and pick one, by rank_by:
 *  - error (the default): the candidate with the fewest free parameters whose error is
 *    within a tolerance of the best candidate's;
 *  - cv: the same with the cross-validated error (bf_fit_cv) in place of the error;
 *  - bic, aic, aicc: the lowest criterion (which weighs error against parameters
 *    itself; the tolerance does not enter).
 * select answers "what is the smallest model good enough", so it defaults to the error
 * with a tolerance: with a million samples a criterion rewards every parameter that
 * lowers the error at all.
 *
 * Among candidates within tolerance (or with equal criteria) the order of preference is:
 * fewer free parameters, then isotropic before anisotropic, one lobe before two, a
 * monochrome (mono) highlight before a coloured one, then the lower error, then the
 * earlier candidate. Nothing depends on wall time.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_SELECT_H
#define BRDFIT_SELECT_H

#include "brdfit/compare.h"
#include "brdfit/error.h"
#include "brdfit/fit.h"
#include "brdfit/options.h"
#include "brdfit/samples.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Frozen (docs/api.md): an array element of bf_select. */
typedef struct bf_select_candidate {
    char spec[160]; /* as given */
    /* From the configured model (bf_select_describe). */
    int k;           /* free parameters for the data's channel count */
    int anisotropic; /* the family is anisotropic */
    int lobes;       /* specular lobes (1 for models without the option) */
    union {
        int colored_specular; /* a colour parameter besides the diffuse colour, C > 1 */
        int coloured_specular BF_DEPRECATED("use colored_specular"); /* as spelled before 0.1 */
    };
    /* The fit (bf_select_run). */
    bf_compare_state state;
    bf_fit_result *result; /* when state is OK or FAILED, else NULL (owned by the selection) */
    double cv_error;       /* rank_by cv: the held-out error (NaN otherwise or failed) */
    double work;           /* sample evaluations (bf_compare_work) */
    double seconds;        /* wall time: written only with bf_select.timing */
    char message[512];     /* ERROR: why */
    /* bf_select_choose. */
    double error;     /* the chosen metric, or cv_error under rank_by cv; NaN
                                unless state is OK */
    double criterion; /* what rank_by orders by (error, cv_error or a criterion) */
    int rank;         /* by criterion, 1 = lowest, ties share; 0: not ranked */
    int within;       /* 1: error <= best (1 + tolerance) + abs_tolerance; by a
                                criterion: the lowest criterion */
} bf_select_candidate;

typedef struct bf_select {
    int n;
    bf_select_candidate *c; /* n (owned) */
    bf_compare_metric metric;
    bf_compare_rank_by rank_by; /* the options' rank (default error) */
    int folds;                  /* of rank_by cv (the options' folds) */
    int timing;                 /* 1: the JSON carries wall times */
    double tolerance;           /* relative, >= 0 */
    double abs_tolerance;       /* absolute, >= 0: errors this close to the best are equal */
    int best, chosen;           /* candidate indices; -1: none fitted (best: lowest error) */
} bf_select;

/* The default candidates for C channels, in order of complexity: diffuse models, one
 * isotropic lobe, anisotropic lobes, two lobes; for C > 1 each model with a coloured
 * highlight also with mono=specular. Returns the count and a malloc'd array of static
 * strings (free the array only). */
BF_API int bf_select_default_candidates(int channels, const char ***specs);

/* A selection among n candidate specs for data of `channels` channels, made by the
 * library (read through the pointer: docs/api.md): each spec checked with bf_model_new
 * (BF_ERR_ARG naming the bad one) and each candidate described; the error metric,
 * ranking, folds, tolerances and timing come from o (brdfit/options.h, BF_TASK_SELECT). */
BF_API bf_status bf_select_new(int n, const char *const *specs, int channels, const bf_options *o, bf_select **out,
                               bf_error *err);
/* Frees s and the fits it holds (NULL allowed). */
BF_API void bf_select_free(bf_select *s);

/* Called after each candidate's fit (i its index; done of s->n finished), for progress
 * output. Calls never overlap; with jobs > 1 they come in the order the fits finish. */
typedef void (*bf_select_progress)(void *user, const bf_select *s, int i, int done);

/* Fits every candidate to data with the fitting options of o, its jobs fits at once
 * (bf_compare_run: each gets threads / jobs threads; the results do not depend on jobs),
 * a candidate whose fit cannot run marked ERROR with the message (the others go on);
 * cross-validates each with s->folds folds (the options' seed) when ranked by cv (a
 * cross-validation that cannot run makes the candidate an ERROR), then
 * bf_select_choose. progress (may be NULL) gets user. Returns BF_OK when the candidates
 * were run, whatever their outcome. */
BF_API bf_status bf_select_run(bf_select *s, bf_samples *data, const bf_options *o, bf_select_progress progress,
                               void *user, bf_error *err);

/* From the candidates' states, errors and criteria: error, criterion, rank, within,
 * best (lowest error) and chosen (see the top). Candidates not OK, or whose criterion
 * is not finite, are never ranked, within nor chosen. */
BF_API void bf_select_choose(bf_select *s);

/* Candidate indices in the order of preference (k, isotropy, lobes, mono, error,
 * index), whatever their state: for tables. order has s->n entries. */
BF_API void bf_select_order(const bf_select *s, int *order);

/* JSON: ranking, metric, tolerances, best, chosen, and per candidate (in input order)
 * spec, k, flags, state, error, criterion, rank, work, within, metrics, parameters,
 * standard errors and warnings when fitted (seconds only with s->timing). Through
 * bf_outfile (path "-": stdout). data names the data file in the output. */
BF_API bf_status bf_select_write_json(const bf_select *s, const char *data, const char *path, bf_error *err);
/* The same text, into *out (freed with bf_free). */
BF_API bf_status bf_select_json(const bf_select *s, const char *data, char **out, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
