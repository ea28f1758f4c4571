/* Numeric CSV tables with line-accurate errors. Only numbers in data cells: every
 * brdfit table (directions, samples) is numeric, and checking each cell here lets the
 * error name the line and column. */
#include "brdfit/io.h"
#include "base/big_alloc.h"
#include "base/cancel.h"
#include "io/read_options.h"
#include "brdfit/limits.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* The field starting at p, in place: blanks around it dropped; a field that starts
 * with '"' is quoted (RFC 4180: "" inside is one quote, commas are text), which is how
 * the writers keep names with commas, quotes or outer blanks. *out is the text, *quoted
 * whether it was quoted, *next where the following field starts. Returns 1 when a
 * comma follows, 0 at the end of the line, -1 for a quoted field without its closing
 * quote or with text after it. */
static int field(char *p, char **out, int *quoted, char **next)
{
    while (isspace((unsigned char)*p))
        p++;
    *out = p;
    *quoted = *p == '"';
    char *end, *e;
    if (*quoted) {
        char *r = p + 1;
        e = p; /* unescaped text is written from the field's start: it is never longer */
        for (;; r++) {
            if (!*r)
                return -1;
            if (*r == '"' && *++r != '"')
                break;
            *e++ = *r;
        }
        while (isspace((unsigned char)*r))
            r++;
        if (*r && *r != ',')
            return -1;
        end = r;
    } else {
        end = strchr(p, ',');
        if (!end)
            end = p + strlen(p);
        e = end;
        while (e > p && isspace((unsigned char)e[-1]))
            e--;
    }
    int more = *end == ',';
    *next = end + more;
    *e = '\0'; /* e <= end: may overwrite the comma, already noted */
    return more;
}

/* Splits line into fields in place; returns the field count (fields beyond max are
 * counted, not kept), or 0 with *bad set to the 1-based column of a broken quote.
 * quoted (may be NULL) gets whether each kept field was quoted. */
static size_t split(char *line, char **fields, unsigned char *quoted, size_t max, size_t *bad)
{
    size_t n = 0;
    for (char *p = line;;) {
        char *text;
        int q, more = field(p, &text, &q, &p);
        if (more < 0) {
            *bad = n + 1;
            return 0;
        }
        if (n < max) {
            fields[n] = text;
            if (quoted)
                quoted[n] = (unsigned char)q;
        }
        n++;
        if (!more)
            return n;
    }
}

/* A field that reads whole as a number (not quoted: "400" in quotes is a name). */
static int is_number(const char *text, int quoted)
{
    char *end;
    if (quoted || !*text)
        return 0;
    strtod(text, &end);
    return *end == '\0';
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

/* Room for more rows, or 0 with *need the bytes the table would take. */
static int grow(bf_csv *t, size_t *cap, size_t *need)
{
    /* A first block of about 64 kB whatever the width, then doubling. */
    size_t ncap = *cap ? 2 * *cap : 8192 / t->ncols + 1;
    *need = SIZE_MAX;
    if (ncap > SIZE_MAX / (sizeof(double) * t->ncols + sizeof(size_t)))
        return 0;
    *need = ncap * (t->ncols * sizeof(double) + sizeof(size_t));
    if (!bf_memory_allows(*need / 2)) /* the half already held is counted as used */
        return 0;
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

static int by_name(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The header row: names (quoted or not), none empty, none twice, not a row of numbers
 * (a file without a header), which spectral names such as "400" alone are not. Sets
 * t->names, t->ncols and *fields (room for a row's fields). */
static bf_status read_header(bf_csv *t, const char *path, size_t lineno, char *line, char ***fields, bf_error *err)
{
    size_t n = 1, bad = 0; /* an upper bound first: commas inside quotes are text */
    for (const char *q = line; *q; q++)
        n += *q == ',';
    if (n > BF_CSV_MAX_COLUMNS) /* counted by commas, quoted ones included */
        return bf_fail(err, BF_ERR_RANGE, "%s:%zu: the header has more than %d columns", path, lineno,
                       BF_CSV_MAX_COLUMNS);
    char **f = calloc(n, sizeof *f), **sorted = NULL;
    unsigned char *quoted = malloc(n);
    bf_status rc = BF_OK;
    *fields = f;
    if (!f || !quoted) {
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
        goto done;
    }
    if (!(n = split(line, f, quoted, n, &bad))) {
        rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: header column %zu: a quoted name must end with its quote", path,
                     lineno, bad);
        goto done;
    }
    size_t numbers = 0;
    for (size_t c = 0; c < n; c++) {
        if (!*f[c]) {
            rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: header column %zu has no name", path, lineno, c + 1);
            goto done;
        }
        numbers += is_number(f[c], quoted[c]);
    }
    if (numbers == n) {
        rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: header expected, found a row of numbers ('%s'%s)", path, lineno, f[0],
                     n > 1 ? ", ..." : "");
        goto done;
    }
    /* Sorted, so that wide headers are checked for repeats in n log n. */
    if (!(sorted = malloc(n * sizeof *sorted))) {
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
        goto done;
    }
    memcpy(sorted, f, n * sizeof *sorted);
    qsort(sorted, n, sizeof *sorted, by_name);
    for (size_t c = 1; c < n; c++)
        if (!strcmp(sorted[c - 1], sorted[c])) {
            rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: column '%s' appears twice", path, lineno, sorted[c]);
            goto done;
        }
    if (!(t->names = calloc(n, sizeof *t->names))) {
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
        goto done;
    }
    t->ncols = n;
    for (size_t c = 0; c < n; c++)
        if (!(t->names[c] = strdup(f[c]))) {
            rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
            goto done;
        }
done:
    free(quoted);
    free(sorted);
    return rc;
}

bf_status bf_csv_read(const char *path, bf_csv **out, bf_error *err)
{
    return bf_csv_read_cancellable(path, NULL, out, err);
}

bf_status bf_csv_read_cancellable(const char *path, const bf_cancel_flag *cancel, bf_csv **out, bf_error *err)
{
    *out = NULL;
    FILE *fp = bf_input_open(path);
    if (!fp)
        return bf_fail(err, BF_ERR_IO, "%s: cannot open: %s", path, bf_input_error(errno));
    bf_csv *t = calloc(1, sizeof *t);
    char *line = NULL, **fields = NULL;
    size_t linecap = 0, lineno = 0, cap = 0;
    ssize_t len;
    bf_status rc = BF_OK;
    if (!t) {
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
        goto done;
    }
    while ((len = getline(&line, &linecap, fp)) >= 0) {
        lineno++;
        if (bf_cancel_is_set(cancel)) { /* every line: one load, cheap beside parsing it */
            rc = bf_read_cancelled(path, err);
            goto done;
        }
        if (memchr(line, '\0', (size_t)len)) {
            rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: binary data (NUL byte) in a CSV file", path, lineno);
            goto done;
        }
        if (is_skippable(line))
            continue;
        if (!t->names) { /* header */
            if ((rc = read_header(t, path, lineno, line, &fields, err)) != BF_OK)
                goto done;
            continue;
        }
        size_t bad = 0, n = split(line, fields, NULL, t->ncols, &bad);
        if (bad) {
            rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: field %zu: a quoted field must end with its quote", path, lineno,
                         bad);
            goto done;
        }
        if (n != t->ncols) {
            rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: expected %zu fields, found %zu", path, lineno, t->ncols, n);
            goto done;
        }
        size_t need;
        if (t->nrows == cap && !grow(t, &cap, &need)) {
            rc = bf_fail_memory(err, path, lineno, need);
            goto done;
        }
        double *row = t->data + t->nrows * t->ncols;
        for (size_t c = 0; c < n; c++) {
            char *end;
            errno = 0;
            double v = strtod(fields[c], &end);
            if (!*fields[c] || *end) {
                rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: column %s: '%s' is not a number", path, lineno, t->names[c],
                             fields[c]);
                goto done;
            }
            if (!isfinite(v)) {
                rc = bf_fail(err, BF_ERR_RANGE, "%s:%zu: column %s: %s is not a finite number", path, lineno,
                             t->names[c], fields[c]);
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
