/* Command-line options for what fits are ranked by (brdfit compare, brdfit select):
 * --rank, --folds (of --rank cv) and --timing (wall times in the outputs). */
#ifndef BRDFIT_RANK_OPTIONS_H
#define BRDFIT_RANK_OPTIONS_H

#include <stdio.h>

#include "brdfit/compare.h"
#include "brdfit/fit.h"
#include "cli.h"

typedef struct rank_options {
    bf_compare_rank_by rank_by;
    int folds;  /* of --rank cv */
    int timing; /* 1: wall times in the JSON and CSV (then runs differ) */
} rank_options;

/* The options, for a command's tables (cli.h), with the command's default ranking in
 * the help (compare: bic, select: error). Both are bound to a rank_options: its
 * cli_take target. */
extern const cli_group rank_options_bic, rank_options_error;

void rank_options_init(rank_options *r, bf_compare_rank_by rank_by);

/* After parsing: a criterion needs a likelihood, and a robust loss has none
 * (metrics.h). Returns 0, or -1 after a one-line error saying so. */
int rank_options_check(const rank_options *r, const bf_fit_options *fit, const char *cmd);

#endif
