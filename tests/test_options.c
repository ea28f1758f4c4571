/* The run options (brdfit/options.h) and loading (brdfit/load.h): the table's defaults are
 * the values a new set holds, values are taken and refused as the command line takes
 * them, couplings are checked, copies and resets replay what was set, model lists split
 * as -m splits them, and loading reads, prepares, applies the scene and subsamples in
 * that order. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "brdfit/load.h"
#include "brdfit/model.h"
#include "brdfit/options.h"
#include "support.h"

static const unsigned tasks[] = {BF_TASK_READ, BF_TASK_FIT, BF_TASK_COMPARE, BF_TASK_SELECT, BF_TASK_TRADEOFF};

static bf_options *make(unsigned task)
{
    bf_options *o = NULL;
    bf_error err;
    assert_int_equal(bf_options_new((bf_task)task, &o, &err), BF_OK);
    return o;
}

static void get(const bf_options *o, const char *name, char *buf, size_t size)
{
    bf_error err;
    if (bf_options_get(o, name, buf, size, &err) != BF_OK)
        fail_msg("%s: %s", name, err.msg);
}

/* Every option that states a default holds it in a new set of each task that takes it,
 * in the words the table uses: the table is the one place defaults are written. */
static void test_defaults_are_the_tables(void **state)
{
    (void)state;
    int checked = 0;
    for (size_t t = 0; t < sizeof tasks / sizeof tasks[0]; t++) {
        bf_options *o = make(tasks[t]);
        for (int i = 0; i < bf_option_count(); i++) {
            const bf_option *d = bf_option_get(i);
            if (!d->def || !(d->tasks & tasks[t]) || bf_option_find(d->name, tasks[t]) != d)
                continue;
            char v[256];
            get(o, d->name, v, sizeof v);
            /* Numbers compare as numbers ("1e-6" is 1e-06). */
            char *end;
            double dv = strtod(d->def, &end);
            if (*end == '\0' && d->type == BF_OPTION_NUMBER)
                assert_true(strtod(v, NULL) == dv);
            else if (strcmp(d->name, "angles")) /* NULL columns mean those names */
                assert_string_equal(v, d->def);
            assert_int_equal(bf_options_given(o, d->name), 0);
            checked++;
        }
        bf_options_free(o);
    }
    assert_true(checked > 20);
}

static void test_table(void **state)
{
    (void)state;
    /* Either spelling finds an option; the task decides which row (compare ranks by bic,
     * select by error). */
    const bf_option *a = bf_option_find("--max-theta", BF_TASK_READ), *b = bf_option_find("max_theta", 0);
    assert_non_null(a);
    assert_ptr_equal(a, b);
    assert_int_equal(a->type, BF_OPTION_NUMBER);
    assert_string_equal(a->range, "degrees in (0, 90]");
    assert_string_equal(bf_option_find("rank", BF_TASK_COMPARE)->def, "bic");
    assert_string_equal(bf_option_find("rank", BF_TASK_SELECT)->def, "error");
    assert_null(bf_option_find("rank", BF_TASK_FIT));
    assert_null(bf_option_find("accuracy", BF_TASK_COMPARE));
    assert_non_null(bf_option_find("accuracy", BF_TASK_SELECT));
    assert_null(bf_option_find("no_such_option", 0));
    /* Every row is described: a group, some task, help; a value's name unless a flag. */
    for (int i = 0; i < bf_option_count(); i++) {
        const bf_option *d = bf_option_get(i);
        assert_non_null(d->name);
        assert_non_null(d->group);
        assert_non_null(d->help);
        assert_true(d->tasks != 0);
        assert_true((d->type == BF_OPTION_FLAG) == (d->arg == NULL));
    }
    assert_null(bf_option_get(-1));
    assert_null(bf_option_get(bf_option_count()));
}

/* Values are taken as the command line takes them and refused with its message, the
 * option named as the set spells it. */
static void test_set_and_refuse(void **state)
{
    (void)state;
    bf_options *o = make(BF_TASK_FIT);
    bf_error err;
    char v[64];
    assert_int_equal(bf_options_set(o, "--max-theta", "80", &err), BF_OK);
    get(o, "max_theta", v, sizeof v);
    assert_true(strtod(v, NULL) == 80.0);
    assert_int_equal(bf_options_given(o, "max_theta"), 1);
    assert_int_equal(bf_options_set(o, "max_theta", "95", &err), BF_ERR_ARG);
    assert_string_equal(err.msg, "--max-theta needs degrees in (0, 90], got '95'");
    bf_options_set_spelling(o, BF_SPELL_KEYWORD);
    assert_int_equal(bf_options_set(o, "max_theta", " 5", &err), BF_ERR_ARG);
    assert_string_equal(err.msg, "max_theta needs degrees in (0, 90], got ' 5'");
    assert_int_equal(bf_options_set(o, "threads", "0", &err), BF_ERR_ARG);
    assert_string_equal(err.msg, "threads needs an integer from 1 to 1024, got '0'");
    assert_int_equal(bf_options_set(o, "seed", "-1", &err), BF_ERR_ARG);
    assert_int_equal(bf_options_set(o, "seed", "18446744073709551615", &err), BF_OK);
    get(o, "seed", v, sizeof v);
    assert_string_equal(v, "18446744073709551615");
    /* Flags: on without a value or with true, off with false; anything else refused. */
    assert_int_equal(bf_options_set(o, "no_weights", NULL, &err), BF_OK);
    get(o, "no_weights", v, sizeof v);
    assert_string_equal(v, "true");
    assert_int_equal(bf_options_set(o, "no_weights", "false", &err), BF_OK);
    get(o, "no_weights", v, sizeof v);
    assert_string_equal(v, "false");
    assert_int_equal(bf_options_set(o, "no_weights", "maybe", &err), BF_ERR_ARG);
    /* Spectral choices exclude each other, but --rgb and --color srgb repeat one, and an
     * option given again replaces its value. */
    assert_int_equal(bf_options_set(o, "rgb", NULL, &err), BF_OK);
    assert_int_equal(bf_options_set(o, "color", "srgb", &err), BF_OK);
    assert_int_equal(bf_options_set(o, "color", "xyz", &err), BF_OK);
    get(o, "color", v, sizeof v);
    assert_string_equal(v, "xyz");
    assert_int_equal(bf_options_set(o, "rgb", NULL, &err), BF_ERR_ARG);
    assert_string_equal(err.msg, "color and rgb exclude each other");
    assert_int_equal(bf_options_set(o, "luminance", NULL, &err), BF_ERR_ARG);
    /* Unknown, and another task's. */
    assert_int_equal(bf_options_set(o, "bogus", "1", &err), BF_ERR_ARG);
    assert_string_equal(err.msg, "unknown option 'bogus'");
    assert_int_equal(bf_options_set(o, "tolerance", "0.1", &err), BF_ERR_ARG);
    assert_string_equal(err.msg, "tolerance is not an option of fit (it is one of compare, select, tradeoff)");
    /* Lists add an entry each time; a bad entry names the option. */
    assert_int_equal(bf_options_set(o, "fix", "rho_d=0.1", &err), BF_OK);
    assert_int_equal(bf_options_set(o, "fix", "alpha[1]=0.2", &err), BF_OK);
    assert_int_equal(bf_options_set(o, "bound", "alpha=0.05:0.5", &err), BF_OK);
    get(o, "fix", v, sizeof v);
    assert_string_equal(v, "rho_d=0.1,alpha[1]=0.2");
    get(o, "bound", v, sizeof v);
    assert_string_equal(v, "alpha=0.05:0.5");
    assert_int_equal(bf_options_set(o, "fix", "rho_d", &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "fix: "));
    bf_options_free(o);
}

/* An accuracy preset fills what was not set, whatever the order; the seed is one. */
static void test_couplings_in_values(void **state)
{
    (void)state;
    bf_options *o = make(BF_TASK_FIT);
    bf_error err;
    char v[64];
    assert_int_equal(bf_options_set(o, "starts", "3", &err), BF_OK);
    assert_int_equal(bf_options_set(o, "accuracy", "fast", &err), BF_OK);
    get(o, "starts", v, sizeof v);
    assert_string_equal(v, "3"); /* given: the preset gives way */
    get(o, "subsample", v, sizeof v);
    assert_string_equal(v, "16000"); /* not given: the preset's */
    assert_int_equal(bf_options_set(o, "subsample", "all", &err), BF_OK);
    get(o, "subsample", v, sizeof v);
    assert_string_equal(v, "all");
    bf_options_free(o);
    /* Compare has no preset: its subsample stays all. */
    o = make(BF_TASK_COMPARE);
    get(o, "subsample", v, sizeof v);
    assert_string_equal(v, "all");
    bf_options_free(o);
}

static void test_check(void **state)
{
    (void)state;
    bf_error err;
    bf_options *o = make(BF_TASK_COMPARE);
    assert_int_equal(bf_options_check(o, &err), BF_OK);
    assert_int_equal(bf_options_set(o, "loss", "huber", &err), BF_OK);
    assert_int_equal(bf_options_check(o, &err), BF_ERR_ARG); /* bic needs a likelihood */
    assert_string_equal(err.msg, "--rank bic needs the likelihood of the residuals, and a robust loss (--loss) has "
                                 "none: rank by cv or error");
    assert_int_equal(bf_options_set(o, "rank", "cv", &err), BF_OK);
    assert_int_equal(bf_options_check(o, &err), BF_OK);
    /* A method and its constraint against the registry. */
    assert_int_equal(bf_options_set(o, "algorithm", "nosuch", &err), BF_OK);
    assert_int_equal(bf_options_check(o, &err), BF_ERR_ARG);
    bf_options_free(o);
    /* Models, and fix and bound against them. */
    o = make(BF_TASK_FIT);
    const char *good[] = {"lambert", "walter"}, *bad[] = {"nosuch"};
    assert_int_equal(bf_options_check_models(o, good, 2, &err), BF_OK);
    assert_int_equal(bf_options_check_models(o, bad, 1, &err), BF_ERR_ARG);
    assert_int_equal(bf_options_set(o, "fix", "alpha=0.1", &err), BF_OK);
    assert_int_equal(bf_options_check_models(o, good, 2, &err), BF_ERR_ARG); /* lambert has no alpha */
    assert_non_null(strstr(err.msg, "alpha"));
    bf_options_free(o);
}

/* Copies and resets set the values again: a reset option is back to its default, the
 * others as they were. */
static void test_copy_and_reset(void **state)
{
    (void)state;
    bf_error err;
    char v[64];
    bf_options *o = make(BF_TASK_FIT), *c = NULL;
    assert_int_equal(bf_options_set(o, "residual", "linear", &err), BF_OK);
    assert_int_equal(bf_options_set(o, "scene", "x.json", &err), BF_OK);
    assert_int_equal(bf_options_set(o, "rgb", NULL, &err), BF_OK);
    assert_int_equal(bf_options_copy(o, &c, &err), BF_OK);
    assert_int_equal(bf_options_reset(c, "scene", &err), BF_OK);
    get(c, "scene", v, sizeof v);
    assert_string_equal(v, "");
    assert_int_equal(bf_options_given(c, "scene"), 0);
    get(c, "residual", v, sizeof v);
    assert_string_equal(v, "linear");
    get(o, "scene", v, sizeof v);
    assert_string_equal(v, "x.json"); /* the original is untouched */
    assert_int_equal(bf_options_reset(c, "rgb", &err), BF_OK);
    assert_int_equal(bf_options_set(c, "color", "xyz", &err), BF_OK); /* no longer excluded */
    assert_int_equal(bf_options_reset(c, "bogus", &err), BF_ERR_ARG);
    bf_options_free(c);
    bf_options_free(o);
    /* A value too long for the caller's buffer is refused, not cut. */
    o = make(BF_TASK_READ);
    assert_int_equal(bf_options_set(o, "scene", "a-rather-long-file-name.json", &err), BF_OK);
    assert_int_equal(bf_options_get(o, "scene", v, 8, &err), BF_ERR_ARG);
    bf_options_free(o);
}

static void split_expect(const char *list, int n, const char *const *want)
{
    char **specs = NULL;
    int got = 0;
    bf_error err;
    assert_int_equal(bf_model_list_split(list, &specs, &got, &err), BF_OK);
    assert_int_equal(got, n);
    for (int k = 0; k < n; k++)
        assert_string_equal(specs[k], want[k]);
    bf_free(specs);
}

static void test_model_lists(void **state)
{
    (void)state;
    const char *three[] = {"lambert", "microfacet:D=ggx,G=smith_ggx", "walter"};
    split_expect("lambert,microfacet:D=ggx,G=smith_ggx,walter", 3, three);
    const char *two[] = {"walter:lobes=2,mono=specular", "disney"};
    split_expect("walter:lobes=2,mono=specular,disney", 2, two);
    char **specs = NULL;
    int n = 0;
    bf_error err;
    assert_int_equal(bf_model_list_split("lambert,all", &specs, &n, &err), BF_OK);
    assert_int_equal(n, 1 + bf_family_count());
    assert_string_equal(specs[1], bf_family_get(0)->name);
    bf_free(specs);
    assert_int_equal(bf_model_list_split("", &specs, &n, &err), BF_ERR_ARG);
    assert_int_equal(bf_model_list_split("a,,b", &specs, &n, &err), BF_ERR_ARG);
    assert_string_equal(err.msg, "empty model name in 'a,,b'");
    assert_int_equal(bf_model_list_split("all,lobes=2", &specs, &n, &err), BF_ERR_ARG);
    assert_null(specs);
}

/* A CSV of n samples: theta_i 5..85 across the samples, the outgoing mirror direction
 * and value 0.1, and every fifth sample below the horizon. */
static const char *write_csv(char *path, size_t size, int n)
{
    snprintf(path, size, "/tmp/test_options_%d.csv", (int)getpid());
    FILE *fp = fopen(path, "w");
    assert_non_null(fp);
    fprintf(fp, "theta_i,phi_i,theta_o,phi_o,value\n");
    for (int i = 0; i < n; i++)
        fprintf(fp, "%.6f,0,%.6f,180,0.1\n", 5.0 + 80.0 * i / (n - 1), i % 5 == 4 ? 95.0 : 5.0 + 80.0 * i / (n - 1));
    fclose(fp);
    return path;
}

static void test_load_order_and_report(void **state)
{
    (void)state;
    char path[64];
    write_csv(path, sizeof path, 500);
    bf_error err;
    bf_samples *s = NULL;
    bf_load_report r;
    bf_load_report_init(&r);
    bf_options *o = make(BF_TASK_READ);
    assert_int_equal(bf_samples_load(path, o, &s, &r, &err), BF_OK);
    assert_int_equal(r.read, 500);
    assert_int_equal(r.below_horizon, 100);
    assert_int_equal(r.kept, 400);
    assert_int_equal(s->n, 400);
    bf_samples_free(s);
    /* The subsample comes after the drops: 50 of the 400. */
    assert_int_equal(bf_options_set(o, "subsample", "50", &err), BF_OK);
    assert_int_equal(bf_samples_load(path, o, &s, &r, &err), BF_OK);
    assert_int_equal(r.subsampled_out, 350);
    assert_int_equal(s->n, 50);
    /* The same preparation of samples in memory gives the same samples. */
    bf_samples *t = NULL, *all = NULL;
    assert_int_equal(bf_samples_read(path, NULL, &t, &err), BF_OK);
    assert_int_equal(t->n, 500); /* read as it is */
    assert_int_equal(bf_samples_copy(t, NULL, &all, &err), BF_OK);
    assert_int_equal(bf_samples_prepare(t, o, &r, &err), BF_OK);
    assert_int_equal(t->n, 50);
    for (size_t i = 0; i < t->n; i++)
        assert_true(t->theta_i[i] == s->theta_i[i]);
    /* Errors name the file; an uninitialised report is refused. */
    bf_samples_free(s);
    bf_samples_free(t);
    bf_samples_free(all);
    s = NULL;
    assert_int_equal(bf_samples_load("/nonexistent.csv", o, &s, NULL, &err), BF_ERR_IO);
    assert_non_null(strstr(err.msg, "/nonexistent.csv"));
    assert_null(s);
    bf_load_report zero;
    memset(&zero, 0, sizeof zero);
    assert_int_equal(bf_samples_load(path, o, &s, &zero, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "bf_load_report"));
    assert_null(s);
    bf_options_free(o);
    remove(path);
}

/* A start for one fit: refused for a comparison and at another length than the model's;
 * a fit from the optimum of the same data, with no other start, stays there. */
static void test_start(void **state)
{
    (void)state;
    char path[64];
    write_csv(path, sizeof path, 200);
    bf_error err;
    bf_options *c = make(BF_TASK_COMPARE), *o = make(BF_TASK_FIT);
    const double x[1] = {0.3};
    assert_int_equal(bf_options_set_start(c, x, 1, &err), BF_ERR_ARG);
    bf_samples *s = NULL;
    assert_int_equal(bf_options_set(o, "starts", "1", &err), BF_OK);
    assert_int_equal(bf_samples_load(path, o, &s, NULL, &err), BF_OK);
    bf_fit_result r;
    bf_fit_result_init(&r);
    assert_int_equal(bf_fit(s, "lambert", o, &r, &err), BF_OK);
    assert_true(r.ok);
    const double best = r.x[0];
    ts_assert_rel(best, 0.1 * M_PI, 1e-6, "rho_d of value 0.1");
    assert_int_equal(bf_options_set_start(o, r.x, 1, &err), BF_OK);
    bf_fit_result_clear(&r);
    assert_int_equal(bf_fit(s, "lambert", o, &r, &err), BF_OK);
    assert_true(r.x[0] == best);
    bf_fit_result_clear(&r);
    assert_int_equal(bf_fit(s, "walter", o, &r, &err), BF_ERR_ARG); /* 1 value, walter has more */
    assert_non_null(strstr(err.msg, "the start has 1 values"));
    bf_options *copy = NULL;
    assert_int_equal(bf_options_copy(o, &copy, &err), BF_OK); /* the start goes with a copy */
    assert_int_equal(bf_fit(s, "walter", copy, &r, &err), BF_ERR_ARG);
    assert_int_equal(bf_options_set_start(copy, NULL, 0, &err), BF_OK);
    assert_int_equal(bf_fit(s, "walter", copy, &r, &err), BF_OK);
    bf_fit_result_clear(&r);
    bf_options_free(copy);
    bf_samples_free(s);
    bf_options_free(o);
    bf_options_free(c);
    remove(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults_are_the_tables),
        cmocka_unit_test(test_table),
        cmocka_unit_test(test_set_and_refuse),
        cmocka_unit_test(test_couplings_in_values),
        cmocka_unit_test(test_check),
        cmocka_unit_test(test_copy_and_reset),
        cmocka_unit_test(test_model_lists),
        cmocka_unit_test(test_load_order_and_report),
        cmocka_unit_test(test_start),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
