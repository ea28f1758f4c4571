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
#include "brdfit/io.h"
#include "brdfit/samples.h"

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
    const union { uint16_t u; unsigned char b[2]; } probe = {0x0102};
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

/* ---- Cell centres ----------------------------------------------------------------- */

/* Centre angles in radians of bin i (theta_h, non-linear), j (theta_d), k (phi_d). */
static double centre_theta_h(int i)
{
    double u = (i + 0.5) / BF_MERL_TH;
    return u * u * (M_PI / 2);
}
static double centre_theta_d(int j) { return (j + 0.5) / BF_MERL_TD * (M_PI / 2); }
static double centre_phi_d(int k) { return (k + 0.5) / BF_MERL_PD * M_PI; }

/* Sines and cosines of the centre angles per bin index, so that a whole table costs
 * 360 sin/cos pairs plus the inverse trigonometry of the output angles. */
typedef struct centre_trig {
    double sth[BF_MERL_TH], cth[BF_MERL_TH];
    double std_[BF_MERL_TD], ctd[BF_MERL_TD];
    double spd[BF_MERL_PD], cpd[BF_MERL_PD];
} centre_trig;

static void centre_trig_init(centre_trig *t)
{
    for (int i = 0; i < BF_MERL_TH; i++) {
        t->sth[i] = sin(centre_theta_h(i));
        t->cth[i] = cos(centre_theta_h(i));
    }
    for (int j = 0; j < BF_MERL_TD; j++) {
        t->std_[j] = sin(centre_theta_d(j));
        t->ctd[j] = cos(centre_theta_d(j));
    }
    for (int k = 0; k < BF_MERL_PD; k++) {
        t->spd[k] = sin(centre_phi_d(k));
        t->cpd[k] = cos(centre_phi_d(k));
    }
}

/* Directions in degrees from the centre's sines and cosines. theta by atan2 rather than
 * acos keeps full precision near the pole; phi_i lies in (0, 180) and phi_o in
 * (180, 360) because phi_d is in (0, pi). */
static void centre_directions(double sth, double cth, double std_, double ctd, double spd,
                              double cpd, double *ti, double *pi_, double *to, double *po)
{
    const double r2d = 180.0 / M_PI;
    double dx = std_ * cpd, dy = std_ * spd, dz = ctd;
    double lx = dx * cth + dz * sth, lz = dz * cth - dx * sth;
    double vx = dz * sth - dx * cth, vz = dz * cth + dx * sth;
    double pxy_l = sqrt(lx * lx + dy * dy), pxy_v = sqrt(vx * vx + dy * dy);
    *ti = atan2(pxy_l, lz) * r2d;
    *pi_ = atan2(dy, lx) * r2d;
    *to = atan2(pxy_v, vz) * r2d;
    *po = (atan2(-dy, vx) + 2 * M_PI) * r2d;
}

void bf_merl_cell_directions(int32_t cell, double *theta_i, double *phi_i, double *theta_o,
                             double *phi_o)
{
    int k = cell % BF_MERL_PD, j = cell / BF_MERL_PD % BF_MERL_TD, i = cell / (BF_MERL_PD * BF_MERL_TD);
    /* The same expressions as centre_trig_init, so a table read and a single cell give
     * identical bits. */
    double th = centre_theta_h(i), td = centre_theta_d(j), pd = centre_phi_d(k);
    centre_directions(sin(th), cos(th), sin(td), cos(td), sin(pd), cos(pd), theta_i, phi_i,
                      theta_o, phi_o);
}

int32_t bf_merl_cell_of(double theta_i, double phi_i, double theta_o, double phi_o)
{
    const double d2r = M_PI / 180.0, tol = 1e-9;
    if (!isfinite(theta_i) || !isfinite(phi_i) || !isfinite(theta_o) || !isfinite(phi_o))
        return -1;
    double ti = theta_i * d2r, pi_ = phi_i * d2r, to = theta_o * d2r, po = phi_o * d2r;
    double L[3] = {sin(ti) * cos(pi_), sin(ti) * sin(pi_), cos(ti)};
    double V[3] = {sin(to) * cos(po), sin(to) * sin(po), cos(to)};
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double hxy = sqrt(H[0] * H[0] + H[1] * H[1]);
    if (hxy == 0.0)
        return -1; /* theta_h = 0 (or L = -V): no cell centre */
    /* MERL's std_coords_to_half_diff_coords: D = Ry(-theta_h) Rz(-phi_h) L. */
    double th = atan2(hxy, H[2]), ph = atan2(H[1], H[0]);
    double cph = cos(ph), sph = sin(ph), cth = cos(th), sth = sin(th);
    double tx = cph * L[0] + sph * L[1], ty = cph * L[1] - sph * L[0], tz = L[2];
    double dx = tx * cth - tz * sth, dy = ty, dz = tx * sth + tz * cth;
    double td = atan2(sqrt(dx * dx + dy * dy), dz), pd = atan2(dy, dx);
    if (pd < 0.0) /* reciprocity: phi_d and phi_d + pi are the same cell */
        pd += M_PI;
    if (pd >= M_PI)
        pd -= M_PI;
    /* MERL's lookup bins (floor), then the centre of that bin must match. */
    double fi = floor(sqrt(th / (M_PI / 2)) * BF_MERL_TH);
    double fj = floor(td / (M_PI / 2) * BF_MERL_TD), fk = floor(pd / M_PI * BF_MERL_PD);
    if (!(fi >= 0 && fi < BF_MERL_TH && fj >= 0 && fj < BF_MERL_TD && fk >= 0 && fk < BF_MERL_PD))
        return -1;
    int i = (int)fi, j = (int)fj, k = (int)fk;
    /* phi_d is measured from the plane of N and H, whose azimuth phi_h is only as
     * precise as (L + V)_xy: near normal H with L and V near grazing (|(L + V)_xy| down to
     * 8.5e-7 at theta_h bin 0, theta_d bin 89) the directions' own rounding (about 1e-15)
     * moves phi_d by more than 1e-9. Its tolerance grows accordingly, which still is far
     * below the bin width (pi/180) and amounts to directions within 1e-14 of the centre. */
    double tol_pd = tol + 1e-14 / hxy;
    if (fabs(th - centre_theta_h(i)) > tol || fabs(td - centre_theta_d(j)) > tol ||
        fabs(pd - centre_phi_d(k)) > tol_pd)
        return -1;
    return (int32_t)(k + BF_MERL_PD * (j + BF_MERL_TD * i));
}

/* ---- Reading ---------------------------------------------------------------------- */

static int cell_valid(const double *raw, size_t c)
{
    return raw[c] >= 0.0 && raw[BF_MERL_CELLS + c] >= 0.0 && raw[2 * (size_t)BF_MERL_CELLS + c] >= 0.0;
}

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

/* Reads the header and the raw table, checked: dimensions, exact size, finite values.
 * On success *raw (3 * BF_MERL_CELLS, host byte order) belongs to the caller. */
static int read_table(const char *path, double **raw, bf_error *err)
{
    *raw = NULL;
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return bf_fail(err, BF_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    int rc = BF_OK;
    double *t = NULL;
    int32_t dims[3];
    size_t got = fread(dims, 1, HEADER_BYTES, fp);
    if (ferror(fp)) {
        rc = bf_fail(err, BF_ERR_IO, "%s: read error: %s", path, strerror(errno));
        goto done;
    }
    if (got == 0) {
        rc = bf_fail(err, BF_ERR_PARSE, "%s: empty file (a MERL table is %zu bytes)", path,
                     (size_t)FILE_BYTES);
        goto done;
    }
    if (got < HEADER_BYTES) {
        rc = bf_fail(err, BF_ERR_PARSE,
                     "%s: byte offset %zu: file ends inside the 12-byte MERL header (3 int32 dimensions)",
                     path, got);
        goto done;
    }
    if (host_is_big_endian())
        swap_bytes(dims, 3, sizeof dims[0]);
    if (dims[0] != merl_dims[0] || dims[1] != merl_dims[1] || dims[2] != merl_dims[2]) {
        rc = bf_fail(err, BF_ERR_PARSE, "%s: byte offset 0: dimensions %ld x %ld x %ld, expected %d x %d x %d",
                     path, (long)dims[0], (long)dims[1], (long)dims[2], BF_MERL_TH, BF_MERL_TD, BF_MERL_PD);
        goto done;
    }
    if (!(t = malloc(TABLE_DOUBLES * sizeof *t))) {
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory for the MERL table", path);
        goto done;
    }
    got = fread(t, 1, TABLE_DOUBLES * sizeof *t, fp);
    if (ferror(fp)) {
        rc = bf_fail(err, BF_ERR_IO, "%s: read error: %s", path, strerror(errno));
        goto done;
    }
    if (got < TABLE_DOUBLES * sizeof *t) {
        rc = bf_fail(err, BF_ERR_PARSE, "%s: truncated: %zu bytes, a %d x %d x %d MERL table is %zu bytes",
                     path, HEADER_BYTES + got, BF_MERL_TH, BF_MERL_TD, BF_MERL_PD, (size_t)FILE_BYTES);
        goto done;
    }
    if (fgetc(fp) != EOF) {
        rc = bf_fail(err, BF_ERR_PARSE, "%s: wrong size: %zu bytes, a %d x %d x %d MERL table is %zu bytes",
                     path, stream_size(fp, FILE_BYTES + 1), BF_MERL_TH, BF_MERL_TD, BF_MERL_PD,
                     (size_t)FILE_BYTES);
        goto done;
    }
    if (host_is_big_endian())
        swap_bytes(t, TABLE_DOUBLES, sizeof *t);
    for (size_t x = 0; x < TABLE_DOUBLES; x++)
        if (!isfinite(t[x])) {
            size_t p = x / BF_MERL_CELLS, c = x % BF_MERL_CELLS;
            rc = bf_fail(err, BF_ERR_PARSE,
                         "%s: byte offset %zu: raw value %s in plane %s (theta_h %zu, theta_d %zu, phi_d %zu)",
                         path, HEADER_BYTES + x * sizeof *t, isnan(t[x]) ? "NaN" : "Inf", plane_name[p],
                         c / (BF_MERL_PD * BF_MERL_TD), c / BF_MERL_PD % BF_MERL_TD, c % BF_MERL_PD);
            goto done;
        }
done:
    fclose(fp);
    if (rc != BF_OK) {
        free(t);
        return rc;
    }
    *raw = t;
    return BF_OK;
}

int bf_samples_read_merl(const char *path, bf_samples **out, bf_error *err)
{
    *out = NULL;
    double *raw;
    int rc = read_table(path, &raw, err);
    if (rc != BF_OK)
        return rc;
    size_t n = 0;
    for (size_t c = 0; c < BF_MERL_CELLS; c++)
        n += (size_t)cell_valid(raw, c);
    bf_samples *s = bf_samples_new(n, 3, err);
    if (!s) {
        free(raw);
        return err ? err->code : BF_ERR_NOMEM;
    }
    /* Channel names are "r", "g", "b" for C = 3 (bf_samples_new). */
    if (!(s->merl = calloc(1, sizeof *s->merl)) || !(s->merl->cell = malloc((n + 1) * sizeof *s->merl->cell))) {
        free(raw);
        bf_samples_free(s);
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory for %zu samples", path, n);
    }
    s->merl->raw = raw;
    centre_trig t;
    centre_trig_init(&t);
    const double *R = raw, *G = raw + BF_MERL_CELLS, *B = raw + 2 * (size_t)BF_MERL_CELLS;
    size_t m = 0, c = 0;
    for (int i = 0; i < BF_MERL_TH; i++)
        for (int j = 0; j < BF_MERL_TD; j++)
            for (int k = 0; k < BF_MERL_PD; k++, c++) {
                if (!(R[c] >= 0.0 && G[c] >= 0.0 && B[c] >= 0.0))
                    continue;
                centre_directions(t.sth[i], t.cth[i], t.std_[j], t.ctd[j], t.spd[k], t.cpd[k],
                                  &s->theta_i[m], &s->phi_i[m], &s->theta_o[m], &s->phi_o[m]);
                s->value[3 * m] = R[c] * merl_scale[0];
                s->value[3 * m + 1] = G[c] * merl_scale[1];
                s->value[3 * m + 2] = B[c] * merl_scale[2];
                s->merl->cell[m] = (int32_t)c;
                m++;
            }
    *out = s;
    return BF_OK;
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
static int fill_table(const bf_samples *s, const char *path, double *table, uint32_t *owner,
                      bf_error *err)
{
    const bf_merl_origin *o = s->merl;
    for (size_t i = 0; i < s->n; i++) {
        int32_t cell = o ? o->cell[i] : bf_merl_cell_of(s->theta_i[i], s->phi_i[i], s->theta_o[i], s->phi_o[i]);
        if (cell < 0 || cell >= BF_MERL_CELLS)
            return bf_fail(err, BF_ERR_ARG,
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
                               "%s: sample %zu, channel %s: value %g cannot be stored in a MERL table (%s)",
                               path, i + 1, s->channel_names[p], v,
                               isfinite(v) ? "negative values mark invalid cells" : "not finite");
            double *slot = table + (size_t)p * BF_MERL_CELLS + (size_t)cell;
            /* Unchanged values keep their raw bits: a table read and written is the same file. */
            if (o && o->raw[(size_t)p * BF_MERL_CELLS + (size_t)cell] * merl_scale[p] == v)
                *slot = o->raw[(size_t)p * BF_MERL_CELLS + (size_t)cell];
            else
                *slot = raw_for(v, merl_scale[p]);
        }
    }
    return BF_OK;
}

int bf_samples_write_merl(const bf_samples *s, const char *path, bf_error *err)
{
    if (s->channels != 3)
        return bf_fail(err, BF_ERR_ARG, "%s: a MERL table needs 3 channels (R, G, B); the samples have %d",
                       path, s->channels);
    if (s->n > (size_t)BF_MERL_CELLS)
        return bf_fail(err, BF_ERR_ARG, "%s: %zu samples, a MERL table holds at most %d", path, s->n,
                       BF_MERL_CELLS);
    double *table = malloc(TABLE_DOUBLES * sizeof *table);
    uint32_t *owner = calloc(BF_MERL_CELLS, sizeof *owner); /* sample number + 1 per cell */
    if (!table || !owner) {
        free(table);
        free(owner);
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory for the MERL table", path);
    }
    if (s->merl)
        memcpy(table, s->merl->raw, TABLE_DOUBLES * sizeof *table);
    else
        for (size_t x = 0; x < TABLE_DOUBLES; x++)
            table[x] = -1.0;
    int rc = fill_table(s, path, table, owner, err);
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
    size_t put = fwrite(dims, sizeof dims[0], 3, o.fp);
    put += fwrite(table, sizeof *table, TABLE_DOUBLES, o.fp);
    free(table);
    if (put != 3 + TABLE_DOUBLES || ferror(o.fp)) {
        int e = errno;
        bf_outfile_abort(&o);
        return bf_fail(err, BF_ERR_IO, "%s: write error: %s", path, strerror(e));
    }
    return bf_outfile_commit(&o, err);
}
