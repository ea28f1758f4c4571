/* What only command-line tools need, apart from the library's API proper (docs/api.md):
 * brdfit's own commands use these, and another tool may. A program that only fits and
 * compares never needs this header.
 * Status codes and ownership follow brdfit/error.h. */
#ifndef BRDFIT_TOOL_H
#define BRDFIT_TOOL_H

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

#ifdef __cplusplus
}
#endif
#endif
