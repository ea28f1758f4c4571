/* bf_compare_run: the comparison's fits in the library. Two synthetic materials x three
 * models: the results are the same to the bit whatever the jobs and threads; the
 * progress callback is called once per fit; a cancel flag set before the run leaves
 * every fit not run, and one set midway keeps what finished; a fit that cannot run is an
 * error and the others go on. */
#include <math.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/compare.h"
#include "compare/compare_run.h"
#include "compare/compare_impl.h"
#include "support.h"

enum { NMAT = 2, NMOD = 3, NFITS = NMAT * NMOD, NPOINTS = 1200 };

static const char *const data_names[NMAT] = {"lambert.csv", "walter.csv"};
static const char *const model_specs[NMOD] = {"lambert", "walter", "cook_torrance"};

/* NPOINTS samples of spec at x (3 channels), with 2% multiplicative noise. */
static bf_samples *material(const char *spec, const double *x, uint64_t seed)
{
    bf_error err;
    bf_samples *s = NULL;
    bf_samples_new(NPOINTS, 3, &s, &err);
    assert_non_null(s);
    ts_rng r = {seed};
    for (size_t i = 0; i < NPOINTS; i++)
        ts_random_pair_deg(&r, i % 4 == 0, &s->theta_i[i], &s->phi_i[i], &s->theta_o[i], &s->phi_o[i]);
    bf_model *m = ts_model(spec, 3);
    assert_non_null(ts_samples_geometry(s));
    bf_model_eval(m, x, ts_samples_geometry(s), s->value, NULL);
    for (size_t k = 0; k < NPOINTS * 3; k++)
        s->value[k] *= 1.0 + 0.02 * (ts_uniform(&r) - 0.5);
    bf_model_free(m);
    return s;
}

typedef struct fixture {
    bf_samples *samples[NMAT];
    bf_fit_options fo;
} fixture;

static int setup(void **state)
{
    static const double lam[] = {0.6, 0.4, 0.2};
    /* walter: rho_d, rho_s, alpha, f0 */
    static const double wal[] = {0.3, 0.2, 0.1, 0.8, 0.8, 0.7, 0.1, 0.05};
    fixture *f = calloc(1, sizeof *f);
    if (!f)
        return -1;
    f->samples[0] = material("lambert", lam, 11);
    f->samples[1] = material("walter", wal, 12);
    bf_objective_options_init(&f->fo.objective); /* the embedded structs carry their sizes */
    bf_solver_options_init(&f->fo.solver);
    f->fo.objective.residual = BF_RESIDUAL_LOG;
    f->fo.objective.use_weights = 1;
    f->fo.solver.backend = BF_BACKEND_CERES;
    f->fo.solver.threads = 1;
    f->fo.starts = 1;
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    for (int i = 0; i < NMAT; i++)
        bf_samples_free(f->samples[i]);
    free(f);
    return 0;
}

/* Records every progress call. Checked after the run: the calls come from the fitting
 * threads, where a cmocka assertion may not jump. */
typedef struct calls {
    int n, last_done, wrong, seen[NFITS];
    volatile sig_atomic_t *cancel_after_first; /* set after the first call (NULL: never) */
} calls;

static void count_calls(void *user, const bf_compare *c, int material, int model, int done, int total)
{
    calls *k = user;
    if (total != NFITS || material < 0 || material >= NMAT || model < 0 || model >= NMOD) {
        k->wrong++;
        return;
    }
    k->wrong += done != k->last_done + 1; /* one call at a time, counted in order */
    k->wrong += c->materials[material].fits[model].state == BF_CMP_NOT_RUN;
    k->last_done = done;
    k->seen[material * NMOD + model]++;
    k->n++;
    if (k->cancel_after_first)
        *k->cancel_after_first = 1;
}

/* Sets up c for specs (folds: cross-validation folds) and runs it on the fixture's
 * materials with jobs jobs, fo's threads, progress into k and the cancel flag. */
static void run(const fixture *f, bf_compare *c, const char *const *specs, int folds, const bf_fit_options *fo,
                int jobs, calls *k, volatile sig_atomic_t *cancel)
{
    bf_error err;
    assert_int_equal(bf_compare_init(c, NMAT, data_names, NMOD, specs, &err), BF_OK);
    c->folds = folds;
    const compare_hooks h = {count_calls, k, cancel};
    assert_int_equal(compare_run_with(c, f->samples, fo, jobs, &h, &err), BF_OK);
    assert_int_equal(k->wrong, 0);
}

static void assert_same_fit(const bf_compare_fit *a, const bf_compare_fit *b)
{
    assert_int_equal(a->state, b->state);
    assert_memory_equal(&a->metrics, &b->metrics, sizeof a->metrics);
    assert_memory_equal(&a->work, &b->work, sizeof a->work);
    assert_memory_equal(&a->cv_error, &b->cv_error, sizeof a->cv_error);
    assert_non_null(a->result);
    assert_non_null(b->result);
    int P = bf_model_nvalues(a->result->model);
    assert_int_equal(P, bf_model_nvalues(b->result->model));
    assert_memory_equal(a->result->x, b->result->x, (size_t)P * sizeof *a->result->x);
}

static void test_jobs_give_identical_results(void **state)
{
    fixture *f = *state;
    bf_compare one, three;
    calls k1 = {0}, k3 = {0};
    run(f, &one, model_specs, 2, &f->fo, 1, &k1, NULL); /* cross-validated too */
    bf_fit_options fo = f->fo;
    fo.solver.threads = 6; /* 2 per fit */
    run(f, &three, model_specs, 2, &fo, 3, &k3, NULL);
    assert_false(one.interrupted);
    assert_false(three.interrupted);
    for (int i = 0; i < NMAT; i++) {
        assert_int_equal(one.materials[i].samples, NPOINTS);
        assert_int_equal(three.materials[i].channels, 3);
        for (int j = 0; j < NMOD; j++) {
            const bf_compare_fit *a = &one.materials[i].fits[j], *b = &three.materials[i].fits[j];
            assert_int_equal(a->state, BF_CMP_OK);
            assert_true(isfinite(a->cv_error));
            assert_ptr_equal(a->result, one.results[i * NMOD + j]);
            assert_same_fit(a, b);
        }
    }
    /* Progress: once per fit, in both. */
    assert_int_equal(k1.n, NFITS);
    assert_int_equal(k3.n, NFITS);
    for (int s = 0; s < NFITS; s++)
        assert_true(k1.seen[s] == 1 && k3.seen[s] == 1);
    /* Ranked the same, and Lambert is the simplest on the Lambert data. */
    bf_compare_rank(&one);
    bf_compare_rank(&three);
    assert_int_equal(one.materials[0].simplest, 0);
    assert_int_equal(one.materials[1].simplest, three.materials[1].simplest);
    /* A table runs once. */
    bf_error err;
    assert_int_equal(compare_run_with(&one, f->samples, &f->fo, 1, NULL, &err), BF_ERR_ARG);
    bf_compare_clear(&one);
    bf_compare_clear(&three);
}

static void test_cancel_before_the_run(void **state)
{
    fixture *f = *state;
    bf_compare c;
    volatile sig_atomic_t cancel = 1;
    calls k = {0};
    run(f, &c, model_specs, 0, &f->fo, 3, &k, &cancel);
    assert_true(c.interrupted);
    assert_int_equal(k.n, 0);
    assert_int_equal(bf_compare_count(&c, BF_CMP_NOT_RUN), NFITS);
    for (int i = 0; i < NMAT; i++)
        for (int j = 0; j < NMOD; j++)
            assert_null(c.materials[i].fits[j].result);
    bf_compare_rank(&c);
    assert_int_equal(c.materials[0].simplest, -1);
    bf_compare_clear(&c);
}

static void test_cancel_midway_keeps_what_finished(void **state)
{
    fixture *f = *state;
    bf_compare c;
    volatile sig_atomic_t cancel = 0;
    calls k = {.cancel_after_first = &cancel};
    run(f, &c, model_specs, 0, &f->fo, 1, &k, &cancel);
    assert_true(c.interrupted);
    /* One job: the flag is read before each fit, so exactly the first one ran. */
    assert_int_equal(k.n, 1);
    assert_int_equal(c.materials[0].fits[0].state, BF_CMP_OK);
    assert_non_null(c.materials[0].fits[0].result);
    assert_int_equal(bf_compare_count(&c, BF_CMP_NOT_RUN), NFITS - 1);
    bf_compare_clear(&c);
}

static void test_a_fit_that_cannot_run(void **state)
{
    fixture *f = *state;
    static const char *const specs[NMOD] = {"lambert", "nonesuch", "walter"};
    bf_compare c;
    calls k = {0};
    run(f, &c, specs, 0, &f->fo, 2, &k, NULL);
    assert_false(c.interrupted);
    assert_int_equal(k.n, NFITS);
    assert_int_equal(bf_compare_count(&c, BF_CMP_ERROR), NMAT);
    assert_int_equal(bf_compare_count(&c, BF_CMP_OK), NFITS - NMAT);
    for (int i = 0; i < NMAT; i++) {
        assert_non_null(strstr(c.materials[i].fits[1].message, "nonesuch"));
        assert_null(c.materials[i].fits[1].result);
    }
    bf_compare_clear(&c);
}

static void test_bad_arguments(void **state)
{
    fixture *f = *state;
    bf_compare c;
    bf_error err;
    assert_int_equal(bf_compare_init(&c, NMAT, data_names, NMOD, model_specs, &err), BF_OK);
    bf_samples *none[NMAT] = {f->samples[0], NULL};
    assert_int_equal(compare_run_with(&c, none, &f->fo, 1, NULL, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "walter.csv"));
    assert_int_equal(compare_run_with(&c, f->samples, NULL, 1, NULL, &err), BF_ERR_ARG);
    assert_int_equal(bf_compare_count(&c, BF_CMP_NOT_RUN), NFITS);
    bf_compare_clear(&c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_jobs_give_identical_results),
        cmocka_unit_test(test_cancel_before_the_run),
        cmocka_unit_test(test_cancel_midway_keeps_what_finished),
        cmocka_unit_test(test_a_fit_that_cannot_run),
        cmocka_unit_test(test_bad_arguments),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
