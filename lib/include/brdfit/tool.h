/* What only command-line tools need, apart from the library's API proper (docs/api.md):
 * brdfit's own commands use these, and another tool may. A program that only fits and
 * compares never needs this header.
 * Status codes and ownership follow brdfit/error.h. */
#ifndef BRDFIT_TOOL_H
#define BRDFIT_TOOL_H

#include <stddef.h>
#include <stdio.h>

#include "brdfit/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Strict numbers for option values: the whole text, no sign or space before an
 * integer, no leading space or trailing junk on a number, a finite number; 1 and *out
 * set when s is one in [lo, hi], else 0 (the caller says what it needed: ' 5', '+5',
 * '5x' and '' are not numbers). */
BF_API int bf_parse_long(const char *s, long lo, long hi, long *out);
BF_API int bf_parse_number(const char *s, double lo, double hi, double *out);

/* ---- Outputs: checked before any work, and never left half-written ------------------ */

/* One file a command reads or writes, with the option or role that names it in
 * messages ("-o", "--json", "data file", "--params"). path NULL: not given (skipped).
 * Frozen (docs/api.md): a small value. */
typedef struct bf_path_use {
    const char *what;
    const char *path;
} bf_path_use;

/* The checks a command makes on its outputs before any work:
 * - an empty name is refused (BF_ERR_ARG), and so is "-" (standard output) twice;
 * - an output that is the same regular file as an input or as another output (same
 *   device and inode, whatever the names: ./x, a hard link, a symbolic link; for files
 *   not there yet, the same name in the same folder) is refused (BF_ERR_ARG, naming
 *   both). Devices, FIFOs and terminals may be shared: /dev/null as two outputs, or as
 *   input and output, destroys nothing;
 * - every output must be writable (bf_outfile_check; BF_ERR_IO).
 * The first problem found is returned, as one line in err. */
BF_API bf_status bf_outputs_check(const bf_path_use *inputs, int ninputs, const bf_path_use *outputs, int noutputs,
                                  bf_error *err);

/* Installs a handler for the signals that end a process by default (SIGHUP, SIGINT,
 * SIGQUIT, SIGTERM, SIGPIPE, SIGALRM, SIGUSR1, SIGUSR2, SIGXCPU, SIGXFSZ, SIGVTALRM,
 * SIGPROF) that removes every temporary file and report folder still being written,
 * then ends the process by the signal's default action. Signals that are ignored or
 * handled already are left alone. For a program's start, before any thread. */
BF_API void bf_remove_temporaries_on_signals(void);

/* CSV fields for the table writers: text quoted when it holds a comma, quote or line
 * break (RFC 4180); a number as ",v" (bf_format_double), or "," alone when not finite. */
BF_API void bf_csv_put_text(FILE *fp, const char *s);
BF_API void bf_csv_put_number(FILE *fp, double v);
/* n strings, each stride bytes apart from items on (a char [n][stride] array), as ",s"
 * with s the strings joined by "; " (quoted as bf_csv_put_text): one field for a list
 * such as a fit's warnings. */
BF_API void bf_csv_put_list(FILE *fp, const char *items, size_t stride, int n);

#ifdef __cplusplus
}
#endif
#endif
