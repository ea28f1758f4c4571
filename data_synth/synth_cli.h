/* brdfit-synth's command-line table (cli.h). */
#ifndef BRDFIT_SYNTH_CLI_H
#define BRDFIT_SYNTH_CLI_H

#include "cli.h"

extern const cli_command cli_synth;

#endif
