/* Whole-file reading for the JSON readers (see read_text.h). */
#include "brdfit/io.h"
#include "read_text.h"

#include "base/cancel.h"
#include "io/read_options.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* 1-based line of byte offset off. */
static size_t line_of(const char *text, size_t off)
{
    size_t line = 1;
    for (size_t i = 0; i < off; i++)
        line += text[i] == '\n';
    return line;
}

bf_status bf_read_text(const char *path, char **text, size_t *len, bf_error *err)
{
    *text = NULL;
    FILE *fp = bf_input_open(path);
    if (!fp)
        return bf_fail(err, BF_ERR_IO, "%s: cannot open: %s", path, bf_input_error(errno));
    size_t cap = 4096, n = 0;
    char *buf = malloc(cap);
    while (buf) {
        n += fread(buf + n, 1, cap - n - 1, fp);
        if (n < cap - 1)
            break;
        char *nb = realloc(buf, cap *= 2);
        if (!nb)
            free(buf);
        buf = nb;
    }
    int bad = ferror(fp);
    fclose(fp);
    if (!buf || bad) {
        free(buf);
        return bf_fail(err, bad ? BF_ERR_IO : BF_ERR_NOMEM, "%s: cannot read", path);
    }
    buf[n] = '\0';
    if (strlen(buf) != n) {
        bf_status rc =
            bf_fail(err, BF_ERR_PARSE, "%s:%zu: not a text file (a NUL byte)", path, line_of(buf, strlen(buf)));
        free(buf);
        return rc;
    }
    *len = n;
    *text = buf;
    return BF_OK;
}

bf_status bf_read_lines(FILE *fp, const char *path, const bf_cancel_flag *cancel, size_t *lineno, bf_line_fn each,
                        void *user, bf_error *err)
{
    char *line = NULL;
    size_t linecap = 0;
    ssize_t len;
    bf_status rc = BF_OK;
    while (rc == BF_OK && (len = getline(&line, &linecap, fp)) >= 0) {
        ++*lineno;
        if (bf_cancel_is_set(cancel))
            rc = bf_read_cancelled(path, err);
        else
            rc = each(user, line, (size_t)len);
    }
    free(line);
    if (rc == BF_OK && ferror(fp))
        rc = bf_fail(err, BF_ERR_IO, "%s: read error after line %zu", path, *lineno);
    return rc;
}
