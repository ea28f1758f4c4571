/* Regression baselines on hand-made fit results (no fitting): parse errors with the
 * file's line, tolerance arithmetic and its layers of overrides, diff lines of a
 * perturbed expectation, missing and extra parameters, ok handling, the JUnit XML
 * (counts, escaping) and --update rewriting values while keeping tolerances. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>
#include <libxml/parser.h>

#include "brdfit/regress.h"
#include "support.h"

/* A Walter fit with three channels and known values. */
typedef struct fake {
    bf_fit_result r;
    double x[8];
} fake;

static void fake_walter(fake *f)
{
    memset(f, 0, sizeof *f);
    f->r.model = ts_model("walter", 3);
    const double x[8] = {0.5, 0.4, 0.3, 0.2, 0.2, 0.2, 0.1, 0.04};
    memcpy(f->x, x, sizeof x);
    f->r.x = f->x;
    f->r.ok = 1;
    f->r.metrics = (bf_metrics){.n = 300,
                                .k = 8,
                                .rmse = 0.01,
                                .rmse_cos = 0.005,
                                .rmse_log = 0.002,
                                .rmse_rel = 0.1,
                                .max_err = 0.05,
                                .aic = -100.0,
                                .bic = -90.0};
    snprintf(f->r.solution.termination, sizeof f->r.solution.termination, "CONVERGENCE");
}

static void fake_free(fake *f)
{
    bf_model_free(f->r.model);
}

static bf_regress_baseline *parse_ok(const char *text)
{
    bf_regress_baseline *b = NULL;
    bf_error err;
    int rc = bf_regress_parse(text, "dir/base.json", &b, &err);
    if (rc != BF_OK)
        fail_msg("parse failed: %s", err.msg);
    return b;
}

static void expect_parse_error(const char *text, const char *start, const char *contains)
{
    bf_regress_baseline *b = NULL;
    bf_error err;
    assert_int_not_equal(bf_regress_parse(text, "base.json", &b, &err), BF_OK);
    assert_null(b);
    if (strncmp(err.msg, start, strlen(start)) || !strstr(err.msg, contains))
        fail_msg("message '%s' should start with '%s' and contain '%s'", err.msg, start, contains);
}

static void test_parse_errors(void **state)
{
    (void)state;
    expect_parse_error("{\"brdfit_baseline\": 1,\n \"cases\": [}\n", "base.json:2:", "malformed JSON");
    expect_parse_error("{\"cases\": []}", "base.json:1:", "brdfit_baseline");
    expect_parse_error("{\"brdfit_baseline\": 2, \"cases\": []}", "base.json:1:", "version");
    expect_parse_error("{\"brdfit_baseline\": 1,\n \"cases\": []}", "base.json:2:", "non-empty");
    const char *head = "{\"brdfit_baseline\": 1,\n \"cases\": [\n";
    char text[2048];
    snprintf(text, sizeof text, "%s{\"name\": \"a\",\n \"data\": \"x.csv\"}]}", head);
    expect_parse_error(text, "base.json:3:", "has no \"model\"");
    snprintf(text, sizeof text, "%s{\"name\": \"a\", \"data\": \"x.csv\",\n\n \"model\": \"nosuch\"}]}", head);
    expect_parse_error(text, "base.json:5:", "nosuch");
    snprintf(text, sizeof text, "%s{\"name\": \"a\", \"data\": \"x.csv\", \"model\": \"lambert\",\n \"optoins\": []}]}",
             head);
    expect_parse_error(text, "base.json:4:", "unknown key \"optoins\"");
    snprintf(text, sizeof text,
             "%s{\"name\": \"a\", \"data\": \"x.csv\", \"model\": \"lambert\",\n \"options\": [\"--rgb\",\n 3]}]}",
             head);
    expect_parse_error(text, "base.json:5:", "option 2 must be a string");
    snprintf(text, sizeof text,
             "%s{\"name\": \"a\", \"data\": \"x.csv\", \"model\": \"lambert\",\n"
             " \"expected\": {\"metrics\": {\"rmse\": 1,\n \"rsme\": 2}}}]}",
             head);
    expect_parse_error(text, "base.json:5:", "unknown metric \"rsme\"");
    snprintf(text, sizeof text,
             "%s{\"name\": \"a\", \"data\": \"x.csv\", \"model\": \"lambert\",\n"
             " \"tolerance\": {\"params\": {\"alpha\": {\"rel\": 1}}}}]}",
             head);
    expect_parse_error(text, "base.json:4:", "unknown parameter \"alpha\" of lambert");
    snprintf(text, sizeof text,
             "{\"brdfit_baseline\": 1,\n \"tolerance\": {\"metrics\": {\"rel\": -1}},\n"
             " \"cases\": [{\"name\": \"a\", \"data\": \"x.csv\", \"model\": \"lambert\"}]}");
    expect_parse_error(text, "base.json:2:", "must be a number >= 0");
    snprintf(text, sizeof text,
             "%s{\"name\": \"a\", \"data\": \"x.csv\", \"model\": \"lambert\"},\n"
             "{\"name\": \"a\", \"data\": \"y.csv\", \"model\": \"lambert\"}]}",
             head);
    expect_parse_error(text, "base.json:4:", "used twice (also line 3)");
}

static void test_parse_fields(void **state)
{
    (void)state;
    bf_regress_baseline *b = parse_ok("{\"brdfit_baseline\": 1,\n"
                                      " \"cases\": [\n"
                                      "  {\"name\": \"w\", \"data\": \"../d/x.csv\", \"model\": \"walter\",\n"
                                      "   \"options\": [\"--rgb\",\n"
                                      "               \"--seed\", \"3\"],\n"
                                      "   \"expected\": {\"ok\": false, \"params\": {\"alpha\": null}}},\n"
                                      "  {\"name\": \"abs\", \"data\": \"/abs/y.csv\", \"model\": \"lambert\"}]}\n");
    assert_int_equal(b->ncases, 2);
    const bf_regress_case *c = &b->cases[0];
    assert_string_equal(c->data_path, "dir/../d/x.csv");
    assert_string_equal(b->cases[1].data_path, "/abs/y.csv");
    assert_int_equal(c->noptions, 3);
    assert_string_equal(c->options[2], "3");
    assert_int_equal(c->option_lines[0], 4);
    assert_int_equal(c->option_lines[1], 5);
    assert_int_equal(c->line, 3);
    assert_int_equal(c->expect_ok, 0);
    assert_int_equal(c->nparams, 1);
    assert_true(isnan(c->params[0].v[0]));
    assert_int_equal(b->cases[1].expect_ok, 1);
    assert_int_equal(b->cases[1].nparams, 0);
    bf_regress_baseline_free(b);
}

/* The base for the tolerance tests: alpha expected 0.1, rho_d[1] 0.4. */
static const char tol_doc[] =
    "{\"brdfit_baseline\": 1,\n"
    " \"tolerance\": {\"params\": {\"rel\": 0.01, \"abs\": 0.0, \"f0\": {\"abs\": 0.5}},\n"
    "               \"metrics\": {\"abs\": 0.001}},\n"
    " \"cases\": [\n"
    "  {\"name\": \"top\", \"data\": \"x.csv\", \"model\": \"walter\",\n"
    "   \"expected\": {\"params\": {\"alpha\": %s, \"f0\": %s}, \"metrics\": {\"rmse\": %s}}},\n"
    "  {\"name\": \"case\", \"data\": \"x.csv\", \"model\": \"walter\",\n"
    "   \"tolerance\": {\"params\": {\"abs\": 0.2, \"alpha\": {\"rel\": 0.5}}},\n"
    "   \"expected\": {\"params\": {\"alpha\": %s, \"rho_d\": [0.5, %s, 0.3]}}}]}\n";

static bf_regress_status status_of(const char *alpha, const char *f0, const char *rmse, const char *alpha2,
                                   const char *rho_d1, int c)
{
    char text[2048];
    snprintf(text, sizeof text, tol_doc, alpha, f0, rmse, alpha2, rho_d1);
    bf_regress_baseline *b = parse_ok(text);
    fake f;
    fake_walter(&f);
    bf_regress_outcome o;
    bf_regress_outcome_init(&o);
    bf_error err;
    assert_int_equal(bf_regress_check(b, c, &f.r, &o, &err), BF_OK);
    bf_regress_status s = o.status;
    bf_regress_outcome_clear(&o);
    fake_free(&f);
    bf_regress_baseline_free(b);
    return s;
}

static void test_tolerance(void **state)
{
    (void)state;
    /* Resolution: defaults, file group, file per-name, case group, case per-name. */
    bf_regress_baseline *b =
        parse_ok("{\"brdfit_baseline\": 1, \"tolerance\": {\"params\": {\"rel\": 0.01, \"alpha\": {\"abs\": 3}}},\n"
                 " \"cases\": [{\"name\": \"a\", \"data\": \"x\", \"model\": \"walter\"},\n"
                 "  {\"name\": \"b\", \"data\": \"x\", \"model\": \"walter\",\n"
                 "   \"tolerance\": {\"params\": {\"abs\": 2, \"alpha\": {\"rel\": 0.5}}, \"metrics\": {\"rmse\": "
                 "{\"rel\": 7}}}}]}");
    bf_tolerance t = bf_regress_tolerance(b, 0, "metrics", "rmse");
    assert_true(t.rel == BF_REGRESS_METRICS_REL && t.abs == BF_REGRESS_METRICS_ABS);
    t = bf_regress_tolerance(b, 0, "params", "rho_d");
    assert_true(t.rel == 0.01 && t.abs == BF_REGRESS_PARAMS_ABS);
    t = bf_regress_tolerance(b, 0, "params", "alpha");
    assert_true(t.rel == 0.01 && t.abs == 3.0);
    t = bf_regress_tolerance(b, 1, "params", "alpha");
    assert_true(t.rel == 0.5 && t.abs == 2.0);
    t = bf_regress_tolerance(b, 1, "params", "f0");
    assert_true(t.rel == 0.01 && t.abs == 2.0);
    t = bf_regress_tolerance(b, 1, "metrics", "rmse");
    assert_true(t.rel == 7.0 && t.abs == BF_REGRESS_METRICS_ABS);
    bf_regress_baseline_free(b);

    /* |got - expected| <= abs + rel |expected|; the fake has alpha 0.1, f0 0.04,
     * rmse 0.01, rho_d[1] 0.4. Case "top": alpha rel 0.01 abs 0 -> tol 0.00101 at
     * expected 0.101; f0 abs 0.5; rmse abs 0.001 (+ 1e-6 rel). */
    assert_int_equal(status_of("0.1", "0.04", "0.01", "0.1", "0.4", 0), BF_REGRESS_PASS);
    assert_int_equal(status_of("0.1009", "0.04", "0.01", "0.1", "0.4", 0), BF_REGRESS_PASS);
    assert_int_equal(status_of("0.1011", "0.04", "0.01", "0.1", "0.4", 0), BF_REGRESS_FAIL);
    assert_int_equal(status_of("0.0991", "0.04", "0.01", "0.1", "0.4", 0), BF_REGRESS_PASS);
    assert_int_equal(status_of("0.0989", "0.04", "0.01", "0.1", "0.4", 0), BF_REGRESS_FAIL);
    assert_int_equal(status_of("0.1", "0.5", "0.01", "0.1", "0.4", 0), BF_REGRESS_PASS); /* f0: abs 0.5 */
    assert_int_equal(status_of("0.1", "0.6", "0.01", "0.1", "0.4", 0), BF_REGRESS_FAIL);
    assert_int_equal(status_of("0.1", "0.04", "0.0109", "0.1", "0.4", 0), BF_REGRESS_PASS);
    assert_int_equal(status_of("0.1", "0.04", "0.0111", "0.1", "0.4", 0), BF_REGRESS_FAIL);
    /* Case "case": abs 0.2 for every parameter, alpha rel 0.5 on top of it. */
    assert_int_equal(status_of("0.1", "0.04", "0.01", "0.29", "0.4", 1), BF_REGRESS_PASS);
    assert_int_equal(status_of("0.1", "0.04", "0.01", "0.1", "0.59", 1), BF_REGRESS_PASS);
    assert_int_equal(status_of("0.1", "0.04", "0.01", "0.1", "0.61", 1), BF_REGRESS_FAIL);
    assert_int_equal(status_of("0.1", "0.04", "0.01", "-0.21", "0.4", 1), BF_REGRESS_FAIL);
    /* A NaN (null) expectation matches only a non-finite value. */
    assert_int_equal(status_of("null", "0.04", "0.01", "0.1", "0.4", 0), BF_REGRESS_FAIL);
}

static bf_regress_outcome check_text(const char *text, fake *f)
{
    bf_regress_baseline *b = parse_ok(text);
    bf_regress_outcome o;
    bf_regress_outcome_init(&o);
    bf_error err;
    assert_int_equal(bf_regress_check(b, 0, &f->r, &o, &err), BF_OK);
    bf_regress_baseline_free(b);
    return o;
}

static void test_diff_lines(void **state)
{
    (void)state;
    fake f;
    fake_walter(&f);
    bf_regress_outcome o =
        check_text("{\"brdfit_baseline\": 1, \"cases\": [{\"name\": \"a\", \"data\": \"x\", \"model\": \"walter\",\n"
                   " \"expected\": {\"ok\": true, \"params\": {\"rho_d\": [0.5, 0.41, 0.3], \"alpha\": 0.1},\n"
                   "               \"metrics\": {\"bic\": -90, \"k\": 7}}}]}",
                   &f);
    assert_int_equal(o.status, BF_REGRESS_FAIL);
    assert_int_equal(o.nlines, 2);
    assert_string_equal(o.lines[0], "  params.rho_d[1]: expected 0.41, got 0.4 (|diff| 0.01 > tol 4.1e-07)");
    assert_string_equal(o.lines[1], "  metrics.k: expected 7, got 8 (|diff| 1 > tol 7e-06)");
    /* Verbose: ok, three channels, alpha, two metrics. */
    assert_int_equal(o.nchecked, 1 + 3 + 1 + 2);
    assert_string_equal(o.checked[4], "  params.alpha: expected 0.1, got 0.1 (|diff| 0 <= tol 1e-07)");
    bf_regress_outcome_clear(&o);

    /* Names the model does not have, a colour parameter with the wrong channel count,
     * a scalar given as an array: each fails with its own line. */
    o = check_text("{\"brdfit_baseline\": 1, \"cases\": [{\"name\": \"a\", \"data\": \"x\", \"model\": \"walter\",\n"
                   " \"expected\": {\"params\": {\"rho_d\": [0.5], \"alpha\": [0.1, 0.1, 0.1], \"m\": 0.2,\n"
                   "                             \"f0\": 0.04}}}]}",
                   &f);
    assert_int_equal(o.status, BF_REGRESS_FAIL);
    assert_int_equal(o.nlines, 3);
    assert_string_equal(o.lines[0], "  params.rho_d: expected holds 1 value, the fit has 3 (one per channel)");
    assert_string_equal(o.lines[1], "  params.alpha: expected holds 3 values, the parameter is a scalar");
    assert_non_null(strstr(o.lines[2], "params.m: not a parameter of walter"));
    assert_non_null(strstr(o.lines[2], "rho_d, rho_s, alpha, f0"));
    bf_regress_outcome_clear(&o);

    /* ok: a failed fit fails unless expected; an unexpected success fails. */
    const char *expect_false = "{\"brdfit_baseline\": 1, \"cases\": [{\"name\": \"a\", \"data\": \"x\", "
                               "\"model\": \"walter\", \"expected\": {\"ok\": false, \"params\": {\"alpha\": 9}}}]}";
    const char *expect_true = "{\"brdfit_baseline\": 1, \"cases\": [{\"name\": \"a\", \"data\": \"x\", "
                              "\"model\": \"walter\", \"expected\": {\"params\": {\"alpha\": 9}}}]}";
    f.r.ok = 0;
    o = check_text(expect_false, &f);
    assert_int_equal(o.status, BF_REGRESS_PASS);
    bf_regress_outcome_clear(&o);
    o = check_text(expect_true, &f);
    assert_int_equal(o.status, BF_REGRESS_FAIL);
    assert_string_equal(o.lines[0], "  ok: expected true, got false (the fit failed)");
    assert_string_equal(o.lines[1], "  termination: CONVERGENCE");
    bf_regress_outcome_clear(&o);
    f.r.ok = 1;
    o = check_text(expect_false, &f);
    assert_int_equal(o.status, BF_REGRESS_FAIL);
    assert_string_equal(o.lines[0], "  ok: expected false, got true");
    bf_regress_outcome_clear(&o);
    fake_free(&f);
}

static char *slurp(const char *path)
{
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    static char buf[1 << 16];
    size_t n = fread(buf, 1, sizeof buf - 1, fp);
    fclose(fp);
    buf[n] = '\0';
    return buf;
}

static void test_junit(void **state)
{
    (void)state;
    bf_regress_baseline *b = parse_ok("{\"brdfit_baseline\": 1, \"cases\": [\n"
                                      " {\"name\": \"ok\", \"data\": \"x\", \"model\": \"lambert\"},\n"
                                      " {\"name\": \"a<b&\\\"c\\\"\", \"data\": \"x\", \"model\": \"lambert\"},\n"
                                      " {\"name\": \"broken\", \"data\": \"x\", \"model\": \"lambert\"},\n"
                                      " {\"name\": \"skipped\", \"data\": \"x\", \"model\": \"lambert\"}]}");
    bf_regress_outcome o[4];
    bf_error err;
    for (int k = 0; k < 4; k++)
        bf_regress_outcome_init(&o[k]);
    o[0].seconds = 0.25;
    o[1].status = BF_REGRESS_FAIL;
    o[1].seconds = 0.5;
    o[1].lines = calloc(2, sizeof *o[1].lines);
    o[1].lines[0] = strdup("  params.alpha: expected 1 < 2 & \"x\"");
    o[1].lines[1] = strdup("  metrics.rmse: moved");
    o[1].nlines = 2;
    assert_int_equal(bf_regress_set_error(&o[2], "x.csv:3: bad <row> & \"quote\"", &err), BF_OK);
    o[3].status = BF_REGRESS_SKIPPED;

    char dir[] = "/tmp/test_regress_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[128];
    snprintf(path, sizeof path, "%s/j.xml", dir);
    assert_int_equal(bf_regress_write_junit(b, o, path, &err), BF_OK);
    const char *xml = slurp(path);
    assert_non_null(strstr(xml, "<testsuites tests=\"3\" failures=\"1\" errors=\"1\" time=\"0.750\">"));
    assert_non_null(strstr(xml, "<testsuite name=\"brdfit regress\" tests=\"3\" failures=\"1\" errors=\"1\""));
    assert_non_null(strstr(xml, "<testcase name=\"ok\" classname=\"dir/base.json\" time=\"0.250\"/>"));
    assert_non_null(strstr(xml, "<testcase name=\"a&lt;b&amp;&quot;c&quot;\" classname=\"dir/base.json\""));
    assert_non_null(strstr(xml, "<failure message=\"2 values differ from the baseline\">"
                                "params.alpha: expected 1 &lt; 2 &amp; &quot;x&quot;\nmetrics.rmse: moved</failure>"));
    assert_non_null(strstr(xml, "<error message=\"x.csv:3: bad &lt;row&gt; &amp; &quot;quote&quot;\">"));
    assert_null(strstr(xml, "skipped"));
    unlink(path);
    /* An unwritable target: an error and no file. */
    snprintf(path, sizeof path, "%s/no/such/dir/j.xml", dir);
    assert_int_equal(bf_regress_write_junit(b, o, path, &err), BF_ERR_IO);
    rmdir(dir);
    for (int i = 0; i < 4; i++)
        bf_regress_outcome_clear(&o[i]);
    bf_regress_baseline_free(b);
}

/* Found by fuzz/fuzz_regress.c: a key given twice. cJSON keeps both, the check read
 * both and the update replaced only the first, so a case failed right after --update. */
static void test_repeated_keys(void **state)
{
    (void)state;
    expect_parse_error("{\"brdfit_baseline\": 1,\"cases\":[{\"name\": \"a\",\"data\": \".\",\"model\":\"walter\","
                       "\"expected\":{\"params\":{ \"rho_s\":[3],\n \"rho_s\":3}}}]}",
                       "base.json:1:", "key \"rho_s\" appears twice in the same object");
    expect_parse_error("{\"brdfit_baseline\": 1,\n\"brdfit_baseline\": 1, \"cases\": []}",
                       "base.json:1:", "key \"brdfit_baseline\" appears twice");
    expect_parse_error("{\"brdfit_baseline\": 1, \"tolerance\": {\"metrics\": {\"rel\": 1,\n\"rel\": 2}},\n"
                       "\"cases\": [{\"name\": \"a\", \"data\": \"x\", \"model\": \"lambert\"}]}",
                       "base.json:1:", "key \"rel\" appears twice");
}

/* Names, paths and keys are printed and reported as they are: control characters and
 * invalid UTF-8 are refused (comments may hold anything); text from elsewhere (the
 * fit, the command line) reaches the JUnit XML escaped, which libxml2 reads. */
static void test_control_characters(void **state)
{
    (void)state;
    expect_parse_error("{\"brdfit_baseline\": 1, \"cases\": [\n"
                       " {\"name\": \"a\\u001b[31m\", \"data\": \"x\", \"model\": \"lambert\"}]}",
                       "base.json:2:", "'a\\x1b[31m' holds control characters or invalid UTF-8");
    expect_parse_error("{\"brdfit_baseline\": 1, \"cases\": [\n"
                       " {\"name\": \"\xff\", \"data\": \"x\", \"model\": \"lambert\"}]}",
                       "base.json:2:", "'\\xff' holds");
    expect_parse_error("{\"brdfit_baseline\": 1, \"cases\": [\n"
                       " {\"name\": \"a\", \"data\": \"x\", \"model\": \"lambert\",\n"
                       "  \"expected\": {\"params\": {\"rho_d\\u009b\": 1}}}]}",
                       "base.json:3:", "'rho_d\\u009b' holds");
    expect_parse_error("{\"brdfit_baseline\": 1, \"cases\": [\n"
                       " {\"name\": \"a\", \"data\": \"x\", \"model\": \"lambert\", \"options\": [\"--rgb\",\n"
                       "  \"\\t\"]}]}",
                       "base.json:3:", "'\\x09' holds");
    bf_regress_baseline *comment =
        parse_ok("{\"brdfit_baseline\": 1, \"comment\": \"line\\nnext\\u001b\", \"cases\": [\n"
                 " {\"name\": \"a\", \"data\": \"x\", \"model\": \"lambert\"}]}");
    bf_regress_baseline_free(comment);
    bf_regress_baseline *b = parse_ok("{\"brdfit_baseline\": 1, \"cases\": [\n"
                                      " {\"name\": \"a\", \"data\": \"x\", \"model\": \"lambert\"}]}");
    bf_regress_outcome o;
    bf_regress_outcome_init(&o);
    o.status = BF_REGRESS_FAIL;
    o.lines = calloc(1, sizeof *o.lines);
    o.lines[0] = strdup("  params.\x1b[2J\x01\xff: not a parameter of lambert");
    o.nlines = 1;
    o.warnings = calloc(1, sizeof *o.warnings);
    o.warnings[0] = strdup("rho_d\x0c at a bound");
    o.nwarnings = 1;
    char dir[] = "/tmp/test_regress_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[128];
    snprintf(path, sizeof path, "%s/j.xml", dir);
    bf_error err;
    assert_int_equal(bf_regress_write_junit(b, &o, path, &err), BF_OK);
    xmlDocPtr doc = xmlReadFile(path, NULL, XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING);
    assert_non_null(doc);
    xmlFreeDoc(doc);
    const char *xml = slurp(path);
    assert_non_null(strstr(xml, "params.\\x1b[2J\\x01\\xff: not a parameter of lambert</failure>"));
    assert_non_null(strstr(xml, "warning: rho_d\\x0c at a bound"));
    unlink(path);
    rmdir(dir);
    bf_regress_outcome_clear(&o);
    bf_regress_baseline_free(b);
}

static void test_update(void **state)
{
    (void)state;
    char dir[] = "/tmp/test_regress_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char path[128];
    snprintf(path, sizeof path, "%s/base.json", dir);
    FILE *fp = fopen(path, "w");
    assert_non_null(fp);
    fputs("{\"brdfit_baseline\": 1, \"tolerance\": {\"params\": {\"rel\": 0.25}},\n"
          " \"cases\": [\n"
          "  {\"name\": \"pinned\", \"data\": \"x.csv\", \"model\": \"walter\", \"options\": [\"--rgb\"],\n"
          "   \"tolerance\": {\"params\": {\"alpha\": {\"abs\": 0.125}}},\n"
          "   \"expected\": {\"params\": {\"alpha\": 0.3, \"rho_d\": [0.5], \"gone\": 1}, \"metrics\": {\"rmse\": "
          "0.01}}},\n"
          "  {\"name\": \"new\", \"data\": \"x.csv\", \"model\": \"walter\"}]}\n",
          fp);
    fclose(fp);
    bf_regress_baseline *b = NULL;
    bf_error err;
    assert_int_equal(bf_regress_load(path, &b, &err), BF_OK);
    fake f;
    fake_walter(&f);
    f.x[6] = 0.11234567890123457; /* alpha: needs 17 digits to read back */
    char **changes = NULL;
    int n = 0;
    assert_int_equal(bf_regress_update(b, 0, &f.r, &changes, &n, &err), BF_OK);
    assert_int_equal(n, 3);
    assert_string_equal(changes[0], "  params.gone: removed (not a parameter of walter:fresnel=schlick,lobes=1)");
    assert_string_equal(changes[1], "  params.rho_d: 1 value -> 3 values");
    assert_non_null(strstr(changes[2], "params.alpha: 0.3 -> 0.11234567890123"));
    for (int i = 0; i < n; i++)
        free(changes[i]);
    free(changes);
    changes = NULL;
    n = 0;
    assert_int_equal(bf_regress_update(b, 1, &f.r, &changes, &n, &err), BF_OK);
    assert_int_equal(n, 4 + bf_regress_nmetric_names);
    for (int i = 0; i < n; i++)
        free(changes[i]);
    free(changes);
    assert_int_equal(bf_regress_write(b, path, &err), BF_OK);
    bf_regress_baseline_free(b);

    /* Read back: values exact, pinned subset kept (rmse only; rho_s unpinned), the new
     * case filled, tolerances and options as they were. */
    assert_int_equal(bf_regress_load(path, &b, &err), BF_OK);
    const bf_regress_case *c = &b->cases[0];
    assert_int_equal(c->nparams, 2);
    assert_string_equal(c->params[0].name, "alpha");
    assert_true(c->params[0].v[0] == f.x[6]);
    assert_string_equal(c->params[1].name, "rho_d");
    assert_int_equal(c->params[1].n, 3);
    assert_true(c->params[1].v[2] == 0.3);
    assert_int_equal(c->nmetrics, 1);
    assert_true(c->metrics[0].v[0] == 0.01);
    assert_int_equal(c->noptions, 1);
    assert_string_equal(c->options[0], "--rgb");
    bf_tolerance t = bf_regress_tolerance(b, 0, "params", "alpha");
    assert_true(t.rel == 0.25 && t.abs == 0.125);
    assert_int_equal(b->cases[1].nparams, 4);
    assert_int_equal(b->cases[1].nmetrics, bf_regress_nmetric_names);
    assert_int_equal(b->cases[1].expect_ok, 1);
    bf_regress_outcome o;
    bf_regress_outcome_init(&o);
    for (int i = 0; i < 2; i++) {
        assert_int_equal(bf_regress_check(b, i, &f.r, &o, &err), BF_OK);
        assert_int_equal(o.status, BF_REGRESS_PASS);
        bf_regress_outcome_clear(&o);
    }
    bf_regress_baseline_free(b);
    /* The layout: two-space indent, small objects and scalar arrays on one line. */
    const char *text = slurp(path);
    assert_non_null(strstr(text, "\n  \"tolerance\": {\n    \"params\": {\"rel\": 0.25}\n  },"));
    assert_non_null(strstr(text, "\"rho_d\": [0.5, 0.4, 0.3],"));
    /* A failed fit sets ok false and keeps the values. */
    assert_int_equal(bf_regress_load(path, &b, &err), BF_OK);
    f.r.ok = 0;
    changes = NULL;
    n = 0;
    assert_int_equal(bf_regress_update(b, 0, &f.r, &changes, &n, &err), BF_OK);
    assert_int_equal(n, 1);
    assert_string_equal(changes[0], "  ok: true -> false");
    free(changes[0]);
    free(changes);
    bf_regress_baseline_free(b);
    fake_free(&f);
    unlink(path);
    rmdir(dir);
}

/* A case's run options, as the library reads them for every runner of baselines:
 * threads 1 unless set, both spellings of a value, --scene relative to the baseline's
 * folder, and each refusal naming the file and line. */
static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static bf_status case_options(const char *dir, const char *data, const char *options, bf_options **o, bf_error *err)
{
    char path[512], text[1024];
    snprintf(path, sizeof path, "%s/base.json", dir);
    snprintf(text, sizeof text,
             "{\"brdfit_baseline\": 1, \"cases\": [\n"
             "{\"name\": \"c\", \"data\": \"%s\", \"model\": \"lambert\",\n"
             "\"options\": [%s]}]}\n",
             data, options);
    bf_regress_baseline *b = NULL;
    bf_error perr;
    if (bf_regress_parse(text, path, &b, &perr) != BF_OK)
        fail_msg("%s", perr.msg);
    bf_status rc = bf_regress_case_options(b, 0, o, err);
    bf_regress_baseline_free(b);
    return rc;
}

static void option_is(const bf_options *o, const char *name, const char *want)
{
    char v[4096];
    assert_int_equal(bf_options_get(o, name, v, sizeof v, NULL), BF_OK);
    assert_string_equal(v, want);
}

static void test_case_options(void **state)
{
    (void)state;
    char dir[] = "/tmp/test_regress_XXXXXX", path[600];
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/d.csv", dir);
    write_file(path, "theta_i,phi_i,theta_o,phi_o,value\n");
    snprintf(path, sizeof path, "%s/s.json", dir);
    write_file(path, "{\"lights\": [{\"theta\": 40, \"phi\": 45}], \"views\": [{\"theta\": 60, \"phi\": 0}]}\n");
    bf_options *o = NULL;
    bf_error err;

    assert_int_equal(case_options(dir, "d.csv", "\"--max-theta=80\", \"--scene\", \"s.json\"", &o, &err), BF_OK);
    option_is(o, "threads", "1");
    option_is(o, "max_theta", "80");
    option_is(o, "scene", path);
    bf_options_free(o);
    assert_int_equal(case_options(dir, "d.csv", "\"--threads\", \"2\", \"--rgb\"", &o, &err), BF_OK);
    option_is(o, "threads", "2");
    option_is(o, "rgb", "true");
    bf_options_free(o);

    static const struct {
        const char *options, *data, *message;
    } bad[] = {
        {"\"--frobnicate\"", "d.csv", "base.json:3: case 'c': unknown option '--frobnicate' (brdfit fit's data"},
        {"\"-m\", \"walter\"", "d.csv", "base.json:3: case 'c': option '-m' has no place in a baseline"},
        {"\"--rank\", \"bic\"", "d.csv", "base.json:3: case 'c': unknown option '--rank'"},
        {"\"--rgb=1\"", "d.csv", "base.json:3: case 'c': --rgb takes no value"},
        {"\"--seed\"", "d.csv", "base.json:3: case 'c': --seed needs a value"},
        {"\"--seed\", \"x\"", "d.csv", "base.json:3: case 'c': --seed needs an integer"},
        {"\"--scene\", \"none.json\"", "d.csv", "base.json:2: case 'c': --scene: "},
        {"\"--rgb\"", "missing.csv", "base.json:2: case 'c': data file '"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        o = (bf_options *)&err; /* refused: set back to NULL */
        assert_int_not_equal(case_options(dir, bad[k].data, bad[k].options, &o, &err), BF_OK);
        assert_null(o);
        const char *at = strstr(err.msg, "base.json:");
        if (!at || strncmp(at, bad[k].message, strlen(bad[k].message)) != 0)
            fail_msg("case %zu: '%s', wanted '%s...'", k, err.msg, bad[k].message);
    }
    snprintf(path, sizeof path, "%s/d.csv", dir);
    unlink(path);
    snprintf(path, sizeof path, "%s/s.json", dir);
    unlink(path);
    rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parse_errors),  cmocka_unit_test(test_parse_fields),
        cmocka_unit_test(test_tolerance),     cmocka_unit_test(test_diff_lines),
        cmocka_unit_test(test_junit),         cmocka_unit_test(test_update),
        cmocka_unit_test(test_repeated_keys), cmocka_unit_test(test_control_characters),
        cmocka_unit_test(test_case_options),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
