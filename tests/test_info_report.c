/* bf_samples_info_json and bf_samples_info_text: brdfit info's report of small CSV files
 * whose every number is known, the words for what the option negative did, the note of a
 * subsample that kept everything, the wavelength range, and the errors. */
#include <cjson/cJSON.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/load.h"
#include "support.h"

/* Five samples: one on the horizon, one negative, one with a zero (tests/cli_info.sh's). */
static const char FIVE[] = "theta_i,phi_i,theta_o,phi_o,r,g,b\n"
                           "10,0,10,180,0.5,0.25,0.125\n"
                           "20,0,40,180,1,2,3\n"
                           "90,0,10,0,7,7,7\n"
                           "30,0,30,180,-0.01,0.2,0.3\n"
                           "50,0,10,180,0,0.1,0.2\n";

/* path's samples loaded with the options words; the report and both texts. */
typedef struct loaded {
    bf_load_report report;
    char *json, *text;
} loaded;

static void load(const char *path, const char *words, loaded *l)
{
    bf_options *o = ts_options(BF_TASK_READ, words);
    bf_samples *s = NULL;
    bf_error err;
    bf_load_report_init(&l->report);
    if (bf_samples_load(path, o, &s, &l->report, &err) != BF_OK)
        fail_msg("%s", err.msg);
    if (bf_samples_info_json(s, &l->report, o, path, &l->json, &err) != BF_OK ||
        bf_samples_info_text(s, &l->report, o, path, &l->text, &err) != BF_OK)
        fail_msg("%s", err.msg);
    bf_samples_free(s);
    bf_options_free(o);
}

static void loaded_clear(loaded *l)
{
    bf_free(l->json);
    bf_free(l->text);
}

static double number(const cJSON *root, const char *a, const char *b)
{
    const cJSON *n = cJSON_GetObjectItemCaseSensitive(root, a);
    if (b)
        n = cJSON_GetObjectItemCaseSensitive(n, b);
    assert_non_null(n);
    assert_true(cJSON_IsNumber(n));
    return n->valuedouble;
}

static const char *text_of(const cJSON *root, const char *a, const char *b)
{
    const cJSON *n = cJSON_GetObjectItemCaseSensitive(root, a);
    if (b)
        n = cJSON_GetObjectItemCaseSensitive(n, b);
    assert_true(cJSON_IsString(n));
    return n->valuestring;
}

/* The line of text that starts with start, whole (without its newline). */
static void assert_line(const char *text, const char *line)
{
    size_t n = strlen(line);
    for (const char *p = text; p && *p; p = strchr(p, '\n'), p = p ? p + 1 : NULL)
        if (!strncmp(p, line, n) && (p[n] == '\n' || p[n] == '\0'))
            return;
    fail_msg("no line '%s' in:\n%s", line, text);
}

static void test_json_holds_every_number(void **state)
{
    (void)state;
    const char *path = ts_tmp_path("five.csv");
    ts_write_file(path, FIVE, sizeof FIVE - 1);
    loaded l;
    load(path, "", &l);
    size_t n = strlen(l.json);
    assert_true(n > 2 && l.json[n - 1] == '\n' && l.json[n - 2] == '}'); /* one document, one newline */
    cJSON *root = cJSON_Parse(l.json);
    assert_non_null(root);
    assert_string_equal(text_of(root, "file", NULL), path);
    assert_int_equal(number(root, "samples_read", NULL), 5);
    assert_int_equal(number(root, "samples", NULL), 4);
    const cJSON *ch = cJSON_GetObjectItemCaseSensitive(root, "channels");
    assert_int_equal(cJSON_GetArraySize(ch), 3);
    assert_string_equal(cJSON_GetArrayItem(ch, 2)->valuestring, "b");
    assert_true(cJSON_IsNull(cJSON_GetObjectItemCaseSensitive(root, "wavelengths")));
    assert_true(cJSON_IsFalse(cJSON_GetObjectItemCaseSensitive(root, "weighted")));
    assert_int_equal(number(root, "prep", "below_horizon"), 1);
    assert_int_equal(number(root, "prep", "negative"), 1);
    assert_int_equal(number(root, "prep", "kept"), 4);
    assert_string_equal(text_of(root, "prep", "negative_action"), "keep");
    assert_true(cJSON_IsNull(cJSON_GetObjectItemCaseSensitive(root, "scene")));
    const cJSON *cov = cJSON_GetObjectItemCaseSensitive(root, "coverage_deg");
    assert_true(number(cov, "theta_i", "min") == 10 && number(cov, "theta_i", "max") == 50);
    assert_true(number(cov, "theta_o", "min") == 10 && number(cov, "theta_o", "max") == 40);
    assert_int_equal(number(root, "counts", "zero"), 1);
    assert_int_equal(number(root, "counts", "negative"), 1);
    const cJSON *r = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "values"), 0);
    assert_string_equal(text_of(r, "channel", NULL), "r");
    assert_true(number(r, "min", NULL) == -0.01 && number(r, "max", NULL) == 1);
    ts_assert_rel(number(r, "mean", NULL), (0.5 + 1 - 0.01 + 0) / 4, 1e-15, "mean of r");
    cJSON_Delete(root);
    loaded_clear(&l);
}

static void test_text_says_it_in_words(void **state)
{
    (void)state;
    const char *path = ts_tmp_path("five.csv");
    ts_write_file(path, FIVE, sizeof FIVE - 1);
    loaded l;
    load(path, "", &l);
    char want[512];
    snprintf(want, sizeof want, "%s: 5 samples read, 4 used", path);
    assert_true(!strncmp(l.text, want, strlen(want)) && l.text[strlen(want)] == '\n'); /* the first line */
    assert_line(l.text, "channels: 3 (r, g, b); unweighted");
    assert_line(l.text, "preprocessing: dropped 1 below the horizon, 0 with NaN or Inf, 0 above max theta, 0 by "
                        "subsampling; 1 with negative values kept");
    assert_line(l.text, "  theta_i           10 .. 50");
    assert_line(l.text, "values (samples used): 1 with a zero, 1 with a negative value");
    assert_line(l.text, "  r                    -0.01             1        0.3725");
    assert_null(strstr(l.text, "subsample"));
    assert_int_equal(l.text[strlen(l.text) - 1], '\n');
    loaded_clear(&l);

    /* What negative did, in words; the subsample that had nothing to leave out. */
    load(path, "--negative clamp --subsample 10", &l);
    assert_line(l.text, "preprocessing: dropped 1 below the horizon, 0 with NaN or Inf, 0 above max theta, 0 by "
                        "subsampling; 1 with negative values clamped to 0");
    assert_line(l.text, "subsample 10: all 4 samples kept (no more available)");
    assert_non_null(strstr(l.json, "\"negative_action\":\t\"clamp\""));
    loaded_clear(&l);
    load(path, "--negative drop --subsample 2 --seed 5", &l);
    assert_line(l.text, "preprocessing: dropped 1 below the horizon, 0 with NaN or Inf, 0 above max theta, 1 by "
                        "subsampling; 1 with negative values dropped");
    assert_null(strstr(l.text, "subsample 2"));
    loaded_clear(&l);
}

static void test_wavelengths_and_many_channels(void **state)
{
    (void)state;
    /* Eleven channels measured at wavelengths out of order (samples in memory, prepared):
     * the range is their least and greatest, and the names are shortened to the first
     * three and the last. */
    static const double nm[11] = {450, 400, 500, 550, 600, 650, 700, 750, 800, 850, 420};
    bf_samples *s = NULL;
    bf_error err;
    assert_int_equal(bf_samples_new(2, 11, &s, &err), BF_OK);
    assert_non_null(s->wavelength = malloc(sizeof nm));
    memcpy(s->wavelength, nm, sizeof nm);
    for (int c = 0; c < 11; c++) {
        char name[16];
        snprintf(name, sizeof name, "%g", nm[c]);
        assert_int_equal(bf_samples_set_channel_name(s, c, name, &err), BF_OK);
    }
    for (size_t i = 0; i < 2; i++) {
        s->theta_i[i] = s->theta_o[i] = 10.0 + 20.0 * (double)i;
        s->phi_o[i] = 180.0;
        for (int c = 0; c < 11; c++)
            s->value[i * 11 + (size_t)c] = 0.1 * (double)(c + 1);
    }
    bf_options *o = ts_options(BF_TASK_READ, "");
    bf_load_report r;
    bf_load_report_init(&r);
    assert_int_equal(bf_samples_prepare(s, o, &r, &err), BF_OK);
    char *text = NULL, *json = NULL;
    assert_int_equal(bf_samples_info_text(s, &r, o, "samples", &text, &err), BF_OK);
    assert_int_equal(bf_samples_info_json(s, &r, o, "samples", &json, &err), BF_OK);
    assert_line(text, "channels: 11 (450, 400, 500, ..., 420), 400-850 nm; unweighted");
    assert_line(text, "  theta_i           10 .. 30");
    assert_line(text, "  420                    1.1           1.1           1.1");
    cJSON *root = cJSON_Parse(json);
    const cJSON *w = cJSON_GetObjectItemCaseSensitive(root, "wavelengths");
    assert_int_equal(cJSON_GetArraySize(w), 11);
    assert_true(cJSON_GetArrayItem(w, 1)->valuedouble == 400 && cJSON_GetArrayItem(w, 10)->valuedouble == 420);
    assert_int_equal(number(root, "samples_read", NULL), 2);
    cJSON_Delete(root);
    bf_free(text);
    bf_free(json);
    bf_options_free(o);
    bf_samples_free(s);
}

static void test_defaults_and_errors(void **state)
{
    (void)state;
    const char *path = ts_tmp_path("five.csv");
    ts_write_file(path, FIVE, sizeof FIVE - 1);
    bf_samples *s = NULL;
    bf_load_report r;
    bf_load_report_init(&r);
    bf_error err;
    bf_options *o = ts_options(BF_TASK_READ, "");
    if (bf_samples_load(path, o, &s, &r, &err) != BF_OK)
        fail_msg("%s", err.msg);
    /* No options: the defaults' words, as a set made for reading says them. */
    char *a = NULL, *b = NULL;
    assert_int_equal(bf_samples_info_text(s, &r, NULL, "data", &a, &err), BF_OK);
    assert_int_equal(bf_samples_info_text(s, &r, o, "data", &b, &err), BF_OK);
    assert_string_equal(a, b);
    assert_true(!strncmp(a, "data: 5 samples read, 4 used\n", 29));
    bf_free(a);
    bf_free(b);
    /* A report whose size was never set, none at all, no name. */
    bf_load_report unset;
    memset(&unset, 0, sizeof unset);
    char *out = (char *)&err; /* set to NULL on failure */
    assert_int_equal(bf_samples_info_json(s, &unset, o, "data", &out, &err), BF_ERR_ARG);
    assert_null(out);
    assert_non_null(strstr(err.msg, "bf_load_report: size 0"));
    assert_int_equal(bf_samples_info_text(s, NULL, o, "data", &out, &err), BF_ERR_ARG);
    assert_int_equal(bf_samples_info_json(s, &r, o, NULL, &out, &err), BF_ERR_ARG);
    assert_int_equal(bf_samples_info_json(NULL, &r, o, "data", &out, &err), BF_ERR_ARG);
    assert_null(out);
    bf_options_free(o);
    bf_samples_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_json_holds_every_number),
        cmocka_unit_test(test_text_says_it_in_words),
        cmocka_unit_test(test_wavelengths_and_many_channels),
        cmocka_unit_test(test_defaults_and_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
