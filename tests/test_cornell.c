/* Cornell spectral BRDF text files: the committed subset and the full shared files of
 * real car-paint measurements, the flat number stream, and every kind of bad input. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/formats.h"
#include "brdfit/samples.h"
#include "support.h"

static bf_samples *read_ok(const char *path)
{
    bf_samples *s = NULL;
    bf_error err = {0};
    if (bf_samples_read_cornell(path, &s, &err) != BF_OK)
        fail_msg("%s", err.msg);
    return s;
}

/* An independent reading of the records: fscanf over the file with '#' lines skipped
 * (the pbrt files put comments on lines of their own). Returns the numbers after the
 * wavelength list, malloc'd, and their count. */
static double *plain_numbers(const char *path, size_t *count)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        fail_msg("cannot open %s", path);
    size_t cap = 1 << 16, n = 0;
    double *v = malloc(cap * sizeof *v);
    char line[4096];
    while (fgets(line, sizeof line, fp)) {
        if (line[0] == '#')
            continue;
        char *p = line, *end;
        for (double x; (x = strtod(p, &end)), end != p; p = end) {
            if (n == cap)
                v = realloc(v, (cap *= 2) * sizeof *v);
            v[n++] = x;
        }
    }
    fclose(fp);
    size_t nwl = (size_t)v[0];
    *count = n - 1 - nwl;
    memmove(v, v + 1 + nwl, *count * sizeof *v);
    return v;
}

/* Every record as the plain reading has it, converted to degrees. */
static void check_against_plain(const bf_samples *s, const char *path)
{
    size_t count;
    double *v = plain_numbers(path, &count);
    const size_t C = (size_t)s->channels, K = 4 + C;
    assert_int_equal(count, s->n * K);
    for (size_t i = 0; i < s->n; i++) {
        const double *r = v + i * K;
        const double want[4] = {r[0] * 180 / M_PI, r[1] * 180 / M_PI, r[2] * 180 / M_PI, r[3] * 180 / M_PI};
        const double got[4] = {s->theta_i[i], s->phi_i[i], s->theta_o[i], s->phi_o[i]};
        for (int k = 0; k < 4; k++)
            if (fabs(got[k] - want[k]) > 1e-12 * (1 + fabs(want[k])))
                fail_msg("%s: record %zu angle %d: %.17g, want %.17g", path, i, k, got[k], want[k]);
        for (size_t c = 0; c < C; c++)
            if (s->value[i * C + c] != r[4 + c])
                fail_msg("%s: record %zu channel %zu: %.17g, want %.17g", path, i, c, s->value[i * C + c], r[4 + c]);
    }
    free(v);
}

static void check_wavelengths(const bf_samples *s)
{
    assert_int_equal(s->channels, 31);
    assert_non_null(s->wavelength);
    for (int c = 0; c < 31; c++) {
        char name[8];
        snprintf(name, sizeof name, "%d", 400 + 10 * c);
        assert_true(s->wavelength[c] == 400.0 + 10.0 * c);
        assert_string_equal(s->channel_names[c], name);
    }
    assert_null(s->weight);
    assert_null(s->merl);
}

/* The committed subset: header, 31 wavelengths, the first 20 records (CRLF kept). */
static void test_subset(void **state)
{
    (void)state;
    const char *path = BRDFIT_TEST_DATA "/cornell/cayman_head20.brdf";
    bf_samples *s = read_ok(path);
    assert_int_equal(s->n, 20);
    check_wavelengths(s);
    /* First record: 0.872665 0.000000 0.573513 0.000000 0.000874 ... 0.002000 */
    ts_assert_rel(s->theta_i[0], 50.0, 1e-6, "theta_i of record 1 (0.872665 rad)");
    assert_true(s->phi_i[0] == 0.0 && s->phi_o[0] == 0.0);
    ts_assert_rel(s->theta_o[0], 0.573513 * 180 / M_PI, 1e-15, "theta_o of record 1");
    assert_true(s->value[0] == 0.000874 && s->value[30] == 0.002);
    /* Last record: 0.174533 0.000000 0.427512 -0.785398 0.000127 ... 0.003593 */
    ts_assert_rel(s->theta_i[19], 10.0, 1e-5, "theta_i of record 20");
    ts_assert_rel(s->phi_o[19], -45.0, 1e-5, "phi_s of record 20 (-0.785398 rad)");
    assert_true(s->value[19 * 31] == 0.000127 && s->value[19 * 31 + 30] == 0.003593);
    check_against_plain(s, path);
    bf_samples_free(s);
}

/* The full bundled files (examples/cornell): 1439 geometries x 31 wavelengths each, all values
 * non-negative; peaks as SOURCE.txt gives them. Missing files fail the test. */
static void check_full(const char *path, double peak)
{
    bf_samples *s = NULL;
    bf_error err = {0};
    if (bf_samples_read_cornell(path, &s, &err) != BF_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(s->n, 1439);
    check_wavelengths(s);
    double max = 0.0;
    size_t negative = 0;
    for (size_t k = 0; k < s->n * 31; k++) {
        max = fmax(max, s->value[k]);
        negative += s->value[k] < 0.0;
    }
    assert_int_equal(negative, 0);
    assert_true(max == peak);
    /* theta_i in {10, 20, ..., 80} degrees, phi_i = 0, theta_s up to 79.05 degrees. */
    for (size_t i = 0; i < s->n; i++) {
        double t = s->theta_i[i] / 10.0;
        if (fabs(t - round(t)) > 1e-5 || t < 0.99 || t > 8.01 || s->phi_i[i] != 0.0)
            fail_msg("%s: record %zu: theta_i %.17g phi_i %.17g", path, i, s->theta_i[i], s->phi_i[i]);
        if (!(s->theta_o[i] >= 0.0 && s->theta_o[i] < 80.0))
            fail_msg("%s: record %zu: theta_s %.17g", path, i, s->theta_o[i]);
    }
    check_against_plain(s, path);
    bf_samples_free(s);
}

static void test_full_shared_files(void **state)
{
    (void)state;
    check_full(BRDFIT_EXAMPLES "/cornell/cayman.brdf", 645.800964);
    check_full(BRDFIT_EXAMPLES "/cornell/garnet_red.brdf", 38.368774);
}

/* Records are a stream: split across lines, several per line, comments anywhere,
 * tabs and CRLF; theta beyond 90 degrees (below the horizon) is data. */
static void test_flat_stream(void **state)
{
    (void)state;
    const char *text = "# two wavelengths\r\n2 # count\r\n412.5\t600\r\n"
                       "0.5 0 # a comment inside a record\r\n1.8\r\n3.141593 0.25 -0.001\r\n"
                       "1.570796 1 0 -2 1e-3 2E2\r\n";
    ts_write_file(ts_tmp_path("stream.brdf"), text, strlen(text));
    bf_samples *s = read_ok(ts_tmp_path("stream.brdf"));
    assert_int_equal(s->n, 2);
    assert_int_equal(s->channels, 2);
    assert_string_equal(s->channel_names[0], "412.5");
    assert_string_equal(s->channel_names[1], "600");
    assert_true(s->wavelength[0] == 412.5 && s->wavelength[1] == 600.0);
    ts_assert_rel(s->theta_i[0], 0.5 * 180 / M_PI, 1e-15, "theta_i");
    ts_assert_rel(s->theta_o[0], 1.8 * 180 / M_PI, 1e-15, "theta_s below the horizon");
    ts_assert_rel(s->phi_o[0], 3.141593 * 180 / M_PI, 1e-15, "phi_s");
    assert_true(s->value[0] == 0.25 && s->value[1] == -0.001); /* negative values are data */
    ts_assert_rel(s->theta_i[1], 90.0, 1e-6, "theta_i on the horizon");
    ts_assert_rel(s->phi_i[1], 180 / M_PI, 1e-15, "phi_i");
    assert_true(s->theta_o[1] == 0.0);
    ts_assert_rel(s->phi_o[1], -2 * 180 / M_PI, 1e-15, "phi_s");
    assert_true(s->value[2] == 1e-3 && s->value[3] == 200.0);
    bf_samples_free(s);
}

/* bf_samples_read finds the format by extension, and by content without one. */
static void test_dispatch(void **state)
{
    (void)state;
    bf_samples *s = NULL;
    bf_error err = {0};
    assert_int_equal(bf_samples_read_with(BRDFIT_TEST_DATA "/cornell/cayman_head20.brdf", NULL, &s, &err), BF_OK);
    assert_int_equal(s->n, 20);
    bf_samples_free(s);
    const char *text = "# no extension\n1\n550\n0.1 0 0.2 3.14 0.5\n";
    ts_write_file(ts_tmp_path("noext"), text, strlen(text));
    assert_int_equal(bf_samples_read_with(ts_tmp_path("noext"), NULL, &s, &err), BF_OK);
    assert_int_equal(s->channels, 1);
    assert_string_equal(s->channel_names[0], "550");
    assert_true(s->value[0] == 0.5);
    bf_samples_free(s);
}

static void expect_error_len(const char *name, const char *text, size_t len, int code, const char *fragment)
{
    ts_expect_read_error(bf_samples_read_cornell, name, text, len, code, fragment);
}

static void expect_error(const char *name, const char *text, int code, const char *fragment)
{
    expect_error_len(name, text, strlen(text), code, fragment);
}

static void test_bad_input(void **state)
{
    (void)state;
    const int P = BF_ERR_PARSE, R = BF_ERR_RANGE;
    expect_error("empty.brdf", "", P, ": empty file");
    expect_error("comments.brdf", "# only\n# comments\n\n", P, ": empty file");
    expect_error("word.brdf", "2\n400 500\n0.1 0 0.2 0\n0.5 abc\n", P, ":4: 'abc' is not a number");
    expect_error("glued.brdf", "2\n400 500\n0.1,0 0.2 0 1 2\n", P, ":3: '0.1,0' is not a number");
    expect_error("nan.brdf", "2\n400 500\n0.1 0 0.2 0\nnan 1\n", R, ":4: nan is not a finite number");
    expect_error("inf.brdf", "2\n400 500\n0.1 0 0.2 0 1 -inf\n", R, ":3: -inf is not a finite number");
    expect_error("huge.brdf", "2\n400 500\n0.1 0 0.2 0 1 1e999\n", R, ":3: 1e999 is not a finite number");
    expect_error("negcount.brdf", "# header\n-3\n400 500 600\n", P, ":2: the wavelength count -3 is negative");
    expect_error("fraccount.brdf", "2.5\n400 500\n", P, ":1: the file must start with the wavelength count");
    expect_error("zerocount.brdf", "0\n0.1 0 0.2 0\n", P, ":1: the file must start with the wavelength count");
    expect_error("negwl.brdf", "2\n400 -500\n", R, ":2: wavelength 2 is -500 nm");
    expect_error("dupwl.brdf", "2\n500\n500\n", P, ":3: wavelength 500 nm appears twice");
    expect_error("shortwl.brdf", "3\n400 500\n", P, "ends within the wavelength list (3 announced, 2 given)");
    expect_error("norecords.brdf", "2\n400 500\n# nothing\n", P, "no records after the 2 wavelengths");
    expect_error("trunc.brdf", "2\n400 500\n0.1 0 0.2 0 1 2\n0.2 0 0.3\n0 1\n", P,
                 ":4: incomplete record 2: records are theta_i phi_i theta_s phi_s and 2 values (6 numbers), "
                 "the last has 5");
    expect_error("dropped.brdf", "1\n500\n0.1 0 0.2 0 1\n0.1 0 0.2 1\n0.1 0 0.2 0 1\n0.1 0 0.2 0 1\n", P,
                 ":5: a record starts mid-line: the one before has a number too many or too few (records are "
                 "theta_i phi_i theta_s phi_s and 1 values)");
    expect_error("theta.brdf", "1\n500\n0.1 0 0.2 0 1\n3.2 0 0.2 0 1\n", R,
                 ":4: record 2: theta_i = 3.2 rad is outside [0, pi]");
    expect_error("negtheta.brdf", "1\n500\n0.1 0\n-0.1 0 1\n", R,
                 ":4: record 1: theta_s = -0.1 rad is outside [0, pi]");
    static const char nul[] = "1\n500\n0.1 0\0 0.1 0 1\n";
    expect_error_len("nul.brdf", nul, sizeof nul - 1, P, ":3: binary data");

    /* The real subset, cut in the middle of its last record. */
    FILE *fp = fopen(BRDFIT_TEST_DATA "/cornell/cayman_head20.brdf", "rb");
    assert_non_null(fp);
    static char buf[1 << 14];
    size_t n = fread(buf, 1, sizeof buf, fp);
    fclose(fp);
    expect_error_len("cut.brdf", buf, n - 40, BF_ERR_PARSE,
                     ":33: incomplete record 20: records are theta_i phi_i "
                     "theta_s phi_s and 31 values (35 numbers), the last has");

    bf_samples *s = NULL;
    bf_error err = {0};
    assert_int_equal(bf_samples_read_cornell(ts_tmp_path("missing.brdf"), &s, &err), BF_ERR_IO);
    assert_null(s);
    assert_non_null(strstr(err.msg, "missing.brdf: cannot open"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_subset),   cmocka_unit_test(test_full_shared_files), cmocka_unit_test(test_flat_stream),
        cmocka_unit_test(test_dispatch), cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests_name("cornell", tests, NULL, NULL);
}
