/* MERL .binary tables: cell-centre geometry against docs/formats.md and MERL's own lookup,
 * reading (scales, invalid cells), byte-exact write-back, writing without an origin,
 * and every malformed-file error. Tables are generated here and written byte by byte
 * (little-endian), independently of the library's writer. */
#include <errno.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "brdfit/formats.h"
#include "brdfit/samples.h"
#include "support.h"

#define NCELLS ((size_t)BF_MERL_CELLS)
#define NRAW (3 * NCELLS)
#define FILE_BYTES (12 + 8 * NRAW)

static const double scale[3] = {1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0};

/* ---- Files -------------------------------------------------------------------------- */

static int dir_entries(void)
{
    DIR *d = opendir(ts_tmpdir());
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
    closedir(d);
    return n;
}

static void put_le(FILE *fp, uint64_t v, int bytes)
{
    for (int b = 0; b < bytes; b++)
        fputc((int)((v >> (8 * b)) & 0xff), fp);
}

/* A MERL file written by hand: dims, then the first `count` doubles of raw, then
 * `extra` zero bytes. */
static void write_raw_file(const char *path, const int32_t dims[3], const double *raw, size_t count, size_t extra)
{
    FILE *fp = fopen(path, "wb");
    assert_non_null(fp);
    for (int d = 0; d < 3; d++)
        put_le(fp, (uint32_t)dims[d], 4);
    for (size_t x = 0; x < count; x++) {
        uint64_t u;
        memcpy(&u, &raw[x], 8);
        put_le(fp, u, 8);
    }
    for (size_t x = 0; x < extra; x++)
        fputc(0, fp);
    assert_int_equal(fclose(fp), 0);
}

static const int32_t good_dims[3] = {90, 90, 180};

static unsigned char *slurp(const char *path, size_t *size)
{
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    fseek(fp, 0, SEEK_END);
    *size = (size_t)ftell(fp);
    rewind(fp);
    unsigned char *b = malloc(*size + 1);
    assert_int_equal(fread(b, 1, *size, fp), *size);
    fclose(fp);
    return b;
}

static double raw_at(const unsigned char *file, size_t x)
{
    uint64_t u = 0;
    for (int b = 7; b >= 0; b--)
        u = u << 8 | file[12 + 8 * x + (size_t)b];
    double v;
    memcpy(&v, &u, 8);
    return v;
}

static int same_bits(double a, double b)
{
    return memcmp(&a, &b, sizeof a) == 0;
}

/* ---- A random table ------------------------------------------------------------------ */

/* Raw values over many magnitudes, exact zeros and -0.0; about 20% of cells invalid in
 * all planes (-1, as MERL writes them) and 3% invalid in one plane only. */
static double *random_table(uint64_t seed, size_t *nvalid)
{
    ts_rng r = {seed};
    double *raw = malloc(NRAW * sizeof *raw);
    *nvalid = 0;
    for (size_t c = 0; c < NCELLS; c++) {
        double u = ts_uniform(&r);
        for (int p = 0; p < 3; p++) {
            double w = ts_uniform(&r);
            raw[p * NCELLS + c] = w < 0.01 ? 0.0 : w < 0.02 ? -0.0 : ts_uniform(&r) * pow(10.0, 8 * w - 4);
        }
        if (u < 0.2) {
            for (int p = 0; p < 3; p++)
                raw[p * NCELLS + c] = -1.0;
        } else if (u < 0.23) {
            int p = (int)(3 * ts_uniform(&r));
            raw[p * NCELLS + c] = -ts_uniform(&r) * 10.0 - 1e-12;
        } else {
            (*nvalid)++;
        }
    }
    return raw;
}

static int valid_cell(const double *raw, size_t c)
{
    return raw[c] >= 0 && raw[NCELLS + c] >= 0 && raw[2 * NCELLS + c] >= 0;
}

static void expect_msg(const bf_error *err, const char *frag)
{
    if (!strstr(err->msg, frag))
        fail_msg("message \"%s\" lacks \"%s\"", err->msg, frag);
}

/* ---- Plain geometry, as docs/formats.md and MERL's BRDFRead.cpp state it ------------- */

static void centre_angles(size_t c, double *th, double *td, double *pd)
{
    int i = (int)(c / (180 * 90)), j = (int)(c / 180 % 90), k = (int)(c % 180);
    *th = pow((i + 0.5) / 90.0, 2) * M_PI / 2;
    *td = (j + 0.5) / 90.0 * M_PI / 2;
    *pd = (k + 0.5) / 180.0 * M_PI;
}

/* MERL's rotate_vector (Rodrigues). */
static void rotate(const double v[3], const double a[3], double ang, double out[3])
{
    double c = cos(ang), s = sin(ang), d = a[0] * v[0] + a[1] * v[1] + a[2] * v[2];
    double x[3] = {a[1] * v[2] - a[2] * v[1], a[2] * v[0] - a[0] * v[2], a[0] * v[1] - a[1] * v[0]};
    for (int q = 0; q < 3; q++)
        out[q] = v[q] * c + a[q] * d * (1 - c) + x[q] * s;
}

static void dir_of(double theta, double phi, double v[3])
{
    v[0] = sin(theta) * cos(phi);
    v[1] = sin(theta) * sin(phi);
    v[2] = cos(theta);
}

/* MERL's lookup_brdf_val index, radians in. */
static long merl_lookup_index(double ti, double pi_, double to, double po)
{
    double in[3], out[3], half[3], tmp[3], diff[3];
    const double Y[3] = {0, 1, 0}, Z[3] = {0, 0, 1};
    dir_of(ti, pi_, in);
    dir_of(to, po, out);
    for (int q = 0; q < 3; q++)
        half[q] = (in[q] + out[q]) / 2;
    double len = sqrt(half[0] * half[0] + half[1] * half[1] + half[2] * half[2]);
    for (int q = 0; q < 3; q++)
        half[q] /= len;
    double th = acos(half[2]), ph = atan2(half[1], half[0]);
    rotate(in, Z, -ph, tmp);
    rotate(tmp, Y, -th, diff);
    double td = acos(diff[2]), pd = atan2(diff[1], diff[0]);
    long i = th <= 0 ? 0 : (long)sqrt(th / (M_PI / 2) * 90 * 90);
    long j = (long)(td / (M_PI / 2) * 90);
    if (pd < 0)
        pd += M_PI;
    long k = (long)(pd / M_PI * 180);
    i = i > 89 ? 89 : i;
    j = j > 89 ? 89 : j;
    k = k > 179 ? 179 : k;
    return k + 180 * (j + 90 * i);
}

/* ---- Geometry tests -------------------------------------------------------------------- */

/* Directions from bf_merl_cell_directions against the centre of docs/formats.md,
 * recomputed with MERL's rotation: L = Ry(theta_h) D, V = L mirrored about H. */
static void test_centre_directions(void **state)
{
    (void)state;
    const double Y[3] = {0, 1, 0};
    for (size_t c = 0; c < NCELLS; c += (c % 180 == 0 ? 1 : 13)) {
        double th, td, pd, D[3], L[3], V[3], H[3] = {0, 0, 0}, l[3], v[3];
        centre_angles(c, &th, &td, &pd);
        dir_of(td, pd, D);
        rotate(D, Y, th, L);
        H[0] = sin(th), H[2] = cos(th);
        double lh = L[0] * H[0] + L[2] * H[2];
        for (int q = 0; q < 3; q++)
            V[q] = 2 * lh * H[q] - L[q];
        double ti, pi_, to, po;
        bf_merl_cell_directions((int32_t)c, &ti, &pi_, &to, &po);
        assert_true(ti >= 0 && ti <= 180 && to >= 0 && to <= 180);
        assert_true(pi_ >= 0 && pi_ < 360 && po >= 0 && po < 360);
        dir_of(ti * DEG, pi_ * DEG, l);
        dir_of(to * DEG, po * DEG, v);
        for (int q = 0; q < 3; q++)
            if (fabs(l[q] - L[q]) > 1e-13 || fabs(v[q] - V[q]) > 1e-13)
                fail_msg("cell %zu: L or V component %d off: %g %g", c, q, l[q] - L[q], v[q] - V[q]);
    }
}

/* Every cell maps back to itself, also rotated about the normal (isotropy) and with L
 * and V swapped (reciprocity); MERL's own lookup agrees; off-centre pairs give -1. */
static void test_cell_of_inverse(void **state)
{
    (void)state;
    for (size_t c = 0; c < NCELLS; c++) {
        double ti, pi_, to, po;
        bf_merl_cell_directions((int32_t)c, &ti, &pi_, &to, &po);
        int32_t got = bf_merl_cell_of(ti, pi_, to, po);
        if (got != (int32_t)c)
            fail_msg("cell %zu came back as %d", c, got);
        long m = merl_lookup_index(ti * DEG, pi_ * DEG, to * DEG, po * DEG);
        if (m != (long)c)
            fail_msg("cell %zu: MERL's lookup gives %ld", c, m);
        if (c % 7 == 0) {
            assert_int_equal(bf_merl_cell_of(to, po, ti, pi_), c);
            assert_int_equal(bf_merl_cell_of(ti, pi_ + 73.25, to, po + 73.25), c);
            assert_int_equal(bf_merl_cell_of(ti, pi_ - 200, to, po - 200), c);
            /* 1e-5 degrees off in theta_i moves a half/difference angle by ~1e-7 rad */
            assert_int_equal(bf_merl_cell_of(ti + 1e-5, pi_, to, po), -1);
        }
    }
    assert_int_equal(bf_merl_cell_of(NAN, 0, 10, 180), -1);
    assert_int_equal(bf_merl_cell_of(10, 0, 10, 0), -1);    /* L = V: theta_h = 0 */
    assert_int_equal(bf_merl_cell_of(10, 0, 170, 180), -1); /* L = -V */
}

/* Cells below the horizon exist in the grid (|tan th tan td cos pd| > 1); the count the
 * directions give matches the plain criterion. */
static void test_horizon_count(void **state)
{
    (void)state;
    size_t below = 0, below_plain = 0;
    for (size_t c = 0; c < NCELLS; c++) {
        double ti, pi_, to, po, th, td, pd;
        bf_merl_cell_directions((int32_t)c, &ti, &pi_, &to, &po);
        below += ti > 90 || to > 90;
        centre_angles(c, &th, &td, &pd);
        below_plain += fabs(tan(th) * tan(td) * cos(pd)) > 1;
    }
    assert_int_equal(below, below_plain);
    assert_int_equal(below, 361784); /* the figure merl.c documents */
}

/* ---- Reading --------------------------------------------------------------------------- */

static void test_read_values(void **state)
{
    (void)state;
    size_t nvalid;
    double *raw = random_table(42, &nvalid);
    /* Known cells: unit raw values, a valid value below the horizon, -0.0 in one plane. */
    size_t unit = 1000, below = (size_t)89 * 180 * 90 + 89 * 180 + 2, negzero = 2000;
    double ti, pi_, to, po;
    bf_merl_cell_directions((int32_t)below, &ti, &pi_, &to, &po);
    assert_true(ti > 90 || to > 90);
    nvalid -= (size_t)(valid_cell(raw, unit) + valid_cell(raw, below) + valid_cell(raw, negzero));
    for (int p = 0; p < 3; p++) {
        raw[p * NCELLS + unit] = 1500.0;
        raw[p * NCELLS + below] = 3.0;
        raw[p * NCELLS + negzero] = p == 1 ? -0.0 : 7.0;
    }
    nvalid += 3; /* all three are valid now (-0.0 is not negative) */
    const char *path = ts_tmp_path("read.binary");
    write_raw_file(path, good_dims, raw, NRAW, 0);
    bf_samples *s;
    bf_error err;
    assert_int_equal(bf_samples_read_merl(path, 1, &s, &err), BF_OK);
    assert_int_equal(s->n, nvalid);
    assert_int_equal(s->channels, 3);
    assert_string_equal(s->channel_names[0], "r");
    assert_string_equal(s->channel_names[1], "g");
    assert_string_equal(s->channel_names[2], "b");
    assert_null(s->weight);
    assert_non_null(s->merl);
    assert_null(s->theta_i); /* addressed by cells: no angle arrays */
    assert_memory_equal(s->merl->raw, raw, NRAW * sizeof *raw);
    /* Every valid cell once, in index order; every invalid one skipped. */
    size_t m = 0;
    for (size_t c = 0; c < NCELLS; c++) {
        if (!valid_cell(raw, c))
            continue;
        assert_true(m < s->n);
        assert_int_equal(s->merl->cell[m], c);
        for (int p = 0; p < 3; p++)
            assert_true(same_bits(s->value[3 * m + (size_t)p], raw[p * NCELLS + c] * scale[p]));
        bf_merl_cell_directions((int32_t)c, &ti, &pi_, &to, &po);
        double dir[4];
        bf_samples_direction(s, m, dir);
        assert_true(dir[0] == ti && dir[1] == pi_ && dir[2] == to && dir[3] == po);
        if (c == unit) {
            ts_assert_rel(s->value[3 * m], 1.0, 1e-15, "R of raw 1500");
            ts_assert_rel(s->value[3 * m + 1], 1.15, 1e-15, "G of raw 1500");
            ts_assert_rel(s->value[3 * m + 2], 1.66, 1e-15, "B of raw 1500");
        }
        if (c == below)
            assert_true(dir[0] > 90 || dir[2] > 90);
        m++;
    }
    assert_int_equal(m, s->n);
    /* Without the raw table: the same samples, cells and values, and no raw. */
    bf_samples *t;
    assert_int_equal(bf_samples_read_merl(path, 0, &t, &err), BF_OK);
    assert_null(t->merl->raw);
    assert_int_equal(t->n, s->n);
    assert_memory_equal(t->merl->cell, s->merl->cell, s->n * sizeof *s->merl->cell);
    assert_memory_equal(t->value, s->value, 3 * s->n * sizeof *s->value);
    bf_samples_free(t);
    bf_samples_free(s);
    free(raw);
}

/* The generated geometry of cell-addressed samples against the stored geometry of the
 * same directions given as angles: the same vectors to rounding, the same horizon. */
static void test_cell_geometry(void **state)
{
    (void)state;
    size_t nvalid;
    double *raw = random_table(13, &nvalid);
    const char *path = ts_tmp_path("geom.binary");
    write_raw_file(path, good_dims, raw, NRAW, 0);
    bf_samples *s;
    bf_error err;
    assert_int_equal(bf_samples_read_merl(path, 0, &s, &err), BF_OK);
    const bf_geometry *g = NULL;
    bf_samples_geometry(s, &g, &err);
    assert_non_null(g);
    assert_false(bf_geometry_stored(g));
    double *rad = malloc(4 * s->n * sizeof *rad);
    for (size_t i = 0; i < s->n; i++) {
        double dir[4];
        bf_samples_direction(s, i, dir);
        for (int k = 0; k < 4; k++)
            rad[k * s->n + i] = dir[k] * (M_PI / 180.0);
    }
    bf_geometry *ga = NULL;
    bf_geometry_from_angles(s->n, rad, rad + s->n, rad + 2 * s->n, rad + 3 * s->n, &ga, &err);
    assert_non_null(ga);
    bf_geometry_block gb;
    for (size_t i0 = 0; i0 < s->n; i0 += BF_GEOMETRY_BLOCK) {
        size_t cnt = s->n - i0 < BF_GEOMETRY_BLOCK ? s->n - i0 : BF_GEOMETRY_BLOCK;
        const bf_geometry *v = bf_geometry_view(g, i0, cnt, &gb);
        for (size_t q = 0; q < cnt; q++) {
            size_t i = i0 + q;
            const double a[11] = {v->lx[q], v->ly[q], v->lz[q], v->vx[q], v->vy[q],   v->vz[q],
                                  v->hx[q], v->hy[q], v->hz[q], v->vh[q], v->sin2h[q]};
            const double b[11] = {ga->lx[i], ga->ly[i], ga->lz[i], ga->vx[i], ga->vy[i],   ga->vz[i],
                                  ga->hx[i], ga->hy[i], ga->hz[i], ga->vh[i], ga->sin2h[i]};
            assert_int_equal(bf_geometry_valid(v, q), bf_geometry_valid(ga, i));
            assert_int_equal(bf_geometry_valid_at(g, i), bf_geometry_valid(ga, i));
            if (!bf_geometry_valid(ga, i))
                continue;
            for (int k = 0; k < 11; k++)
                if (fabs(a[k] - b[k]) > 1e-13)
                    fail_msg("sample %zu, field %d: %.17g generated, %.17g from angles", i, k, a[k], b[k]);
        }
    }
    bf_geometry_free(ga);
    free(rad);
    bf_samples_free(s);
    free(raw);
}

/* ---- Writing --------------------------------------------------------------------------- */

static void test_round_trip_bytes(void **state)
{
    (void)state;
    size_t nvalid, n1, n2, n3;
    double *raw = random_table(7, &nvalid);
    const char *in = ts_tmp_path("in.binary"), *out = ts_tmp_path("out.binary"), *out2 = ts_tmp_path("out2.binary");
    write_raw_file(in, good_dims, raw, NRAW, 0);
    bf_samples *s;
    bf_error err;
    assert_int_equal(bf_samples_read_merl(in, 1, &s, &err), BF_OK);
    assert_int_equal(bf_samples_write_merl(s, out, &err), BF_OK);
    assert_int_equal(bf_samples_write(s, out2, BF_FORMAT_AUTO, &err), BF_OK); /* by extension */
    unsigned char *a = slurp(in, &n1), *b = slurp(out, &n2), *c = slurp(out2, &n3);
    assert_int_equal(n1, FILE_BYTES);
    assert_int_equal(n2, n1);
    assert_int_equal(n3, n1);
    assert_memory_equal(a, b, n1);
    assert_memory_equal(a, c, n1);
    free(a), free(b), free(c);
    bf_samples_free(s);
    free(raw);
}

/* Dropped samples become invalid cells; the rest keeps its bytes. */
static void test_keep_then_write(void **state)
{
    (void)state;
    size_t nvalid, size;
    double *raw = random_table(9, &nvalid);
    const char *in = ts_tmp_path("keep_in.binary"), *out = ts_tmp_path("keep_out.binary");
    write_raw_file(in, good_dims, raw, NRAW, 0);
    bf_samples *s;
    bf_error err;
    assert_int_equal(bf_samples_read_merl(in, 1, &s, &err), BF_OK);
    unsigned char *keep = malloc(s->n);
    unsigned char *dropped = calloc(NCELLS, 1);
    for (size_t i = 0; i < s->n; i++) {
        keep[i] = i % 3 != 0;
        if (!keep[i])
            dropped[s->merl->cell[i]] = 1;
    }
    assert_int_equal(bf_samples_keep(s, keep, &err), BF_OK);
    assert_int_equal(bf_samples_write_merl(s, out, &err), BF_OK);
    unsigned char *f = slurp(out, &size);
    assert_int_equal(size, FILE_BYTES);
    for (size_t x = 0; x < NRAW; x++) {
        double want = dropped[x % NCELLS] ? -1.0 : raw[x];
        if (!same_bits(raw_at(f, x), want))
            fail_msg("raw %zu: %g, want %g", x, raw_at(f, x), want);
    }
    free(f), free(keep), free(dropped);
    bf_samples_free(s);
    free(raw);
}

/* Changed values are written so that they read back exactly. */
static void test_changed_values(void **state)
{
    (void)state;
    size_t nvalid;
    double *raw = random_table(11, &nvalid);
    const char *in = ts_tmp_path("chg_in.binary"), *out = ts_tmp_path("chg_out.binary");
    write_raw_file(in, good_dims, raw, NRAW, 0);
    bf_samples *s, *t;
    bf_error err;
    assert_int_equal(bf_samples_read_merl(in, 1, &s, &err), BF_OK);
    ts_rng r = {5};
    for (size_t x = 0; x < 3 * s->n; x += 2)
        s->value[x] = ts_uniform(&r) * pow(10.0, 6 * ts_uniform(&r) - 3);
    assert_int_equal(bf_samples_write_merl(s, out, &err), BF_OK);
    assert_int_equal(bf_samples_read_merl(out, 0, &t, &err), BF_OK);
    assert_int_equal(t->n, s->n);
    /* Raw * scale cannot reach every double: within one ulp, and exact for most. */
    size_t exact = 0;
    for (size_t x = 0; x < 3 * s->n; x++) {
        double w = s->value[x], got = t->value[x];
        exact += same_bits(got, w);
        if (!same_bits(got, w) && got != nextafter(w, INFINITY) && got != nextafter(w, -INFINITY))
            fail_msg("value %zu: wrote %.17g, read %.17g", x, w, got);
    }
    assert_true(exact > 3 * s->n / 2);
    bf_samples_free(s);
    bf_samples_free(t);
    free(raw);
}

/* A few cell-centre samples and no origin: their cells hold value/scale, every other
 * cell -1 in all planes; reading gives the samples back. */
static void test_write_without_origin(void **state)
{
    (void)state;
    const int32_t cells[4] = {0, 12345, 700001, BF_MERL_CELLS - 1};
    bf_error err;
    bf_samples *s = NULL;
    bf_samples_new(4, 3, &s, &err);
    ts_rng r = {3};
    for (int i = 0; i < 4; i++) {
        bf_merl_cell_directions(cells[i], &s->theta_i[i], &s->phi_i[i], &s->theta_o[i], &s->phi_o[i]);
        for (int p = 0; p < 3; p++)
            s->value[3 * i + p] = ts_uniform(&r) * 10;
    }
    /* Any azimuth, and L and V exchanged, name the same cell. */
    s->phi_i[1] += 100, s->phi_o[1] += 100;
    double t = s->theta_i[2], p_ = s->phi_i[2];
    s->theta_i[2] = s->theta_o[2], s->phi_i[2] = s->phi_o[2];
    s->theta_o[2] = t, s->phi_o[2] = p_;
    s->value[0] = 0.0;
    const char *path = ts_tmp_path("few.binary");
    assert_int_equal(bf_samples_write_merl(s, path, &err), BF_OK);
    size_t size;
    unsigned char *f = slurp(path, &size);
    assert_int_equal(size, FILE_BYTES);
    for (int d = 0; d < 3; d++)
        assert_int_equal(f[4 * d] | f[4 * d + 1] << 8 | f[4 * d + 2] << 16 | f[4 * d + 3] << 24, good_dims[d]);
    for (size_t x = 0; x < NRAW; x++) {
        size_t c = x % NCELLS;
        int i = -1;
        for (int q = 0; q < 4; q++)
            i = (size_t)cells[q] == c ? q : i;
        double got = raw_at(f, x);
        if (i < 0) {
            if (!same_bits(got, -1.0))
                fail_msg("cell %zu plane %zu: %g, want -1", c, x / NCELLS, got);
            continue;
        }
        int p = (int)(x / NCELLS);
        ts_assert_rel(got, s->value[3 * i + p] / scale[p], 1e-15, "raw written");
        assert_true(fabs(got * scale[p] - s->value[3 * i + p]) <= 2.3e-16 * s->value[3 * i + p]);
    }
    free(f);
    bf_samples *back;
    assert_int_equal(bf_samples_read_merl(path, 0, &back, &err), BF_OK);
    assert_int_equal(back->n, 4);
    for (int i = 0; i < 4; i++) {
        assert_int_equal(back->merl->cell[i], cells[i]);
        for (int p = 0; p < 3; p++)
            ts_assert_rel(back->value[3 * i + p], s->value[3 * i + p], 2.3e-16, "value read back");
    }
    bf_samples_free(back);
    bf_samples_free(s);
}

static void expect_write_error(bf_samples *s, int code, const char *frag)
{
    bf_error err;
    const char *path = ts_tmp_path("bad_out.binary");
    int before = dir_entries();
    assert_int_equal(bf_samples_write_merl(s, path, &err), code);
    expect_msg(&err, path);
    expect_msg(&err, frag);
    assert_int_equal(access(path, F_OK), -1); /* no output, no temporary left */
    assert_int_equal(dir_entries(), before);
}

static void test_write_errors(void **state)
{
    (void)state;
    bf_error err;
    bf_samples *mono = NULL;
    bf_samples_new(1, 1, &mono, &err);
    bf_merl_cell_directions(5, &mono->theta_i[0], &mono->phi_i[0], &mono->theta_o[0], &mono->phi_o[0]);
    expect_write_error(mono, BF_ERR_ARG, "3 channels");
    bf_samples_free(mono);

    bf_samples *s = NULL;
    bf_samples_new(3, 3, &s, &err);
    for (int i = 0; i < 3; i++) {
        bf_merl_cell_directions(100 * i + 1, &s->theta_i[i], &s->phi_i[i], &s->theta_o[i], &s->phi_o[i]);
        for (int p = 0; p < 3; p++)
            s->value[3 * i + p] = 0.5;
    }
    s->theta_o[1] += 0.01;
    expect_write_error(s, BF_ERR_ARG, "sample 2 ");
    s->theta_o[1] -= 0.01;
    assert_int_equal(bf_merl_cell_of(s->theta_i[1], s->phi_i[1], s->theta_o[1], s->phi_o[1]), 101);
    s->value[7] = -1e-3; /* sample 3, channel g */
    expect_write_error(s, BF_ERR_RANGE, "sample 3, channel g");
    s->value[7] = NAN;
    expect_write_error(s, BF_ERR_RANGE, "not finite");
    s->value[7] = 0.5;
    bf_merl_cell_directions(1, &s->theta_o[2], &s->phi_o[2], &s->theta_i[2], &s->phi_i[2]);
    expect_write_error(s, BF_ERR_ARG, "samples 1 and 3");
    bf_samples_free(s);
}

/* ---- Malformed files --------------------------------------------------------------------- */

static void expect_read_error(const char *path, int code, const char *frag1, const char *frag2)
{
    for (int keep_raw = 0; keep_raw < 2; keep_raw++) { /* both layouts of the reader */
        bf_samples *s = (bf_samples *)&s;              /* must come back NULL */
        bf_error err;
        assert_int_equal(bf_samples_read_merl(path, keep_raw, &s, &err), code);
        assert_null(s);
        assert_null(strchr(err.msg, '\n'));
        expect_msg(&err, path);
        expect_msg(&err, frag1);
        if (frag2)
            expect_msg(&err, frag2);
    }
}

static void test_read_errors(void **state)
{
    (void)state;
    expect_read_error(ts_tmp_path("missing.binary"), BF_ERR_IO, "cannot open", NULL);
    expect_read_error(ts_tmpdir(), BF_ERR_IO, "read error", NULL);

    const char *p = ts_tmp_path("bad.binary");
    write_raw_file(p, good_dims, NULL, 0, 0);
    assert_int_equal(truncate(p, 0), 0);
    expect_read_error(p, BF_ERR_PARSE, "empty file", NULL);
    write_raw_file(p, good_dims, NULL, 0, 0);
    assert_int_equal(truncate(p, 5), 0);
    expect_read_error(p, BF_ERR_PARSE, "byte offset 5", "12-byte MERL header");

    size_t nvalid;
    double *raw = random_table(13, &nvalid);
    const int32_t wide[3] = {90, 90, 360};
    write_raw_file(p, wide, raw, NRAW, 0);
    expect_read_error(p, BF_ERR_PARSE, "dimensions 90 x 90 x 360", "expected 90 x 90 x 180");
    const int32_t neg[3] = {-1, 90, 180};
    write_raw_file(p, neg, raw, NRAW, 0);
    expect_read_error(p, BF_ERR_PARSE, "dimensions -1 x 90 x 180", NULL);

    write_raw_file(p, good_dims, raw, NRAW - 1, 0);
    expect_read_error(p, BF_ERR_PARSE, "34992004 bytes", "34992012 bytes");
    write_raw_file(p, good_dims, raw, NRAW, 3);
    expect_read_error(p, BF_ERR_PARSE, "34992015 bytes", "34992012 bytes");
    write_raw_file(p, good_dims, raw, 0, 0);
    expect_read_error(p, BF_ERR_PARSE, "truncated: 12 bytes", NULL);

    double keep = raw[1000];
    raw[1000] = NAN;
    write_raw_file(p, good_dims, raw, NRAW, 0);
    expect_read_error(p, BF_ERR_PARSE, "byte offset 8012:", "NaN in plane R");
    raw[1000] = keep;
    raw[2 * NCELLS + 5] = -INFINITY;
    write_raw_file(p, good_dims, raw, NRAW, 0);
    char frag[64];
    snprintf(frag, sizeof frag, "byte offset %zu:", 12 + 8 * (2 * NCELLS + 5));
    expect_read_error(p, BF_ERR_PARSE, frag, "Inf in plane B");
    free(raw);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_centre_directions),    cmocka_unit_test(test_cell_of_inverse),
        cmocka_unit_test(test_horizon_count),        cmocka_unit_test(test_read_values),
        cmocka_unit_test(test_cell_geometry),        cmocka_unit_test(test_round_trip_bytes),
        cmocka_unit_test(test_keep_then_write),      cmocka_unit_test(test_changed_values),
        cmocka_unit_test(test_write_without_origin), cmocka_unit_test(test_write_errors),
        cmocka_unit_test(test_read_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
