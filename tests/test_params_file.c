/* Parameter files against hostile input: the findings of the fuzz harness
 * (fuzz/fuzz_params.c), each answered with one line naming file, line and problem,
 * and the models they would have built checked at the source (bf_model_new). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/fit.h"
#include "brdfit/io.h"
#include "brdfit/model.h"
#include "support.h"

static void expect_error(const char *name, const char *text, int code, const char *fragment)
{
    const char *path = ts_tmp_path(name);
    ts_write_file(path, text, strlen(text));
    bf_model *m = NULL;
    double *x = NULL;
    bf_error err = {0};
    int rc = bf_params_read(path, &m, &x, &err);
    if (rc == BF_OK)
        fail_msg("%s accepted", name);
    assert_null(m);
    assert_null(x);
    if (rc != code || !strstr(err.msg, fragment) || !strstr(err.msg, name) || strchr(err.msg, '\n'))
        fail_msg("%s: code %d, message '%s'; expected code %d and '%s'", name, rc, err.msg, code, fragment);
}

static void test_channel_counts(void **state)
{
    (void)state;
    const char *msg = "\"channels\" must be an integer from 1 to 10000";
    /* Heap overflow in the mono= mapping (SIGSEGV in brdfit eval before). */
    expect_error("mono.json", "{\"model\":\"walter:mono=all\",\"channels\":2147483647,\"params\":{}}", BF_ERR_PARSE,
                 msg);
    /* Signed overflow of the parameter count. */
    expect_error("count.json", "{\"model\":\"walter\",\"channels\":1073741824,\"params\":{}}", BF_ERR_PARSE, msg);
    /* Undefined float-to-int conversions. */
    expect_error("huge.json", "{\"model\":\"walter\",\"channels\":1e30,\"params\":{}}", BF_ERR_PARSE, msg);
    expect_error("tiny.json", "{\"model\":\"walter\",\n\"channels\":-1e30,\"params\":{}}", BF_ERR_PARSE, ":2: ");
    expect_error("frac.json", "{\"model\":\"walter\",\"channels\":2.5,\"params\":{}}", BF_ERR_PARSE, msg);
    expect_error("over.json", "{\"model\":\"walter\",\"channels\":10001,\"params\":{}}", BF_ERR_PARSE, msg);
    /* The largest count is read (and a colour parameter then needs that many values). */
    expect_error("max.json", "{\"model\":\"lambert\",\"channels\":10000,\"params\":{\"rho_d\":[0.5]}}", BF_ERR_PARSE,
                 "colour parameter rho_d has 1 values for 10000 channels");
    /* Without "channels", the first array's length, within the same limit. */
    char *text = malloc(4 * 10001 + 64);
    int n = sprintf(text, "{\"model\":\"lambert\",\"params\":{\"rho_d\":[0");
    for (int c = 1; c < 10001; c++)
        n += sprintf(text + n, ",0");
    strcpy(text + n, "]}}");
    expect_error("array.json", text, BF_ERR_PARSE, "too long array: a parameter has 1 to 10000 values");
    free(text);
    /* At the source: no model of more channels than the limit. */
    bf_error err;
    bf_model *m;
    assert_int_equal(bf_model_new("walter:mono=all", 2147483647, &m, &err), BF_ERR_ARG);
    assert_null(m);
    assert_string_equal(err.msg, "channel count must be from 1 to 10000, got 2147483647");
    bf_samples *s;
    assert_int_equal(bf_samples_new(1, 10001, &s, &err), BF_ERR_ARG);
    assert_null(s);
}

static void test_model_spec(void **state)
{
    (void)state;
    /* A very long model name with options overflowed the spec buffer on the stack. */
    char text[1200];
    char name[1001];
    memset(name, 'w', 1000);
    name[1000] = '\0';
    snprintf(text, sizeof text, "{\"model\":\"%s\",\"options\":{\"fresnel\":\"schlick\"},\"params\":{}}", name);
    expect_error("long.json", text, BF_ERR_PARSE, ":1: \"model\" is too long (1000 characters, at most 255)");
    /* Options that together do not fit. */
    snprintf(text, sizeof text, "{\"model\":\"walter\",\"options\":{\"fresnel\":\"%.250s\"},\"params\":{}}", name);
    expect_error("longopt.json", text, BF_ERR_PARSE, "model and options too long (at most 255 characters)");
    /* A numeric option value out of int range (undefined conversion before). */
    expect_error("fresnel.json", "{\"model\":\"walter\",\"options\":{\"fresnel\":1e30},\"params\":{}}", BF_ERR_PARSE,
                 ":1: option \"fresnel\" must be a string or an integer");
    expect_error("lobes.json", "{\"model\":\"walter\",\"options\":{\"lobes\":-2147483649},\"params\":{}}", BF_ERR_PARSE,
                 "option \"lobes\" must be a string or an integer");
    expect_error("lobes9.json", "{\"model\":\"walter\",\"options\":{\"lobes\":9},\"params\":{}}", BF_ERR_ARG,
                 "lobes must be an integer from 1 to 8, got '9'");
    /* An option value cannot smuggle in another option. */
    expect_error("smuggle.json", "{\"model\":\"walter\",\"options\":{\"fresnel\":\"schlick,mono=all\"},\"params\":{}}",
                 BF_ERR_PARSE, "option \"fresnel\": names and values cannot be empty or hold ','");
    /* A key given twice: cJSON would answer with the first and a rewrite keep both. */
    expect_error("twice.json", "{\"model\":\"lambert\",\n\"channels\":3,\n\"channels\":1,\"params\":{\"rho_d\":[0.5]}}",
                 BF_ERR_PARSE, ":2: \"channels\" given twice");
}

/* Found by fuzz/fuzz_params.c: a result file lost the last bit of alpha =
 * 0.88888888888888884, as of about one value in five, since cJSON prints 15 digits
 * when they read back within a relative DBL_EPSILON. Values now read back exactly. */
static void test_result_file_exact(void **state)
{
    (void)state;
    enum { C = 1000 };
    bf_fit_result r;
    memset(&r, 0, sizeof r);
    r.model = ts_model("lambert", C);
    double x[C], stderr_[C];
    unsigned char fixed[C] = {0};
    ts_rng rng = {42};
    for (int c = 0; c < C; c++) {
        x[c] = ts_uniform(&rng);
        stderr_[c] = 1e-3 * ts_uniform(&rng);
    }
    x[0] = 0.88888888888888884;
    r.x = x;
    r.stderr_ = stderr_;
    r.fixed = fixed;
    r.ok = 1;
    bf_error err;
    const char *path = ts_tmp_path("result.json");
    assert_int_equal(bf_fit_write_json(&r, "data.csv", path, &err), BF_OK);
    bf_model *m = NULL;
    double *back = NULL;
    if (bf_params_read(path, &m, &back, &err) != BF_OK)
        fail_msg("%s", err.msg);
    for (int c = 0; c < C; c++)
        if (back[c] != x[c])
            fail_msg("rho_d[%d] = %.17g read back as %.17g", c, x[c], back[c]);
    bf_model_free(m);
    free(back);
    /* The same text in memory (bf_fit_result_json) parses to the same values, and its
     * errors name what the caller calls it. */
    char *text = NULL;
    assert_int_equal(bf_fit_result_json(&r, "data.csv", &text, &err), BF_OK);
    assert_int_equal(bf_params_parse(text, "the fit", &m, &back, &err), BF_OK);
    for (int c = 0; c < C; c++)
        assert_true(back[c] == x[c]);
    bf_model_free(m);
    bf_free(back);
    bf_free(text);
    assert_int_equal(bf_params_parse("{\"model\": \"lambert\"}", "the fit", &m, &back, &err), BF_ERR_PARSE);
    assert_string_equal(err.msg, "the fit:1: \"params\" object missing");
    assert_null(m);
    bf_model_free(r.model);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_channel_counts),
        cmocka_unit_test(test_model_spec),
        cmocka_unit_test(test_result_file_exact),
    };
    return cmocka_run_group_tests_name("params_file", tests, NULL, NULL);
}
