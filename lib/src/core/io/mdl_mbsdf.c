/* NVIDIA MDL measured BSDFs (.mbsdf, "NVIDIA ARC MBSDF V1"): the text line
 * "NVIDIA ARC MBSDF V1", then one or two parts, each a text line
 * "MBSDF_DATA_REFLECTION=" or "MBSDF_DATA_TRANSMISSION=" followed by uint32 type
 * (0: one scalar per cell, 1: RGB), uint32 n_theta, uint32 n_phi and the float32 table,
 * all little-endian. Cell (i_in, i_out, j) is at index (i_in * n_theta + i_out) * n_phi
 * + j, times 3 for RGB: the incident elevation outermost, then the outgoing one, then
 * the azimuth difference phi_out - phi_in folded into [0, pi].
 *
 * The MDL SDK places the values as the texels of a 3D texture over
 * (phi / pi, theta_out / (pi/2), theta_in / (pi/2)), so value k of an axis of n stands
 * for the centre of the k-th of n equal cells: theta = (k + 1/2) (pi/2) / n,
 * phi = (j + 1/2) pi / n_phi; between them it interpolates trilinearly, clamped at the
 * edges, which is what evaluating on a direction grid does here.
 *
 * The MDL SDK evaluates the reciprocal average of the table, (f(in, out) + f(out, in)) / 2
 * (its prepare_mbsdfs_part makes "lookup data symmetric"), and so do the samples here:
 * measured tables are not exactly reciprocal, and the car paint of examples/mdl shows
 * why it matters: its raw rows peak one theta cell short of the mirror direction, the
 * average peaks on it.
 *
 * The reflection part is the BRDF (1/sr) and becomes the samples (phi_i = 0,
 * phi_o = the azimuth difference). A transmission part is a BTDF, which no brdfit model
 * describes: it is read and checked like the reflection (so a broken file is refused
 * whole) and then left out; a file with only a transmission part is refused. Negative
 * values are kept (they are data; --negative decides); NaN or Inf is an error. */
#include "brdfit/formats.h"
#include "brdfit/samples.h"

#include "base/big_alloc.h"
#include "direction_grid.h"
#include "read_binary.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define MAGIC "NVIDIA ARC MBSDF V1\n"
#define MAX_LINE 4096 /* a text line longer than this is not a header */
#define MAX_RES 65536 /* cells per axis; the MDL SDK's examples use 45 x 90 */

typedef struct mbsdf_part {
    int present, channels;
    size_t n_theta, n_phi;
    size_t offset; /* byte offset of the first value */
} mbsdf_part;

/* One text line at *pos (without its '\n') into line; 0, or -1 when the file ends
 * first or the line is too long. */
static int text_line(const unsigned char *b, size_t size, size_t *pos, char *line)
{
    size_t n = 0;
    while (*pos + n < size && b[*pos + n] != '\n') {
        if (n + 1 >= MAX_LINE)
            return -1;
        line[n] = (char)b[*pos + n];
        n++;
    }
    if (*pos + n >= size)
        return -1;
    line[n] = '\0';
    *pos += n + 1;
    return 0;
}

/* A part's header and table at *pos: sizes checked, every value finite. */
static bf_status read_part(const char *path, const unsigned char *b, size_t size, size_t *pos, const char *what,
                           mbsdf_part *p, bf_error *err)
{
    if (size - *pos < 12)
        return bf_fail(err, BF_ERR_PARSE, "%s: byte offset %zu: file ends inside the %s header (3 uint32)", path, *pos,
                       what);
    const uint32_t type = bf_le_u32(b + *pos), nt = bf_le_u32(b + *pos + 4), np = bf_le_u32(b + *pos + 8);
    if (type > 1)
        return bf_fail(err, BF_ERR_PARSE, "%s: byte offset %zu: %s data type %lu (0 scalar, 1 RGB)", path, *pos, what,
                       (unsigned long)type);
    if (nt < 1 || np < 1 || nt > MAX_RES || np > MAX_RES)
        return bf_fail(err, BF_ERR_PARSE, "%s: byte offset %zu: %s resolution %lu theta x %lu phi (1 to %d each)", path,
                       *pos + 4, what, (unsigned long)nt, (unsigned long)np, MAX_RES);
    p->present = 1;
    p->channels = type ? 3 : 1;
    p->n_theta = nt;
    p->n_phi = np;
    p->offset = *pos + 12;
    const size_t count = (size_t)nt * nt * np * (size_t)p->channels; /* < 2^50: no overflow */
    if (count > (size - p->offset) / 4)
        return bf_fail(err, BF_ERR_PARSE,
                       "%s: truncated: the %s table of %lu x %lu x %lu x %d floats needs %zu bytes, "
                       "%zu are left",
                       path, what, (unsigned long)nt, (unsigned long)nt, (unsigned long)np, p->channels, count * 4,
                       size - p->offset);
    for (size_t i = 0; i < count; i++) {
        const float v = bf_le_f32(b + p->offset + 4 * i);
        if (!isfinite(v))
            return bf_fail(err, BF_ERR_PARSE, "%s: byte offset %zu: %s value %zu is %s", path, p->offset + 4 * i, what,
                           i, isnan(v) ? "NaN" : "Inf");
    }
    *pos = p->offset + count * 4;
    return BF_OK;
}

/* The whole file: the magic line, text lines (metadata) until the first part, then the
 * parts, nothing after them. */
static bf_status parse(const char *path, const unsigned char *b, size_t size, mbsdf_part *refl, bf_error *err)
{
    const size_t magic_len = strlen(MAGIC);
    if (size < magic_len || memcmp(b, MAGIC, magic_len) != 0)
        return bf_fail(err, BF_ERR_PARSE,
                       "%s: byte offset 0: not an mbsdf file (it starts with \"NVIDIA ARC MBSDF V1\")", path);
    mbsdf_part parts[2] = {{0}, {0}};
    static const char *const markers[2] = {"MBSDF_DATA_REFLECTION=", "MBSDF_DATA_TRANSMISSION="};
    static const char *const what[2] = {"reflection", "transmission"};
    char *line = malloc(MAX_LINE);
    if (!line)
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
    bf_status rc = BF_OK;
    size_t pos = magic_len;
    while (rc == BF_OK && pos < size) {
        const size_t at = pos;
        if (text_line(b, size, &pos, line) != 0) {
            rc = bf_fail(err, BF_ERR_PARSE, "%s: byte offset %zu: expected a text line (MBSDF_DATA_REFLECTION=)", path,
                         at);
            break;
        }
        int k = !strcmp(line, markers[0]) ? 0 : !strcmp(line, markers[1]) ? 1 : -1;
        if (k < 0 && (parts[0].present || parts[1].present))
            rc = bf_fail(err, BF_ERR_PARSE, "%s: byte offset %zu: unexpected data after a table", path, at);
        else if (k >= 0 && parts[k].present)
            rc = bf_fail(err, BF_ERR_PARSE, "%s: byte offset %zu: a second %s part", path, at, what[k]);
        else if (k >= 0)
            rc = read_part(path, b, size, &pos, what[k], &parts[k], err);
        /* other text lines before the first part: metadata, skipped */
    }
    free(line);
    if (rc == BF_OK && !parts[0].present)
        rc = bf_fail(err, BF_ERR_PARSE, "%s: no reflection part (MBSDF_DATA_REFLECTION=)%s", path,
                     parts[1].present ? ": a transmission-only table is not a BRDF" : "");
    *refl = parts[0];
    return rc;
}

/* ---- Evaluation ------------------------------------------------------------------ */

typedef struct mbsdf_table {
    double *values; /* the reciprocal average, in the file's layout */
    size_t n_theta, n_phi;
    int channels;
} mbsdf_table;

static size_t index_of(const mbsdf_table *t, size_t ti, size_t to, size_t j, int c)
{
    return ((ti * t->n_theta + to) * t->n_phi + j) * (size_t)t->channels + (size_t)c;
}

static double value_at(const mbsdf_table *t, size_t ti, size_t to, size_t j, int c)
{
    return t->values[index_of(t, ti, to, j, c)];
}

/* The part's table as the MDL SDK evaluates it: each cell the mean of itself and its
 * reciprocal (theta_in and theta_out exchanged). */
static bf_status symmetric_table(const char *path, const unsigned char *bytes, const mbsdf_part *p, mbsdf_table *t,
                                 bf_error *err)
{
    t->n_theta = p->n_theta;
    t->n_phi = p->n_phi;
    t->channels = p->channels;
    const size_t count = p->n_theta * p->n_theta * p->n_phi * (size_t)p->channels;
    if (!(t->values = bf_big_malloc(count * sizeof *t->values)))
        return bf_fail_memory(err, path, 0, count * sizeof *t->values);
    const unsigned char *raw = bytes + p->offset;
    for (size_t ti = 0; ti < t->n_theta; ti++)
        for (size_t to = 0; to < t->n_theta; to++)
            for (size_t j = 0; j < t->n_phi; j++)
                for (int c = 0; c < t->channels; c++)
                    t->values[index_of(t, ti, to, j, c)] =
                        0.5 * ((double)bf_le_f32(raw + 4 * index_of(t, ti, to, j, c)) +
                               (double)bf_le_f32(raw + 4 * index_of(t, to, ti, j, c)));
    return BF_OK;
}

/* A texture axis of n texels over [0, 1]: the two texels around coordinate u and the
 * weight of the second, clamped at the edges. */
static void texels(double u, size_t n, size_t i[2], double *t)
{
    double p = u * (double)n - 0.5;
    if (p < 0.0)
        p = 0.0;
    if (p > (double)(n - 1))
        p = (double)(n - 1);
    i[0] = (size_t)p;
    i[1] = i[0] + 1 < n ? i[0] + 1 : i[0];
    *t = p - (double)i[0];
}

/* Trilinear value at theta_in, theta_out, phi (radians, phi folded into [0, pi]). */
static void eval_table(const mbsdf_table *t, double theta_in, double theta_out, double phi, double *out)
{
    size_t a[2], b[2], c[2];
    double ta, tb, tc;
    texels(theta_in / (M_PI / 2), t->n_theta, a, &ta);
    texels(theta_out / (M_PI / 2), t->n_theta, b, &tb);
    texels(phi / M_PI, t->n_phi, c, &tc);
    for (int ch = 0; ch < t->channels; ch++) {
        double v = 0.0;
        for (int x = 0; x < 2; x++)
            for (int y = 0; y < 2; y++)
                for (int z = 0; z < 2; z++)
                    v += (x ? ta : 1 - ta) * (y ? tb : 1 - tb) * (z ? tc : 1 - tc) * value_at(t, a[x], b[y], c[z], ch);
        out[ch] = v;
    }
}

/* The cells' centres, in file order. */
static bf_status cell_samples(const mbsdf_table *t, bf_samples **out, bf_error *err)
{
    const size_t n = t->n_theta * t->n_theta * t->n_phi, C = (size_t)t->channels;
    bf_samples *s;
    bf_status rc = bf_samples_new(n, t->channels, &s, err);
    if (rc != BF_OK)
        return rc;
    size_t i = 0;
    for (size_t ti = 0; ti < t->n_theta; ti++)
        for (size_t to = 0; to < t->n_theta; to++)
            for (size_t j = 0; j < t->n_phi; j++, i++) {
                s->theta_i[i] = (ti + 0.5) * 90.0 / (double)t->n_theta;
                s->phi_i[i] = 0.0;
                s->theta_o[i] = (to + 0.5) * 90.0 / (double)t->n_theta;
                s->phi_o[i] = (j + 0.5) * 180.0 / (double)t->n_phi;
                for (size_t c = 0; c < C; c++)
                    s->value[i * C + c] = value_at(t, ti, to, j, (int)c);
            }
    *out = s;
    return BF_OK;
}

/* The table interpolated on a direction grid; 0 where a direction is not above the
 * horizon. */
static bf_status grid_samples(const mbsdf_table *t, const char *grid, bf_samples **out, bf_error *err)
{
    bf_samples *s;
    bf_status rc = bf_direction_grid(grid, t->channels, &s, err);
    if (rc != BF_OK)
        return rc;
    const size_t C = (size_t)t->channels;
    for (size_t i = 0; i < s->n; i++) {
        double d[4];
        bf_samples_direction(s, i, d);
        if (!(d[0] < 90.0 && d[2] < 90.0))
            continue; /* values are zeroed */
        double phi = fmod(fabs(d[3] - d[1]), 360.0);
        if (phi > 180.0)
            phi = 360.0 - phi;
        eval_table(t, d[0] * (M_PI / 180), d[2] * (M_PI / 180), phi * (M_PI / 180), s->value + i * C);
    }
    *out = s;
    return BF_OK;
}

bf_status bf_samples_read_mbsdf(const char *path, const char *grid, bf_samples **out, bf_error *err)
{
    *out = NULL;
    unsigned char *bytes;
    size_t size;
    bf_status rc = bf_read_binary(path, &bytes, &size, err);
    if (rc != BF_OK)
        return rc;
    mbsdf_part refl = {0, 0, 0, 0, 0};
    rc = parse(path, bytes, size, &refl, err);
    mbsdf_table t = {NULL, 0, 0, 0};
    if (rc == BF_OK)
        rc = symmetric_table(path, bytes, &refl, &t, err);
    free(bytes);
    if (rc == BF_OK)
        rc = grid ? grid_samples(&t, grid, out, err) : cell_samples(&t, out, err);
    free(t.values);
    return rc;
}
