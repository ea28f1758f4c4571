/* MERL BRDF database tables (.binary): three int32 dimensions (90, 90, 180), then three
 * planes (R, G, B) of 90*90*180 float64 raw values, little-endian as MERL's tools wrote
 * them on x86. Cell (i, j, k) = (theta_h, theta_d, phi_d) is at index
 * k + j*180 + i*180*90; value = raw * scale (MERL's BRDFRead.cpp scales); a cell with
 * any negative raw value was not measured and is no sample.
 *
 * A cell stands for the direction pair at its centre, in MERL's own half/difference
 * convention (std_coords_to_half_diff_coords in BRDFRead.cpp: the difference vector is
 * L rotated by -phi_h about N and then by -theta_h about the binormal Y). With phi_h = 0
 * the inverse is L = Ry(theta_h) D and V = Ry(theta_h) (-Dx, -Dy, Dz), which is L
 * mirrored about H = Ry(theta_h) N.
 *
 * The horizon: 361,784 of the 1,458,000 cell centres (25%) have L or V below it
 * (|tan theta_h tan theta_d cos phi_d| > 1); the grid covers them because it is a
 * product of ranges. MERL stores them as negative (invalid). A non-negative value in
 * such a cell is still read as a sample, with theta_i or theta_o above 90 degrees: it is
 * what the file says, and the geometry marks it invalid (lz or vz <= 0), so models give
 * it 0 and preprocessing decides whether to drop it. */
#include "brdfit/formats.h"
#include "brdfit/io.h"
#include "brdfit/samples.h"

#include "base/big_alloc.h"
#include "base/cancel.h"
#include "io/read_options.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#define HEADER_BYTES 12
#define TABLE_DOUBLES ((size_t)3 * BF_MERL_CELLS)
#define FILE_BYTES (HEADER_BYTES + TABLE_DOUBLES * sizeof(double))

/* Exactly MERL's RED_SCALE, GREEN_SCALE, BLUE_SCALE expressions. */
static const double merl_scale[3] = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};
static const char *const plane_name[3] = {"R", "G", "B"};
static const int32_t merl_dims[3] = {BF_MERL_TH, BF_MERL_TD, BF_MERL_PD};

/* ---- Byte order: the file is little-endian whatever the host. -------------------- */

static int host_is_big_endian(void)
{
    const union {
        uint16_t u;
        unsigned char b[2];
    } probe = {0x0102};
    return probe.b[0] == 0x01;
}

static void swap_bytes(void *data, size_t count, size_t width)
{
    unsigned char *p = data;
    for (size_t i = 0; i < count; i++, p += width)
        for (size_t a = 0, b = width - 1; a < b; a++, b--) {
            unsigned char t = p[a];
            p[a] = p[b];
            p[b] = t;
        }
}

/* ---- Reading ---------------------------------------------------------------------- */

/* Size of the rest of a stream already read up to `pos`, for the error message. */
static size_t stream_size(FILE *fp, size_t pos)
{
    struct stat st;
    if (fstat(fileno(fp), &st) == 0 && S_ISREG(st.st_mode))
        return (size_t)st.st_size;
    char buf[65536];
    size_t got;
    while ((got = fread(buf, 1, sizeof buf, fp)) > 0)
        pos += got;
    return pos;
}

static bf_status read_error(FILE *fp, const char *path, bf_error *err)
{
    (void)fp;
    return bf_fail(err, BF_ERR_IO, "%s: read error: %s", path, strerror(errno));
}

/* The header: dimensions checked, fp left at the first table byte. */
static bf_status read_header(FILE *fp, const char *path, bf_error *err)
{
    int32_t dims[3];
    size_t got = fread(dims, 1, HEADER_BYTES, fp);
    if (ferror(fp))
        return read_error(fp, path, err);
    if (got == 0)
        return bf_fail(err, BF_ERR_PARSE, "%s: empty file (a MERL table is %zu bytes)", path, (size_t)FILE_BYTES);
    if (got < HEADER_BYTES)
        return bf_fail(err, BF_ERR_PARSE,
                       "%s: byte offset %zu: file ends inside the 12-byte MERL header (3 int32 dimensions)", path, got);
    if (host_is_big_endian())
        swap_bytes(dims, 3, sizeof dims[0]);
    if (dims[0] != merl_dims[0] || dims[1] != merl_dims[1] || dims[2] != merl_dims[2])
        return bf_fail(err, BF_ERR_PARSE, "%s: byte offset 0: dimensions %ld x %ld x %ld, expected %d x %d x %d", path,
                       (long)dims[0], (long)dims[1], (long)dims[2], BF_MERL_TH, BF_MERL_TD, BF_MERL_PD);
    return BF_OK;
}

/* The three planes, checked (exact size, finite values), into dst: planar
 * (dst[p * CELLS + c], the raw table as stored) or interleaved (dst[c * 3 + p], the
 * samples' layout), a chunk at a time so no second copy of the table is needed. */
enum { READ_CHUNK = 65536 }; /* doubles */

static bf_status read_planes(FILE *fp, const char *path, double *dst, int interleaved, const bf_cancel_flag *cancel,
                             bf_error *err)
{
    double *buf = malloc(READ_CHUNK * sizeof *buf);
    if (!buf)
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory reading the MERL table", path);
    bf_status rc = BF_OK;
    for (size_t p = 0; p < 3 && rc == BF_OK; p++)
        for (size_t c0 = 0; c0 < (size_t)BF_MERL_CELLS && rc == BF_OK; c0 += READ_CHUNK) {
            const size_t want = (size_t)BF_MERL_CELLS - c0 < READ_CHUNK ? (size_t)BF_MERL_CELLS - c0 : READ_CHUNK;
            const size_t x0 = p * (size_t)BF_MERL_CELLS + c0; /* doubles before this chunk */
            if (bf_cancel_is_set(cancel)) {
                rc = bf_read_cancelled(path, err);
                break;
            }
            size_t got = fread(buf, 1, want * sizeof *buf, fp);
            if (ferror(fp)) {
                rc = read_error(fp, path, err);
                break;
            }
            if (got < want * sizeof *buf) {
                rc = bf_fail(err, BF_ERR_PARSE, "%s: truncated: %zu bytes, a %d x %d x %d MERL table is %zu bytes",
                             path, HEADER_BYTES + x0 * sizeof *buf + got, BF_MERL_TH, BF_MERL_TD, BF_MERL_PD,
                             (size_t)FILE_BYTES);
                break;
            }
            if (host_is_big_endian())
                swap_bytes(buf, want, sizeof *buf);
            size_t bad = want;
            for (size_t q = 0; q < want; q++)
                if (!isfinite(buf[q])) {
                    bad = q;
                    break;
                }
            if (bad < want) {
                const size_t c = c0 + bad;
                rc = bf_fail(err, BF_ERR_PARSE,
                             "%s: byte offset %zu: raw value %s in plane %s (theta_h %zu, theta_d %zu, phi_d %zu)",
                             path, HEADER_BYTES + (x0 + bad) * sizeof *buf, isnan(buf[bad]) ? "NaN" : "Inf",
                             plane_name[p], c / (BF_MERL_PD * BF_MERL_TD), c / BF_MERL_PD % BF_MERL_TD, c % BF_MERL_PD);
                break;
            }
            if (interleaved)
                for (size_t q = 0; q < want; q++)
                    dst[3 * (c0 + q) + p] = buf[q];
            else
                memcpy(dst + x0, buf, want * sizeof *buf);
        }
    free(buf);
    if (rc == BF_OK && fgetc(fp) != EOF)
        rc = bf_fail(err, BF_ERR_PARSE, "%s: wrong size: %zu bytes, a %d x %d x %d MERL table is %zu bytes", path,
                     stream_size(fp, FILE_BYTES + 1), BF_MERL_TH, BF_MERL_TD, BF_MERL_PD, (size_t)FILE_BYTES);
    return rc;
}

/* Samples from a table: the valid cells (every plane >= 0), values scaled. `raw` is
 * planar or interleaved as read_planes wrote it; interleaved, values are compacted in
 * place and the buffer becomes the samples' value array (n is only known after the
 * whole table is read, and this keeps the peak at one table instead of two). */
static bf_status table_samples(const char *path, double *table, int interleaved, bf_samples **out, bf_error *err)
{
    int32_t *cell = bf_big_malloc((size_t)BF_MERL_CELLS * sizeof *cell);
    double *vals = interleaved ? table : bf_big_malloc(TABLE_DOUBLES * sizeof *vals);
    bf_samples *s = NULL;
    bf_samples_new_cells(0, 3, &s, err);
    if (!cell || !vals || !s) {
        free(cell);
        if (!interleaved)
            free(vals);
        bf_samples_free(s);
        return bf_fail_memory(err, path, 0, (size_t)BF_MERL_CELLS * sizeof *cell + TABLE_DOUBLES * sizeof *vals);
    }
    size_t n = 0;
    for (size_t c = 0; c < (size_t)BF_MERL_CELLS; c++) {
        double r[3];
        for (int p = 0; p < 3; p++)
            r[p] = interleaved ? table[3 * c + (size_t)p] : table[(size_t)p * BF_MERL_CELLS + c];
        if (!(r[0] >= 0.0 && r[1] >= 0.0 && r[2] >= 0.0))
            continue;
        for (int p = 0; p < 3; p++)
            vals[3 * n + (size_t)p] = r[p] * merl_scale[p]; /* 3n <= 3c: in place is safe */
        cell[n++] = (int32_t)c;
    }
    /* Shrinking: realloc only fails to move, never to keep what it has. */
    double *v2 = realloc(vals, (3 * n + 1) * sizeof *vals);
    int32_t *c2 = realloc(cell, (n + 1) * sizeof *cell);
    free(s->value);
    free(s->merl->cell);
    s->value = v2 ? v2 : vals;
    s->merl->cell = c2 ? c2 : cell;
    s->n = n;
    if (!interleaved)
        s->merl->raw = table;
    *out = s;
    return BF_OK;
}

bf_status bf_samples_read_merl(const char *path, int keep_raw, bf_samples **out, bf_error *err)
{
    return bf_samples_read_merl_cancellable(path, keep_raw, NULL, out, err);
}

bf_status bf_samples_read_merl_cancellable(const char *path, int keep_raw, const bf_cancel_flag *cancel,
                                           bf_samples **out, bf_error *err)
{
    *out = NULL;
    FILE *fp = bf_input_open(path);
    if (!fp)
        return bf_fail(err, BF_ERR_IO, "%s: cannot open: %s", path, bf_input_error(errno));
    double *table = NULL;
    bf_status rc = read_header(fp, path, err);
    /* A short file is refused before the 35 MB table is allocated (where its size can be
     * known: a regular file or standard input kept in memory; a pipe reads to its end). */
    long size = -1;
    struct stat st;
    if (fstat(fileno(fp), &st) == 0 && S_ISREG(st.st_mode))
        size = (long)st.st_size;
    else if (fileno(fp) < 0 && fseek(fp, 0, SEEK_END) == 0) {
        size = ftell(fp);
        if (fseek(fp, HEADER_BYTES, SEEK_SET) != 0)
            size = -1;
    }
    if (rc == BF_OK && size >= 0 && (size_t)size < (size_t)FILE_BYTES)
        rc = bf_fail(err, BF_ERR_PARSE, "%s: truncated: %zu bytes, a %d x %d x %d MERL table is %zu bytes", path,
                     (size_t)size, BF_MERL_TH, BF_MERL_TD, BF_MERL_PD, (size_t)FILE_BYTES);
    if (rc == BF_OK && !(table = bf_big_malloc(TABLE_DOUBLES * sizeof *table)))
        rc = bf_fail_memory(err, path, 0, TABLE_DOUBLES * sizeof *table);
    if (rc == BF_OK)
        rc = read_planes(fp, path, table, !keep_raw, cancel, err);
    fclose(fp);
    if (rc == BF_OK && bf_cancel_is_set(cancel))
        rc = bf_read_cancelled(path, err);
    if (rc == BF_OK)
        rc = table_samples(path, table, !keep_raw, out, err);
    if (rc != BF_OK)
        free(table);
    return rc;
}

/* ---- Writing ---------------------------------------------------------------------- */

/* The raw value that reads back closest to v: v / scale, or a neighbour of it where
 * the division and the reader's multiplication round differently. Multiplying by a
 * scale below 1 cannot reach every double, so some values come back 1 ulp off. */
static double raw_for(double v, double scale)
{
    double r = v / scale, best = r, best_err = fabs(r * scale - v);
    const double cand[2] = {nextafter(r, INFINITY), nextafter(r, -INFINITY)};
    for (int q = 0; q < 2 && best_err > 0.0; q++)
        if (cand[q] >= 0.0 && fabs(cand[q] * scale - v) < best_err) {
            best = cand[q];
            best_err = fabs(cand[q] * scale - v);
        }
    return best;
}

/* Fills table (raw, host order) from the samples; 0 or an error. */
static bf_status fill_table(const bf_samples *s, const char *path, double *table, uint32_t *owner, bf_error *err)
{
    const bf_merl_origin *o = s->merl;
    const double *raw = o ? o->raw : NULL;
    for (size_t i = 0; i < s->n; i++) {
        int32_t cell = o ? o->cell[i] : bf_merl_cell_of(s->theta_i[i], s->phi_i[i], s->theta_o[i], s->phi_o[i]);
        if (o && (cell < 0 || cell >= BF_MERL_CELLS))
            return bf_fail(err, BF_ERR_ARG, "%s: sample %zu: MERL cell %ld is out of range", path, i + 1, (long)cell);
        if (cell < 0)
            return bf_fail(
                err, BF_ERR_ARG,
                "%s: sample %zu (theta_i %.17g, phi_i %.17g, theta_o %.17g, phi_o %.17g) is not at a MERL cell centre",
                path, i + 1, s->theta_i[i], s->phi_i[i], s->theta_o[i], s->phi_o[i]);
        if (owner[cell])
            return bf_fail(err, BF_ERR_ARG, "%s: samples %lu and %zu are both in MERL cell %ld", path,
                           (unsigned long)owner[cell], i + 1, (long)cell);
        owner[cell] = (uint32_t)(i + 1);
        for (int p = 0; p < 3; p++) {
            double v = s->value[3 * i + (size_t)p];
            /* MERL marks negative cells invalid, so a negative value would silently turn
             * into a missing sample: refuse it rather than change the data. */
            if (!isfinite(v) || v < 0.0)
                return bf_fail(err, BF_ERR_RANGE,
                               "%s: sample %zu, channel %s: value %g cannot be stored in a MERL table (%s)", path,
                               i + 1, s->channel_names[p], v,
                               isfinite(v) ? "negative values mark invalid cells" : "not finite");
            double *slot = table + (size_t)p * BF_MERL_CELLS + (size_t)cell;
            /* Unchanged values keep their raw bits: a table read and written is the same file. */
            if (raw && raw[(size_t)p * BF_MERL_CELLS + (size_t)cell] * merl_scale[p] == v)
                *slot = raw[(size_t)p * BF_MERL_CELLS + (size_t)cell];
            else
                *slot = raw_for(v, merl_scale[p]);
        }
    }
    return BF_OK;
}

bf_status bf_samples_write_merl(const bf_samples *s, const char *path, bf_error *err)
{
    if (s->channels != 3)
        return bf_fail(err, BF_ERR_ARG, "%s: a MERL table needs 3 channels (R, G, B); the samples have %d", path,
                       s->channels);
    if (s->n > (size_t)BF_MERL_CELLS)
        return bf_fail(err, BF_ERR_ARG, "%s: %zu samples, a MERL table holds at most %d", path, s->n, BF_MERL_CELLS);
    double *table = malloc(TABLE_DOUBLES * sizeof *table);
    uint32_t *owner = calloc(BF_MERL_CELLS, sizeof *owner); /* sample number + 1 per cell */
    if (!table || !owner) {
        free(table);
        free(owner);
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory for the MERL table", path);
    }
    if (s->merl && s->merl->raw)
        memcpy(table, s->merl->raw, TABLE_DOUBLES * sizeof *table);
    else
        for (size_t x = 0; x < TABLE_DOUBLES; x++)
            table[x] = -1.0;
    bf_status rc = fill_table(s, path, table, owner, err);
    free(owner);
    if (rc != BF_OK) {
        free(table);
        return rc;
    }
    int32_t dims[3] = {merl_dims[0], merl_dims[1], merl_dims[2]};
    if (host_is_big_endian()) {
        swap_bytes(dims, 3, sizeof dims[0]);
        swap_bytes(table, TABLE_DOUBLES, sizeof *table);
    }
    bf_outfile o;
    if ((rc = bf_outfile_open(&o, path, err)) != BF_OK) {
        free(table);
        return rc;
    }
    fwrite(dims, sizeof dims[0], 3, o.fp);
    fwrite(table, sizeof *table, TABLE_DOUBLES, o.fp);
    free(table);
    return bf_outfile_commit(&o, err); /* checks every write */
}
