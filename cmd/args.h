/* Command-line helpers every subcommand shares. */
#ifndef BRDFIT_ARGS_H
#define BRDFIT_ARGS_H

#include <stddef.h>

#include "brdfit/io.h"
#include "brdfit/tool.h"

/* Strict numbers for option values: the whole text, no sign or space before an integer,
 * no leading space or trailing junk on a number; 1 and *out set when s is one in
 * [lo, hi], else 0 (the caller prints the usage error). ' 5', '+5', '5x', '' are not. */
int args_int(const char *s, long lo, long hi, long *out);
int args_number(const char *s, double lo, double hi, double *out);
/* --jobs N (fits at once: compare, select, batch) into *jobs: 0, or -1 after a one-line
 * error naming cmd. */
int args_jobs(const char *cmd, const char *v, int *jobs);
/* An image size "N" (square) or "WxH", each side an integer in [lo, hi]. */
int args_size(const char *s, int lo, int hi, int *w, int *h);
/* A command's outputs checked before any work (bf_outputs_check: empty names, an output
 * that is an input or another output under any name, unwritable folders). NULL paths
 * are skipped. Returns 0 when they pass; otherwise the exit status after printing
 * "CMD: problem": 2 for bad usage (an empty name, an output that is the same file as an
 * input or as another output), 1 for an output that cannot be written. */
int args_check_outputs(const char *cmd, const bf_path_use *inputs, int ninputs, const bf_path_use *outputs,
                       int noutputs);

/* Appends " word" to *text (a growing string; left as it was when out of memory), quoted
 * for a shell when it holds anything but plain characters: the command line as typed,
 * for the outputs that record it. */
void args_append_word(char **text, const char *word);

#endif
