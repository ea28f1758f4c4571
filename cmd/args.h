/* Command-line helpers every subcommand shares. */
#ifndef BRDFIT_ARGS_H
#define BRDFIT_ARGS_H

#include <stddef.h>

/* argv[*i] is an option the shared parsers did not take: when it is one of the n names
 * in valued, returns its value and advances *i past it; otherwise NULL after printing
 * "CMD: unknown option 'X' (see CMD --help)" or "CMD: X needs a value" (bad usage). */
const char *args_value(int argc, char **argv, int *i, const char *const *valued, size_t n, const char *cmd);

#endif
