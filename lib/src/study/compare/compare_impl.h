/* A comparison, a selection and a trade-off table held by value, for the library's own
 * callers and the tests (bf_select_run compares on the stack): the public API makes
 * them with bf_x_new and frees them with bf_x_free (docs/api.md). */
#ifndef BRDFIT_COMPARE_IMPL_H
#define BRDFIT_COMPARE_IMPL_H

#include "brdfit/compare.h"
#include "brdfit/select.h"
#include "brdfit/tradeoff.h"

/* Sets up c (tables zeroed, every fit NOT_RUN, names copied); bf_compare_clear frees
 * what it holds (clearing twice is harmless). */
bf_status bf_compare_init(bf_compare *c, int nmaterials, const char *const *data, int nmodels,
                          const char *const *models, bf_error *err);
void bf_compare_clear(bf_compare *c);
/* c->references: every reference file of o, in order (compare_reference.c; the old set
 * freed first; NULL when o names none). On an error c holds none. */
bf_status compare_read_references(bf_compare *c, const bf_options *o, bf_error *err);

bf_status bf_select_init(bf_select *s, int n, const char *const *specs, int channels, const bf_options *o,
                         bf_error *err);
void bf_select_clear(bf_select *s);

bf_status bf_tradeoff_init(bf_tradeoff *t, const char *data, const char *model, size_t train_n,
                           const bf_tradeoff_grid *g, bf_error *err);
void bf_tradeoff_clear(bf_tradeoff *t);

#endif
