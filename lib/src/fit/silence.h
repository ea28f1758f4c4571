/* Internal: which entries of a point sit on a bound, which have no effect there (their
 * column of the Jacobian is zero over the samples), and which parameter's place on a
 * bound silences them: Disney's clearcoat_gloss while clearcoat = 0, a lobe's width and
 * f0 while its weight is 0. The search (search.c) moves such bounds inward to look for
 * a better optimum; the diagnostics (diagnostics.c) report the silent entries once, as
 * inactive, and the criteria leave them out of k. */
#ifndef BF_FIT_SILENCE_H
#define BF_FIT_SILENCE_H

#include "brdfit/solve.h"
#include "objective_state.h"

typedef struct bf_silence {
    int nz;                /* internal entries */
    signed char *bound;    /* per entry: -1 on its lower bound, 1 on its upper, 0 inside */
    unsigned char *silent; /* per entry: 1 when the residuals do not depend on it here */
    int *gate;             /* per silent entry: the model parameter whose entries on a bound
                            silence it (moved inward, they give it an effect), or -1 */
    int nsilent;
} bf_silence;

/* On a bound: within 1e-9 of the entry's (internal) range of it. */
int bf_silence_at_bound(const bf_problem *p, const double *z, int j);

/* The model parameter of model-vector entry k (-1 when none). */
int bf_silence_param_of(const bf_model *m, int k);

/* Fills *out for point z of problem p, whose internal entries are objective o's (o->kidx
 * maps them to model entries). One fused pass at z, and one more per model parameter on a
 * bound when some entry is silent. */
bf_status bf_silence_find(const bf_problem *p, const bf_objective *o, const double *z, const bf_loss *loss, int threads,
                          bf_silence *out, bf_error *err);
void bf_silence_free(bf_silence *s);

#endif
