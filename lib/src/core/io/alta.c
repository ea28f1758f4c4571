/* ALTA text data (github.com/belcour/alta): a header of '#KEY value' lines, then one
 * sample per line, nin coordinates and nout values separated by blanks or tabs.
 *
 *   #DIM nin nout                  coordinates and values per row
 *   #PARAM_IN  <parametrisation>   what the nin coordinates mean (radians)
 *   #PARAM_OUT <unit>              what the nout values mean
 *   #VS 0|1|2                      optional: 1 or 2 extra numbers per row
 *
 * Conventions follow ALTA's sources/core/params.h and params.cpp (params::to_cartesian,
 * half_to_cartesian, classical_to_cartesian) and sources/core/args.h
 * (arguments::parse_header: '# ' with a blank after the hash is a comment, '#KEY' a
 * key). '#VS' marks the vertical segments of Pacanowski et al. 2012, confidence
 * intervals on the value (data_storage.cpp, read_confidence_interval: 1 = a half-width,
 * 2 = a lower and an upper bound), not variances: they are checked and ignored.
 *
 * Where ALTA and this library differ: ALTA's CARTESIAN packs the view vector first
 * ([V, L], params.h), kept here; for half/difference angles ALTA calls the rotated
 * difference vector V, while this library uses the Rusinkiewicz and MERL convention of
 * docs/formats.md (L is the difference vector rotated by theta_h about Y, V mirrors L about
 * H). For reciprocal data the two name the same pair of directions, swapped. */
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

/* Text rounding alone can push an angle or a cosine just past its bound (pi/2 written
 * 1.570796 is below it, 1.5708 above); within these it is clamped, beyond an error. */
#define ANGLE_SLACK 1e-4
#define COS_SLACK 1e-9
/* Unit vectors written with a few digits; a length further from 1 is a wrong column. */
#define UNIT_SLACK 1e-3

typedef enum {
    P_COS_TH,
    P_COS_TH_TD,
    P_RUSIN_TH_TD,
    P_RUSIN_TH_TD_PD,
    P_RUSIN_TH_PH_TD_PD,
    P_RUSIN_VH,
    P_ISOTROPIC_TV_TL_DPHI,
    P_ISOTROPIC_TL_TV_PROJ_DPHI,
    P_SPHERICAL_TL_PL_TV_PV,
    P_CARTESIAN,
} param_in;

static const struct {
    const char *name;
    int dim;
} inputs[] = {
    [P_COS_TH] = {"COS_TH", 1},
    [P_COS_TH_TD] = {"COS_TH_TD", 2},
    [P_RUSIN_TH_TD] = {"RUSIN_TH_TD", 2},
    [P_RUSIN_TH_TD_PD] = {"RUSIN_TH_TD_PD", 3},
    [P_RUSIN_TH_PH_TD_PD] = {"RUSIN_TH_PH_TD_PD", 4},
    [P_RUSIN_VH] = {"RUSIN_VH", 3},
    [P_ISOTROPIC_TV_TL_DPHI] = {"ISOTROPIC_TV_TL_DPHI", 3},
    [P_ISOTROPIC_TL_TV_PROJ_DPHI] = {"ISOTROPIC_TL_TV_PROJ_DPHI", 3},
    [P_SPHERICAL_TL_PL_TV_PV] = {"SPHERICAL_TL_PL_TV_PV", 4},
    [P_CARTESIAN] = {"CARTESIAN", 6},
};
#define N_INPUTS ((int)(sizeof inputs / sizeof inputs[0]))

/* ALTA names whose mapping to directions is degenerate (one direction fixed at the
 * normal, vectors that are not unit length) or a research parametrisation: named in
 * the error so the user knows the file is ALTA data that needs converting first. */
static const char *const unsupported_inputs[] = {
    "COS_TK",
    "COS_TLV",
    "COS_TLR",
    "ISOTROPIC_TV_PROJ_DPHI",
    "STARK_2D",
    "NEUMANN_2D",
    "SCHLICK_VH",
    "SCHLICK_TL_TK_PROJ_DPHI",
    "RETRO_TL_TVL_PROJ_DPHI",
    "STARK_3D",
    "NEUMANN_3D",
    "STEREOGRAPHIC",
};

typedef enum { O_INV_STERADIAN, O_INV_STERADIAN_COSINE_FACTOR, O_RGB_COLOR, O_XYZ_COLOR } param_out;

static const char *const outputs[] = {"INV_STERADIAN", "INV_STERADIAN_COSINE_FACTOR", "RGB_COLOR", "XYZ_COLOR"};
#define N_OUTPUTS ((int)(sizeof outputs / sizeof outputs[0]))

typedef struct header {
    int nin, nout, vs;
    int in, out;                        /* -1 until given */
    size_t dim_line, in_line, out_line; /* where each was given; 0 = not yet */
} header;

typedef struct rows {
    double *v; /* per row: theta_i, phi_i, theta_o, phi_o (degrees), nout values */
    size_t n, cap, width;
} rows;

static double *row_slot(rows *r)
{
    if (r->n == r->cap) {
        /* A first block of about 64 kB whatever the width, then doubling. */
        size_t cap = r->cap ? 2 * r->cap : 8192 / r->width + 1;
        if (cap > SIZE_MAX / sizeof(double) / r->width || !bf_memory_allows(r->cap * r->width * sizeof(double)))
            return NULL; /* doubling: the new half must be available */
        double *v = realloc(r->v, cap * r->width * sizeof *v);
        if (!v)
            return NULL;
        r->v = v;
        r->cap = cap;
    }
    return r->v + r->n++ * r->width;
}

/* ---- Directions ---------------------------------------------------------------- */

static const double to_deg = 180.0 / M_PI;

/* Polar and azimuthal angle of d (any length > 0), in degrees. A z within 1e-15 of zero
 * (relative) is on the horizon, exactly 90 degrees, as bf_geometry treats it. */
static void angles_of(const double d[3], double *theta, double *phi)
{
    double r = hypot(d[0], d[1]);
    double len = hypot(r, d[2]);
    *theta = fabs(d[2]) <= 1e-15 * len ? 90.0 : atan2(r, d[2]) * to_deg;
    *phi = r > 0.0 ? atan2(d[1], d[0]) * to_deg : 0.0;
}

/* Rusinkiewicz half/difference angles to L and V: the difference vector rotated by
 * theta_h about Y, then by phi_h about Z, is L; V mirrors L about H. */
static void half_diff(double th, double ph, double td, double pd, double L[3], double V[3])
{
    const double d[3] = {sin(td) * cos(pd), sin(td) * sin(pd), cos(td)};
    const double x = d[0] * cos(th) + d[2] * sin(th), y = d[1], z = -d[0] * sin(th) + d[2] * cos(th);
    L[0] = x * cos(ph) - y * sin(ph);
    L[1] = x * sin(ph) + y * cos(ph);
    L[2] = z;
    const double H[3] = {sin(th) * cos(ph), sin(th) * sin(ph), cos(th)};
    const double lh = L[0] * H[0] + L[1] * H[1] + L[2] * H[2];
    for (int k = 0; k < 3; k++)
        V[k] = 2.0 * lh * H[k] - L[k];
}

/* A coordinate's domain: [lo, hi], widened by slack for text rounding, and how the
 * message names it. */
typedef struct domain {
    double lo, hi, slack;
    const char *bounds;
} domain;

static const domain cos_any = {-1.0, 1.0, COS_SLACK, "[-1, 1]"};
static const domain cos_upper = {0.0, 1.0, COS_SLACK, "[0, 1]"};
static const domain theta_any = {0.0, M_PI, ANGLE_SLACK, "[0, pi]"};
static const domain theta_upper = {0.0, M_PI / 2, ANGLE_SLACK, "[0, pi/2]"};

/* x clamped into d when within its slack; 0 (and *msg set) beyond. */
static int in_range(double *x, const domain *d, const char *what, char *msg, size_t size)
{
    const double lo = d->lo, hi = d->hi;
    if (*x < lo - d->slack || *x > hi + d->slack) {
        snprintf(msg, size, "%s = %.10g is outside %s", what, *x, d->bounds);
        return 0;
    }
    *x = *x < lo ? lo : *x > hi ? hi : *x;
    return 1;
}

static int unit(const double *d, const char *what, char *msg, size_t size)
{
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(fabs(len - 1.0) <= UNIT_SLACK)) {
        snprintf(msg, size, "%s has length %.6g, not 1", what, len);
        return 0;
    }
    return 1;
}

/* The row's coordinates x (ALTA radians) as theta_i, phi_i, theta_o, phi_o in degrees
 * (ang[4]); 0 with msg on a coordinate outside the parametrisation's domain. */
static int directions(param_in p, double *x, double ang[4], char *msg, size_t size)
{
    double L[3], V[3];
    switch (p) {
    case P_COS_TH: /* half_to_cartesian(acos x0, 0, 0, 0): L = V = H */
        if (!in_range(&x[0], &cos_any, "cos theta_h", msg, size))
            return 0;
        half_diff(acos(x[0]), 0.0, 0.0, 0.0, L, V);
        break;
    case P_COS_TH_TD: /* half_to_cartesian(acos x0, 0, acos x1, 0) */
        if (!in_range(&x[0], &cos_any, "cos theta_h", msg, size) ||
            !in_range(&x[1], &cos_upper, "cos theta_d", msg, size))
            return 0;
        half_diff(acos(x[0]), 0.0, acos(x[1]), 0.0, L, V);
        break;
    case P_RUSIN_TH_TD: /* ALTA fixes phi_d = pi/2: half_to_cartesian(x0, 0, x1, pi/2) */
    case P_RUSIN_TH_TD_PD:
    case P_RUSIN_TH_PH_TD_PD: {
        const int four = p == P_RUSIN_TH_PH_TD_PD;
        double *th = &x[0], *td = &x[four ? 2 : 1];
        if (!in_range(th, &theta_any, "theta_h", msg, size) || !in_range(td, &theta_upper, "theta_d", msg, size))
            return 0;
        double ph = four ? x[1] : 0.0;
        double pd = p == P_RUSIN_TH_TD ? M_PI / 2 : four ? x[3] : x[2];
        half_diff(*th, ph, *td, pd, L, V);
        break;
    }
    case P_RUSIN_VH: /* the half vector alone: L = V = H */
        if (!unit(x, "the half vector", msg, size))
            return 0;
        memcpy(L, x, sizeof L);
        memcpy(V, x, sizeof V);
        break;
    case P_ISOTROPIC_TV_TL_DPHI: /* classical_to_cartesian(x0, 0, x1, x2) into [V, L] */
        if (!in_range(&x[0], &theta_any, "theta_v", msg, size) || !in_range(&x[1], &theta_any, "theta_l", msg, size))
            return 0;
        ang[0] = x[1] * to_deg;
        ang[1] = x[2] * to_deg;
        ang[2] = x[0] * to_deg;
        ang[3] = 0.0;
        return 1;
    case P_ISOTROPIC_TL_TV_PROJ_DPHI: { /* L = (theta_l, 0), V = (|x12|, atan2(x2, x1)) */
        double tv = hypot(x[1], x[2]);
        if (!in_range(&x[0], &theta_any, "theta_l", msg, size) ||
            !in_range(&tv, &theta_any, "theta_v (the length of the projected pair)", msg, size))
            return 0;
        ang[0] = x[0] * to_deg;
        ang[1] = 0.0;
        ang[2] = tv * to_deg;
        ang[3] = tv > 0.0 ? atan2(x[2], x[1]) * to_deg : 0.0;
        return 1;
    }
    case P_SPHERICAL_TL_PL_TV_PV:
        if (!in_range(&x[0], &theta_any, "theta_l", msg, size) || !in_range(&x[2], &theta_any, "theta_v", msg, size))
            return 0;
        for (int k = 0; k < 4; k++)
            ang[k] = x[k] * to_deg;
        return 1;
    case P_CARTESIAN: /* [V.x V.y V.z L.x L.y L.z] */
        if (!unit(x, "V (numbers 1-3)", msg, size) || !unit(x + 3, "L (numbers 4-6)", msg, size))
            return 0;
        memcpy(V, x, sizeof V);
        memcpy(L, x + 3, sizeof L);
        break;
    }
    angles_of(L, &ang[0], &ang[1]);
    angles_of(V, &ang[2], &ang[3]);
    return 1;
}

/* ---- Header -------------------------------------------------------------------- */

/* The next blank-separated word of *p (advanced past it) into buf; 0 if none. */
static int word(const char **p, char *buf, size_t size)
{
    const char *s = *p;
    while (isspace((unsigned char)*s))
        s++;
    const char *e = s;
    while (*e && !isspace((unsigned char)*e))
        e++;
    *p = e;
    if (e == s)
        return 0;
    snprintf(buf, size, "%.*s", (int)(e - s), s);
    return 1;
}

/* A non-negative integer that is all of word w. */
static int integer(const char *w, long max, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(w, &end, 10);
    if (end == w || *end || errno || v < 0 || v > max)
        return 0;
    *out = (int)v;
    return 1;
}

/* One '#KEY value' line (line + 1 is past the hash). */
static bf_status header_line(header *h, const char *path, size_t lineno, const char *line, bf_error *err)
{
    const char *p = line;
    char key[64], val[128], extra[8];
    if (!word(&p, key, sizeof key))
        return BF_OK;
    if (!strcmp(key, "DIM")) {
        char a[64] = "", b[64] = "";
        if (h->dim_line)
            return bf_fail(err, BF_ERR_PARSE, "%s:%zu: #DIM given twice (first on line %zu)", path, lineno,
                           h->dim_line);
        if (!word(&p, a, sizeof a) || !word(&p, b, sizeof b) || word(&p, extra, sizeof extra) ||
            !integer(a, 6, &h->nin) || !integer(b, BF_MAX_CHANNELS, &h->nout) || h->nin < 1 || h->nout < 1)
            return bf_fail(err, BF_ERR_PARSE,
                           "%s:%zu: #DIM needs two positive integers, the input (at most 6) and output (at most "
                           "%d) counts",
                           path, lineno, BF_MAX_CHANNELS);
        h->dim_line = lineno;
    } else if (!strcmp(key, "PARAM_IN") || !strcmp(key, "PARAM_OUT")) {
        const int in = key[6] == 'I';
        if (in ? h->in_line : h->out_line)
            return bf_fail(err, BF_ERR_PARSE, "%s:%zu: #%s given twice (first on line %zu)", path, lineno, key,
                           in ? h->in_line : h->out_line);
        if (!word(&p, val, sizeof val) || word(&p, extra, sizeof extra))
            return bf_fail(err, BF_ERR_PARSE, "%s:%zu: #%s needs one name", path, lineno, key);
        if (in) {
            for (int k = 0; k < N_INPUTS; k++)
                if (!strcmp(val, inputs[k].name))
                    h->in = k;
            for (size_t k = 0; h->in < 0 && k < sizeof unsupported_inputs / sizeof *unsupported_inputs; k++)
                if (!strcmp(val, unsupported_inputs[k]))
                    return bf_fail(err, BF_ERR_PARSE,
                                   "%s:%zu: #PARAM_IN %s is not supported; convert the data to CARTESIAN or "
                                   "SPHERICAL_TL_PL_TV_PV first (ALTA's data2data)",
                                   path, lineno, val);
            if (h->in < 0)
                return bf_fail(err, BF_ERR_PARSE,
                               "%s:%zu: unknown #PARAM_IN '%s' (known: COS_TH[_TD], RUSIN_TH_TD[_PD], "
                               "RUSIN_TH_PH_TD_PD, RUSIN_VH, ISOTROPIC_TV_TL_DPHI, ISOTROPIC_TL_TV_PROJ_DPHI, "
                               "SPHERICAL_TL_PL_TV_PV, CARTESIAN)",
                               path, lineno, val);
            h->in_line = lineno;
        } else {
            for (int k = 0; k < N_OUTPUTS; k++)
                if (!strcmp(val, outputs[k]))
                    h->out = k;
            if (!strcmp(val, "ENERGY"))
                return bf_fail(err, BF_ERR_PARSE,
                               "%s:%zu: #PARAM_OUT ENERGY values are not a BRDF; brdfit reads INV_STERADIAN, "
                               "INV_STERADIAN_COSINE_FACTOR, RGB_COLOR and XYZ_COLOR",
                               path, lineno);
            if (h->out < 0)
                return bf_fail(err, BF_ERR_PARSE,
                               "%s:%zu: unknown #PARAM_OUT '%s' (known: INV_STERADIAN, "
                               "INV_STERADIAN_COSINE_FACTOR, RGB_COLOR, XYZ_COLOR)",
                               path, lineno, val);
            h->out_line = lineno;
        }
    } else if (!strcmp(key, "VS")) {
        if (!word(&p, val, sizeof val) || word(&p, extra, sizeof extra) || !integer(val, 2, &h->vs))
            return bf_fail(err, BF_ERR_PARSE, "%s:%zu: #VS must be 0, 1 or 2", path, lineno);
    } else if (!strcmp(key, "FORMAT")) {
        if (word(&p, val, sizeof val) && strcmp(val, "text") != 0)
            return bf_fail(err, BF_ERR_PARSE, "%s:%zu: ALTA '#FORMAT %s' data is not supported, only text", path,
                           lineno, val);
    }
    /* Other keys (#ALTA HEADER BEGIN/END, #CMD, ...) say nothing about the samples. */
    return BF_OK;
}

/* Called at the first data row (lineno) or at the end of a file without rows. */
static bf_status header_complete(const header *h, const char *path, size_t lineno, bf_error *err)
{
    if (!h->dim_line)
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: missing #DIM header line before the data", path, lineno);
    if (!h->in_line)
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: missing #PARAM_IN header line before the data", path, lineno);
    if (!h->out_line)
        return bf_fail(err, BF_ERR_PARSE,
                       "%s:%zu: missing #PARAM_OUT header line before the data (the unit of the values)", path, lineno);
    if (h->nin != inputs[h->in].dim)
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: #DIM gives %d input coordinates but %s has %d", path, h->dim_line,
                       h->nin, inputs[h->in].name, inputs[h->in].dim);
    if ((h->out == O_RGB_COLOR || h->out == O_XYZ_COLOR) && h->nout != 3)
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: #DIM gives %d output values but %s has 3", path, h->dim_line,
                       h->nout, outputs[h->out]);
    return BF_OK;
}

/* ---- Reading ------------------------------------------------------------------- */

/* One read: the file, where it is, the header and the rows read so far. The phases
 * below fill it in order (read_rows, check_rows, build_samples). */
typedef struct alta_reader {
    const char *path;
    FILE *fp;
    bf_error *err;
    size_t lineno;
    header h;
    int any_header;
    rows r;        /* width 0 until the first row */
    double *x;     /* one row as read */
    size_t maxnum; /* numbers x holds */
} alta_reader;

/* At the first row: the header is complete, and the row buffer sized for it. */
static bf_status start_rows(alta_reader *rd)
{
    const header *h = &rd->h;
    bf_status rc;
    if ((rc = header_complete(h, rd->path, rd->lineno, rd->err)) != BF_OK)
        return rc;
    rd->r.width = 4 + (size_t)h->nout;
    /* #VS intervals: one or two numbers for the first value (ALTA's reader), or
     * for every value. */
    rd->maxnum = (size_t)(h->nin + h->nout + h->vs * h->nout);
    if (!(rd->x = malloc(rd->maxnum * sizeof *rd->x)))
        return bf_fail(rd->err, BF_ERR_NOMEM, "%s: out of memory", rd->path);
    return BF_OK;
}

/* The row's numbers into rd->x (as many as it holds), their count into *count. */
static bf_status read_numbers(alta_reader *rd, const char *line, size_t *count)
{
    *count = 0;
    for (const char *p = line;;) {
        while (isspace((unsigned char)*p))
            p++;
        if (!*p)
            break;
        const char *tok = p;
        while (*p && !isspace((unsigned char)*p))
            p++;
        int tlen = (int)(p - tok);
        char *end;
        double v = strtod(tok, &end);
        if (end != p)
            return bf_fail(rd->err, BF_ERR_PARSE, "%s:%zu: number %zu: '%.*s' is not a number", rd->path, rd->lineno,
                           *count + 1, tlen > 40 ? 40 : tlen, tok);
        if (!isfinite(v))
            return bf_fail(rd->err, BF_ERR_RANGE, "%s:%zu: number %zu: %.*s is not a finite number", rd->path,
                           rd->lineno, *count + 1, tlen > 40 ? 40 : tlen, tok);
        if (*count < rd->maxnum)
            rd->x[*count] = v;
        (*count)++;
    }
    return BF_OK;
}

/* #DIM's numbers, with or without the #VS interval. */
static bf_status check_count(const alta_reader *rd, size_t count)
{
    const header *h = &rd->h;
    const size_t base = (size_t)(h->nin + h->nout);
    const size_t vs1 = base + (size_t)h->vs, vsn = base + (size_t)(h->vs * h->nout);
    if (count == base || (h->vs != 0 && (count == vs1 || count == vsn)))
        return BF_OK;
    if (h->vs == 0)
        return bf_fail(rd->err, BF_ERR_PARSE, "%s:%zu: expected %zu numbers (#DIM %d %d), found %zu", rd->path,
                       rd->lineno, base, h->nin, h->nout, count);
    return bf_fail(rd->err, BF_ERR_PARSE,
                   "%s:%zu: expected %zu numbers (#DIM %d %d) and the #VS %d interval (%zu or %zu in all), "
                   "found %zu",
                   rd->path, rd->lineno, base, h->nin, h->nout, h->vs, vs1, vsn, count);
}

/* The row as read (rd->x) as directions and values, appended to rd->r. */
static bf_status store_row(alta_reader *rd)
{
    const header *h = &rd->h;
    double *row = row_slot(&rd->r);
    if (!row)
        return bf_fail_memory(rd->err, rd->path, rd->lineno, 2 * rd->r.cap * rd->r.width * sizeof(double));
    char msg[160];
    if (!directions((param_in)h->in, rd->x, row, msg, sizeof msg))
        return bf_fail(rd->err, BF_ERR_RANGE, "%s:%zu: %s: %s", rd->path, rd->lineno, inputs[h->in].name, msg);
    memcpy(row + 4, rd->x + h->nin, (size_t)h->nout * sizeof *row);
    if (h->out == O_INV_STERADIAN_COSINE_FACTOR) {
        /* ALTA (params.h): "inverse steradian weighted by the cosine factor of the
         * output direction", V. On or below the horizon there is no cosine to divide
         * by and no BRDF to recover: the value stays, preprocessing drops the sample. */
        double c = cos(row[2] / to_deg);
        if (c > 1e-15) /* as bf_geometry: closer to zero is on the horizon */
            for (int k = 0; k < h->nout; k++)
                row[4 + k] /= c;
    }
    return BF_OK;
}

/* One line: a header key, a comment, a blank line or a row. */
static bf_status read_line(alta_reader *rd, char *line, size_t len)
{
    bf_status rc;
    if (memchr(line, '\0', len))
        return bf_fail(rd->err, BF_ERR_PARSE, "%s:%zu: binary data (NUL byte) in an ALTA text file", rd->path,
                       rd->lineno);
    const char *first = line;
    while (isspace((unsigned char)*first))
        first++;
    if (*first == '#') {
        rd->any_header = 1;
        /* After the first row '#' lines are comments, as in ALTA's reader; before it
         * '#KEY' at the start of a line is a key and '# ' (hash, blank) a comment. */
        if (!rd->r.width && first == line && line[1] && !isspace((unsigned char)line[1]))
            return header_line(&rd->h, rd->path, rd->lineno, line + 1, rd->err);
        return BF_OK;
    }
    if (!*first)
        return BF_OK;
    if (!rd->r.width && (rc = start_rows(rd)) != BF_OK)
        return rc;
    size_t count;
    if ((rc = read_numbers(rd, line, &count)) != BF_OK || (rc = check_count(rd, count)) != BF_OK)
        return rc;
    return store_row(rd);
}

static bf_status each_line(void *user, char *line, size_t len)
{
    return read_line(user, line, len);
}

/* Every line of the file: the header into rd->h, the rows into rd->r. */
static bf_status read_rows(alta_reader *rd, const bf_cancel_flag *cancel)
{
    return bf_read_lines(rd->fp, rd->path, cancel, &rd->lineno, each_line, rd, rd->err);
}

/* A header and at least one row. */
static bf_status check_rows(const alta_reader *rd)
{
    bf_status rc;
    if (!rd->any_header && rd->r.n == 0)
        return bf_fail(rd->err, BF_ERR_PARSE, "%s: empty file (an ALTA header #DIM, #PARAM_IN, #PARAM_OUT is required)",
                       rd->path);
    if (rd->r.n == 0) {
        if ((rc = header_complete(&rd->h, rd->path, rd->lineno, rd->err)) == BF_OK)
            rc = bf_fail(rd->err, BF_ERR_PARSE, "%s:%zu: no data rows after the header", rd->path, rd->lineno);
        return rc;
    }
    return BF_OK;
}

/* The rows as samples (*s, freed by the caller on failure), channels named for colours
 * and for three plain values. */
static bf_status build_samples(const alta_reader *rd, bf_samples **s)
{
    const header *h = &rd->h;
    bf_status rc;
    if ((rc = bf_samples_new(rd->r.n, h->nout, s, rd->err)) != BF_OK)
        return rc;
    bf_samples *sm = *s;
    if (h->out == O_XYZ_COLOR) {
        static const char *const xyz[3] = {"X", "Y", "Z"};
        for (int c = 0; c < 3; c++)
            if ((rc = bf_samples_set_channel_name(sm, c, xyz[c], rd->err)) != BF_OK)
                return rc;
    } else if (h->out != O_RGB_COLOR && h->nout == 3) {
        /* Three values in 1/sr are channels, not necessarily colours. */
        for (int c = 0; c < 3; c++) {
            char name[8];
            snprintf(name, sizeof name, "c%d", c);
            if ((rc = bf_samples_set_channel_name(sm, c, name, rd->err)) != BF_OK)
                return rc;
        }
    }
    const size_t C = (size_t)h->nout;
    for (size_t i = 0; i < rd->r.n; i++) {
        const double *row = rd->r.v + i * rd->r.width;
        sm->theta_i[i] = row[0];
        sm->phi_i[i] = row[1];
        sm->theta_o[i] = row[2];
        sm->phi_o[i] = row[3];
        memcpy(sm->value + i * C, row + 4, C * sizeof *sm->value);
    }
    return BF_OK;
}

bf_status bf_samples_read_alta(const char *path, bf_samples **out, bf_error *err)
{
    return bf_samples_read_alta_cancellable(path, NULL, out, err);
}

bf_status bf_samples_read_alta_cancellable(const char *path, const bf_cancel_flag *cancel, bf_samples **out,
                                           bf_error *err)
{
    *out = NULL;
    FILE *fp = bf_input_open(path);
    if (!fp)
        return bf_fail(err, BF_ERR_IO, "%s: cannot open: %s", path, bf_input_error(errno));
    alta_reader rd = {.path = path, .fp = fp, .err = err, .h = {0, 0, 0, -1, -1, 0, 0, 0}};
    bf_samples *s = NULL;
    bf_status rc = read_rows(&rd, cancel);
    if (rc == BF_OK)
        rc = check_rows(&rd);
    if (rc == BF_OK)
        rc = build_samples(&rd, &s);
    free(rd.x);
    free(rd.r.v);
    fclose(fp);
    if (rc != BF_OK) {
        bf_samples_free(s);
        return rc;
    }
    *out = s;
    return BF_OK;
}
