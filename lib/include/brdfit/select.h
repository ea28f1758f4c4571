/* Choosing the smallest model that serves: fit candidates to one data set (restricted
 * to a scene's directions beforehand, if the user has one) and pick the one with the
 * fewest free parameters whose error is within a tolerance of the best candidate's.
 *
 * Among candidates within tolerance the order of preference is: fewer free parameters,
 * then isotropic before anisotropic, one lobe before two, a monochrome (mono) highlight
 * before a coloured one, then the lower error, then the earlier candidate. */
#ifndef BRDFIT_SELECT_H
#define BRDFIT_SELECT_H

#include "brdfit/compare.h"
#include "brdfit/error.h"
#include "brdfit/fit.h"
#include "brdfit/samples.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct bf_select_candidate {
    char spec[160];          /* as given */
    /* From the configured model (bf_select_describe). */
    int k;                   /* free parameters for the data's channel count */
    int anisotropic;         /* the family is anisotropic */
    int lobes;               /* specular lobes (1 for models without the option) */
    int coloured_specular;   /* a colour parameter besides the diffuse colour, C > 1 */
    /* The fit (bf_select_run). */
    bf_compare_state state;
    bf_fit_result result;    /* valid when state is OK or FAILED (free with bf_select_free) */
    double error;            /* the chosen metric, NaN unless state is OK */
    double seconds;
    char message[512];       /* ERROR: why */
    /* bf_select_choose. */
    int within;              /* 1: error <= best (1 + tolerance) + abs_tolerance */
} bf_select_candidate;

typedef struct bf_select {
    int n;
    bf_select_candidate *c;  /* n (owned) */
    bf_compare_metric metric;
    double tolerance;        /* relative, >= 0 */
    double abs_tolerance;    /* absolute, >= 0: errors this close to the best are equal */
    int best, chosen;        /* candidate indices; -1: none fitted */
} bf_select;

/* The default candidates for C channels, in order of complexity: diffuse models, one
 * isotropic lobe, anisotropic lobes, two lobes; for C > 1 each model with a coloured
 * highlight also with mono=specular. Returns the count and a malloc'd array of static
 * strings (free the array only). */
int bf_select_default_candidates(int channels, const char ***specs);

/* Sets up s for the specs (each checked with bf_model_create: BF_ERR_ARG naming the
 * bad one) and fills each candidate's description. */
int bf_select_init(bf_select *s, int n, const char *const *specs, int channels, bf_compare_metric metric,
                   double tolerance, double abs_tolerance, bf_error *err);
void bf_select_free(bf_select *s);

/* Called after each candidate's fit (i its index), for progress output. */
typedef void (*bf_select_progress)(void *ctx, const bf_select *s, int i);

/* Fits every candidate to data with the options (a candidate whose fit cannot run is
 * marked ERROR with the message; the others go on), then bf_select_choose. Returns
 * BF_OK when the candidates were run, whatever their outcome. */
int bf_select_run(bf_select *s, bf_samples *data, const bf_fit_options *o, bf_select_progress progress,
                  void *ctx, bf_error *err);

/* From the candidates' states and errors: within, best (lowest error) and chosen (see
 * the order of preference above). Candidates not OK are never within nor chosen. */
void bf_select_choose(bf_select *s);

/* Candidate indices in the order of preference (k, isotropy, lobes, mono, error,
 * index), whatever their state: for tables. order has s->n entries. */
void bf_select_order(const bf_select *s, int *order);

/* JSON: metric, tolerances, best, chosen, and per candidate (in input order) spec,
 * k, flags, state, error, metrics, seconds, within, and parameters when fitted. Through
 * bf_outfile (path "-": stdout). data names the data file in the output. */
int bf_select_write_json(const bf_select *s, const char *data, const char *path, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
