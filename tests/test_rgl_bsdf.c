/* RGL-EPFL measured materials (.bsdf): the evaluation reproduces the file's stored
 * values at its own measured points, the samples and direction grids agree with it,
 * and hostile files (truncated, bad header, wrong sizes, NaN, anisotropic) are refused
 * with one-line errors. Real files: examples/rgl. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/formats.h"
#include "brdfit/samples.h"
#include "io/read_binary.h"
#include "io/rgl_bsdf.h"
#include "io/rgl_tensor_file.h"
#include "support.h"

#define PAPER BRDFIT_EXAMPLES "/rgl/paper_white_rgb.bsdf"
#define IBIZA BRDFIT_EXAMPLES "/rgl/cc_ibiza_sunset_rgb.bsdf"
#define FLOAT_EPS 1.2e-7 /* 2^-23 */

/* The raw float32 of the "rgb" field at (elevation k, channel c, row y, column x),
 * read from the file's bytes by the field's offset. */
static double raw_rgb(const bf_tensor_file *t, size_t k, int c, size_t y, size_t x)
{
    const bf_tensor_field *f = bf_tensor_file_field(t, "rgb");
    const size_t ny = f->shape[3], nx = f->shape[4];
    const size_t i = ((k * 3 + (size_t)c) * ny + y) * nx + x;
    return bf_le_f32(t->bytes + f->offset + 4 * i);
}

/* Every measured point: the evaluation's interpolated table value is the stored one to
 * float precision, and the BRDF is it times D / (4 sigma cos theta_o), as the point's
 * own value says. Column 0 of the grid is the exception the parameterization makes: the
 * warp maps all its nodes to theta_m = 0, one direction pair, where the 32 stored values
 * (noise around one value) cannot all come back; they are checked to be that. */
static void check_stored(const char *path, size_t want_points)
{
    bf_error err;
    bf_rgl_bsdf b;
    if (bf_rgl_bsdf_read(path, &b, &err) != BF_OK)
        fail_msg("%s", err.msg);
    size_t len;
    unsigned char *bytes = ts_read_binary(path, &len);
    bf_tensor_file t;
    assert_int_equal(bf_tensor_file_parse(path, bytes, len, &t, &err), BF_OK);
    assert_int_equal(b.channels, 3);
    assert_int_equal(b.n_theta, 8);
    assert_int_equal(b.values.nx, 32);
    assert_int_equal(b.values.ny, 32);
    size_t points = 0;
    double worst = 0.0;
    size_t wk = 0, wx = 0, wy = 0;
    for (size_t k = 0; k < b.n_theta; k++)
        for (size_t y = 0; y < b.values.ny; y++)
            for (size_t x = 0; x < b.values.nx; x++) {
                double wi[3], wo[3], f[3], stored[3], fp[3];
                if (bf_rgl_bsdf_point(&b, k, x, y, wi, wo, fp) != 0)
                    continue;
                points++;
                assert_true(fabs(wi[0] * wi[0] + wi[1] * wi[1] + wi[2] * wi[2] - 1.0) < 1e-12);
                assert_true(fabs(wo[0] * wo[0] + wo[1] * wo[1] + wo[2] * wo[2] - 1.0) < 1e-12);
                bf_rgl_bsdf_eval(&b, wi, wo, f, stored);
                for (int c = 0; c < 3; c++) {
                    const double want = raw_rgb(&t, k, c, y, x);
                    if (want > 1e-3)
                        ts_assert_rel(fp[c] / want, f[0] / stored[0], 1e-6, "the point's own BRDF");
                    if (x == 0) { /* the pole: one of the column's values, interpolated */
                        double lo = INFINITY, hi = -INFINITY;
                        for (size_t r = 0; r < b.values.ny; r++) {
                            lo = fmin(lo, raw_rgb(&t, k, c, r, 0));
                            hi = fmax(hi, raw_rgb(&t, k, c, r, 0));
                        }
                        if (!(stored[c] >= lo * (1 - FLOAT_EPS) && stored[c] <= hi * (1 + FLOAT_EPS)))
                            fail_msg("%s: pole (%zu, %zu) channel %d: %g outside the column's [%g, %g]", path, k, y, c,
                                     stored[c], lo, hi);
                        continue;
                    }
                    /* float precision, with a floor for the zeros. Rows 0 and ny - 1 are
                     * the azimuth seam (phi_m - phi_i = -pi and pi): one direction set,
                     * measured twice, so either row's value is right there. */
                    double e = fabs(stored[c] - want) / fmax(fabs(want), 1e-3);
                    if (y == b.values.ny - 1) {
                        const double w0 = raw_rgb(&t, k, c, 0, x);
                        e = fmin(e, fabs(stored[c] - w0) / fmax(fabs(w0), 1e-3));
                    }
                    if (e > worst) {
                        worst = e;
                        wk = k, wx = x, wy = y;
                    }
                    if (e > FLOAT_EPS)
                        fail_msg("%s: point (%zu, %zu, %zu) channel %d: %.9g, stored %.9g", path, k, x, y, c, stored[c],
                                 want);
                    /* The BRDF factor is one number for all channels. */
                    if (want > 1e-3)
                        ts_assert_rel(f[c] / stored[c], f[0] / stored[0], 1e-12, "D / (4 sigma cos)");
                }
            }
    assert_int_equal(points, want_points);
    print_message("%s: %zu points, worst relative difference %.3g at (%zu, %zu, %zu)\n", path, points, worst, wk, wx,
                  wy);
    bf_tensor_file_clear(&t);
    free(bytes);
    bf_rgl_bsdf_clear(&b);
}

static void test_stored_values(void **state)
{
    (void)state;
    check_stored(PAPER, 7118);
    check_stored(IBIZA, 7652);
}

/* The BRDF itself: isotropic (a rotation of both directions changes nothing), zero
 * below the horizon, and the paper diffuse: f within 30% of its mean far from the
 * mirror direction, with a mean near 1/pi (white paper reflects nearly everything). */
static void test_brdf_values(void **state)
{
    (void)state;
    bf_error err;
    bf_rgl_bsdf b;
    assert_int_equal(bf_rgl_bsdf_read(PAPER, &b, &err), BF_OK);
    double wi[3], wo[3], f[3], g[3];
    ts_dirs_deg(40, 0, 30, 60, wi, wo);
    bf_rgl_bsdf_eval(&b, wi, wo, f, NULL);
    ts_dirs_deg(40, 123, 30, 183, wi, wo);
    bf_rgl_bsdf_eval(&b, wi, wo, g, NULL);
    for (int c = 0; c < 3; c++)
        ts_assert_rel(g[c], f[c], 1e-9, "isotropy");
    ts_dirs_deg(40, 0, 95, 60, wi, wo);
    bf_rgl_bsdf_eval(&b, wi, wo, g, NULL);
    assert_true(g[0] == 0.0 && g[1] == 0.0 && g[2] == 0.0);
    double sum = 0.0;
    int n = 0;
    for (int ti = 10; ti <= 50; ti += 20)
        for (int to = 10; to <= 50; to += 20)
            for (int po = 30; po <= 90; po += 30) {
                ts_dirs_deg(ti, 0, to, po, wi, wo);
                bf_rgl_bsdf_eval(&b, wi, wo, f, NULL);
                sum += f[1];
                n++;
            }
    const double mean = sum / n;
    assert_true(mean > 0.8 / M_PI && mean < 1.2 / M_PI);
    bf_rgl_bsdf_clear(&b);
}

/* The reader: the measured points as samples (degrees, r g b, the evaluated BRDF). */
static void test_samples(void **state)
{
    (void)state;
    bf_error err;
    bf_samples *s;
    assert_int_equal(bf_samples_read_rgl(IBIZA, NULL, &s, &err), BF_OK);
    assert_int_equal(s->n, 7652);
    assert_int_equal(s->channels, 3);
    assert_string_equal(s->channel_names[0], "r");
    assert_null(s->wavelength);
    bf_rgl_bsdf b;
    assert_int_equal(bf_rgl_bsdf_read(IBIZA, &b, &err), BF_OK);
    size_t i = 0;
    for (size_t k = 0; k < b.n_theta; k++)
        for (size_t y = 0; y < b.values.ny; y++)
            for (size_t x = 0; x < b.values.nx; x++) {
                double wi[3], wo[3], f[3], d[3];
                if (bf_rgl_bsdf_point(&b, k, x, y, wi, wo, f) != 0)
                    continue;
                assert_true(s->theta_i[i] >= 0 && s->theta_i[i] <= 90 && s->theta_o[i] < 90);
                ts_dirs_deg(s->theta_i[i], s->phi_i[i], s->theta_o[i], s->phi_o[i], d, d);
                for (int c = 0; c < 3; c++)
                    assert_true(s->value[3 * i + (size_t)c] == f[c]);
                ts_dirs_deg(s->theta_i[i], s->phi_i[i], s->theta_o[i], s->phi_o[i], wi, d);
                for (int c = 0; c < 3; c++)
                    assert_true(fabs(d[c] - wo[c]) < 1e-12);
                i++;
            }
    assert_int_equal(i, s->n);
    /* The red film: red reflects most, away from the highlight. */
    double wi[3], wo[3], f[3];
    ts_dirs_deg(30, 0, 30, 90, wi, wo);
    bf_rgl_bsdf_eval(&b, wi, wo, f, NULL);
    assert_true(f[0] > 2 * f[1] && f[0] > 2 * f[2]);
    /* The highlight: mirror direction far above the side. */
    double m[3];
    ts_dirs_deg(30, 0, 30, 180, wi, wo);
    bf_rgl_bsdf_eval(&b, wi, wo, m, NULL);
    assert_true(m[1] > 20 * f[1]);
    bf_rgl_bsdf_clear(&b);
    bf_samples_free(s);
}

/* Direction grids: uniform:N counts and positions, MERL cells, a CSV of directions, all
 * evaluated as bf_rgl_bsdf_eval does. */
static void test_grids(void **state)
{
    (void)state;
    bf_error err;
    bf_samples *s;
    bf_rgl_bsdf b;
    assert_int_equal(bf_rgl_bsdf_read(PAPER, &b, &err), BF_OK);
    assert_int_equal(bf_samples_read_rgl(PAPER, "uniform:3", &s, &err), BF_OK);
    assert_int_equal(s->n, 27);
    assert_true(s->theta_i[0] == 15.0 && s->theta_o[0] == 15.0 && s->phi_o[0] == 30.0 && s->phi_i[0] == 0.0);
    assert_true(s->theta_i[26] == 75.0 && s->theta_o[26] == 75.0 && s->phi_o[26] == 150.0);
    for (size_t i = 0; i < s->n; i++) {
        double wi[3], wo[3], f[3];
        ts_dirs_deg(s->theta_i[i], s->phi_i[i], s->theta_o[i], s->phi_o[i], wi, wo);
        bf_rgl_bsdf_eval(&b, wi, wo, f, NULL);
        for (int c = 0; c < 3; c++)
            ts_assert_rel(s->value[3 * i + c], f[c], 1e-12, "uniform grid value");
    }
    bf_samples_free(s);

    const char *csv = ts_tmp_path("dirs.csv");
    const char *text = "theta_i,phi_i,theta_o,phi_o,extra\n10,0,20,180,1\n45,90,60,200,2\n30,0,95,0,3\n";
    ts_write_file(csv, text, strlen(text));
    assert_int_equal(bf_samples_read_rgl(PAPER, csv, &s, &err), BF_OK);
    assert_int_equal(s->n, 3);
    for (size_t i = 0; i < 3; i++) {
        double wi[3], wo[3], f[3];
        ts_dirs_deg(s->theta_i[i], s->phi_i[i], s->theta_o[i], s->phi_o[i], wi, wo);
        bf_rgl_bsdf_eval(&b, wi, wo, f, NULL);
        for (int c = 0; c < 3; c++)
            ts_assert_near(s->value[3 * i + c], f[c], 1e-12, 0, "CSV grid value");
    }
    assert_true(s->value[6] == 0.0); /* below the horizon */
    bf_samples_free(s);

    assert_int_equal(bf_samples_read_rgl(PAPER, "merl", &s, &err), BF_OK);
    assert_non_null(s->merl);
    assert_int_equal(s->n, 1096216); /* the cell centres above the horizon */
    for (size_t i = 0; i < s->n; i += 100003) {
        double d[4], wi[3], wo[3], f[3];
        bf_samples_direction(s, i, d);
        ts_dirs_deg(d[0], d[1], d[2], d[3], wi, wo);
        bf_rgl_bsdf_eval(&b, wi, wo, f, NULL);
        ts_assert_near(s->value[3 * i], f[0], 1e-9, 1e-12, "MERL grid value");
    }
    bf_samples_free(s);

    const char *bad[][2] = {{"uniform:0", "uniform:N needs N from 1 to 128"},
                            {"uniform:129", "uniform:N needs N"},
                            {"uniform:x", "uniform:N needs N"}};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        s = (bf_samples *)&s;
        assert_int_equal(bf_samples_read_rgl(PAPER, bad[k][0], &s, &err), BF_ERR_ARG);
        assert_null(s);
        assert_non_null(strstr(err.msg, bad[k][1]));
    }
    text = "theta_i,phi_i,theta_o\n10,0,20\n";
    ts_write_file(csv, text, strlen(text));
    assert_int_not_equal(bf_samples_read_rgl(PAPER, csv, &s, &err), BF_OK);
    assert_non_null(strstr(err.msg, "no column phi_o"));
    bf_rgl_bsdf_clear(&b);
}

/* Dispatch: by extension, by content under another name, by --format; a grid for a
 * format that cannot be evaluated is refused. */
static void test_dispatch(void **state)
{
    (void)state;
    bf_error err;
    bf_samples *s;
    size_t len;
    unsigned char *bytes = ts_read_binary(PAPER, &len);
    const char *other = ts_tmp_path("paper.dat");
    ts_write_file(other, (const char *)bytes, len);
    free(bytes);
    bf_read_options o = {0};
    assert_int_equal(bf_samples_read_with(other, &o, &s, &err), BF_OK);
    assert_int_equal(s->n, 7118);
    bf_samples_free(s);
    assert_int_equal(bf_format_parse("rgl", &o.format, NULL), BF_OK);
    assert_int_equal(o.format, BF_FORMAT_RGL);
    o.grid = "uniform:2";
    assert_int_equal(bf_samples_read_with(other, &o, &s, &err), BF_OK);
    assert_int_equal(s->n, 8);
    bf_samples_free(s);
    o.format = BF_FORMAT_AUTO;
    const char *csv = ts_tmp_path("d.csv");
    ts_write_file(csv, "theta_i,phi_i,theta_o,phi_o,v\n10,0,10,180,1\n", 44);
    assert_int_equal(bf_samples_read_with(csv, &o, &s, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "needs a format that can be evaluated anywhere"));
}

/* ---- Hostile files ---------------------------------------------------------------- */

static bf_status read_rgl(const char *path, bf_samples **out, bf_error *err)
{
    return bf_samples_read_rgl(path, NULL, out, err);
}

/* The paper file with `n` bytes at `at` replaced (or cut at `cut` when >= 0). */
static void expect_edit(const char *name, size_t at, const void *with, size_t n, long cut, const char *fragment)
{
    size_t len;
    unsigned char *b = ts_read_binary(PAPER, &len);
    memcpy(b + at, with, n);
    ts_expect_read_error(read_rgl, name, (const char *)b, cut >= 0 ? (size_t)cut : len, BF_ERR_PARSE, fragment);
    free(b);
}

/* The header offset of a field's record (name length), for edits. */
static size_t field_record(const char *name)
{
    size_t len;
    unsigned char *b = ts_read_binary(PAPER, &len);
    size_t pos = 18;
    for (;;) {
        const size_t nl = bf_le_u16(b + pos);
        if (nl == strlen(name) && !memcmp(b + pos + 2, name, nl))
            break;
        pos += 2 + nl + 11 + 8 * (size_t)bf_le_u16(b + pos + 2 + nl);
    }
    free(b);
    return pos;
}

static void test_hostile(void **state)
{
    (void)state;
    size_t len;
    unsigned char *b = ts_read_binary(PAPER, &len);
    free(b);
    /* Truncations: inside the header, inside a field record, inside the data. */
    const long cuts[] = {0, 5, 13, 17, 30, 200, 411, 2000, 600000, (long)len - 1};
    for (size_t k = 0; k < sizeof cuts / sizeof cuts[0]; k++) {
        char name[32];
        snprintf(name, sizeof name, "cut%ld.bsdf", cuts[k]);
        expect_edit(name, 0, "t", 1, cuts[k], cuts[k] == 0 ? "empty file" : cuts[k] < 18 ? "not a tensor file" : "");
    }
    expect_edit("magic.bsdf", 0, "TENSOR", 6, -1, "not a tensor file");
    expect_edit("version.bsdf", 12, "\2", 1, -1, "version 2.0");
    expect_edit("fields.bsdf", 14, "\377\377\377\377", 4, -1, "fields (at most");
    const size_t rgb = field_record("rgb"), vndf = field_record("vndf"), theta = field_record("theta_i");
    /* rgb: name(2+3), ndim(2), dtype(1), offset(8), 5 extents */
    const unsigned char huge[8] = {0, 0, 0, 0, 0, 0, 0, 1};
    expect_edit("offset.bsdf", rgb + 5 + 3, huge, 8, -1, "does not fit");
    expect_edit("extent.bsdf", rgb + 5 + 11, huge, 8, -1, "larger than the file");
    const unsigned char two[8] = {2, 0, 0, 0, 0, 0, 0, 0};
    expect_edit("channels.bsdf", rgb + 5 + 11 + 16, two, 8, -1, "has 2 channels, expected 3");
    expect_edit("dtype.bsdf", vndf + 6 + 2, "\1", 1, -1, "field 'vndf' is uint8 with 4 dimensions");
    expect_edit("dims.bsdf", vndf + 6, "\3", 1, -1, "byte offset");
    expect_edit("type.bsdf", vndf + 6 + 2, "\77", 1, -1, "unknown data type 63");
    expect_edit("ndims.bsdf", vndf + 6, "\377", 1, -1, "dimensions (at most 8)");
    expect_edit("noname.bsdf", rgb + 2, "xyz", 3, -1, "no field 'spectra'");
    expect_edit("stack.bsdf", vndf + 6 + 11 + 8, two, 8, -1, "stacked 1 x 2, expected 1 x 8");
    /* NaN and Inf in the data; theta_i out of order; a negative VNDF. */
    size_t l2;
    b = ts_read_binary(PAPER, &l2);
    const size_t rgb_data = (size_t)bf_le_u64(b + rgb + 5 + 3), theta_data = (size_t)bf_le_u64(b + theta + 9 + 3),
                 vndf_data = (size_t)bf_le_u64(b + vndf + 6 + 3);
    free(b);
    const float nan = NAN, inf = INFINITY, neg = -1.0f, big = 3.0f;
    expect_edit("nan.bsdf", rgb_data + 4 * 100, &nan, 4, -1, "field 'rgb' value 100 is NaN");
    expect_edit("inf.bsdf", theta_data + 4, &inf, 4, -1, "field 'theta_i' value 1 is Inf");
    expect_edit("order.bsdf", theta_data + 4, &big, 4, -1, "not increasing within [0, pi/2]");
    expect_edit("negvndf.bsdf", vndf_data + 4 * 7, &neg, 4, -1, "slice 0 is not a density");
    /* Anisotropic: phi_i with 3 values (the extent only: refused before the data). */
    const unsigned char three[8] = {3, 0, 0, 0, 0, 0, 0, 0};
    expect_edit("aniso.bsdf", field_record("phi_i") + 7 + 11, three, 8, -1,
                "anisotropic material (3 incident azimuths)");
    /* Every prefix of the header fails cleanly (no crash, no acceptance). */
    b = ts_read_binary(PAPER, &l2);
    for (size_t cut = 1; cut < 420; cut += 7) {
        const char *p = ts_tmp_path("prefix.bsdf");
        ts_write_file(p, (const char *)b, cut);
        bf_samples *s = NULL;
        bf_error err;
        assert_int_not_equal(bf_samples_read_rgl(p, NULL, &s, &err), BF_OK);
        assert_null(s);
        assert_null(strchr(err.msg, '\n'));
    }
    free(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stored_values), cmocka_unit_test(test_brdf_values), cmocka_unit_test(test_samples),
        cmocka_unit_test(test_grids),         cmocka_unit_test(test_dispatch),    cmocka_unit_test(test_hostile),
    };
    return cmocka_run_group_tests_name("rgl_bsdf", tests, NULL, NULL);
}
