/* NVIDIA MDL measured BSDFs (.mbsdf): the real car paint (examples/mdl) at its cell
 * centres, its specular peak at theta_out = theta_in and phi = 180 degrees, the table
 * interpolated on direction grids, negative values under every --negative mode, the
 * transmission part, and hostile files. */
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
#include "brdfit/prep.h"
#include "brdfit/samples.h"
#include "io/read_binary.h"
#include "support.h"

#define CARPAINT BRDFIT_EXAMPLES "/mdl/carpaint_red.mbsdf"
#define NT 45
#define NP 90
#define HEAD 55 /* the magic line, the reflection line, 3 uint32 */

static bf_samples *read_ok(const char *path, const char *grid)
{
    bf_samples *s;
    bf_error err;
    if (bf_samples_read_mbsdf(path, grid, &s, &err) != BF_OK)
        fail_msg("%s", err.msg);
    return s;
}

/* Every cell: its centre's angles and the mean of the file's floats at the cell and at
 * its reciprocal (theta_in and theta_out exchanged), in file order. */
static void test_cells(void **state)
{
    (void)state;
    size_t len;
    unsigned char *b = ts_read_binary(CARPAINT, &len);
    assert_int_equal(len, HEAD + (size_t)NT * NT * NP * 3 * 4);
    bf_samples *s = read_ok(CARPAINT, NULL);
    assert_int_equal(s->n, (size_t)NT * NT * NP);
    assert_int_equal(s->channels, 3);
    assert_string_equal(s->channel_names[2], "b");
    for (size_t i = 0; i < s->n; i++) {
        const size_t ti = i / (NT * NP), to = i / NP % NT, j = i % NP;
        if (s->theta_i[i] != (ti + 0.5) * 2.0 || s->theta_o[i] != (to + 0.5) * 2.0 || s->phi_i[i] != 0.0 ||
            s->phi_o[i] != (j + 0.5) * 2.0)
            fail_msg("cell %zu at %g %g %g %g", i, s->theta_i[i], s->phi_i[i], s->theta_o[i], s->phi_o[i]);
        const size_t r = (to * NT + ti) * NP + j; /* the reciprocal cell */
        for (int c = 0; c < 3; c++) {
            const double a = bf_le_f32(b + HEAD + 4 * (3 * i + (size_t)c)),
                         z = bf_le_f32(b + HEAD + 4 * (3 * r + (size_t)c));
            if (s->value[3 * i + c] != 0.5 * (a + z))
                fail_msg("cell %zu channel %d", i, c);
        }
    }
    free(b);
    bf_samples_free(s);
}

/* The check: the brightest cell of the table (sum of channels) is a mirror one,
 * theta_out = theta_in at the azimuth cell next to 180 degrees (centre 179), and so is
 * the brightest of each incident elevation from 11 to 65 degrees. Nearer the normal
 * every cell is within a few degrees of the mirror direction and the lobe is wider than
 * a cell; beyond 65 degrees the table repeats its last measured row (its peak stays at
 * theta_out = 65 degrees, the azimuth at 179). */
static void test_specular_peak(void **state)
{
    (void)state;
    bf_samples *s = read_ok(CARPAINT, NULL);
    size_t top = 0;
    for (size_t i = 0; i < s->n; i++)
        if (s->value[3 * i] + s->value[3 * i + 1] + s->value[3 * i + 2] >
            s->value[3 * top] + s->value[3 * top + 1] + s->value[3 * top + 2])
            top = i;
    assert_true(s->theta_o[top] == s->theta_i[top] && s->phi_o[top] == 179.0);
    for (size_t ti = 5; ti < NT; ti++) {
        size_t best = 0;
        double best_v = -INFINITY;
        for (size_t k = 0; k < (size_t)NT * NP; k++) {
            const size_t i = ti * NT * NP + k;
            const double v = s->value[3 * i] + s->value[3 * i + 1] + s->value[3 * i + 2];
            if (v > best_v) {
                best_v = v;
                best = i;
            }
        }
        if (s->phi_o[best] != 179.0)
            fail_msg("theta_in %g: peak at phi %g", s->theta_i[best], s->phi_o[best]);
        if (s->theta_i[best] <= 65.0 && s->theta_o[best] != s->theta_i[best])
            fail_msg("theta_in %g: peak at theta_out %g", s->theta_i[best], s->theta_o[best]);
        assert_true(best_v > 1.0); /* a highlight, far above the diffuse ~0.05 */
    }
    bf_samples_free(s);
}

/* Grids: at cell centres the table's values, half way between two azimuth cells their
 * mean (the MDL SDK's trilinear texture lookup), 0 below the horizon; uniform:N counts. */
static void test_grid(void **state)
{
    (void)state;
    bf_samples *cells = read_ok(CARPAINT, NULL);
    const char *csv = ts_tmp_path("dirs.csv");
    const char *text = "theta_i,phi_i,theta_o,phi_o\n"
                       "31,0,31,179\n"  /* cell (15, 15, 89) */
                       "31,10,31,189\n" /* the same, rotated */
                       "31,0,31,-179\n" /* azimuth folded into [0, 180] */
                       "31,0,31,178\n"  /* between cells 88 and 89 */
                       "31,0,95,179\n"; /* below the horizon */
    ts_write_file(csv, text, strlen(text));
    bf_samples *s = read_ok(CARPAINT, csv);
    assert_int_equal(s->n, 5);
    const size_t c89 = (15 * NT + 15) * NP + 89, c88 = c89 - 1;
    for (int c = 0; c < 3; c++) {
        const double v89 = cells->value[3 * c89 + (size_t)c], v88 = cells->value[3 * c88 + (size_t)c];
        ts_assert_near(s->value[c], v89, 1e-12, 1e-15, "cell centre");
        ts_assert_near(s->value[3 + c], v89, 1e-9, 1e-12, "rotated");
        ts_assert_near(s->value[6 + c], v89, 1e-9, 1e-12, "folded azimuth");
        ts_assert_near(s->value[9 + c], 0.5 * (v88 + v89), 1e-9, 1e-12, "between cells");
        assert_true(s->value[12 + c] == 0.0);
    }
    bf_samples_free(s);
    s = read_ok(CARPAINT, "uniform:5");
    assert_int_equal(s->n, 125);
    bf_samples_free(s);
    bf_samples_free(cells);
}

/* Negative values are data: kept, dropped or clamped as --negative says. */
static void test_negative(void **state)
{
    (void)state;
    const bf_negative modes[3] = {BF_NEGATIVE_KEEP, BF_NEGATIVE_DROP, BF_NEGATIVE_CLAMP};
    for (int k = 0; k < 3; k++) {
        bf_samples *s = read_ok(CARPAINT, NULL);
        bf_prep p = {0};
        p.negative = modes[k];
        bf_prep_report r;
        bf_error err;
        assert_int_equal(bf_samples_prep(s, &p, &r, &err), BF_OK);
        assert_int_equal(r.negative, 48238);
        assert_int_equal(s->n, modes[k] == BF_NEGATIVE_DROP ? (size_t)NT * NT * NP - 48238 : (size_t)NT * NT * NP);
        size_t neg = 0;
        for (size_t i = 0; i < 3 * s->n; i++)
            neg += s->value[i] < 0;
        assert_true(modes[k] == BF_NEGATIVE_KEEP ? neg > 0 : neg == 0);
        bf_samples_free(s);
    }
}

/* A small file: magic, optional lines, parts of type/res given, values v. */
static size_t make(unsigned char *out, const char *lines, int with_refl, int with_trans, uint32_t type, uint32_t nt,
                   uint32_t np, float v)
{
    size_t n = 0;
    n += (size_t)sprintf((char *)out + n, "NVIDIA ARC MBSDF V1\n%s", lines);
    for (int part = 0; part < 2; part++) {
        if (!(part ? with_trans : with_refl))
            continue;
        n += (size_t)sprintf((char *)out + n, "%s\n", part ? "MBSDF_DATA_TRANSMISSION=" : "MBSDF_DATA_REFLECTION=");
        const uint32_t h[3] = {type, nt, np};
        for (int k = 0; k < 3; k++)
            for (int j = 0; j < 4; j++)
                out[n++] = (unsigned char)(h[k] >> (8 * j));
        for (size_t i = 0; i < (size_t)nt * nt * np * (type ? 3 : 1); i++) {
            uint32_t u;
            float x = i == 5 ? v : 0.25f;
            memcpy(&u, &x, 4);
            for (int j = 0; j < 4; j++)
                out[n++] = (unsigned char)(u >> (8 * j));
        }
    }
    return n;
}

static bf_status read_mbsdf(const char *path, bf_samples **out, bf_error *err)
{
    return bf_samples_read_mbsdf(path, NULL, out, err);
}

static void test_small_files(void **state)
{
    (void)state;
    static unsigned char buf[1 << 16];
    /* Scalar, metadata lines before the data, a transmission part after it: read. */
    size_t n = make(buf, "some metadata\nmore=1\n", 1, 1, 0, 2, 3, -0.5f);
    const char *p = ts_tmp_path("small.mbsdf");
    ts_write_file(p, (const char *)buf, n);
    bf_samples *s = read_ok(p, NULL);
    assert_int_equal(s->n, 12);
    assert_int_equal(s->channels, 1);
    assert_string_equal(s->channel_names[0], "value");
    assert_true(s->value[5] == -0.125 && s->value[8] == -0.125 && s->value[4] == 0.25); /* reciprocal mean */
    assert_true(s->theta_i[11] == 67.5 && s->theta_o[11] == 67.5 && s->phi_o[11] == 150.0);
    bf_samples_free(s);

    struct {
        const char *name, *lines, *fragment;
        int refl, trans;
        uint32_t type, nt, np;
        float v;
        long cut;
    } bad[] = {
        {"magic.mbsdf", "", "not an mbsdf file", 1, 0, 1, 2, 2, 0, -2},
        {"trans.mbsdf", "", "no reflection part (MBSDF_DATA_REFLECTION=): a transmission-only", 0, 1, 1, 2, 2, 0, -1},
        {"none.mbsdf", "", "no reflection part", 0, 0, 1, 2, 2, 0, -1},
        {"type.mbsdf", "", "reflection data type 2 (0 scalar, 1 RGB)", 1, 0, 2, 2, 2, 0, -1},
        {"res0.mbsdf", "", "resolution 0 theta x 2 phi", 1, 0, 1, 0, 2, 0, -1},
        {"huge.mbsdf", "", "resolution 2 theta x 4000000000 phi", 1, 0, 1, 2, 4000000000u, 0, -1},
        {"nan.mbsdf", "", "reflection value 5 is NaN", 1, 0, 1, 2, 2, NAN, -1},
        {"inf.mbsdf", "", "reflection value 5 is Inf", 1, 1, 1, 2, 2, INFINITY, -1},
        {"cut.mbsdf", "", "truncated: the reflection table", 1, 0, 1, 2, 2, 0, 90},
        {"cuthead.mbsdf", "", "file ends inside the reflection header", 1, 0, 1, 2, 2, 0, 50},
        {"noline.mbsdf", "no newline", "expected a text line", 0, 0, 1, 2, 2, 0, -1},
        {"two.mbsdf", "", "a second reflection part", 1, 0, 1, 2, 2, 0, -3},
        {"junk.mbsdf", "", "unexpected data after a table", 1, 0, 1, 2, 2, 0, -4},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        n = make(buf, bad[k].lines, bad[k].refl, bad[k].trans, bad[k].type, bad[k].nt, bad[k].np > 100 ? 1 : bad[k].np,
                 bad[k].v);
        if (bad[k].np > 100) /* the header says more than the data holds */
            buf[20 + 23 + 8] = 0, buf[20 + 23 + 9] = 0x28, buf[20 + 23 + 10] = 0x6b, buf[20 + 23 + 11] = 0xee;
        if (bad[k].cut == -2)
            buf[0] = 'X';
        if (bad[k].cut >= 0)
            n = (size_t)bad[k].cut;
        if (bad[k].cut == -3)
            n += (size_t)sprintf((char *)buf + n, "MBSDF_DATA_REFLECTION=\n");
        if (bad[k].cut == -4)
            n += (size_t)sprintf((char *)buf + n, "trailing text\n");
        ts_expect_read_error(read_mbsdf, bad[k].name, (const char *)buf, n, BF_ERR_PARSE, bad[k].fragment);
    }
    /* Every prefix of a good small file but the whole fails cleanly. */
    n = make(buf, "", 1, 0, 1, 2, 2, 1.0f);
    for (size_t cut = 0; cut < n; cut++) {
        ts_write_file(p, (const char *)buf, cut);
        bf_samples *t = NULL;
        bf_error err;
        assert_int_not_equal(bf_samples_read_mbsdf(p, NULL, &t, &err), BF_OK);
        assert_null(t);
        assert_null(strchr(err.msg, '\n'));
    }
}

/* Dispatch by extension, by content, and by name. */
static void test_dispatch(void **state)
{
    (void)state;
    size_t len;
    unsigned char *b = ts_read_binary(CARPAINT, &len);
    const char *other = ts_tmp_path("paint.bin");
    ts_write_file(other, (const char *)b, len);
    free(b);
    bf_read_options o = {0};
    bf_samples *s;
    bf_error err;
    assert_int_equal(bf_samples_read_with(other, &o, &s, &err), BF_OK);
    assert_int_equal(s->n, (size_t)NT * NT * NP);
    bf_samples_free(s);
    bf_format f = BF_FORMAT_AUTO;
    assert_int_equal(bf_format_parse("mbsdf", &f, NULL), BF_OK);
    assert_int_equal(f, BF_FORMAT_MBSDF);
    assert_string_equal(bf_format_name(BF_FORMAT_MBSDF), "mbsdf");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cells),    cmocka_unit_test(test_specular_peak), cmocka_unit_test(test_grid),
        cmocka_unit_test(test_negative), cmocka_unit_test(test_small_files),   cmocka_unit_test(test_dispatch),
    };
    return cmocka_run_group_tests_name("mbsdf", tests, NULL, NULL);
}
