/* The library's fitting options (brdfit/options.h) as command-line groups, model lists
 * and the checks made before any data is read, with their errors printed. */
#ifndef BRDFIT_FIT_OPTIONS_H
#define BRDFIT_FIT_OPTIONS_H

#include "brdfit/options.h"
#include "cli.h"

/* The options, for a command's tables (cli.h): --accuracy (fit, select, regress), the
 * objective and the optimizer (every command that fits). Each takes a bf_options * as
 * its cli_take target. */
extern const cli_group fit_options_accuracy, fit_options_fitting, fit_options_optimizer;

/* A -m list split by the library (bf_model_list_split) into model specs appended to
 * specs[n..max-1] (each malloc'd). Returns the new count, or -1 after a one-line error. */
int fit_options_split_models(const char *list, char **specs, int n, int max, const char *cmd);

/* Bad usage found before any data is read: every spec names a model and the fix and
 * bound options suit each, then what couples options (bf_options_check). 0, or -1
 * after printing the first problem's one-line error. */
int fit_options_check(const bf_options *o, char *const *specs, int n, const char *cmd);

#endif
