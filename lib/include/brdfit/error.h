/* Error reporting: the library never prints or exits; it fills a bf_error. */
#ifndef BRDFIT_ERROR_H
#define BRDFIT_ERROR_H

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

typedef struct bf_error {
    bf_status code;
    char msg[512];   /* one line, no trailing newline */
} bf_error;

/* Sets err (if not NULL) and returns code, so callers can `return bf_fail(...)`. */
int bf_fail(bf_error *err, bf_status code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

void bf_error_clear(bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
