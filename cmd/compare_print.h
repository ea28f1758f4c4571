/* The ranking tables brdfit compare prints, shared with brdfit report (which prints
 * them from a batch database): per material, then the summary across materials; and
 * the report's --plot-format, which both take. */
#ifndef BRDFIT_COMPARE_PRINT_H
#define BRDFIT_COMPARE_PRINT_H

#include <stdio.h>

#include "brdfit/compare.h"

/* Every material's table (ranked fits by rank, then the others with their state), then
 * the summary when there are several materials; flushed. */
void compare_print_tables(FILE *out, const bf_compare *c);

/* compare's JSON and CSV files (NULL paths: not written): 0, or 1 after "cmd: problem". */
int compare_write_tables(const char *cmd, const bf_compare *c, const char *json_path, const char *csv_path);

/* The fits of c: all, those never run, those failed or in error (for the closing line
 * and the exit status). */
void compare_counts(const bf_compare *c, int *total, int *not_run, int *bad);

/* --plot-format png|svg|pdf into *format (a bf_plot_format): 0, or -1 after a one-line
 * error naming cmd. */
int compare_plot_format(const char *cmd, const char *v, int *format);

#endif
