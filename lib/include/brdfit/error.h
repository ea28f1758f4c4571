/* Error reporting, and the conventions every public header follows.
 *
 * Failing: the library never prints or exits. A function that can fail returns a
 * bf_status (BF_OK = 0) and, if its last argument err is not NULL, fills it with a
 * one-line message; the returned code and err->code are the same. Functions that
 * cannot fail return their result (a count, a value, void).
 *
 * Owning:
 *  - Objects the library allocates (bf_model, bf_samples, bf_geometry, bf_objective,
 *    bf_csv, bf_scene, bf_regress_baseline) are made by bf_x_new or by a function named
 *    after their source (bf_x_read: a file, bf_x_parse: text, bf_x_from_*, bf_x_copy),
 *    which hands the object back through an out pointer (set to NULL on failure), and
 *    are released with bf_x_free (NULL allowed).
 *  - Structs the caller owns (bf_compare, bf_select, bf_tradeoff, bf_fit_result,
 *    bf_regress_outcome, bf_image, bf_samples_info, ...) are set up by bf_x_init or by
 *    the function that fills them (bf_fit, bf_image_read, ...), and their contents
 *    released with bf_x_clear (clearing twice is harmless).
 *    bf_outfile is a file being written: bf_outfile_open, then commit or abort.
 *  - Pointers passed in are borrowed unless a function says it keeps them. */
#ifndef BRDFIT_ERROR_H
#define BRDFIT_ERROR_H

#include <signal.h>
#include <stdarg.h>
#include <stddef.h>

#include "brdfit/api.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum bf_status {
    BF_OK = 0,
    BF_ERR_ARG,   /* bad argument or specification */
    BF_ERR_IO,    /* cannot open, read or write a file */
    BF_ERR_PARSE, /* malformed input file */
    BF_ERR_RANGE, /* value outside its bounds, NaN or Inf */
    BF_ERR_NOMEM,
    BF_ERR_CANCELLED /* stopped by the caller's cancel flag (bf_options_set_cancel) before it
                        was done: nothing was made (bf_samples_load) */
} bf_status;

/* A flag a signal handler or another thread sets non-zero to stop work: the one type of
 * every cancel flag the library reads (it never writes one). Read with an atomic load
 * where the compiler has one: a handler sets it with an atomic store there, or a plain
 * one. */
typedef volatile sig_atomic_t bf_cancel_flag;

/* Messages quote what hostile files hold, and are printed on terminals: bf_fail makes
 * every message one line of at most BF_ERROR_MAX_CHARS characters, with runs of more
 * than BF_ERROR_TOKEN_CHARS characters without a blank (a 9 kB number, a binary
 * header) shortened to their start and end around "...", and control bytes and invalid
 * UTF-8 escaped (bf_printable). */
#define BF_ERROR_MAX_CHARS 200
#define BF_ERROR_TOKEN_CHARS 64

/* Frozen (docs/api.md): a small value. */
typedef struct bf_error {
    bf_status code;
    char msg[512]; /* one line, no trailing newline, safe to print (see above) */
} bf_error;

/* Sets err (if not NULL) and returns code, so callers can `return bf_fail(...)`. */
BF_API bf_status bf_fail(bf_error *err, bf_status code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;
BF_API bf_status bf_failv(bf_error *err, bf_status code, const char *fmt, va_list ap)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 0)))
#endif
    ;

BF_API void bf_error_clear(bf_error *err);

/* The status's name: "ok", "arg", "io", "parse", "range", "nomem", "cancelled" ("unknown"
 * for any other value). Stable: front ends map them to their own error types. */
BF_API const char *bf_status_name(bf_status code);

/* Frees what the library allocated and handed over as plain memory (a text such as
 * bf_models_json's or bf_fit_result_json's, an array it made): the library's free,
 * whatever allocator the calling program uses. NULL is allowed. Objects with their own
 * bf_x_free are freed with that. */
BF_API void bf_free(void *p);

/* s made safe to print on one terminal line, into buf (size >= 8 bytes): bytes below
 * 0x20, DEL and invalid UTF-8 as \xHH; C1 controls, line separators, bidirectional
 * overrides and U+FFFE, U+FFFF (not characters, nor allowed in XML) as \uHHHH; other
 * UTF-8 kept. A run of more than max_token characters
 * without a blank keeps its first and last characters around "..." (0: no limit); the
 * whole is cut to max_chars characters (0: only to size), ending in "...". Returns buf. */
BF_API const char *bf_printable(const char *s, size_t max_token, size_t max_chars, char *buf, size_t size);
/* All of s escaped as above, nothing shortened (for reports: XML and HTML cannot hold
 * control characters either); malloc'd, NULL when out of memory. */
BF_API char *bf_printable_dup(const char *s);

#ifdef __cplusplus
}
#endif
#endif
