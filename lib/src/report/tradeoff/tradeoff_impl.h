/* The tradeoff's method setting, for the library's own callers and tests: sets a
 * method as the command line names it into solver options (backend and the
 * registry's algorithm name) after checking it with their other settings. */
#ifndef BRDFIT_TRADEOFF_IMPL_H
#define BRDFIT_TRADEOFF_IMPL_H

#include "brdfit/solve.h"

bf_status bf_tradeoff_method_apply(const char *text, bf_solver_options *so, bf_error *err);

#endif
