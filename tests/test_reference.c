/* Reference files (brdfit/reference.h) and compare's use of them: reference sets,
 * parameter files and folders read in order, with one-line errors naming the file, the
 * line and the entry; materials matched by stem and canonical spec; values outside the
 * bounds kept and named; and a reference judged exactly as a fit judges itself: brdfit's
 * own result read back as a reference gives the fit's metrics to the bit and its
 * objective, so compare warns only when brdfit's search stopped above a reference. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <cmocka.h>

#include "brdfit/compare.h"
#include "brdfit/fit.h"
#include "brdfit/reference.h"
#include "support.h"

enum { NPOINTS = 1500 };

static const char set_text[] =
    "{\"source\": \"Ngan, Durand & Matusik 2005 (EGSR)\", \"table\": \"ngan_ward\",\n"
    " \"materials\": {\n"
    "  \"blue-acrylic\": {\"model\": \"ward_iso\", \"channels\": 3,\n"
    "    \"params\": {\"rho_d\": [0.1, 0.2, 0.3], \"rho_s\": [0.05, 0.05, 0.06], \"alpha\": 0.0162}},\n"
    "  \"gold-paint\": {\"model\": \"ward_iso\", \"channels\": 3,\n"
    "    \"params\": {\"rho_d\": [0.3, 0.2, 0.1], \"rho_s\": [1.4, 0.5, 0.2], \"alpha\": 1.5}}\n"
    " }}\n";

static bf_reference_set *new_set(void)
{
    bf_reference_set *s = NULL;
    assert_int_equal(bf_reference_set_new(&s, NULL), BF_OK);
    return s;
}

static void test_set_read(void **state)
{
    (void)state;
    bf_reference_set *s = new_set();
    bf_error err;
    assert_int_equal(bf_reference_parse(s, set_text, "ngan.json", &err), BF_OK);
    assert_int_equal(s->n, 2);
    const bf_reference *a = &s->refs[0], *b = &s->refs[1];
    assert_string_equal(a->material, "blue-acrylic");
    assert_string_equal(a->source, "Ngan, Durand & Matusik 2005 (EGSR)");
    assert_string_equal(a->table, "ngan_ward");
    assert_string_equal(a->file, "ngan.json");
    assert_int_equal(a->line, 3);
    assert_string_equal(bf_model_spec(a->model), "ward_iso");
    assert_int_equal(bf_model_channels(a->model), 3);
    assert_true(a->x[6] == 0.0162);
    assert_string_equal(a->outside, "");
    /* Outside brdfit's bounds: kept as published, and named. */
    assert_string_equal(b->material, "gold-paint");
    assert_int_equal(b->line, 5);
    assert_true(b->x[3] == 1.4 && b->x[6] == 1.5);
    assert_string_equal(b->outside, "rho_s[0], alpha");
    bf_reference_set_free(s);
}

/* A plain parameter file: the material is the file's stem, the source the file (or its
 * "source"). */
static void test_parameter_file(void **state)
{
    (void)state;
    bf_reference_set *s = new_set();
    const char *p = "{\"model\": \"lambert\", \"params\": {\"rho_d\": 0.4}}";
    assert_int_equal(bf_reference_parse(s, p, "refs/red-plastic.json", NULL), BF_OK);
    const char *q = "{\"source\": \"a lab\", \"model\": \"lambert\", \"params\": {\"rho_d\": 0.5}}";
    assert_int_equal(bf_reference_parse(s, q, "white.json", NULL), BF_OK);
    assert_int_equal(s->n, 2);
    assert_string_equal(s->refs[0].material, "red-plastic");
    assert_string_equal(s->refs[0].source, "refs/red-plastic.json");
    assert_null(s->refs[0].table);
    assert_string_equal(s->refs[1].source, "a lab");
    assert_int_equal(s->refs[1].line, 1);
    bf_reference_set_free(s);
}

static void expect_bad(const char *text, bf_status code, const char *fragment)
{
    bf_reference_set *s = new_set();
    bf_error err;
    assert_int_equal(bf_reference_parse(s, set_text, "good.json", NULL), BF_OK);
    assert_int_equal(bf_reference_parse(s, text, "bad.json", &err), code);
    if (!strstr(err.msg, fragment) || strncmp(err.msg, "bad.json:", 9) || strchr(err.msg, '\n'))
        fail_msg("message '%s' lacks '%s' or the file", err.msg, fragment);
    assert_int_equal(s->n, 2); /* a bad file leaves the set as it was */
    bf_reference_set_free(s);
}

static void test_bad_files(void **state)
{
    (void)state;
    expect_bad("{\"source\": \"x\", \"materials\": {", BF_ERR_PARSE, "bad.json:1: malformed JSON");
    expect_bad("[1, 2]", BF_ERR_PARSE, "bad.json:1: expected a JSON object");
    expect_bad("{\"materials\": {\"a\": {}}}", BF_ERR_PARSE, "needs \"source\"");
    expect_bad("{\"source\": \"x\",\n\"materials\": []}", BF_ERR_PARSE, "bad.json:2: \"materials\" must be an object");
    expect_bad("{\"source\": \"x\", \"materials\": {}}", BF_ERR_PARSE, "\"materials\" must be an object");
    expect_bad("{\"source\": 3, \"materials\": {}}", BF_ERR_PARSE, "\"source\" must be a non-empty string");
    expect_bad(
        "{\"source\": \"x\",\n \"materials\": {\n  \"a\": {\"model\": \"lambert\", \"params\": {\"rho_d\": 0.4}},\n"
        "  \"b\": {\"model\": \"lambert\",\n   \"params\": {\"rho_d\": \"x\"}}}}",
        BF_ERR_PARSE, "bad.json:5: materials/b: parameter rho_d: expected a number");
    expect_bad("{\"source\": \"x\", \"materials\": {\"a\": {\"model\": \"nosuch\", \"params\": {}}}}", BF_ERR_ARG,
               "materials/a:");
    expect_bad("{\"source\": \"x\", \"materials\": {\"a\": {\"model\": \"lambert\", \"params\": {\"rho_d\": 1e999}}}}",
               BF_ERR_RANGE, "materials/a: parameter rho_d is not finite");
    expect_bad("{\"source\": \"x\", \"materials\": {\"a\": {\"model\": \"lambert\", \"params\": {}}}}", BF_ERR_PARSE,
               "missing parameter \"rho_d\"");
    expect_bad("{\"source\": \"x\", \"materials\": {\"a\": {\"model\": \"lambert\", \"params\": {\"rho_d\": 0.1}},"
               " \"a\": {\"model\": \"lambert\", \"params\": {\"rho_d\": 0.2}}}}",
               BF_ERR_PARSE, "material \"a\" given twice");
    expect_bad("{\"model\": \"lambert\", \"params\": {\"rho_d\": [0.1, 0.2]}, \"channels\": 3}", BF_ERR_PARSE,
               "2 values for 3 channels");
    /* A material named with bytes that are not text is escaped in the message (found by
     * fuzz_reference). */
    expect_bad("{\"source\": \"x\", \"materials\": {\"gold-\xff\x02\": {\"mhdel\": \"lambert\"}}}", BF_ERR_PARSE,
               "materials/gold-\\xff\\x02: ");
}

/* A folder: its *.json files in byte order of their names, other files left out. */
static void test_directory_order(void **state)
{
    (void)state;
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", ts_tmp_path("refs"));
    assert_int_equal(mkdir(dir, 0777), 0);
    const char *names[] = {"b.json", "a.json", "B.json", "notes.txt"};
    const double values[] = {0.2, 0.1, 0.3, 0.9};
    for (int k = 0; k < 4; k++) {
        char path[4200], text[128];
        snprintf(path, sizeof path, "%s/%s", dir, names[k]);
        int n = snprintf(text, sizeof text, "{\"model\": \"lambert\", \"params\": {\"rho_d\": %g}}", values[k]);
        ts_write_file(path, text, (size_t)n);
    }
    bf_reference_set *s = new_set();
    bf_error err;
    assert_int_equal(bf_reference_read(s, dir, &err), BF_OK);
    assert_int_equal(s->n, 3);
    assert_string_equal(s->refs[0].material, "B"); /* 'B' < 'a' < 'b' */
    assert_string_equal(s->refs[1].material, "a");
    assert_string_equal(s->refs[2].material, "b");
    assert_true(s->refs[1].x[0] == 0.1);
    /* A folder without reference files, and a missing file, are errors. */
    char empty[4096];
    snprintf(empty, sizeof empty, "%s", ts_tmp_path("empty"));
    assert_int_equal(mkdir(empty, 0777), 0);
    assert_int_equal(bf_reference_read(s, empty, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "without a *.json"));
    assert_int_equal(bf_reference_read(s, ts_tmp_path("nosuch.json"), &err), BF_ERR_IO);
    assert_non_null(strstr(err.msg, "nosuch.json"));
    assert_int_equal(s->n, 3);
    bf_reference_set_free(s);
}

static void test_matching(void **state)
{
    (void)state;
    char buf[64];
    assert_string_equal(bf_reference_material("data/blue-acrylic.binary", buf, sizeof buf), "blue-acrylic");
    assert_string_equal(bf_reference_material("gold.paint.csv", buf, sizeof buf), "gold.paint");
    assert_string_equal(bf_reference_material("/x/.hidden", buf, sizeof buf), ".hidden");
    bf_reference_set *s = new_set();
    assert_int_equal(bf_reference_parse(s, set_text, "ngan.json", NULL), BF_OK);
    const char *w = "{\"model\": \"walter\", \"options\": {\"fresnel\": \"schlick\"}, \"params\": "
                    "{\"rho_d\": 0.1, \"rho_s\": 0.2, \"alpha\": 0.1, \"f0\": 0.04}}";
    assert_int_equal(bf_reference_parse(s, w, "blue-acrylic.json", NULL), BF_OK);
    assert_true(bf_reference_matches(&s->refs[0], "blue-acrylic", "ward_iso"));
    assert_false(bf_reference_matches(&s->refs[0], "blue-acrylic", "ward"));
    assert_false(bf_reference_matches(&s->refs[0], "gold-paint", "ward_iso"));
    assert_false(bf_reference_matches(&s->refs[0], "blue-acrylic", "nosuch"));
    /* Specs compare canonically: the default option spelled or not. */
    assert_true(bf_reference_matches(&s->refs[2], "blue-acrylic", "walter"));
    assert_true(bf_reference_matches(&s->refs[2], "blue-acrylic", "walter:fresnel=schlick"));
    assert_false(bf_reference_matches(&s->refs[2], "blue-acrylic", "walter:lobes=2"));
    bf_reference_set_free(s);
}

/* NPOINTS samples of ward_iso at x (3 channels), with 2% multiplicative noise. */
static bf_samples *material(const double *x)
{
    bf_samples *s = NULL;
    assert_int_equal(bf_samples_new(NPOINTS, 3, &s, NULL), BF_OK);
    ts_rng r = {7};
    for (size_t i = 0; i < NPOINTS; i++)
        ts_random_pair_deg(&r, i % 4 == 0, &s->theta_i[i], &s->phi_i[i], &s->theta_o[i], &s->phi_o[i]);
    bf_model *m = ts_model("ward_iso", 3);
    bf_model_eval(m, x, ts_samples_geometry(s), s->value, NULL);
    for (size_t k = 0; k < NPOINTS * 3; k++)
        s->value[k] *= 1.0 + 0.02 * (ts_uniform(&r) - 0.5);
    bf_model_free(m);
    return s;
}

static const double truth[] = {0.3, 0.2, 0.1, 0.2, 0.2, 0.2, 0.12};

/* brdfit's own result, read back as a reference, is judged as the fit judged itself. */
static void test_own_fit_as_reference(void **state)
{
    (void)state;
    bf_samples *s = material(truth);
    bf_options *o = ts_options(BF_TASK_COMPARE, "--threads 1 --starts 2 --screen 8 --rank error --loss huber");
    bf_fit_result r;
    bf_fit_result_init(&r);
    bf_error err;
    assert_int_equal(bf_fit(s, "ward_iso", o, &r, &err), BF_OK);
    assert_true(r.ok);
    char *json = NULL;
    assert_int_equal(bf_fit_result_json(&r, "gold.csv", &json, &err), BF_OK);
    bf_reference_set *set = new_set();
    assert_int_equal(bf_reference_parse(set, json, "gold.json", &err), BF_OK);
    bf_free(json);
    double cost = NAN;
    bf_metrics m;
    assert_int_equal(bf_reference_evaluate(&set->refs[0], s, o, &cost, &m, &err), BF_OK);
    assert_true(m.rmse == r.metrics.rmse && m.rmse_log == r.metrics.rmse_log);
    assert_true(m.rmse_cos == r.metrics.rmse_cos && m.rmse_rel == r.metrics.rmse_rel);
    assert_true(m.max_err == r.metrics.max_err && m.n == r.metrics.n);
    /* The objective the solver reported, to its rounding (the solver sums it its way). */
    ts_assert_rel(cost, r.solution.final_cost, 1e-12, "cost");
    /* The true parameters: near the noise, and above the fitted optimum. */
    set->refs[0].x[6] = truth[6];
    for (int k = 0; k < 6; k++)
        set->refs[0].x[k] = truth[k];
    double true_cost;
    assert_int_equal(bf_reference_evaluate(&set->refs[0], s, o, &true_cost, &m, &err), BF_OK);
    assert_true(true_cost > cost);
    ts_assert_rel(true_cost, cost, 0.05, "the truth's cost is the noise's");
    /* Another channel count cannot be judged on this data. */
    bf_reference_set *mono = new_set();
    assert_int_equal(bf_reference_parse(mono, "{\"model\": \"lambert\", \"params\": {\"rho_d\": 0.4}}", "g.json", NULL),
                     BF_OK);
    assert_int_equal(bf_reference_evaluate(&mono->refs[0], s, o, &cost, &m, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "1 channel, the data 3"));
    bf_reference_set_free(mono);
    bf_reference_set_free(set);
    bf_fit_result_clear(&r);
    bf_options_free(o);
    bf_samples_free(s);
}

static int count_kind(const bf_fit_result *r, bf_warning_kind k)
{
    int n = 0;
    for (int w = 0; w < r->nwarnings; w++)
        n += r->warning_kind[w] == k;
    return n;
}

/* bf_compare_run with references: its own fit as one, then a crippled fit beside it. */
static void test_compare_warns(void **state)
{
    (void)state;
    bf_samples *s = material(truth);
    const char *data = "gold.csv", *spec = "ward_iso";
    bf_options *o = ts_options(BF_TASK_COMPARE, "--threads 1 --starts 2 --screen 8");
    bf_fit_result r;
    bf_fit_result_init(&r);
    assert_int_equal(bf_fit(s, spec, o, &r, NULL), BF_OK);
    const char *path = ts_tmp_path("gold.json");
    assert_int_equal(bf_fit_write_json(&r, data, path, NULL), BF_OK);
    assert_int_equal(bf_options_set(o, "reference", path, NULL), BF_OK);
    for (int crippled = 0; crippled < 2; crippled++) {
        if (crippled)
            assert_int_equal(bf_options_set(o, "max_iterations", "1", NULL), BF_OK);
        if (crippled)
            assert_int_equal(bf_options_set(o, "starts", "1", NULL), BF_OK);
        bf_compare *c = NULL;
        bf_error err;
        assert_int_equal(bf_compare_new(1, &data, 1, &spec, &c, &err), BF_OK);
        bf_samples *const samples[] = {s};
        assert_int_equal(bf_compare_run(c, samples, o, NULL, NULL, &err), BF_OK);
        assert_int_equal(c->nreference, 1);
        const bf_compare_reference *q = &c->reference[0];
        const bf_fit_result *own = c->materials[0].fits[0].result;
        assert_true(q->metrics.rmse_log == r.metrics.rmse_log);
        if (!crippled) { /* the same fit: the same bits, no warning */
            assert_true(q->cost == q->brdfit_cost);
            assert_false(q->brdfit_worse);
            assert_int_equal(count_kind(own, BF_WARN_REFERENCE_BETTER), 0);
        } else {
            assert_true(q->brdfit_cost > q->cost);
            assert_true(q->brdfit_worse);
            assert_int_equal(count_kind(own, BF_WARN_REFERENCE_BETTER), 1);
        }
        char *json = NULL;
        assert_int_equal(bf_compare_json(c, &json, &err), BF_OK);
        assert_non_null(strstr(json, crippled ? "\"brdfit_worse\":\ttrue" : "\"brdfit_worse\":\tfalse"));
        bf_free(json);
        bf_compare_free(c);
    }
    /* A bad reference file fails the run before any fit. */
    assert_int_equal(bf_options_set(o, "reference", ts_tmp_path("nosuch.json"), NULL), BF_OK);
    bf_compare *c = NULL;
    assert_int_equal(bf_compare_new(1, &data, 1, &spec, &c, NULL), BF_OK);
    bf_error err;
    bf_samples *const samples[] = {s};
    assert_int_equal(bf_compare_run(c, samples, o, NULL, NULL, &err), BF_ERR_IO);
    assert_null(c->results);
    bf_compare_free(c);
    bf_fit_result_clear(&r);
    bf_options_free(o);
    bf_samples_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_set_read),      cmocka_unit_test(test_parameter_file),
        cmocka_unit_test(test_bad_files),     cmocka_unit_test(test_directory_order),
        cmocka_unit_test(test_matching),      cmocka_unit_test(test_own_fit_as_reference),
        cmocka_unit_test(test_compare_warns),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
