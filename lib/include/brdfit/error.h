/* Error reporting: the library never prints or exits; it fills a bf_error. */
#ifndef BRDFIT_ERROR_H
#define BRDFIT_ERROR_H

#include <stdarg.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum bf_status {
    BF_OK = 0,
    BF_ERR_ARG,      /* bad argument or specification */
    BF_ERR_IO,       /* cannot open, read or write a file */
    BF_ERR_PARSE,    /* malformed input file */
    BF_ERR_RANGE,    /* value outside its bounds, NaN or Inf */
    BF_ERR_NOMEM
} bf_status;

/* Messages quote what hostile files hold, and are printed on terminals: bf_fail makes
 * every message one line of at most BF_ERROR_MAX_CHARS characters, with runs of more
 * than BF_ERROR_TOKEN_CHARS characters without a blank (a 9 kB number, a binary
 * header) shortened to their start and end around "...", and control bytes and invalid
 * UTF-8 escaped (bf_printable). */
#define BF_ERROR_MAX_CHARS 200
#define BF_ERROR_TOKEN_CHARS 64

typedef struct bf_error {
    bf_status code;
    char msg[512];   /* one line, no trailing newline, safe to print (see above) */
} bf_error;

/* Sets err (if not NULL) and returns code, so callers can `return bf_fail(...)`. */
int bf_fail(bf_error *err, bf_status code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
int bf_failv(bf_error *err, bf_status code, const char *fmt, va_list ap)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 0)))
#endif
    ;

void bf_error_clear(bf_error *err);

/* s made safe to print on one terminal line, into buf (size >= 8 bytes): bytes below
 * 0x20, DEL and invalid UTF-8 as \xHH; C1 controls, line separators, bidirectional
 * overrides and U+FFFE, U+FFFF (not characters, nor allowed in XML) as \uHHHH; other
 * UTF-8 kept. A run of more than max_token characters
 * without a blank keeps its first and last characters around "..." (0: no limit); the
 * whole is cut to max_chars characters (0: only to size), ending in "...". Returns buf. */
const char *bf_printable(const char *s, size_t max_token, size_t max_chars, char *buf, size_t size);
/* All of s escaped as above, nothing shortened (for reports: XML and HTML cannot hold
 * control characters either); malloc'd, NULL when out of memory. */
char *bf_printable_dup(const char *s);

#ifdef __cplusplus
}
#endif
#endif
