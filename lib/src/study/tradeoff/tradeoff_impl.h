/* The tradeoff's method setting, for the library's own callers and tests: sets a
 * method as the command line names it into solver options (backend and the
 * registry's algorithm name) after checking it with their other settings. It lives with
 * the tradeoff's options (fit/tradeoff_options.h), which check the methods list. */
#ifndef BRDFIT_TRADEOFF_IMPL_H
#define BRDFIT_TRADEOFF_IMPL_H

#include "tradeoff_options.h"

#endif
