/* Command-line options shared by the commands that fit (brdfit fit, brdfit compare):
 * objective, optimizer, starts, threads, and the -m model list. */
#ifndef BRDFIT_FIT_OPTIONS_H
#define BRDFIT_FIT_OPTIONS_H

#include "brdfit/fit.h"
#include "data_options.h"

#define FIT_OPTIONS_MAX_OVERRIDES 64
#define FIT_OPTIONS_MAX_THREADS 1024 /* --threads */
#define FIT_OPTIONS_MAX_STARTS 10000 /* --starts */

typedef struct fit_options {
    bf_fit_options fit;
    bf_override overrides[FIT_OPTIONS_MAX_OVERRIDES];
    int noverrides;
    bf_fit_accuracy accuracy; /* --accuracy (brdfit/fit.h); BF_ACCURACY_NONE: not given */
    unsigned given;           /* BF_FIT_GIVEN_*: the options the user set explicitly */
} fit_options;

/* The options, for a command's tables (cli.h): --accuracy (fit, select, regress), the
 * objective and the optimizer (every command that fits). All three are bound to a
 * fit_options: its cli_take target. */
extern const cli_group fit_options_accuracy, fit_options_fitting, fit_options_optimizer;

/* brdfit fit's defaults (bf_fit_options_init), no overrides, no preset. */
void fit_options_init(fit_options *o);

/* After parsing (so order on the line is moot): points the fit options at the
 * overrides, takes the data options' seed, fills in the --accuracy preset where the user
 * set nothing (bf_fit_options_apply_accuracy; its subsample goes to d unless
 * --subsample was given), and with a scene asks for metrics over the scene's directions
 * (weighted as the scene weighs them). */
void fit_options_finish(fit_options *o, data_options *d);

/* Splits a -m list into model specs appended to specs[n..max-1]: a comma starts a new
 * model only where the next token has no '=' or has a ':' of its own, so option lists
 * stay whole ("microfacet:D=ggx,G=smith_ggx,walter" is two models). Returns the new
 * count, or -1 after printing a one-line error. */
int fit_options_split_models(const char *list, char **specs, int n, int max, const char *cmd);

/* Checks that every spec names a model and that --fix/--bound suit each (before any
 * data is read): 0, or -1 after printing the first problem's one-line error. */
int fit_options_check_models(const fit_options *o, char *const *specs, int n, const char *cmd);

#endif
