/* Sample sets from and to CSV: column mapping, units, weights, byte-exact round trips,
 * a real goniometer file, and bad input. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "brdfit/formats.h"
#include "brdfit/samples.h"
#include "support.h"

static void test_round_trip_is_byte_exact(void **state)
{
    (void)state;
    const char *text = "theta_i,phi_i,theta_o,phi_o,r,g,b,weight\n"
                       "30,0,45,180,0.1,0.2,0.30000000000000004,1\n"
                       "89.999,-25.81760513,0,33.5,-0.001,1e-300,123456.789,0.5\n"
                       "0,0,90,0,0,0,0,2\n";
    ts_write_file(ts_tmp_path("a.csv"), text, strlen(text));
    bf_samples *s;
    bf_error err;
    assert_int_equal(bf_samples_read_csv(ts_tmp_path("a.csv"), NULL, &s, &err), BF_OK);
    assert_int_equal(s->n, 3);
    assert_int_equal(s->channels, 3);
    assert_string_equal(s->channel_names[2], "b");
    assert_non_null(s->weight);
    assert_true(s->weight[1] == 0.5);
    assert_true(s->value[1 * 3 + 0] == -0.001); /* negative values are data */
    assert_true(s->phi_i[1] == -25.81760513);
    assert_int_equal(bf_samples_write_csv(s, ts_tmp_path("b.csv"), &err), BF_OK);
    assert_string_equal(ts_read_file(ts_tmp_path("b.csv")), text);
    bf_samples_free(s);
}

static void test_mapping_and_radians(void **state)
{
    (void)state;
    const char *text = "# a comment\nid,ti,pi,to,po,lum,w\n"
                       "7,0.5235987755982988,0,0.7853981633974483,3.141592653589793,0.25,3\n";
    ts_write_file(ts_tmp_path("m.csv"), text, strlen(text));
    bf_csv_map map = {{"ti", "pi", "to", "po"}, 1, "lum", "w"};
    bf_samples *s;
    bf_error err;
    assert_int_equal(bf_samples_read_csv(ts_tmp_path("m.csv"), &map, &s, &err), BF_OK);
    assert_int_equal(s->channels, 1);
    assert_string_equal(s->channel_names[0], "lum");
    ts_assert_rel(s->theta_i[0], 30.0, 1e-15, "theta_i from radians");
    ts_assert_rel(s->phi_o[0], 180.0, 1e-15, "phi_o from radians");
    assert_true(s->weight[0] == 3.0 && s->value[0] == 0.25);
    /* The geometry follows the degrees: L at 30 degrees from N. */
    const bf_geometry *g = NULL;
    bf_samples_geometry(s, &g, &err);
    ts_assert_rel(g->lz[0], cos(M_PI / 6), 1e-15, "N.L");
    bf_samples_free(s);
}

/* Default channels: every column but the angles and the weight, in file order. */
static void test_default_channels(void **state)
{
    (void)state;
    const char *text = "phi_o,x,theta_o,y,theta_i,phi_i\n1,2,3,4,5,6\n";
    ts_write_file(ts_tmp_path("d.csv"), text, strlen(text));
    bf_samples *s;
    assert_int_equal(bf_samples_read_csv(ts_tmp_path("d.csv"), NULL, &s, NULL), BF_OK);
    assert_int_equal(s->channels, 2);
    assert_string_equal(s->channel_names[0], "x");
    assert_string_equal(s->channel_names[1], "y");
    assert_true(s->theta_i[0] == 5 && s->phi_i[0] == 6 && s->theta_o[0] == 3 && s->phi_o[0] == 1);
    assert_true(s->value[0] == 2 && s->value[1] == 4 && s->weight == NULL);
    bf_samples_free(s);
}

/* NIST's PTFE goniometer file reads with options alone (columns thetai, phi, thetar,
 * phir, f_r11). */
static void check_ptfe(const char *path, size_t rows)
{
    bf_csv_map map = {{"thetai", "phi", "thetar", "phir"}, 0, "f_r11", NULL};
    bf_samples *s;
    bf_error err;
    if (bf_samples_read_csv(path, &map, &s, &err) != BF_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(s->n, rows);
    assert_int_equal(s->channels, 1);
    assert_string_equal(s->channel_names[0], "f_r11");
    /* First row: 0.532,39.76471842,-25.81760513,66.42507623,41.77096264,0.29269651 */
    assert_true(s->theta_i[0] == 39.76471842 && s->phi_i[0] == -25.81760513);
    assert_true(s->theta_o[0] == 66.42507623 && s->phi_o[0] == 41.77096264);
    assert_true(s->value[0] == 0.29269651);
    for (size_t i = 0; i < s->n; i++) /* near-Lambertian: f_r11 about 0.27 .. 0.45 */
        if (!(s->value[i] > 0.2 && s->value[i] < 0.5))
            fail_msg("%s: row %zu f_r11 = %g", path, i, s->value[i]);
    bf_samples_free(s);
}

static void test_ptfe(void **state)
{
    (void)state;
    check_ptfe(BRDFIT_TEST_DATA "/nist_ptfe/PTFE.data.random.head40.csv", 40);
    check_ptfe(BRDFIT_TEST_DATA "/nist_ptfe/PTFE.data.random.csv", 1760);
}

static void expect_error(const char *name, const char *text, const bf_csv_map *map, const char *fragment)
{
    ts_write_file(ts_tmp_path(name), text, strlen(text));
    bf_samples *s = NULL;
    bf_error err = {0};
    if (bf_samples_read_csv(ts_tmp_path(name), map, &s, &err) == BF_OK)
        fail_msg("%s accepted", name);
    assert_null(s);
    if (!strstr(err.msg, fragment) || !strstr(err.msg, name))
        fail_msg("%s: message '%s' lacks the file name or '%s'", name, err.msg, fragment);
}

static void test_bad_input(void **state)
{
    (void)state;
    const char *H = "theta_i,phi_i,theta_o,phi_o,v\n";
    char buf[256];
    expect_error("empty.csv", "", NULL, "empty file");
    expect_error("noheader.csv", "1,2,3,4,5\n", NULL, ":1: header expected");
    expect_error("nocol.csv", "theta_i,phi_i,theta_o,v\n1,2,3,4\n", NULL, "missing angle column 'phi_o'");
    expect_error("novalue.csv", "theta_i,phi_i,theta_o,phi_o\n1,2,3,4\n", NULL, "no value columns");
    snprintf(buf, sizeof buf, "%s1,2,3,4,x\n", H);
    expect_error("word.csv", buf, NULL, ":2: column v: 'x' is not a number");
    snprintf(buf, sizeof buf, "%s1,2,3,4,5\n1,2,3,4\n", H);
    expect_error("ragged.csv", buf, NULL, ":3: expected 5 fields, found 4");
    snprintf(buf, sizeof buf, "%s1,2,3,4,nan\n", H);
    expect_error("nan.csv", buf, NULL, ":2: column v: nan is not a finite number");
    snprintf(buf, sizeof buf, "%s1,2,3,4,inf\n", H);
    expect_error("inf.csv", buf, NULL, ":2: column v: inf is not a finite number");
    snprintf(buf, sizeof buf, "%s1,2,181,4,5\n", H);
    expect_error("theta.csv", buf, NULL, ":2: theta_o = 181 is outside [0, 180]");
    snprintf(buf, sizeof buf, "%s-1,2,1,4,5\n", H);
    expect_error("negtheta.csv", buf, NULL, ":2: theta_i = -1 is outside [0, 180]");
    expect_error("weight.csv", "theta_i,phi_i,theta_o,phi_o,v,weight\n1,2,3,4,5,-1\n", NULL,
                 ":2: weight -1 is negative");
    bf_csv_map map = {{NULL, NULL, NULL, NULL}, 0, "v,nope", NULL};
    snprintf(buf, sizeof buf, "%s1,2,3,4,5\n", H);
    expect_error("values.csv", buf, &map, "no column 'nope'");
    bf_csv_map wmap = {{NULL, NULL, NULL, NULL}, 0, NULL, "w"};
    expect_error("wcol.csv", buf, &wmap, "no weight column 'w'");
    expect_error("numbers.csv", "400,410\n1,2\n", NULL, ":1: header expected, found a row of numbers ('400', ...)");
    expect_error("quote.csv", "theta_i,phi_i,theta_o,phi_o,\"v\n", NULL,
                 ":1: header column 5: a quoted name must end with its quote");
    expect_error("quote2.csv", "theta_i,phi_i,theta_o,phi_o,\"v\"x\n", NULL, ":1: header column 5: a quoted name");
    snprintf(buf, sizeof buf, "%s1,\"2,3,4,5\n", H);
    expect_error("quoterow.csv", buf, NULL, ":2: field 2: a quoted field must end with its quote");
}

/* Hostile files get a message that is safe to print and still names file, line and
 * problem: a header of binary junk, a 9 kB number, a header of 70,000 columns. */
static void test_hostile_messages(void **state)
{
    (void)state;
    const char junk[] = "theta_i,phi_i,theta_o,phi_o,\x1b[2J\xff\xfe\x9b,\x1b[2J\xff\xfe\x9b\n";
    expect_error("junk.csv", junk, NULL, ":1: column '\\x1b[2J\\xff\\xfe\\x9b' appears twice");
    size_t n = 9000;
    char *big = malloc(n + 64);
    int k = snprintf(big, n + 64, "theta_i,phi_i,theta_o,phi_o,v\n0,0,0,0,");
    memset(big + k, '7', n);
    strcpy(big + k + n, "x\n");
    expect_error("big.csv", big, NULL, ":2: column v: '777777777777777777777777777777...");
    bf_samples *s = NULL;
    bf_error err;
    assert_int_not_equal(bf_samples_read_csv(ts_tmp_path("big.csv"), NULL, &s, &err), BF_OK);
    assert_non_null(strstr(err.msg, "777x' is not a number"));
    assert_true(strlen(err.msg) <= BF_ERROR_MAX_CHARS);
    free(big);
    char *wide = malloc(2 * 70000 + 2);
    for (int c = 0; c < 70000; c++)
        memcpy(wide + 2 * c, "a,", 2);
    strcpy(wide + 2 * 70000 - 1, "\n");
    expect_error("wide.csv", wide, NULL, ":1: the header has more than 65536 columns");
    free(wide);
}

/* A writer that fails leaves no file behind. */
static void test_no_partial_output(void **state)
{
    (void)state;
    bf_samples *s = NULL;
    bf_samples_new(2, 1, &s, NULL);
    bf_error err;
    assert_int_not_equal(bf_samples_write_csv(s, "/nonexistent-dir/x.csv", &err), BF_OK);
    assert_non_null(strstr(
        err.msg, "/nonexistent-dir/x.csv: cannot write in the folder /nonexistent-dir: No such file or directory"));
    assert_int_not_equal(bf_samples_write(s, ts_tmp_path("x.txt"), BF_FORMAT_AUTO, &err), BF_OK);
    assert_non_null(strstr(err.msg, "cannot write"));
    assert_int_equal(access(ts_tmp_path("x.txt"), F_OK), -1);
    bf_samples_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip_is_byte_exact),
        cmocka_unit_test(test_mapping_and_radians),
        cmocka_unit_test(test_default_channels),
        cmocka_unit_test(test_ptfe),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_hostile_messages),
        cmocka_unit_test(test_no_partial_output),
    };
    return cmocka_run_group_tests_name("samples_csv", tests, NULL, NULL);
}
