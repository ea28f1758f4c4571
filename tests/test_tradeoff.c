/* The tradeoff table: grid size and order (ascending, deduplicated sample counts, one
 * "all" row), a disjoint seeded train/test split of the right sizes, reproducible errors
 * for one seed, the Pareto front and the recommendation on hand-made timings, method
 * names, and the JSON and CSV outputs; the tradeoff's options (their defaults from the
 * base setting, the lists' checks and messages) and the whole measurement from them
 * (bf_tradeoff_run) on generated data, step for step the same as the parts. */
#include <cjson/cJSON.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "brdfit/tradeoff.h"
#include "compare/compare_impl.h"
#include "support.h"
#include "synth.h"
#include "tradeoff/tradeoff_impl.h"

static const char *const methods2[] = {"ceres", "LD_LBFGS"}, *const methods1[] = {"ceres"};

/* g set up by its init with four arrays as its lists (their lengths from the arrays); &g. */
#define NELEM(a) (int)(sizeof(a) / sizeof *(a))
#define GRID(g, c, m, r, s)                                                                                            \
    (bf_tradeoff_grid_init(&(g)), (g).ncounts = NELEM(c), (g).counts = (c), (g).nmethods = NELEM(m),                   \
     (g).methods = (m), (g).nresiduals = NELEM(r), (g).residuals = (r), (g).nstarts = NELEM(s), (g).starts = (s),      \
     &(g))

/* n samples of a one-channel walter model at random directions; theta_i is made unique
 * per sample (a tiny index offset) so that a split can be traced back. */
static bf_samples *synthetic(size_t n)
{
    bf_error err;
    bf_samples *s = NULL;
    bf_samples_new(n, 1, &s, &err);
    assert_non_null(s);
    ts_rng r = {12345};
    ts_random_dirs(&r, n, s->theta_i, s->phi_i, s->theta_o, s->phi_o);
    for (size_t i = 0; i < n; i++) {
        s->theta_i[i] = s->theta_i[i] / DEG * 0.99 + 1e-7 * (double)i;
        s->phi_i[i] /= DEG;
        s->theta_o[i] = s->theta_o[i] / DEG * 0.99;
        s->phi_o[i] /= DEG;
    }
    bf_model *m = ts_model("walter", 1);
    double x[8];
    assert_true(bf_model_nvalues(m) <= 8);
    bf_model_defaults(m, x);
    const bf_geometry *g = NULL;
    bf_samples_geometry(s, &g, &err);
    assert_non_null(g);
    bf_model_eval(m, x, g, s->value, NULL);
    bf_model_free(m);
    return s;
}

static void test_grid_size_and_order(void **state)
{
    (void)state;
    bf_tradeoff t;
    bf_tradeoff_grid g;
    bf_error err;
    const size_t counts[] = {4000, 500, 0, 2000, 500, 99999};
    const bf_residual res[] = {BF_RESIDUAL_LOG, BF_RESIDUAL_LINEAR};
    const int starts[] = {1, 4, 2};
    assert_int_equal(bf_tradeoff_init(&t, "d.csv", "walter", 3000, GRID(g, counts, methods2, res, starts), &err),
                     BF_OK);
    /* 500, 2000, all (4000, 0 and 99999 are all one "all") x 2 x 2 x 3 */
    assert_int_equal(t.nrows, 3 * 2 * 2 * 3);
    const size_t want[] = {500, 2000, 3000};
    for (int i = 0; i < t.nrows; i++) {
        const bf_tradeoff_row *r = &t.rows[i];
        int a = i / 12, m = (i / 6) % 2, q = (i / 3) % 2, s = i % 3;
        assert_int_equal(r->samples, want[a]);
        assert_int_equal(r->all, a == 2);
        assert_string_equal(r->method, methods2[m]);
        assert_int_equal(r->residual, res[q]);
        assert_int_equal(r->starts, starts[s]);
        if (i > 0)
            assert_true(r->samples >= t.rows[i - 1].samples);
    }
    bf_tradeoff_clear(&t);

    /* Every count beyond the training size: one row, "all". */
    const size_t big[] = {5000, 8000};
    const bf_residual log1[] = {BF_RESIDUAL_LOG};
    const int one[] = {1};
    assert_int_equal(bf_tradeoff_init(&t, "d", "walter", 1000, GRID(g, big, methods1, log1, one), &err), BF_OK);
    assert_int_equal(t.nrows, 1);
    assert_int_equal(t.rows[0].all, 1);
    assert_int_equal(t.rows[0].samples, 1000);
    bf_tradeoff_clear(&t);

    /* Empty lists and negative starts are refused; 0 is brdfit fit's automatic count. */
    (void)GRID(g, big, methods1, log1, one);
    g.ncounts = 0;
    assert_int_equal(bf_tradeoff_init(&t, "d", "walter", 1000, &g, &err), BF_ERR_ARG);
    const size_t big1[] = {5000};
    const int negative[] = {-1}, automatic[] = {0};
    assert_int_equal(bf_tradeoff_init(&t, "d", "walter", 1000, GRID(g, big1, methods1, log1, negative), &err),
                     BF_ERR_ARG);
    assert_int_equal(bf_tradeoff_init(&t, "d", "walter", 1000, GRID(g, big1, methods1, log1, automatic), &err), BF_OK);
    assert_int_equal(t.rows[0].starts, 0);
    bf_tradeoff_clear(&t);

    /* A grid whose size was never set is refused, naming it. */
    (void)GRID(g, big1, methods1, log1, one);
    g.size = 0;
    assert_int_equal(bf_tradeoff_init(&t, "d", "walter", 1000, &g, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "bf_tradeoff_grid"));
}

static void test_split_disjoint(void **state)
{
    (void)state;
    bf_error err;
    bf_samples *s = synthetic(1001), *train, *test, *train2, *test2;
    assert_int_equal(bf_tradeoff_split(s, 0.2, 7, &train, &test, &err), BF_OK);
    assert_int_equal(test->n, 200);
    assert_int_equal(train->n, 801);
    /* Every sample in exactly one of the two, each in the original order. */
    unsigned char *seen = calloc(s->n, 1);
    const bf_samples *parts[2] = {train, test};
    for (int p = 0; p < 2; p++) {
        size_t last = 0;
        for (size_t j = 0; j < parts[p]->n; j++) {
            size_t i;
            for (i = 0; i < s->n && s->theta_i[i] != parts[p]->theta_i[j]; i++)
                ;
            assert_true(i < s->n);
            assert_int_equal(seen[i], 0);
            assert_true(j == 0 || i > last);
            assert_true(parts[p]->value[j] == s->value[i]);
            seen[i] = 1;
            last = i;
        }
    }
    for (size_t i = 0; i < s->n; i++)
        assert_int_equal(seen[i], 1);
    free(seen);
    /* The same seed gives the same split; another seed another one. */
    assert_int_equal(bf_tradeoff_split(s, 0.2, 7, &train2, &test2, &err), BF_OK);
    assert_memory_equal(test->theta_i, test2->theta_i, test->n * sizeof(double));
    bf_samples_free(train2);
    bf_samples_free(test2);
    assert_int_equal(bf_tradeoff_split(s, 0.2, 8, &train2, &test2, &err), BF_OK);
    assert_int_equal(test2->n, 200);
    assert_true(memcmp(test->theta_i, test2->theta_i, test->n * sizeof(double)) != 0);
    bf_samples_free(train2);
    bf_samples_free(test2);
    bf_samples_free(train);
    bf_samples_free(test);
    /* Bad fractions. */
    assert_int_equal(bf_tradeoff_split(s, 0.0, 7, &train, &test, &err), BF_ERR_ARG);
    assert_int_equal(bf_tradeoff_split(s, 1.0, 7, &train, &test, &err), BF_ERR_ARG);
    assert_null(train);
    bf_samples_free(s);
}

/* Rows with hand-made costs (work = seconds x 1e6, until a test sets them apart) and
 * test errors (rmse_log). */
static void set_row(bf_tradeoff_row *r, double seconds, double e, double rmse)
{
    r->ran = r->ok = 1;
    r->seconds = seconds;
    r->work = seconds * 1e6;
    r->test.rmse_log = e;
    r->test.rmse = rmse;
}

static void test_rank_front_and_recommendation(void **state)
{
    (void)state;
    bf_tradeoff t;
    bf_tradeoff_grid g;
    bf_error err;
    const size_t counts[] = {100, 200, 300, 400, 500, 0};
    const bf_residual res[] = {BF_RESIDUAL_LOG};
    const int starts[] = {1};
    assert_int_equal(bf_tradeoff_init(&t, "d", "walter", 1000, GRID(g, counts, methods1, res, starts), &err), BF_OK);
    assert_int_equal(t.nrows, 6);
    t.tolerance = 0.05;
    set_row(&t.rows[0], 0.10, 0.200, 1.0); /* fastest, poor: front */
    set_row(&t.rows[1], 0.50, 0.104, 9.0); /* within 5% of 0.100, and the fastest such */
    set_row(&t.rows[2], 0.40, 0.300, 1.0); /* dominated by row 0 */
    set_row(&t.rows[3], 2.00, 0.100, 1.0); /* best */
    set_row(&t.rows[4], 3.00, 0.100, 1.0); /* as good but slower: not on the front */
    set_row(&t.rows[5], 0.01, 0.001, 1.0);
    t.rows[5].ok = 0; /* failed: never ranked */
    bf_tradeoff_rank(&t);
    assert_int_equal(t.best, 3);
    assert_int_equal(t.recommended, 1);
    const int front[] = {1, 1, 0, 1, 0, 0}, tol[] = {0, 1, 0, 1, 1, 0};
    for (int i = 0; i < 6; i++) {
        assert_int_equal(t.rows[i].on_front, front[i]);
        assert_int_equal(t.rows[i].within_tolerance, tol[i]);
    }
    assert_true(isnan(t.rows[5].error));
    /* The recommended row is within tolerance and no row within it is cheaper. */
    for (int i = 0; i < 6; i++)
        if (t.rows[i].within_tolerance)
            assert_true(t.rows[i].work >= t.rows[t.recommended].work);
    /* Wall time decides nothing unless asked: row 1 measured slow changes no choice by
     * work, and the choice by seconds goes to row 3 (2 s against 5 and 3). */
    t.rows[1].seconds = 5.0;
    bf_tradeoff_rank(&t);
    assert_int_equal(t.recommended, 1);
    assert_int_equal(t.rows[1].on_front, 1);
    t.cost = BF_TRADEOFF_COST_SECONDS;
    bf_tradeoff_rank(&t);
    assert_int_equal(t.recommended, 3);
    assert_int_equal(t.rows[1].on_front, 0);
    assert_string_equal(bf_tradeoff_cost_name(t.cost), "seconds");
    t.cost = BF_TRADEOFF_COST_WORK;
    t.rows[1].seconds = 0.5;
    /* Zero tolerance: the best itself. Another metric: another ranking. */
    t.tolerance = 0.0;
    bf_tradeoff_rank(&t);
    assert_int_equal(t.recommended, 3);
    t.metric = BF_CMP_RMSE;
    t.tolerance = 0.05;
    bf_tradeoff_rank(&t);
    assert_int_equal(t.best, 0); /* rmse 1.0 ties rows 0, 2, 3, 4: the fastest is best */
    assert_int_equal(t.recommended, 0);
    bf_tradeoff_clear(&t);
}

static void test_same_seed_same_errors(void **state)
{
    (void)state;
    bf_error err;
    bf_samples *s = synthetic(1500), *train, *test;
    assert_int_equal(bf_tradeoff_split(s, 0.25, 3, &train, &test, &err), BF_OK);
    const size_t counts[] = {300, 0};
    const bf_residual res[] = {BF_RESIDUAL_LOG};
    const int starts[] = {1, 2};
    bf_tradeoff t[2];
    bf_tradeoff_grid g;
    bf_options *fo = ts_options(BF_TASK_FIT, "--residual log --threads 1 --starts 1");
    for (int k = 0; k < 2; k++) {
        assert_int_equal(
            bf_tradeoff_init(&t[k], "synthetic", "walter", train->n, GRID(g, counts, methods2, res, starts), &err),
            BF_OK);
        t[k].seed = 11;
        t[k].repeats = 2;
        for (int i = 0; i < t[k].nrows; i++) {
            assert_int_equal(bf_tradeoff_run_row(&t[k], i, train, test, fo, &err), BF_OK);
            const bf_tradeoff_row *r = &t[k].rows[i];
            assert_true(r->ran && r->ok);
            assert_int_equal(r->train.n, r->all ? train->n : 300);
            assert_int_equal(r->test.n, test->n);
            assert_true(r->seconds >= 0.0);
        }
        bf_tradeoff_rank(&t[k]);
    }
    assert_int_equal(t[0].nrows, 8);
    for (int i = 0; i < t[0].nrows; i++) {
        assert_true(t[0].rows[i].test.rmse_log == t[1].rows[i].test.rmse_log);
        assert_true(t[0].rows[i].train.rmse == t[1].rows[i].train.rmse);
        /* noiseless data of the model itself: the fit finds it */
        assert_true(t[0].rows[i].test.rmse_log < 1e-4);
    }
    assert_true(t[0].best >= 0 && t[0].recommended >= 0);
    bf_tradeoff_clear(&t[0]);
    bf_tradeoff_clear(&t[1]);
    bf_options_free(fo);
    bf_samples_free(train);
    bf_samples_free(test);
    bf_samples_free(s);
}

static void test_methods(void **state)
{
    (void)state;
    bf_error err;
    bf_solver_options so;
    bf_solver_options_init(&so);
    assert_int_equal(bf_tradeoff_method_apply("LD_LBFGS", &so, &err), BF_OK);
    assert_int_equal(so.backend, BF_BACKEND_NLOPT);
    assert_string_equal(so.algorithm, "LD_LBFGS");
    assert_int_equal(bf_tradeoff_method_apply("ceres:dogleg", &so, &err), BF_OK);
    assert_int_equal(so.backend, BF_BACKEND_CERES);
    assert_string_equal(so.algorithm, "dogleg");
    assert_int_equal(bf_tradeoff_method_apply("ceres", &so, &err), BF_OK);
    assert_string_equal(so.algorithm, "lm");
    assert_int_equal(bf_tradeoff_method_apply("LN_BOBYQA", &so, &err), BF_OK);
    assert_int_equal(so.backend, BF_BACKEND_NLOPT);
    assert_int_equal(bf_tradeoff_method_apply("LD_NOPE", &so, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "LD_NOPE"));
    assert_string_equal(so.algorithm, "LN_BOBYQA"); /* unchanged on error */
    assert_int_equal(bf_tradeoff_method_apply("", &so, &err), BF_ERR_ARG);
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *b = malloc((size_t)n + 1);
    assert_int_equal(fread(b, 1, (size_t)n, f), (size_t)n);
    b[n] = '\0';
    fclose(f);
    return b;
}

static void test_json_and_csv(void **state)
{
    (void)state;
    bf_tradeoff t;
    bf_tradeoff_grid g;
    bf_error err;
    const size_t counts[] = {100, 0};
    const bf_residual res[] = {BF_RESIDUAL_LOG};
    const int starts[] = {1};
    const char *const methods[] = {"ceres", "odd,\"name\""};
    assert_int_equal(bf_tradeoff_init(&t, "d.csv", "walter", 1000, GRID(g, counts, methods, res, starts), &err), BF_OK);
    set_row(&t.rows[0], 0.1, 0.2, 1.0);
    set_row(&t.rows[1], 0.2, 0.1, 1.0);
    set_row(&t.rows[2], 0.3, 0.1, 1.0);
    snprintf(t.rows[3].message, sizeof t.rows[3].message, "could not run");
    bf_tradeoff_rank(&t);

    char path[] = "/tmp/test_tradeoff_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    close(fd);
    assert_int_equal(bf_tradeoff_write_json(&t, path, &err), BF_OK);
    char *text = slurp(path);
    cJSON *root = cJSON_Parse(text);
    assert_non_null(root);
    const char *top[] = {"version",  "data",          "model",  "samples", "train_samples", "test_samples",
                         "channels", "test_fraction", "seed",   "repeats", "error",         "tolerance",
                         "cost",     "work",          "timing", "best",    "recommended",   "rows"};
    for (size_t k = 0; k < sizeof top / sizeof top[0]; k++)
        assert_non_null(cJSON_GetObjectItemCaseSensitive(root, top[k]));
    assert_int_equal(cJSON_GetObjectItem(root, "recommended")->valueint, 1);
    cJSON *rows = cJSON_GetObjectItem(root, "rows");
    assert_int_equal(cJSON_GetArraySize(rows), 4);
    const char *keys[] = {"index",    "samples",          "all",  "method",      "residual", "starts", "status",
                          "ok",       "message",          "work", "iterations",  "error",    "train",  "test",
                          "on_front", "within_tolerance", "best", "recommended", "warnings"};
    for (int i = 0; i < 4; i++) {
        cJSON *r = cJSON_GetArrayItem(rows, i);
        for (size_t k = 0; k < sizeof keys / sizeof keys[0]; k++)
            assert_non_null(cJSON_GetObjectItemCaseSensitive(r, keys[k]));
    }
    assert_null(strstr(text, "seconds")); /* no wall time unless asked */
    cJSON *r3 = cJSON_GetArrayItem(rows, 3);
    assert_string_equal(cJSON_GetObjectItem(r3, "status")->valuestring, "error");
    assert_true(cJSON_IsNull(cJSON_GetObjectItem(r3, "test")));
    assert_true(cJSON_IsTrue(cJSON_GetObjectItem(cJSON_GetArrayItem(rows, 1), "recommended")));
    cJSON *test1 = cJSON_GetObjectItem(cJSON_GetArrayItem(rows, 1), "test");
    assert_true(fabs(cJSON_GetObjectItem(test1, "rmse_log")->valuedouble - 0.1) < 1e-15);
    cJSON_Delete(root);
    free(text);

    assert_int_equal(bf_tradeoff_write_csv(&t, path, &err), BF_OK);
    text = slurp(path);
    int lines = 0;
    for (char *p = text; *p; p++)
        lines += *p == '\n';
    assert_int_equal(lines, 1 + 4);
    assert_true(!strncmp(text, "samples,all,method,residual,starts,status,work", 46));
    assert_null(strstr(text, "seconds"));
    assert_non_null(strstr(text, "\n100,0,ceres,log,1,ok,100000,"));
    assert_non_null(strstr(text, "\n100,0,\"odd,\"\"name\"\"\",log,1,ok,200000,"));
    assert_non_null(strstr(text, "\n1000,1,\"odd,\"\"name\"\"\",log,1,error,,"));
    free(text);
    /* with timing: a seconds column last, and the warnings before it, one field */
    t.timing = 1;
    t.rows[0].nwarnings = 2;
    t.rows[0].warnings = calloc(2, sizeof *t.rows[0].warnings);
    assert_non_null(t.rows[0].warnings);
    strcpy(t.rows[0].warnings[0], "alpha = 1 is at its upper bound 1");
    strcpy(t.rows[0].warnings[1], "f0, \"x\"");
    assert_int_equal(bf_tradeoff_write_csv(&t, path, &err), BF_OK);
    text = slurp(path);
    assert_non_null(strstr(text, ",recommended,warnings,seconds\n"));
    assert_non_null(strstr(text, ",\"alpha = 1 is at its upper bound 1; f0, \"\"x\"\"\",0.1\n"));
    free(text);
    assert_int_equal(bf_tradeoff_write_json(&t, path, &err), BF_OK);
    text = slurp(path);
    root = cJSON_Parse(text);
    cJSON *w0 = cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(root, "rows"), 0), "warnings");
    assert_int_equal(cJSON_GetArraySize(w0), 2);
    assert_string_equal(cJSON_GetArrayItem(w0, 1)->valuestring, "f0, \"x\"");
    assert_true(
        cJSON_IsNumber(cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(root, "rows"), 0), "seconds")));
    cJSON_Delete(root);
    free(text);
    unlink(path);
    bf_tradeoff_clear(&t);
}

/* ---- The options and the whole measurement ------------------------------------------ */

static void value(const bf_options *o, const char *name, const char *want)
{
    char v[256];
    bf_error err;
    if (bf_options_get(o, name, v, sizeof v, &err) != BF_OK)
        fail_msg("%s: %s", name, err.msg);
    assert_string_equal(v, want);
}

/* The lists' defaults follow the base setting; the other values are the table's or as
 * given (a count may end in k). */
static void test_options_defaults(void **state)
{
    (void)state;
    bf_options *o = ts_options(BF_TASK_TRADEOFF, NULL);
    value(o, "samples", "1000,4000,16000,64000,all");
    value(o, "methods", "ceres,LD_LBFGS");
    value(o, "residuals", "log");
    value(o, "starts_list", "auto");
    value(o, "test_fraction", "0.2");
    value(o, "cost", "work");
    value(o, "repeats", "1");
    value(o, "error", "rmse_log");
    char v[64];
    assert_int_equal(bf_options_get(o, "tolerance", v, sizeof v, NULL), BF_OK);
    assert_true(strtod(v, NULL) == 0.05);
    value(o, "plot_size", "640x400");
    value(o, "timing", "false");
    assert_int_equal(bf_options_check(o, NULL), BF_OK);
    bf_options_free(o);

    o = ts_options(BF_TASK_TRADEOFF, "--backend nlopt --algorithm LN_BOBYQA --residual linear --starts 3 --repeats 1k");
    value(o, "methods", "LN_BOBYQA");
    value(o, "residuals", "linear");
    value(o, "starts_list", "3");
    value(o, "repeats", "1k");
    bf_options_free(o);
    o = ts_options(BF_TASK_TRADEOFF, "--algorithm dogleg --methods ceres,LN_SBPLX --starts-list 1,auto");
    value(o, "methods", "ceres,LN_SBPLX");
    value(o, "starts_list", "1,auto");
    assert_int_equal(bf_options_reset(o, "methods", NULL), BF_OK);
    value(o, "methods", "ceres:dogleg");
    bf_options_free(o);
    /* Only a tradeoff takes them; a tradeoff takes no --accuracy. */
    assert_null(bf_option_find("samples", BF_TASK_FIT));
    assert_null(bf_option_find("accuracy", BF_TASK_TRADEOFF));
    assert_non_null(bf_option_find("max_theta", BF_TASK_TRADEOFF));
    assert_non_null(bf_option_find("starts", BF_TASK_TRADEOFF));
}

/* Set is refused with the command line's message when the value alone is wrong; set but
 * refused by bf_options_check when the lists are (their defaults and methods depend on
 * the other options). Messages name the option as the set spells it. */
static void refused_when_set(bf_option_spelling spelling, const char *name, const char *v, const char *msg)
{
    bf_options *o = ts_options(BF_TASK_TRADEOFF, NULL);
    bf_error err;
    bf_options_set_spelling(o, spelling);
    assert_int_equal(bf_options_set(o, name, v, &err), BF_ERR_ARG);
    assert_string_equal(err.msg, msg);
    bf_options_free(o);
}

static void refused_by_check(bf_option_spelling spelling, const char *words, const char *msg)
{
    bf_options *o = ts_options(BF_TASK_TRADEOFF, words);
    bf_error err;
    bf_options_set_spelling(o, spelling);
    if (bf_options_check(o, &err) != BF_ERR_ARG)
        fail_msg("%s: taken", words);
    assert_string_equal(err.msg, msg);
    bf_options_free(o);
}

static void test_options_refused(void **state)
{
    (void)state;
    const bf_option_spelling cl = BF_SPELL_COMMAND_LINE, kw = BF_SPELL_KEYWORD;
    refused_when_set(cl, "test_fraction", "1", "--test-fraction needs a number between 0 and 1 (exclusive), got '1'");
    refused_when_set(kw, "test_fraction", "0", "test_fraction needs a number between 0 and 1 (exclusive), got '0'");
    refused_when_set(cl, "repeats", "2k", "--repeats needs an integer from 1 to 1000, got '2k'");
    refused_when_set(kw, "repeats", "0", "repeats needs an integer from 1 to 1000, got '0'");
    refused_when_set(cl, "cost", "time", "--cost needs work or seconds, got 'time'");
    refused_when_set(cl, "plot_size", "10x10", "--plot-size needs WxH, each 40 to 8192, got '10x10'");
    refused_when_set(kw, "plot_size", "400", "plot_size needs WxH, each 40 to 8192, got '400'");
    refused_when_set(cl, "tolerance", "-1", "--tolerance needs a number >= 0 (relative, 0.05 = 5%), got '-1'");
    refused_when_set(kw, "error", "mse", "error: unknown error metric 'mse' (rmse, rmse_log, rmse_cos, rmse_rel)");
    refused_by_check(cl, "--samples 500,lots", "--samples: 'lots' is not a positive count or 'all'");
    refused_by_check(kw, "--samples 0", "samples: '0' is not a positive count or 'all'");
    refused_by_check(kw, "--samples 500,,all", "samples: empty item in the list");
    refused_by_check(cl, "--starts-list 1,x", "--starts-list: 'x' is not a positive integer or auto");
    refused_by_check(kw, "--starts-list 100001", "starts_list: '100001' is not a positive integer or auto");
    refused_by_check(kw, "--residuals log,square",
                     "residuals: unknown residual form 'square' (linear, cosine, log, cbrt, relative)");
    /* A list's form is checked before any list's items. */
    refused_by_check(cl, "--samples lots --starts-list 1,", "--starts-list: empty item in the list");
    /* A method against the base's other settings. */
    refused_by_check(cl, "--backend nlopt --algorithm LD_SLSQP --constrain-energy --methods LD_SLSQP,LN_BOBYQA",
                     "--methods: method \"LN_BOBYQA\": nlopt method LN_BOBYQA does not take constraints (those that "
                     "do: LD_SLSQP, LD_MMA, LN_COBYLA, GN_ISRES)");
    char many[512] = "--samples ";
    for (int k = 1; k <= 65; k++)
        snprintf(many + strlen(many), sizeof many - strlen(many), "%s%d", k > 1 ? "," : "", k);
    refused_by_check(kw, many, "samples: more than 64 items");
    /* 20 counts x 2 methods x 64 residuals x 64 starts: the product, before the counts
     * merge. */
    char big[1024] = "--samples 1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20 --residuals ";
    for (int k = 0; k < 64; k++)
        snprintf(big + strlen(big), sizeof big - strlen(big), "%s%s", k ? "," : "", k % 2 ? "log" : "linear");
    snprintf(big + strlen(big), sizeof big - strlen(big), " --starts-list ");
    for (int k = 1; k <= 64; k++)
        snprintf(big + strlen(big), sizeof big - strlen(big), "%s%d", k > 1 ? "," : "", k);
    refused_by_check(cl, big, "163840 settings is too many (at most 100000): shorten the lists");
}

/* noise_level relative noise on lambert (rho 0.5, one channel) at n uniform directions. */
static bf_samples *lambert_data(size_t n, double noise_level)
{
    bf_error err;
    bf_model *m = ts_model("lambert", 1);
    const double rho[] = {0.5};
    bf_synth_options so;
    memset(&so, 0, sizeof so);
    so.pattern = BF_SYNTH_UNIFORM;
    so.count = n;
    so.seed = 5;
    so.noise.model = BF_NOISE_RELATIVE;
    so.noise.level = noise_level;
    bf_samples *s = NULL;
    if (bf_synth_generate(m, rho, &so, &s, &err) != BF_OK)
        fail_msg("%s", err.msg);
    bf_model_free(m);
    return s;
}

static int progress_calls;
static void count_progress(void *user, const bf_tradeoff *t, int i)
{
    assert_ptr_equal(user, &progress_calls);
    assert_int_equal(i, progress_calls); /* in order, each once */
    assert_true(t->rows[i].ran);
    progress_calls++;
}

/* bf_tradeoff_run is the parts in their order: the same split, grid, rows and ranking. */
static void test_run_is_the_parts(void **state)
{
    (void)state;
    bf_error err;
    bf_samples *data = lambert_data(1000, 0.01);
    bf_options *o = ts_options(BF_TASK_TRADEOFF, "--samples 200,all,5000 --starts-list 1 --threads 1 --seed 3 "
                                                 "--test-fraction 0.25 --tolerance 0.1");
    bf_tradeoff *t = NULL;
    progress_calls = 0;
    assert_int_equal(bf_tradeoff_run(data, "synth.csv", "lambert", o, count_progress, &progress_calls, &t, &err),
                     BF_OK);
    assert_int_equal(progress_calls, 4);
    assert_string_equal(t->data, "synth.csv");
    assert_string_equal(t->model, "lambert");
    assert_int_equal(t->total, 1000);
    assert_int_equal(t->train_n, 750);
    assert_int_equal(t->test_n, 250);
    assert_int_equal(t->channels, 1);
    assert_true(t->test_fraction == 0.25 && t->tolerance == 0.1);
    assert_int_equal(t->seed, 3);
    assert_int_equal(t->repeats, 1);
    assert_int_equal(t->cost, BF_TRADEOFF_COST_WORK);
    assert_int_equal(t->timing, 0);
    assert_int_equal(t->plot_width, 640);
    assert_int_equal(t->plot_height, 400);
    /* The held-out error of the truth (rho 0.5), which a fit to the rest can only near. */
    bf_samples *train, *test;
    assert_int_equal(bf_tradeoff_split(data, 0.25, 3, &train, &test, &err), BF_OK);
    bf_model *truth = ts_model("lambert", 1);
    const double rho[] = {0.5};
    bf_metrics tm;
    assert_int_equal(bf_metrics_compute(truth, rho, test, 1, 1, &tm, &err), BF_OK);
    bf_model_free(truth);
    assert_true(tm.rmse_log > 1e-4); /* the noise is there */
    /* 200 and all (5000 is all) x ceres, LD_LBFGS x log x 1 start. */
    assert_int_equal(t->nrows, 4);
    const char *const methods[] = {"ceres", "LD_LBFGS", "ceres", "LD_LBFGS"};
    for (int i = 0; i < 4; i++) {
        const bf_tradeoff_row *r = &t->rows[i];
        assert_int_equal(r->all, i >= 2);
        assert_int_equal(r->samples, i < 2 ? 200 : 750);
        assert_string_equal(r->method, methods[i]);
        assert_int_equal(r->starts, 1);
        assert_true(r->ran && r->ok);
        assert_int_equal(r->train.n, r->samples);
        assert_int_equal(r->test.n, 250);
        /* 1% relative noise: the log error of the fitted constant is about 0.01 */
        assert_true(r->test.rmse_log > 0.98 * tm.rmse_log && r->test.rmse_log < 1.05 * tm.rmse_log);
        assert_true(r->error == r->test.rmse_log);
    }
    /* Lambert from 200 samples is as good as from 750: the cheapest row is recommended. */
    assert_true(t->best >= 0);
    assert_int_equal(t->recommended, 0);

    /* The parts: split, grid, rows, rank, with the same options. */
    const size_t counts[] = {200, 0, 5000};
    const bf_residual res[] = {BF_RESIDUAL_LOG};
    const int starts[] = {1};
    bf_tradeoff *p = NULL;
    bf_tradeoff_grid g;
    assert_int_equal(
        bf_tradeoff_new_grid("synth.csv", "lambert", train->n, GRID(g, counts, methods2, res, starts), &p, &err),
        BF_OK);
    p->seed = 3;
    p->tolerance = 0.1;
    for (int i = 0; i < p->nrows; i++)
        assert_int_equal(bf_tradeoff_run_row(p, i, train, test, o, &err), BF_OK);
    bf_tradeoff_rank(p);
    assert_int_equal(p->nrows, t->nrows);
    assert_int_equal(p->best, t->best);
    assert_int_equal(p->recommended, t->recommended);
    for (int i = 0; i < p->nrows; i++) {
        assert_true(p->rows[i].test.rmse_log == t->rows[i].test.rmse_log);
        assert_true(p->rows[i].train.rmse == t->rows[i].train.rmse);
        assert_true(p->rows[i].work == t->rows[i].work);
        assert_int_equal(p->rows[i].on_front, t->rows[i].on_front);
    }
    /* The deprecated positional form makes the same grid, for programs written against it. */
    bf_tradeoff *q = NULL;
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#endif
    assert_int_equal(
        bf_tradeoff_new("synth.csv", "lambert", train->n, 3, counts, 2, methods2, 1, res, 1, starts, &q, &err), BF_OK);
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif
    assert_int_equal(q->nrows, p->nrows);
    for (int i = 0; i < q->nrows; i++) {
        assert_int_equal(q->rows[i].samples, p->rows[i].samples);
        assert_string_equal(q->rows[i].method, p->rows[i].method);
        assert_int_equal(q->rows[i].residual, p->rows[i].residual);
        assert_int_equal(q->rows[i].starts, p->rows[i].starts);
    }
    bf_tradeoff_free(q);

    /* The JSON in memory is the file's text. */
    char *text = NULL;
    assert_int_equal(bf_tradeoff_json(t, &text, &err), BF_OK);
    char path[] = "/tmp/test_tradeoff_run_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    close(fd);
    assert_int_equal(bf_tradeoff_write_json(t, path, &err), BF_OK);
    char *file = slurp(path);
    assert_string_equal(text, file);
    assert_non_null(strstr(text, "\"test_fraction\":\t0.25,"));
    free(file);
    bf_free(text);
    unlink(path);

    /* The recommendation as brdfit fit's command line: the base options as set, then
     * the row's. */
    char *command = NULL;
    assert_int_equal(bf_tradeoff_fit_command(t, t->recommended, &command, &err), BF_OK);
    assert_string_equal(command, "brdfit fit synth.csv --threads 1 --seed 3 -m lambert --subsample 200 --backend ceres "
                                 "--residual log --starts 1");
    bf_free(command);
    assert_int_equal(bf_tradeoff_fit_command(t, 3, &command, &err), BF_OK);
    assert_string_equal(command, "brdfit fit synth.csv --threads 1 --seed 3 -m lambert --backend nlopt --algorithm "
                                 "LD_LBFGS --residual log --starts 1");
    bf_free(command);
    assert_int_equal(bf_tradeoff_fit_command(t, 4, &command, &err), BF_ERR_ARG);
    assert_null(command);
    /* A table of the parts has no base options. */
    assert_int_equal(bf_tradeoff_fit_command(p, 2, &command, &err), BF_OK);
    assert_string_equal(command, "brdfit fit synth.csv -m lambert --backend ceres --residual log --starts 1");
    bf_free(command);

    bf_tradeoff_free(p);
    bf_tradeoff_free(t);
    bf_samples_free(train);
    bf_samples_free(test);
    bf_options_free(o);
    bf_samples_free(data);
}

/* The base options repeated in the command: quoted for a shell, flags by name, the
 * tradeoff's own and the row's left out; seconds as the cost imply timing; repeats. */
static void test_run_options_carried(void **state)
{
    (void)state;
    bf_error err;
    bf_samples *data = lambert_data(300, 0.01);
    bf_options *o = ts_options(BF_TASK_TRADEOFF, "--samples all --methods ceres --residual linear --starts 2 "
                                                 "--threads 1 --cost seconds --repeats 2 --plot-size 320x200");
    assert_int_equal(bf_options_set(o, "fix", "rho_d=0.5", &err), BF_OK);
    assert_int_equal(bf_options_set(o, "no_weights", "true", &err), BF_OK);
    assert_int_equal(bf_options_set(o, "solid_angle", "false", &err), BF_OK);
    assert_int_equal(bf_options_set(o, "channels", "it's 0", &err), BF_OK);
    assert_int_equal(bf_options_reset(o, "channels", &err), BF_OK); /* gone from the command too */
    assert_int_equal(bf_options_set(o, "weight", "my weight", &err), BF_OK);
    bf_tradeoff *t = NULL;
    assert_int_equal(bf_tradeoff_run(data, NULL, "lambert", o, NULL, NULL, &t, &err), BF_OK);
    assert_string_equal(t->data, "");
    assert_int_equal(t->nrows, 1);
    assert_int_equal(t->rows[0].residual, BF_RESIDUAL_LINEAR);
    assert_int_equal(t->rows[0].starts, 2);
    assert_int_equal(t->cost, BF_TRADEOFF_COST_SECONDS);
    assert_int_equal(t->timing, 1);
    assert_int_equal(t->repeats, 2);
    assert_int_equal(t->plot_width, 320);
    assert_int_equal(t->plot_height, 200);
    assert_true(t->rows[0].ok && t->rows[0].seconds >= 0.0);
    char *command = NULL;
    assert_int_equal(bf_tradeoff_fit_command(t, 0, &command, &err), BF_OK);
    assert_string_equal(command, "brdfit fit  --threads 1 --fix rho_d=0.5 --no-weights --weight 'my weight' -m "
                                 "lambert --backend ceres --residual linear --starts 2");
    bf_free(command);
    bf_tradeoff_free(t);
    assert_int_equal(bf_options_set(o, "weight", "it's", &err), BF_OK);
    assert_int_equal(bf_tradeoff_run(data, "d.csv", "lambert", o, NULL, NULL, &t, &err), BF_OK);
    assert_int_equal(bf_tradeoff_fit_command(t, 0, &command, &err), BF_OK);
    assert_non_null(strstr(command, " --weight 'my weight' --weight 'it'\\''s' -m lambert"));
    bf_free(command);
    bf_tradeoff_free(t);
    bf_options_free(o);
    bf_samples_free(data);
}

static void test_run_refuses(void **state)
{
    (void)state;
    bf_error err;
    bf_samples *data = lambert_data(300, 0.0), *one = lambert_data(1, 0.0);
    bf_tradeoff *t = (bf_tradeoff *)&err; /* set to NULL on failure */
    bf_options *o = ts_options(BF_TASK_TRADEOFF, "--samples 0");
    bf_options_set_spelling(o, BF_SPELL_KEYWORD);
    assert_int_equal(bf_tradeoff_run(data, "d.csv", "lambert", o, NULL, NULL, &t, &err), BF_ERR_ARG);
    assert_null(t);
    assert_string_equal(err.msg, "samples: '0' is not a positive count or 'all'");
    bf_options_free(o);
    o = ts_options(BF_TASK_TRADEOFF, "--fix nosuch=1");
    assert_int_equal(bf_tradeoff_run(data, "d.csv", "lambert", o, NULL, NULL, &t, &err), BF_ERR_ARG);
    assert_string_equal(err.msg, "fix nosuch: model lambert has no parameter 'nosuch'");
    assert_int_equal(bf_tradeoff_run(data, "d.csv", "nosuch", o, NULL, NULL, &t, &err), BF_ERR_ARG);
    bf_options_free(o);
    o = ts_options(BF_TASK_TRADEOFF, NULL);
    assert_int_equal(bf_tradeoff_run(one, "one.csv", "lambert", o, NULL, NULL, &t, &err), BF_ERR_ARG);
    assert_string_equal(err.msg, "one.csv: 1 sample: too few to hold any out for testing");
    assert_null(t);
    bf_options_free(o);
    /* Options for another task. */
    o = ts_options(BF_TASK_FIT, NULL);
    assert_int_equal(bf_tradeoff_run(data, "d.csv", "lambert", o, NULL, NULL, &t, &err), BF_ERR_ARG);
    bf_options_free(o);
    /* Cancelled before it starts: a table whose rows did not run, nothing recommended. */
    o = ts_options(BF_TASK_TRADEOFF, "--samples 100,all --threads 1");
    bf_cancel_flag cancel = 1;
    bf_options_set_cancel(o, &cancel, NULL);
    assert_int_equal(bf_tradeoff_run(data, "d.csv", "lambert", o, NULL, NULL, &t, &err), BF_OK);
    assert_int_equal(t->nrows, 4);
    for (int i = 0; i < t->nrows; i++)
        assert_false(t->rows[i].ran);
    assert_int_equal(t->recommended, -1);
    bf_tradeoff_free(t);
    bf_options_free(o);
    bf_samples_free(data);
    bf_samples_free(one);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_grid_size_and_order),
        cmocka_unit_test(test_split_disjoint),
        cmocka_unit_test(test_rank_front_and_recommendation),
        cmocka_unit_test(test_same_seed_same_errors),
        cmocka_unit_test(test_methods),
        cmocka_unit_test(test_json_and_csv),
        cmocka_unit_test(test_options_defaults),
        cmocka_unit_test(test_options_refused),
        cmocka_unit_test(test_run_is_the_parts),
        cmocka_unit_test(test_run_options_carried),
        cmocka_unit_test(test_run_refuses),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
