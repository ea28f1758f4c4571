/* Cornell Program of Computer Graphics spectral BRDF text (.brdf, as shipped with
 * pbrt-v2 in scenes/brdfs/). '#' starts a comment to the end of the line; what is left
 * is one flat stream of whitespace-separated numbers, not one record per line:
 *
 *   numWls  wl_1 .. wl_numWls  { theta_i phi_i theta_s phi_s v_1 .. v_numWls }*
 *
 * Angles in radians, both directions pointing away from the surface (the mirror
 * direction is theta_s = theta_i, phi_s = phi_i + pi), which is this library's
 * convention for (theta_i, phi_i, theta_o, phi_o). Values: spectral BRDF in 1/sr.
 * One channel per wavelength, named by it ("400"). */
#include "brdfit/formats.h"
#include "brdfit/io.h"
#include "brdfit/samples.h"
#include "base/big_alloc.h"
#include "base/cancel.h"
#include "io/read_options.h"
#include "io/read_text.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The files give radians with six decimals: pi/2 is written 1.570796 and pi 3.141593,
 * so a bound may be exceeded by rounding alone. */
#define ANGLE_SLACK 1e-6

typedef struct numbers {
    double *v;
    size_t n, cap;
} numbers;

static int push(numbers *a, double x)
{
    if (a->n == a->cap) {
        size_t cap = a->cap ? 2 * a->cap : 4096;
        if (cap > SIZE_MAX / sizeof(double) || !bf_memory_allows(a->cap * sizeof(double)))
            return 0; /* doubling: the new half must be available */
        double *v = realloc(a->v, cap * sizeof *v);
        if (!v)
            return 0;
        a->v = v;
        a->cap = cap;
    }
    a->v[a->n++] = x;
    return 1;
}

/* Where a token sits in the stream: the count, the wavelengths, the records. */
enum { IN_COUNT, IN_WAVELENGTHS, IN_RECORDS };

/* One read: the file, where it is, the numbers read so far and what the count announced.
 * The phases below fill it in order (read_stream, check_counts, build_samples). */
typedef struct cornell_reader {
    const char *path;
    FILE *fp;
    bf_error *err;
    size_t lineno;
    numbers num;
    size_t nwl, record_len;
    size_t record_line; /* line where the last (possibly incomplete) record starts */
    /* The pbrt files hold one record per line; when a count is off, the first record that
     * does not start a line shows where a number went missing or extra. */
    int line_aligned;
    size_t misaligned_line;
} cornell_reader;

/* One token of the stream as text, and whether it starts its line. */
typedef struct token {
    const char *text;
    int len;
    int first;
} token;

/* The first number: the wavelength count. */
static bf_status read_count(cornell_reader *rd, double x, const token *tk)
{
    const int tlen = tk->len;
    if (x < 0.0)
        return bf_fail(rd->err, BF_ERR_PARSE, "%s:%zu: the wavelength count %.*s is negative", rd->path, rd->lineno,
                       tlen, tk->text);
    if (x != floor(x) || x < 1.0 || x > BF_MAX_CHANNELS)
        return bf_fail(rd->err, BF_ERR_PARSE,
                       "%s:%zu: the file must start with the wavelength count (an integer from 1 "
                       "to %d), found %.*s",
                       rd->path, rd->lineno, BF_MAX_CHANNELS, tlen > 40 ? 40 : tlen, tk->text);
    rd->nwl = (size_t)x;
    rd->record_len = 4 + rd->nwl;
    return BF_OK;
}

/* Wavelength t (1-based): positive and not given before. */
static bf_status read_wavelength(cornell_reader *rd, size_t t, double x, const token *tk)
{
    if (x <= 0.0)
        return bf_fail(rd->err, BF_ERR_RANGE, "%s:%zu: wavelength %zu is %.*s nm; wavelengths are positive", rd->path,
                       rd->lineno, t, tk->len, tk->text);
    for (size_t k = 1; k < t; k++)
        if (rd->num.v[k] == x)
            return bf_fail(rd->err, BF_ERR_PARSE, "%s:%zu: wavelength %.*s nm appears twice", rd->path, rd->lineno,
                           tk->len, tk->text);
    return BF_OK;
}

/* Number t of the stream within a record: notes where records start, checks the thetas
 * and clamps them (*x) onto [0, pi] within the slack. */
static bf_status read_record_number(cornell_reader *rd, size_t t, double *x, const token *tk)
{
    const size_t nwl = rd->nwl, record_len = rd->record_len;
    size_t pos = (t - 1 - nwl) % record_len; /* position within the record */
    if (pos == 0) {
        rd->record_line = rd->lineno;
        if (rd->line_aligned && !tk->first) {
            rd->line_aligned = 0;
            rd->misaligned_line = t == 1 + nwl ? 0 : rd->lineno; /* 0: not a per-line file */
        }
    }
    /* theta beyond [0, pi] names no direction; beyond pi/2 it is a direction
     * below the horizon, which is data (preprocessing drops it). */
    if ((pos == 0 || pos == 2) && (*x < -ANGLE_SLACK || *x > M_PI + ANGLE_SLACK))
        return bf_fail(rd->err, BF_ERR_RANGE, "%s:%zu: record %zu: %s = %.*s rad is outside [0, pi]", rd->path,
                       rd->lineno, (t - 1 - nwl) / record_len + 1, pos == 0 ? "theta_i" : "theta_s", tk->len, tk->text);
    /* Within the slack, on the bound: a theta of 3.141593 (pi rounded up) is pi,
     * so the samples hold no angle the other readers refuse (CSV, when
     * converted: theta in [0, 180] degrees). */
    if (pos == 0 || pos == 2)
        *x = *x < 0.0 ? 0.0 : *x > M_PI ? M_PI : *x;
    return BF_OK;
}

/* One token: a finite number, checked for its place in the stream and appended. */
static bf_status read_token(cornell_reader *rd, const token *tk)
{
    const int tlen = tk->len;
    char *end;
    double x = strtod(tk->text, &end);
    if (end != tk->text + tlen)
        return bf_fail(rd->err, BF_ERR_PARSE, "%s:%zu: '%.*s' is not a number", rd->path, rd->lineno,
                       tlen > 40 ? 40 : tlen, tk->text);
    if (!isfinite(x))
        return bf_fail(rd->err, BF_ERR_RANGE, "%s:%zu: %.*s is not a finite number", rd->path, rd->lineno,
                       tlen > 40 ? 40 : tlen, tk->text);
    size_t t = rd->num.n; /* this token's index in the stream */
    int where = t == 0 ? IN_COUNT : t <= rd->nwl ? IN_WAVELENGTHS : IN_RECORDS;
    bf_status rc = where == IN_COUNT         ? read_count(rd, x, tk)
                   : where == IN_WAVELENGTHS ? read_wavelength(rd, t, x, tk)
                                             : read_record_number(rd, t, &x, tk);
    if (rc != BF_OK)
        return rc;
    if (!push(&rd->num, x))
        return bf_fail_memory(rd->err, rd->path, rd->lineno, 2 * rd->num.cap * sizeof(double));
    return BF_OK;
}

/* One line: its numbers up to a '#'. */
static bf_status read_line(cornell_reader *rd, char *line, size_t len)
{
    if (memchr(line, '\0', len))
        return bf_fail(rd->err, BF_ERR_PARSE, "%s:%zu: binary data (NUL byte) in a Cornell text file", rd->path,
                       rd->lineno);
    char *hash = strchr(line, '#');
    if (hash)
        *hash = '\0';
    token tk = {NULL, 0, 1};
    for (char *p = line;; tk.first = 0) {
        while (isspace((unsigned char)*p))
            p++;
        if (!*p)
            break;
        char *tok = p;
        while (*p && !isspace((unsigned char)*p))
            p++;
        tk.text = tok;
        tk.len = (int)(p - tok);
        bf_status rc = read_token(rd, &tk);
        if (rc != BF_OK)
            return rc;
    }
    return BF_OK;
}

static bf_status each_line(void *user, char *line, size_t len)
{
    return read_line(user, line, len);
}

/* Every line of the file into rd->num. */
static bf_status read_stream(cornell_reader *rd, const bf_cancel_flag *cancel)
{
    return bf_read_lines(rd->fp, rd->path, cancel, &rd->lineno, each_line, rd, rd->err);
}

/* The stream holds the count, every wavelength and whole records, at least one: their
 * number into *n. */
static bf_status check_counts(const cornell_reader *rd, size_t *n)
{
    const char *path = rd->path;
    const size_t nwl = rd->nwl, record_len = rd->record_len;
    if (rd->num.n == 0)
        return bf_fail(rd->err, BF_ERR_PARSE, "%s: empty file (no wavelength count)", path);
    if (rd->num.n < 1 + nwl)
        return bf_fail(rd->err, BF_ERR_PARSE,
                       "%s:%zu: the file ends within the wavelength list (%zu announced, %zu given)", path, rd->lineno,
                       nwl, rd->num.n - 1);
    size_t body = rd->num.n - 1 - nwl;
    *n = body / record_len;
    if (body % record_len) {
        if (rd->misaligned_line)
            return bf_fail(rd->err, BF_ERR_PARSE,
                           "%s:%zu: a record starts mid-line: the one before has a number too many or too few "
                           "(records are theta_i phi_i theta_s phi_s and %zu values)",
                           path, rd->misaligned_line, nwl);
        return bf_fail(rd->err, BF_ERR_PARSE,
                       "%s:%zu: incomplete record %zu: records are theta_i phi_i theta_s phi_s and %zu values "
                       "(%zu numbers), the last has %zu (truncated or malformed)",
                       path, rd->record_line, *n + 1, nwl, record_len, body % record_len);
    }
    if (*n == 0)
        return bf_fail(rd->err, BF_ERR_PARSE, "%s:%zu: no records after the %zu wavelengths", path, rd->lineno, nwl);
    return BF_OK;
}

/* The n records as samples (*s, freed by the caller on failure): a channel per
 * wavelength, angles in degrees. */
static bf_status build_samples(const cornell_reader *rd, size_t n, bf_samples **s)
{
    const size_t nwl = rd->nwl, record_len = rd->record_len;
    const double *v = rd->num.v;
    bf_status rc;
    if ((rc = bf_samples_new(n, (int)nwl, s, rd->err)) != BF_OK)
        return rc;
    bf_samples *sm = *s;
    if (!(sm->wavelength = malloc(nwl * sizeof *sm->wavelength)))
        return bf_fail(rd->err, BF_ERR_NOMEM, "%s: out of memory", rd->path);
    for (size_t c = 0; c < nwl; c++) {
        char buf[40];
        sm->wavelength[c] = v[1 + c];
        if ((rc = bf_samples_set_channel_name(sm, (int)c, bf_format_double(v[1 + c], buf, sizeof buf), rd->err)) !=
            BF_OK)
            return rc;
    }
    const double to_deg = 180.0 / M_PI;
    for (size_t i = 0; i < n; i++) {
        const double *r = v + 1 + nwl + i * record_len;
        sm->theta_i[i] = r[0] * to_deg;
        sm->phi_i[i] = r[1] * to_deg;
        sm->theta_o[i] = r[2] * to_deg;
        sm->phi_o[i] = r[3] * to_deg;
        memcpy(sm->value + i * nwl, r + 4, nwl * sizeof *sm->value);
    }
    return BF_OK;
}

bf_status bf_samples_read_cornell(const char *path, bf_samples **out, bf_error *err)
{
    return bf_samples_read_cornell_cancellable(path, NULL, out, err);
}

bf_status bf_samples_read_cornell_cancellable(const char *path, const bf_cancel_flag *cancel, bf_samples **out,
                                              bf_error *err)
{
    *out = NULL;
    FILE *fp = bf_input_open(path);
    if (!fp)
        return bf_fail(err, BF_ERR_IO, "%s: cannot open: %s", path, bf_input_error(errno));
    cornell_reader rd = {.path = path, .fp = fp, .err = err, .line_aligned = 1};
    bf_samples *s = NULL;
    size_t n = 0;
    bf_status rc = read_stream(&rd, cancel);
    if (rc == BF_OK)
        rc = check_counts(&rd, &n);
    if (rc == BF_OK)
        rc = build_samples(&rd, n, &s);
    free(rd.num.v);
    fclose(fp);
    if (rc != BF_OK) {
        bf_samples_free(s);
        return rc;
    }
    *out = s;
    return BF_OK;
}
