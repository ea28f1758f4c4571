/* Model comparison on hand-made fit results with known errors: BIC/AIC ranks with ties,
 * Pareto fronts with dominated and duplicate points, the simplest model within
 * tolerance, the summary across materials, and the JSON and CSV outputs. */
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

#include "brdfit/compare.h"
#include "compare/compare_impl.h"
#include "support.h"

/* A ranked-to-be fit: k parameters, rmse_log e, the given criteria (AICc = AIC here)
 * and fitting work. */
static void set_fit(bf_compare_fit *f, int k, double e, double aic, double bic, double work)
{
    memset(f, 0, sizeof *f);
    f->state = BF_CMP_OK;
    f->metrics.k = k;
    f->metrics.n = 100;
    f->metrics.rmse_log = e;
    f->metrics.rmse = 10 * e; /* a different metric, to see --error pick */
    f->metrics.aic = aic;
    f->metrics.aicc = aic;
    f->metrics.bic = bic;
    f->work = work;
    f->cv_error = NAN;
    f->seconds = 1.0 / (1.0 + work); /* wall time: must decide nothing */
}

static bf_compare make(int nmat, int nmod)
{
    const char *data[] = {"a.csv", "b,\"q\".csv", "c.csv"};
    const char *models[] = {"lambert", "phong", "walter", "microfacet:D=ggx,G=smith_ggx", "ward"};
    bf_compare c;
    bf_error err;
    assert_int_equal(bf_compare_init(&c, nmat, data, nmod, models, &err), BF_OK);
    return c;
}

static void test_ranks_and_ties(void **state)
{
    (void)state;
    bf_compare c = make(1, 5);
    bf_compare_fit *f = c.materials[0].fits;
    /* BIC: 30, 10, 20, 10, (failed); AIC: 5, 6, 5, 1 */
    set_fit(&f[0], 3, 0.30, 5, 30, 0.1);
    set_fit(&f[1], 4, 0.20, 6, 10, 0.2);
    set_fit(&f[2], 8, 0.10, 5, 20, 0.3);
    set_fit(&f[3], 9, 0.10, 1, 10, 0.4);
    set_fit(&f[4], 2, 0.01, -100, -100, 0.01);
    f[4].state = BF_CMP_FAILED; /* the best numbers, but a failed fit is not ranked */
    bf_compare_rank(&c);
    for (int j = 0; j < 5; j++)
        assert_int_equal(f[j].rank, f[j].rank_bic); /* BIC is the default */
    assert_int_equal(f[0].rank_cv, 0);              /* no cross-validation ran */
    assert_int_equal(f[0].rank_bic, 4);
    assert_int_equal(f[1].rank_bic, 1);
    assert_int_equal(f[2].rank_bic, 3);
    assert_int_equal(f[3].rank_bic, 1); /* tie with f[1]: both 1, next is 3 */
    assert_int_equal(f[4].rank_bic, 0);
    assert_int_equal(f[0].rank_aic, 2);
    assert_int_equal(f[1].rank_aic, 4);
    assert_int_equal(f[2].rank_aic, 2);
    assert_int_equal(f[3].rank_aic, 1);
    assert_int_equal(f[4].rank_aic, 0);
    assert_true(isnan(f[4].error));
    assert_int_equal(f[4].pareto_k, 0);
    /* best: first of the two at 0.10 (f[2]); within 5%: f[2], f[3]; simplest: k 8 */
    assert_int_equal(c.materials[0].best, 2);
    assert_int_equal(c.materials[0].simplest, 2);
    assert_int_equal(f[0].within_tolerance + f[1].within_tolerance, 0);
    assert_int_equal(f[2].within_tolerance + f[3].within_tolerance, 2);
    /* --error rmse gives the same order here (10x), so the same choice */
    c.metric = BF_CMP_RMSE;
    bf_compare_rank(&c);
    assert_int_equal(c.materials[0].simplest, 2);
    assert_true(fabs(f[2].error - 1.0) < 1e-15);
    /* ranked by AIC: the chosen rank follows it; by the error: ties at 0.10 share 1 */
    c.rank_by = BF_RANK_AIC;
    bf_compare_rank(&c);
    assert_int_equal(f[3].rank, 1);
    assert_int_equal(f[1].rank, 4);
    c.rank_by = BF_RANK_ERROR;
    bf_compare_rank(&c);
    assert_int_equal(f[2].rank, 1);
    assert_int_equal(f[3].rank, 1);
    assert_int_equal(f[1].rank, 3);
    assert_int_equal(f[0].rank, 4);
    bf_compare_clear(&c);
}

/* Ranked by cross-validation: cv_error orders the fits and is the error of the
 * tolerance; a fit without one is not ranked. */
static void test_rank_by_cv(void **state)
{
    (void)state;
    bf_compare c = make(1, 3);
    bf_compare_fit *f = c.materials[0].fits;
    set_fit(&f[0], 1, 0.30, 5, 5, 10);
    set_fit(&f[1], 4, 0.10, 1, 1, 20);
    set_fit(&f[2], 9, 0.05, 0, 0, 30);
    f[0].cv_error = 0.31;
    f[1].cv_error = 0.12;
    f[2].cv_error = 0.20; /* the best in-sample error, but it does not generalise */
    c.rank_by = BF_RANK_CV;
    bf_compare_rank(&c);
    assert_int_equal(f[1].rank, 1);
    assert_int_equal(f[2].rank, 2);
    assert_int_equal(f[0].rank, 3);
    assert_int_equal(f[1].rank_cv, 1);
    assert_int_equal(c.materials[0].best, 1);
    assert_int_equal(c.materials[0].simplest, 1);
    assert_true(fabs(f[2].error - 0.20) < 1e-15);
    f[1].cv_error = NAN;
    bf_compare_rank(&c);
    assert_int_equal(f[1].rank, 0);
    assert_int_equal(c.materials[0].best, 2);
    bf_error err;
    bf_compare_rank_by by;
    const char *names[] = {"bic", "aic", "aicc", "cv", "error"};
    for (int i = 0; i < 5; i++) {
        assert_int_equal(bf_compare_rank_parse(names[i], &by, &err), BF_OK);
        assert_string_equal(bf_compare_rank_name(by), names[i]);
    }
    assert_int_equal(bf_compare_rank_parse("mdl", &by, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "'mdl'"));
    bf_compare_clear(&c);
}

static void test_pareto_known_set(void **state)
{
    (void)state;
    /* (k, error): A(1, 5) B(2, 3) C(3, 3) dominated by B, D(2, 3) duplicate of B,
     * E(4, 1) F(5, 2) dominated by E, G(1, 6) dominated by A, H(NaN) never. */
    const double x[] = {1, 2, 3, 2, 4, 5, 1, NAN};
    const double y[] = {5, 3, 3, 3, 1, 2, 6, 0};
    const int want[] = {1, 1, 0, 1, 1, 0, 0, 0};
    int on[8];
    bf_compare_pareto(8, x, y, on);
    for (int i = 0; i < 8; i++)
        assert_int_equal(on[i], want[i]);
    /* A single point is its own front; identical points both stay. */
    const double one = 3, two[] = {1, 1};
    bf_compare_pareto(1, &one, &one, on);
    assert_int_equal(on[0], 1);
    bf_compare_pareto(2, two, two, on);
    assert_int_equal(on[0] + on[1], 2);
}

static void test_pareto_marks_in_rank(void **state)
{
    (void)state;
    bf_compare c = make(1, 4);
    bf_compare_fit *f = c.materials[0].fits;
    set_fit(&f[0], 3, 0.5, 0, 0, 1e6); /* fewest k, least work: on both fronts */
    set_fit(&f[1], 4, 0.6, 0, 0, 5e7); /* dominated by f[0] on both */
    set_fit(&f[2], 8, 0.1, 0, 0, 1e8); /* best error: on both */
    set_fit(&f[3], 8, 0.2, 0, 0, 2e6); /* k: dominated by f[2]; work: on the front */
    bf_compare_rank(&c);
    assert_int_equal(f[0].pareto_k, 1);
    assert_int_equal(f[1].pareto_k, 0);
    assert_int_equal(f[2].pareto_k, 1);
    assert_int_equal(f[3].pareto_k, 0);
    assert_int_equal(f[0].pareto_work, 1);
    assert_int_equal(f[1].pareto_work, 0);
    assert_int_equal(f[2].pareto_work, 1);
    assert_int_equal(f[3].pareto_work, 1);
    /* equal criteria: everyone ranks 1 */
    for (int j = 0; j < 4; j++)
        assert_int_equal(f[j].rank_bic, 1);
    bf_compare_clear(&c);
}

static void test_simplest_within_tolerance(void **state)
{
    (void)state;
    bf_compare c = make(1, 5);
    bf_compare_fit *f = c.materials[0].fits;
    set_fit(&f[0], 3, 0.1049, 0, 0, 0); /* within 5% of 0.1: fewest parameters */
    set_fit(&f[1], 2, 0.1051, 0, 0, 0); /* fewer, but just outside */
    set_fit(&f[2], 8, 0.1000, 0, 0, 0); /* best */
    set_fit(&f[3], 3, 0.1020, 0, 0, 0); /* same k as f[0], lower error: wins the tie */
    set_fit(&f[4], 3, 0.1020, 0, 0, 0); /* exact tie with f[3]: the earlier model stays */
    bf_compare_rank(&c);
    assert_int_equal(c.materials[0].best, 2);
    assert_int_equal(c.materials[0].simplest, 3);
    assert_int_equal(f[1].within_tolerance, 0);
    assert_int_equal(f[0].within_tolerance, 1);
    /* tolerance 0: only the best */
    c.tolerance = 0;
    bf_compare_rank(&c);
    assert_int_equal(c.materials[0].simplest, 2);
    /* a wide tolerance takes the 2-parameter model */
    c.tolerance = 0.5;
    bf_compare_rank(&c);
    assert_int_equal(c.materials[0].simplest, 1);
    /* nothing ranked: no best, no simplest */
    for (int j = 0; j < 5; j++)
        f[j].state = j % 2 ? BF_CMP_ERROR : BF_CMP_NOT_RUN;
    bf_compare_rank(&c);
    assert_int_equal(c.materials[0].best, -1);
    assert_int_equal(c.materials[0].simplest, -1);
    bf_compare_clear(&c);
}

/* Three materials x three models with the choices worked out by hand. */
static bf_compare summary_set(void)
{
    bf_compare c = make(3, 3);
    bf_compare_fit *a = c.materials[0].fits, *b = c.materials[1].fits, *d = c.materials[2].fits;
    /* a: lambert simplest (errors 0.10, 0.10, 0.099), BIC ranks 1, 2, 3 */
    set_fit(&a[0], 3, 0.100, 10, 10, 0);
    set_fit(&a[1], 5, 0.100, 20, 20, 0);
    set_fit(&a[2], 8, 0.099, 30, 30, 0);
    /* b: walter alone is good; BIC ranks 3, 2, 1 */
    set_fit(&b[0], 3, 0.500, 30, 30, 0);
    set_fit(&b[1], 5, 0.300, 20, 20, 0);
    set_fit(&b[2], 8, 0.050, 10, 10, 0);
    /* c: phong failed; lambert's error 0.2 within 5% of walter's 0.195 */
    set_fit(&d[0], 3, 0.200, 20, 20, 0);
    set_fit(&d[1], 5, 0.010, 0, 0, 0);
    d[1].state = BF_CMP_FAILED;
    set_fit(&d[2], 8, 0.195, 10, 10, 0);
    bf_compare_rank(&c);
    return c;
}

static void test_summary(void **state)
{
    (void)state;
    bf_compare c = summary_set();
    assert_int_equal(c.materials[0].simplest, 0);
    assert_int_equal(c.materials[1].simplest, 2);
    assert_int_equal(c.materials[2].simplest, 0);
    const bf_compare_summary *s = c.summary;
    assert_int_equal(s[0].ranked, 3);
    assert_int_equal(s[1].ranked, 2);
    assert_int_equal(s[2].ranked, 3);
    assert_int_equal(s[0].chosen, 2);
    assert_int_equal(s[1].chosen, 0);
    assert_int_equal(s[2].chosen, 1);
    assert_true(fabs(s[0].mean_rank_bic - (1 + 3 + 2) / 3.0) < 1e-12);
    assert_true(fabs(s[1].mean_rank_bic - (2 + 2) / 2.0) < 1e-12);
    assert_true(fabs(s[2].mean_rank_bic - (3 + 1 + 1) / 3.0) < 1e-12);
    assert_true(fabs(s[0].mean_error - (0.1 + 0.5 + 0.2) / 3) < 1e-12);
    assert_true(fabs(s[1].mean_error - (0.1 + 0.3) / 2) < 1e-12);
    bf_compare_clear(&c);
}

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    rewind(f);
    char *s = malloc((size_t)n + 1);
    assert_int_equal(fread(s, 1, (size_t)n, f), (size_t)n);
    s[n] = '\0';
    fclose(f);
    return s;
}

static void test_json_keys(void **state)
{
    (void)state;
    bf_compare c = summary_set();
    c.residual = "log";
    char path[] = "/tmp/test_compare_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    close(fd);
    bf_error err;
    assert_int_equal(bf_compare_write_json(&c, path, &err), BF_OK);
    char *text = slurp(path);
    cJSON *root = cJSON_Parse(text);
    assert_non_null(root);
    const char *top[] = {"version", "rank_by", "error",       "folds",  "tolerance", "residual",
                         "work",    "timing",  "interrupted", "models", "materials", "summary"};
    for (size_t k = 0; k < sizeof top / sizeof top[0]; k++)
        assert_true(cJSON_HasObjectItem(root, top[k]));
    assert_string_equal(cJSON_GetObjectItem(root, "error")->valuestring, "rmse_log");
    cJSON *mats = cJSON_GetObjectItem(root, "materials");
    assert_int_equal(cJSON_GetArraySize(mats), 3);
    const char *fit_keys[] = {"model",    "spec",        "status",
                              "ok",       "message",     "k",
                              "n",        "error",       "rmse",
                              "rmse_log", "rmse_cos",    "rmse_rel",
                              "max_err",  "loglik",      "aic",
                              "aicc",     "bic",         "cv",
                              "work",     "rank",        "rank_bic",
                              "rank_aic", "rank_aicc",   "rank_cv",
                              "pareto_k", "pareto_work", "within_tolerance",
                              "params",   "stderr",      "warnings"};
    cJSON *m;
    /* no wall times unless asked */
    assert_null(strstr(text, "seconds"));
    cJSON_ArrayForEach(m, mats)
    {
        const char *mk[] = {"data", "samples", "channels", "best", "simplest", "fits"};
        for (size_t k = 0; k < sizeof mk / sizeof mk[0]; k++)
            assert_true(cJSON_HasObjectItem(m, mk[k]));
        cJSON *fits = cJSON_GetObjectItem(m, "fits"), *f;
        assert_int_equal(cJSON_GetArraySize(fits), 3);
        /* every fit has every key, ranked or not */
        cJSON_ArrayForEach(f, fits) for (size_t k = 0; k < sizeof fit_keys / sizeof fit_keys[0]; k++)
            assert_true(cJSON_HasObjectItem(f, fit_keys[k]));
    }
    cJSON *m2 = cJSON_GetArrayItem(mats, 2);
    assert_string_equal(cJSON_GetObjectItem(m2, "simplest")->valuestring, "lambert");
    assert_string_equal(cJSON_GetObjectItem(m2, "best")->valuestring, "walter");
    cJSON *failed = cJSON_GetArrayItem(cJSON_GetObjectItem(m2, "fits"), 1);
    assert_string_equal(cJSON_GetObjectItem(failed, "status")->valuestring, "failed");
    assert_true(cJSON_IsNull(cJSON_GetObjectItem(failed, "rank_bic")));
    assert_true(cJSON_IsNull(cJSON_GetObjectItem(failed, "error")));
    cJSON *s0 = cJSON_GetArrayItem(cJSON_GetObjectItem(root, "summary"), 0);
    assert_int_equal(cJSON_GetObjectItem(s0, "chosen_simplest")->valueint, 2);
    assert_true(fabs(cJSON_GetObjectItem(s0, "mean_rank_bic")->valuedouble - 2.0) < 1e-12);
    cJSON_Delete(root);
    free(text);
    /* with timing: every fit carries seconds */
    c.timing = 1;
    assert_int_equal(bf_compare_write_json(&c, path, &err), BF_OK);
    text = slurp(path);
    root = cJSON_Parse(text);
    cJSON *f0 = cJSON_GetArrayItem(
        cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(root, "materials"), 0), "fits"), 0);
    assert_true(cJSON_IsNumber(cJSON_GetObjectItem(f0, "seconds")));
    cJSON_Delete(root);
    free(text);
    unlink(path);
    bf_compare_clear(&c);
}

static void test_csv_rows(void **state)
{
    (void)state;
    bf_compare c = summary_set();
    char path[] = "/tmp/test_compare_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    close(fd);
    bf_error err;
    assert_int_equal(bf_compare_write_csv(&c, path, &err), BF_OK);
    char *text = slurp(path);
    int lines = 0;
    for (char *p = text; *p; p++)
        lines += *p == '\n';
    assert_int_equal(lines, 1 + 3 * 3);
    assert_true(!strncmp(text, "material,model,status,k,", 24));
    /* quoting: a material name with a comma and quotes */
    assert_non_null(strstr(text, "\n\"b,\"\"q\"\".csv\",lambert,ok,3,"));
    /* the failed fit: a status and empty ranks */
    assert_non_null(strstr(text, "\nc.csv,phong,failed,5,100,,"));
    assert_null(strstr(text, "seconds"));
    free(text);
    c.timing = 1;
    assert_int_equal(bf_compare_write_csv(&c, path, &err), BF_OK);
    text = slurp(path);
    assert_non_null(strstr(text, ",warnings,seconds\n"));
    free(text);
    unlink(path);
    /* an unwritable path: an error, nothing written */
    assert_int_not_equal(bf_compare_write_csv(&c, "/nonexistent/dir/r.csv", &err), BF_OK);
    bf_compare_clear(&c);
}

static void test_metric_names(void **state)
{
    (void)state;
    bf_compare_metric m;
    bf_error err;
    const char *names[] = {"rmse", "rmse_log", "rmse_cos", "rmse_rel"};
    for (int i = 0; i < 4; i++) {
        assert_int_equal(bf_compare_metric_parse(names[i], &m, &err), BF_OK);
        assert_string_equal(bf_compare_metric_name(m), names[i]);
    }
    assert_int_equal(bf_compare_metric_parse("rmse_xyz", &m, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "rmse_xyz"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ranks_and_ties),
        cmocka_unit_test(test_pareto_known_set),
        cmocka_unit_test(test_pareto_marks_in_rank),
        cmocka_unit_test(test_simplest_within_tolerance),
        cmocka_unit_test(test_summary),
        cmocka_unit_test(test_json_keys),
        cmocka_unit_test(test_csv_rows),
        cmocka_unit_test(test_metric_names),
        cmocka_unit_test(test_rank_by_cv),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
