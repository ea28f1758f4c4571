/* The tradeoff table: grid size and order (ascending, deduplicated sample counts, one
 * "all" row), a disjoint seeded train/test split of the right sizes, reproducible errors
 * for one seed, the Pareto front and the recommendation on hand-made timings, method
 * names, and the JSON and CSV outputs. */
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
#include "tradeoff/tradeoff_impl.h"

static const char *const methods2[] = {"ceres", "LD_LBFGS"};

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
    bf_error err;
    const size_t counts[] = {4000, 500, 0, 2000, 500, 99999};
    const bf_residual res[] = {BF_RESIDUAL_LOG, BF_RESIDUAL_LINEAR};
    const int starts[] = {1, 4, 2};
    assert_int_equal(bf_tradeoff_init(&t, "d.csv", "walter", 3000, 6, counts, 2, methods2, 2, res, 3, starts, &err),
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
    assert_int_equal(bf_tradeoff_init(&t, "d", "walter", 1000, 2, big, 1, methods2, 1, res, 1, starts, &err), BF_OK);
    assert_int_equal(t.nrows, 1);
    assert_int_equal(t.rows[0].all, 1);
    assert_int_equal(t.rows[0].samples, 1000);
    bf_tradeoff_clear(&t);

    /* Empty lists and negative starts are refused; 0 is brdfit fit's automatic count. */
    assert_int_equal(bf_tradeoff_init(&t, "d", "walter", 1000, 0, big, 1, methods2, 1, res, 1, starts, &err),
                     BF_ERR_ARG);
    const int negative[] = {-1}, automatic[] = {0};
    assert_int_equal(bf_tradeoff_init(&t, "d", "walter", 1000, 1, big, 1, methods2, 1, res, 1, negative, &err),
                     BF_ERR_ARG);
    assert_int_equal(bf_tradeoff_init(&t, "d", "walter", 1000, 1, big, 1, methods2, 1, res, 1, automatic, &err), BF_OK);
    assert_int_equal(t.rows[0].starts, 0);
    bf_tradeoff_clear(&t);
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
    bf_error err;
    const size_t counts[] = {100, 200, 300, 400, 500, 0};
    const bf_residual res[] = {BF_RESIDUAL_LOG};
    const int starts[] = {1};
    assert_int_equal(bf_tradeoff_init(&t, "d", "walter", 1000, 6, counts, 1, methods2, 1, res, 1, starts, &err),
                     BF_OK);
    assert_int_equal(t.nrows, 6);
    t.tolerance = 0.05;
    set_row(&t.rows[0], 0.10, 0.200, 1.0); /* fastest, poor: front */
    set_row(&t.rows[1], 0.50, 0.104, 9.0); /* within 5% of 0.100, and the fastest such */
    set_row(&t.rows[2], 0.40, 0.300, 1.0); /* dominated by row 0 */
    set_row(&t.rows[3], 2.00, 0.100, 1.0); /* best */
    set_row(&t.rows[4], 3.00, 0.100, 1.0); /* as good but slower: not on the front */
    set_row(&t.rows[5], 0.01, 0.001, 1.0);
    t.rows[5].ok = 0;                      /* failed: never ranked */
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
    bf_options *fo = ts_options(BF_TASK_FIT, "--residual log --threads 1 --starts 1");
    for (int k = 0; k < 2; k++) {
        assert_int_equal(
            bf_tradeoff_init(&t[k], "synthetic", "walter", train->n, 2, counts, 2, methods2, 1, res, 2, starts, &err),
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
    bf_error err;
    const size_t counts[] = {100, 0};
    const bf_residual res[] = {BF_RESIDUAL_LOG};
    const int starts[] = {1};
    const char *const methods[] = {"ceres", "odd,\"name\""};
    assert_int_equal(bf_tradeoff_init(&t, "d.csv", "walter", 1000, 2, counts, 2, methods, 1, res, 1, starts, &err),
                     BF_OK);
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
    const char *top[] = {"version", "data", "model", "samples", "train_samples", "test_samples", "channels",
                         "test_fraction", "seed", "repeats", "error", "tolerance", "cost", "work", "timing",
                         "best", "recommended", "rows"};
    for (size_t k = 0; k < sizeof top / sizeof top[0]; k++)
        assert_non_null(cJSON_GetObjectItemCaseSensitive(root, top[k]));
    assert_int_equal(cJSON_GetObjectItem(root, "recommended")->valueint, 1);
    cJSON *rows = cJSON_GetObjectItem(root, "rows");
    assert_int_equal(cJSON_GetArraySize(rows), 4);
    const char *keys[] = {"index", "samples", "all", "method", "residual", "starts", "status", "ok", "message",
                          "work", "iterations", "error", "train", "test", "on_front", "within_tolerance",
                          "best", "recommended", "warnings"};
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
    assert_true(cJSON_IsNumber(cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(root, "rows"), 0), "seconds")));
    cJSON_Delete(root);
    free(text);
    unlink(path);
    bf_tradeoff_clear(&t);
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
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
