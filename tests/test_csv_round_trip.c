/* Whatever brdfit writes as CSV it reads back to the same samples: spectral channel
 * names ("400"), value columns named like the angle or weight columns (renamed NAME_2),
 * names that need quoting (commas, quotes, outer blanks), and Cornell data converted. */
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

static bf_samples *read_csv(const char *name, const char *text, const bf_csv_map *map)
{
    ts_write_file(ts_tmp_path(name), text, strlen(text));
    bf_samples *s = NULL;
    bf_error err;
    if (bf_samples_read_csv(ts_tmp_path(name), map, &s, &err) != BF_OK)
        fail_msg("%s: %s", name, err.msg);
    return s;
}

/* Writes s, reads it back with the default mapping; the same directions, values and
 * weights bit for bit. Returns the samples read back. */
static bf_samples *round_trip(const bf_samples *s, const char *name)
{
    bf_error err;
    if (bf_samples_write_csv(s, ts_tmp_path(name), &err) != BF_OK)
        fail_msg("write %s: %s", name, err.msg);
    bf_samples *b = NULL;
    if (bf_samples_read_csv(ts_tmp_path(name), NULL, &b, &err) != BF_OK)
        fail_msg("read back %s: %s", name, err.msg);
    assert_int_equal(b->n, s->n);
    assert_int_equal(b->channels, s->channels);
    assert_int_equal(b->weight != NULL, s->weight != NULL);
    for (size_t i = 0; i < s->n; i++) {
        double da[4], db[4];
        bf_samples_direction(s, i, da);
        bf_samples_direction(b, i, db);
        for (int k = 0; k < 4; k++)
            assert_true(da[k] == db[k]);
        for (size_t c = 0; c < (size_t)s->channels; c++)
            assert_true(s->value[i * (size_t)s->channels + c] == b->value[i * (size_t)s->channels + c]);
        if (s->weight)
            assert_true(s->weight[i] == b->weight[i]);
    }
    return b;
}

/* Spectral headers: numbers are names once the row is not all numbers. */
static void test_spectral_names(void **state)
{
    (void)state;
    const char *text = "theta_i,phi_i,theta_o,phi_o,400,410.5,1e3\n10,0,10,180,0.1,0.2,0.3\n";
    bf_samples *s = read_csv("spec.csv", text, NULL);
    assert_int_equal(s->channels, 3);
    assert_string_equal(s->channel_names[0], "400");
    assert_string_equal(s->channel_names[2], "1e3");
    bf_samples *b = round_trip(s, "spec2.csv");
    assert_string_equal(ts_read_file(ts_tmp_path("spec2.csv")), text);
    bf_samples_free(b);
    bf_samples_free(s);
}

/* Cornell data (wavelength channels, angles in radians rounded past pi) converted to
 * CSV reads back the same. */
static void test_cornell_converted(void **state)
{
    (void)state;
    bf_samples *s = NULL;
    bf_error err;
    assert_int_equal(bf_samples_read_cornell(BRDFIT_TEST_DATA "/cornell/cayman_head20.brdf", &s, &err), BF_OK);
    bf_samples *b = round_trip(s, "cayman.csv");
    for (int c = 0; c < s->channels; c++)
        assert_string_equal(b->channel_names[c], s->channel_names[c]);
    bf_samples_free(b);
    bf_samples_free(s);
    /* theta_s written 3.141593, past pi: on the bound, which the CSV reader accepts. */
    const char *pi_up = "1\n550\n0 0 3.141593 0 0.25\n";
    ts_write_file(ts_tmp_path("pi.brdf"), pi_up, strlen(pi_up));
    assert_int_equal(bf_samples_read_cornell(ts_tmp_path("pi.brdf"), &s, &err), BF_OK);
    assert_true(s->theta_o[0] == 180.0);
    b = round_trip(s, "pi.csv");
    bf_samples_free(b);
    bf_samples_free(s);
}

/* Value columns called like the angle or weight columns (read with --angles and
 * --weight) are written as NAME_2 (or the next free number), never as a second
 * theta_i or weight. */
static void test_clashing_names(void **state)
{
    (void)state;
    const char *text = "a,b,c,d,theta_i,weight,theta_i_2,w\n10,20,30,40,0.5,0.25,0.125,2\n";
    bf_csv_map map = {{"a", "b", "c", "d"}, 0, NULL, "w"};
    bf_samples *s = read_csv("clash.csv", text, &map);
    assert_int_equal(s->channels, 3);
    assert_string_equal(s->channel_names[0], "theta_i");
    bf_samples *b = round_trip(s, "clash2.csv");
    assert_string_equal(
        ts_read_file(ts_tmp_path("clash2.csv")),
        "theta_i,phi_i,theta_o,phi_o,theta_i_3,weight_2,theta_i_2,weight\n10,20,30,40,0.5,0.25,0.125,2\n");
    assert_string_equal(b->channel_names[0], "theta_i_3");
    assert_string_equal(b->channel_names[1], "weight_2");
    assert_string_equal(b->channel_names[2], "theta_i_2");
    bf_samples_free(b);
    bf_samples_free(s);
    /* The weight column given as a channel too: a channel "weight" and the weights. */
    bf_csv_map both = {{NULL, NULL, NULL, NULL}, 0, "v,weight", NULL};
    s = read_csv("both.csv", "theta_i,phi_i,theta_o,phi_o,v,weight\n1,2,3,4,5,6\n", &both);
    assert_int_equal(s->channels, 2);
    assert_non_null(s->weight);
    b = round_trip(s, "both2.csv");
    assert_string_equal(b->channel_names[1], "weight_2");
    assert_true(b->weight[0] == 6.0 && b->value[1] == 6.0);
    bf_samples_free(b);
    bf_samples_free(s);
}

/* Names with commas, quotes or outer blanks are quoted (RFC 4180) and read back. */
static void test_quoted_names(void **state)
{
    (void)state;
    const char *text = "theta_i,phi_i,theta_o,phi_o,\"a,b\",\"say \"\"hi\"\"\",\" pad \",x\"y\n1,2,3,4,5,6,7,8\n";
    bf_samples *s = read_csv("q.csv", text, NULL);
    assert_int_equal(s->channels, 4);
    assert_string_equal(s->channel_names[0], "a,b");
    assert_string_equal(s->channel_names[1], "say \"hi\"");
    assert_string_equal(s->channel_names[2], " pad ");
    assert_string_equal(s->channel_names[3], "x\"y"); /* a quote inside an unquoted name is text */
    bf_samples *b = round_trip(s, "q2.csv");
    assert_string_equal(
        ts_read_file(ts_tmp_path("q2.csv")),
        "theta_i,phi_i,theta_o,phi_o,\"a,b\",\"say \"\"hi\"\"\",\" pad \",\"x\"\"y\"\n1,2,3,4,5,6,7,8\n");
    for (int c = 0; c < 4; c++)
        assert_string_equal(b->channel_names[c], s->channel_names[c]);
    bf_samples_free(b);
    bf_samples_free(s);
    /* Quoted numbers in rows, blanks around quotes, CRLF line ends. */
    s = read_csv("qr.csv", "\"theta_i\" ,phi_i,theta_o,phi_o,v\r\n \"1.5\" ,2,3,4,5\r\n", NULL);
    assert_true(s->theta_i[0] == 1.5);
    bf_samples_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_spectral_names),
        cmocka_unit_test(test_cornell_converted),
        cmocka_unit_test(test_clashing_names),
        cmocka_unit_test(test_quoted_names),
    };
    return cmocka_run_group_tests_name("csv_round_trip", tests, NULL, NULL);
}
