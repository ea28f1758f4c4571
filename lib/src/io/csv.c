/* Numeric CSV tables with line-accurate errors. Only numbers in data cells: every
 * brdfit table (directions, samples) is numeric, and checking each cell here lets the
 * error name the line and column. */
#include "brdfit/io.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static char *trim(char *s)
{
    while (isspace((unsigned char)*s))
        s++;
    char *e = s + strlen(s);
    while (e > s && isspace((unsigned char)e[-1]))
        *--e = '\0';
    if (e - s >= 2 && *s == '"' && e[-1] == '"') { /* a quoted header name */
        e[-1] = '\0';
        s++;
    }
    return s;
}

/* Splits line at commas in place; returns the field count (fields beyond max dropped). */
static size_t split(char *line, char **fields, size_t max)
{
    size_t n = 0;
    for (char *p = line;;) {
        char *comma = strchr(p, ',');
        if (comma)
            *comma = '\0';
        if (n < max)
            fields[n] = trim(p);
        n++;
        if (!comma)
            return n;
        p = comma + 1;
    }
}

static int is_skippable(const char *line)
{
    while (isspace((unsigned char)*line))
        line++;
    return *line == '\0' || *line == '#';
}

void bf_csv_free(bf_csv *t)
{
    if (!t)
        return;
    for (size_t c = 0; t->names && c < t->ncols; c++)
        free(t->names[c]);
    free(t->names);
    free(t->data);
    free(t->line);
    free(t);
}

int bf_csv_column(const bf_csv *t, const char *name)
{
    for (size_t c = 0; c < t->ncols; c++)
        if (strcmp(t->names[c], name) == 0)
            return (int)c;
    return -1;
}

static int grow(bf_csv *t, size_t *cap)
{
    size_t ncap = *cap ? 2 * *cap : 1024;
    double *d = realloc(t->data, ncap * t->ncols * sizeof *d);
    if (!d)
        return 0;
    t->data = d;
    size_t *l = realloc(t->line, ncap * sizeof *l);
    if (!l)
        return 0;
    t->line = l;
    *cap = ncap;
    return 1;
}

int bf_csv_read(const char *path, bf_csv **out, bf_error *err)
{
    *out = NULL;
    FILE *fp = fopen(path, "r");
    if (!fp)
        return bf_fail(err, BF_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    bf_csv *t = calloc(1, sizeof *t);
    char *line = NULL, **fields = NULL;
    size_t linecap = 0, lineno = 0, cap = 0;
    ssize_t len;
    int rc = BF_OK;
    if (!t) {
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
        goto done;
    }
    while ((len = getline(&line, &linecap, fp)) >= 0) {
        lineno++;
        if (memchr(line, '\0', (size_t)len)) {
            rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: binary data (NUL byte) in a CSV file", path, lineno);
            goto done;
        }
        if (is_skippable(line))
            continue;
        if (!t->names) { /* header */
            size_t n = 1;
            for (const char *q = line; *q; q++)
                n += *q == ',';
            t->names = calloc(n, sizeof *t->names);
            fields = calloc(n, sizeof *fields);
            if (!t->names || !fields) {
                rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
                goto done;
            }
            t->ncols = n;
            split(line, fields, n);
            for (size_t c = 0; c < n; c++) {
                if (!*fields[c]) {
                    rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: header column %zu has no name", path, lineno, c + 1);
                    goto done;
                }
                char *end;
                strtod(fields[c], &end);
                if (*end == '\0') {
                    rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: header expected, found a number ('%s')",
                                 path, lineno, fields[c]);
                    goto done;
                }
                for (size_t d = 0; d < c; d++)
                    if (strcmp(t->names[d], fields[c]) == 0) {
                        rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: column '%s' appears twice", path, lineno, fields[c]);
                        goto done;
                    }
                t->names[c] = strdup(fields[c]);
            }
            continue;
        }
        size_t n = split(line, fields, t->ncols);
        if (n != t->ncols) {
            rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: expected %zu fields, found %zu", path, lineno, t->ncols, n);
            goto done;
        }
        if (t->nrows == cap && !grow(t, &cap)) {
            rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory at line %zu", path, lineno);
            goto done;
        }
        double *row = t->data + t->nrows * t->ncols;
        for (size_t c = 0; c < n; c++) {
            char *end;
            errno = 0;
            double v = strtod(fields[c], &end);
            if (!*fields[c] || *end) {
                rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: column %s: '%s' is not a number", path, lineno,
                             t->names[c], fields[c]);
                goto done;
            }
            if (!isfinite(v)) {
                rc = bf_fail(err, BF_ERR_RANGE, "%s:%zu: column %s: %s is not a finite number", path,
                             lineno, t->names[c], fields[c]);
                goto done;
            }
            row[c] = v;
        }
        t->line[t->nrows++] = lineno;
    }
    if (ferror(fp)) {
        rc = bf_fail(err, BF_ERR_IO, "%s: read error after line %zu: %s", path, lineno, strerror(errno));
        goto done;
    }
    if (!t->names)
        rc = bf_fail(err, BF_ERR_PARSE, "%s: empty file (a header row is required)", path);
done:
    free(line);
    free(fields);
    fclose(fp);
    if (rc != BF_OK) {
        bf_csv_free(t);
        return rc;
    }
    *out = t;
    return BF_OK;
}
