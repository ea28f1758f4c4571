/* Command-line helpers every subcommand shares. */
#ifndef BRDFIT_ARGS_H
#define BRDFIT_ARGS_H

#include <stddef.h>

#include "brdfit/io.h"

/* argv[*i] is an option the shared parsers did not take: when it is one of the n names
 * in valued, returns its value and advances *i past it; otherwise NULL after printing
 * "CMD: unknown option 'X' (see CMD --help)" or "CMD: X needs a value" (bad usage). */
const char *args_value(int argc, char **argv, int *i, const char *const *valued, size_t n, const char *cmd);

/* A command's outputs checked before any work (bf_outputs_check: empty names, an output
 * that is an input or another output under any name, unwritable folders). NULL paths
 * are skipped. Returns 0 when they pass; otherwise the exit status after printing
 * "CMD: problem": 2 for bad usage (an empty name, an output that is the same file as an
 * input or as another output), 1 for an output that cannot be written. */
int args_check_outputs(const char *cmd, const bf_path_use *inputs, int ninputs, const bf_path_use *outputs,
                       int noutputs);

#endif
