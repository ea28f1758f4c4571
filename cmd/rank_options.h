/* The library's ranking options (--rank, --folds, --timing; brdfit/options.h) as
 * command-line groups, with the command's default ranking in the help (compare: bic,
 * select: error). Each takes a bf_options * as its cli_take target. */
#ifndef BRDFIT_RANK_OPTIONS_H
#define BRDFIT_RANK_OPTIONS_H

#include "cli.h"

extern const cli_group rank_options_bic, rank_options_error;

#endif
