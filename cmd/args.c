/* Command-line helpers every subcommand shares (see args.h). */
#include "args.h"

#include "brdfit/tool.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int args_int(const char *s, long lo, long hi, long *out)
{
    return bf_parse_long(s, lo, hi, out);
}

int args_jobs(const char *cmd, const char *v, int *jobs)
{
    long n;
    if (!args_int(v, 1, 1024, &n)) {
        fprintf(stderr, "%s: --jobs needs an integer from 1 to 1024, got '%s'\n", cmd, v);
        return -1;
    }
    *jobs = (int)n;
    return 0;
}

int args_number(const char *s, double lo, double hi, double *out)
{
    return bf_parse_number(s, lo, hi, out);
}

int args_size(const char *s, int lo, int hi, int *w, int *h)
{
    char buf[32];
    const char *x = strchr(s, 'x');
    long a, b;
    if (!x)
        return args_int(s, lo, hi, &a) ? (*w = *h = (int)a, 1) : 0;
    if ((size_t)(x - s) >= sizeof buf)
        return 0;
    memcpy(buf, s, (size_t)(x - s));
    buf[x - s] = '\0';
    if (!args_int(buf, lo, hi, &a) || !args_int(x + 1, lo, hi, &b))
        return 0;
    *w = (int)a;
    *h = (int)b;
    return 1;
}

int args_check_outputs(const char *cmd, const bf_path_use *inputs, int ninputs, const bf_path_use *outputs,
                       int noutputs)
{
    bf_error err;
    int rc = bf_outputs_check(inputs, ninputs, outputs, noutputs, &err);
    if (rc == BF_OK)
        return 0;
    fprintf(stderr, "%s: %s\n", cmd, err.msg);
    return rc == BF_ERR_ARG ? 2 : 1;
}

/* Appends " word" to *text (a growing string; left as it was when out of memory), quoted
 * for a shell when it holds anything but plain characters. */
void args_append_word(char **text, const char *word)
{
    int plain = *word != '\0';
    for (const char *c = word; *c; c++)
        plain &= !!strchr("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-_./,:=+@%", *c);
    size_t old = *text ? strlen(*text) : 0, add = 4 * strlen(word) + 4;
    char *t = realloc(*text, old + add);
    if (!t)
        return;
    *text = t;
    char *at = t + old;
    if (old)
        *at++ = ' ';
    if (plain) {
        strcpy(at, word);
        return;
    }
    *at++ = '\'';
    for (const char *c = word; *c; c++) {
        if (*c == '\'') {
            memcpy(at, "'\\''", 4);
            at += 4;
        } else
            *at++ = *c;
    }
    *at++ = '\'';
    *at = '\0';
}
