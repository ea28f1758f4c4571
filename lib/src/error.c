#include "brdfit/error.h"

#include <stdarg.h>
#include <stdio.h>

int bf_fail(bf_error *err, bf_status code, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
        err->code = code;
    }
    return (int)code;
}

void bf_error_clear(bf_error *err)
{
    if (err) {
        err->code = BF_OK;
        err->msg[0] = '\0';
    }
}
