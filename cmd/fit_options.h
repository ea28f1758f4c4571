/* Command-line options shared by the commands that fit (brdfit fit, brdfit compare):
 * objective, optimizer, starts, threads, and the -m model list. */
#ifndef BRDFIT_FIT_OPTIONS_H
#define BRDFIT_FIT_OPTIONS_H

#include "brdfit/fit.h"

#define FIT_OPTIONS_MAX_OVERRIDES 64

typedef struct fit_options {
    bf_fit_options fit;
    bf_override overrides[FIT_OPTIONS_MAX_OVERRIDES];
    int noverrides;
} fit_options;

/* Usage lines for the options below, for a command's --help. */
extern const char fit_options_usage[];

/* brdfit fit's defaults: log residual, sample weights on, Ceres, one start, every core. */
void fit_options_init(fit_options *o);

/* If argv[*i] is one of the options, consumes it (and its value) and returns 1; returns
 * 0 if it is not one; -1 after printing a one-line error (prefix: cmd). */
int fit_options_parse(fit_options *o, int argc, char **argv, int *i, const char *cmd);

/* Points the fit options at the overrides and takes the seed (after parsing). */
void fit_options_finish(fit_options *o, uint64_t seed);

/* Splits a -m list into model specs appended to specs[n..max-1]: a comma starts a new
 * model only where the next token has no '=' or has a ':' of its own, so option lists
 * stay whole ("microfacet:D=ggx,G=smith_ggx,walter" is two models). Returns the new
 * count, or -1 after printing a one-line error. */
int fit_options_split_models(const char *list, char **specs, int n, int max, const char *cmd);

#endif
