/* brdfit-synth's command-line table (cli.h) and the strings it fills. */
#ifndef BRDFIT_SYNTH_CLI_H
#define BRDFIT_SYNTH_CLI_H

#include "cli.h"

/* The options as given (NULL: not given), checked by synth_main.c once all are read:
 * what one means depends on others (--count on the pattern, --noise on the model). */
typedef struct synth_args {
    const char *params, *out, *pattern, *count, *noise, *noise_model, *counts, *outliers, *seed, *incidence, *step;
    int clamp;
} synth_args;

extern const cli_command cli_synth;

#endif
