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
    numbers num = {NULL, 0, 0};
    bf_samples *s = NULL;
    char *line = NULL;
    size_t linecap = 0, lineno = 0, nwl = 0, record_len = 0;
    size_t record_line = 0; /* line where the last (possibly incomplete) record starts */
    /* The pbrt files hold one record per line; when a count is off, the first record that
     * does not start a line shows where a number went missing or extra. */
    int line_aligned = 1;
    size_t misaligned_line = 0;
    ssize_t len;
    bf_status rc = BF_OK;

    while ((len = getline(&line, &linecap, fp)) >= 0) {
        lineno++;
        if (bf_cancel_is_set(cancel)) {
            rc = bf_read_cancelled(path, err);
            goto done;
        }
        if (memchr(line, '\0', (size_t)len)) {
            rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: binary data (NUL byte) in a Cornell text file", path, lineno);
            goto done;
        }
        char *hash = strchr(line, '#');
        if (hash)
            *hash = '\0';
        int first_token = 1;
        for (char *p = line;; first_token = 0) {
            while (isspace((unsigned char)*p))
                p++;
            if (!*p)
                break;
            char *tok = p;
            while (*p && !isspace((unsigned char)*p))
                p++;
            int tlen = (int)(p - tok);
            char *end;
            double x = strtod(tok, &end);
            if (end != p) {
                rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: '%.*s' is not a number", path, lineno, tlen > 40 ? 40 : tlen,
                             tok);
                goto done;
            }
            if (!isfinite(x)) {
                rc = bf_fail(err, BF_ERR_RANGE, "%s:%zu: %.*s is not a finite number", path, lineno,
                             tlen > 40 ? 40 : tlen, tok);
                goto done;
            }
            size_t t = num.n; /* this token's index in the stream */
            int where = t == 0 ? IN_COUNT : t <= nwl ? IN_WAVELENGTHS : IN_RECORDS;
            if (where == IN_COUNT) {
                if (x < 0.0) {
                    rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: the wavelength count %.*s is negative", path, lineno, tlen,
                                 tok);
                    goto done;
                }
                if (x != floor(x) || x < 1.0 || x > BF_MAX_CHANNELS) {
                    rc = bf_fail(err, BF_ERR_PARSE,
                                 "%s:%zu: the file must start with the wavelength count (an integer from 1 "
                                 "to %d), found %.*s",
                                 path, lineno, BF_MAX_CHANNELS, tlen > 40 ? 40 : tlen, tok);
                    goto done;
                }
                nwl = (size_t)x;
                record_len = 4 + nwl;
            } else if (where == IN_WAVELENGTHS) {
                if (x <= 0.0) {
                    rc = bf_fail(err, BF_ERR_RANGE, "%s:%zu: wavelength %zu is %.*s nm; wavelengths are positive", path,
                                 lineno, t, tlen, tok);
                    goto done;
                }
                for (size_t k = 1; k < t; k++)
                    if (num.v[k] == x) {
                        rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: wavelength %.*s nm appears twice", path, lineno, tlen,
                                     tok);
                        goto done;
                    }
            } else {
                size_t pos = (t - 1 - nwl) % record_len; /* position within the record */
                if (pos == 0) {
                    record_line = lineno;
                    if (line_aligned && !first_token) {
                        line_aligned = 0;
                        misaligned_line = t == 1 + nwl ? 0 : lineno; /* 0: not a per-line file */
                    }
                }
                /* theta beyond [0, pi] names no direction; beyond pi/2 it is a direction
                 * below the horizon, which is data (preprocessing drops it). */
                if ((pos == 0 || pos == 2) && (x < -ANGLE_SLACK || x > M_PI + ANGLE_SLACK)) {
                    rc = bf_fail(err, BF_ERR_RANGE, "%s:%zu: record %zu: %s = %.*s rad is outside [0, pi]", path,
                                 lineno, (t - 1 - nwl) / record_len + 1, pos == 0 ? "theta_i" : "theta_s", tlen, tok);
                    goto done;
                }
                /* Within the slack, on the bound: a theta of 3.141593 (pi rounded up) is pi,
                 * so the samples hold no angle the other readers refuse (CSV, when
                 * converted: theta in [0, 180] degrees). */
                if (pos == 0 || pos == 2)
                    x = x < 0.0 ? 0.0 : x > M_PI ? M_PI : x;
            }
            if (!push(&num, x)) {
                rc = bf_fail_memory(err, path, lineno, 2 * num.cap * sizeof(double));
                goto done;
            }
        }
    }
    if (ferror(fp)) {
        rc = bf_fail(err, BF_ERR_IO, "%s: read error after line %zu", path, lineno);
        goto done;
    }
    if (num.n == 0) {
        rc = bf_fail(err, BF_ERR_PARSE, "%s: empty file (no wavelength count)", path);
        goto done;
    }
    if (num.n < 1 + nwl) {
        rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: the file ends within the wavelength list (%zu announced, %zu given)",
                     path, lineno, nwl, num.n - 1);
        goto done;
    }
    size_t body = num.n - 1 - nwl, n = body / record_len;
    if (body % record_len) {
        if (misaligned_line)
            rc = bf_fail(err, BF_ERR_PARSE,
                         "%s:%zu: a record starts mid-line: the one before has a number too many or too few "
                         "(records are theta_i phi_i theta_s phi_s and %zu values)",
                         path, misaligned_line, nwl);
        else
            rc = bf_fail(err, BF_ERR_PARSE,
                         "%s:%zu: incomplete record %zu: records are theta_i phi_i theta_s phi_s and %zu values "
                         "(%zu numbers), the last has %zu (truncated or malformed)",
                         path, record_line, n + 1, nwl, record_len, body % record_len);
        goto done;
    }
    if (n == 0) {
        rc = bf_fail(err, BF_ERR_PARSE, "%s:%zu: no records after the %zu wavelengths", path, lineno, nwl);
        goto done;
    }
    if ((rc = bf_samples_new(n, (int)nwl, &s, err)) != BF_OK) {
        goto done;
    }
    if (!(s->wavelength = malloc(nwl * sizeof *s->wavelength))) {
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
        goto done;
    }
    for (size_t c = 0; c < nwl; c++) {
        char buf[40];
        s->wavelength[c] = num.v[1 + c];
        if ((rc = bf_samples_set_channel_name(s, (int)c, bf_format_double(num.v[1 + c], buf, sizeof buf), err)) !=
            BF_OK)
            goto done;
    }
    const double to_deg = 180.0 / M_PI;
    for (size_t i = 0; i < n; i++) {
        const double *r = num.v + 1 + nwl + i * record_len;
        s->theta_i[i] = r[0] * to_deg;
        s->phi_i[i] = r[1] * to_deg;
        s->theta_o[i] = r[2] * to_deg;
        s->phi_o[i] = r[3] * to_deg;
        memcpy(s->value + i * nwl, r + 4, nwl * sizeof *s->value);
    }
done:
    free(line);
    free(num.v);
    fclose(fp);
    if (rc != BF_OK) {
        bf_samples_free(s);
        return rc;
    }
    *out = s;
    return BF_OK;
}
