/* Strict numbers for option values (brdfit/tool.h): strtol and strtod alone take
 * leading spaces, signs and partial text. */
#include "brdfit/tool.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>

int bf_parse_long(const char *s, long lo, long hi, long *out)
{
    if (!s || !isdigit((unsigned char)s[0]))
        return 0;
    char *end;
    errno = 0;
    long v = strtol(s, &end, 10);
    if (*end || errno || v < lo || v > hi)
        return 0;
    *out = v;
    return 1;
}

int bf_parse_number(const char *s, double lo, double hi, double *out)
{
    if (!s || !*s || isspace((unsigned char)s[0]))
        return 0;
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (*end || errno || !isfinite(v) || v < lo || v > hi)
        return 0;
    *out = v;
    return 1;
}
