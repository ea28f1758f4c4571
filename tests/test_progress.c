/* Progress reports (brdfit/options.h, bf_options_set_progress_report): the sequence a
 * small fit reports (its phases in order, each start within its phase's count, each
 * phase on the set the options say: the screening set, the presolve's subsample, the
 * data; then one report that it is done), a fit of small data and a plain multistart,
 * the old callback beside the new one, a report that stops the fit, and which material,
 * model, candidate and fold the reports of a comparison and a selection name. */
#include <math.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/compare.h"
#include "brdfit/fit.h"
#include "brdfit/load.h"
#include "brdfit/select.h"
#include "support.h"

#define CAYMAN BRDFIT_EXAMPLES "/cornell/cayman.brdf"

/* One report as the callback saw it (the texts copied: they live for the call only). */
typedef struct seen_report {
    bf_progress_report r;
    char spec[64], material_name[256];
} seen_report;

typedef struct seen {
    pthread_mutex_t lock; /* a comparison's fits report from several threads */
    seen_report *r;
    int n, cap;
    int stop_at;   /* the report callback returns 1 at this report (0: never) */
    int old_calls; /* calls of the old (iteration, cost) callback */
} seen;

static void seen_init(seen *s)
{
    memset(s, 0, sizeof *s);
    pthread_mutex_init(&s->lock, NULL);
}

static void seen_clear(seen *s)
{
    free(s->r);
    pthread_mutex_destroy(&s->lock);
}

static int record(void *user, const bf_progress_report *r)
{
    seen *s = user;
    pthread_mutex_lock(&s->lock);
    if (s->n == s->cap) {
        s->cap = s->cap ? 2 * s->cap : 256;
        s->r = realloc(s->r, (size_t)s->cap * sizeof *s->r);
        assert_non_null(s->r);
    }
    seen_report *k = &s->r[s->n++];
    k->r = *r;
    snprintf(k->spec, sizeof k->spec, "%s", r->spec ? r->spec : "");
    snprintf(k->material_name, sizeof k->material_name, "%s", r->material_name ? r->material_name : "");
    const int stop = s->stop_at && s->n >= s->stop_at;
    pthread_mutex_unlock(&s->lock);
    return stop;
}

static int old_progress(void *user, int iteration, double cost)
{
    seen *s = user;
    (void)iteration, (void)cost;
    pthread_mutex_lock(&s->lock);
    s->old_calls++;
    pthread_mutex_unlock(&s->lock);
    return 0;
}

static bf_samples *load(const char *path, const char *words)
{
    bf_options *o = ts_options(BF_TASK_READ, words);
    bf_samples *s = NULL;
    bf_error err;
    if (bf_samples_load(path, o, &s, NULL, &err) != BF_OK)
        fail_msg("%s", err.msg);
    bf_options_free(o);
    return s;
}

/* Fits spec to s with the options words, every report recorded into k. */
static void fit_seen(bf_samples *s, const char *spec, const char *words, seen *k, bf_fit_result *r)
{
    bf_options *o = ts_options(BF_TASK_FIT, words);
    bf_options_set_progress_report(o, record, k);
    bf_error err;
    bf_fit_result_init(r);
    if (bf_fit(s, spec, o, r, &err) != BF_OK)
        fail_msg("bf_fit: %s", err.msg);
    bf_options_free(o);
}

/* The phases in the order the reports came, each once: asserts they never go back.
 * Returns how many, into phases. */
static int phases_of(const seen *k, bf_fit_phase *phases)
{
    int n = 0;
    for (int i = 0; i < k->n; i++) {
        const bf_fit_phase p = k->r[i].r.phase;
        if (n == 0 || phases[n - 1] != p) {
            if (n > 0 && p < phases[n - 1])
                fail_msg("report %d: phase %s after %s", i, bf_fit_phase_name(p), bf_fit_phase_name(phases[n - 1]));
            phases[n++] = p;
        }
    }
    return n;
}

/* What every report of a fit alone (result r) says, and within each phase: one count of
 * starts and one set size, starts that never go back and stay below the count,
 * iterations of a solve that never go back, finite costs for solves; the last report,
 * and only it, says the fit is done, with the result's cost and iterations. */
static void assert_sane(const seen *k, const char *spec, const bf_fit_result *res)
{
    assert_true(k->n > 1);
    const bf_progress_report *done = &k->r[k->n - 1].r;
    assert_int_equal(done->phase, BF_PHASE_DONE);
    assert_int_equal(done->start, 0);
    assert_int_equal(done->starts, 1);
    assert_int_equal(done->iteration, res->solution.iterations);
    assert_true(done->cost == res->solution.final_cost);
    assert_int_equal(done->samples, res->samples);
    for (int i = 0; i < k->n - 1; i++)
        assert_int_not_equal(k->r[i].r.phase, BF_PHASE_DONE);
    for (int i = 0; i < k->n; i++) {
        const bf_progress_report *r = &k->r[i].r;
        assert_int_equal(r->size, sizeof *r);
        assert_string_equal(k->r[i].spec, spec);
        assert_int_equal(r->material, -1);
        assert_int_equal(r->model, -1);
        assert_int_equal(r->fold, 0);
        assert_null(r->material_name);
        assert_true(r->start >= 0 && r->start < r->starts);
        assert_true(r->iteration >= 0);
        if (r->phase != BF_PHASE_CANDIDATES)
            assert_true(isfinite(r->cost) && r->cost >= 0.0);
        else
            assert_int_equal(r->iteration, 0);
        if (i > 0 && k->r[i - 1].r.phase == r->phase) {
            const bf_progress_report *q = &k->r[i - 1].r;
            assert_int_equal(q->starts, r->starts);
            assert_int_equal(q->samples, r->samples);
            assert_true(q->start <= r->start);
            if (q->start == r->start && r->phase != BF_PHASE_CANDIDATES)
                assert_true(q->iteration <= r->iteration);
        }
    }
}

/* The distinct starts phase p reported. */
static int starts_in(const seen *k, bf_fit_phase p)
{
    int n = 0, last = -1;
    for (int i = 0; i < k->n; i++)
        if (k->r[i].r.phase == p && k->r[i].r.start != last) {
            last = k->r[i].r.start;
            n++;
        }
    return n;
}

static const bf_progress_report *first_in(const seen *k, bf_fit_phase p)
{
    for (int i = 0; i < k->n; i++)
        if (k->r[i].r.phase == p)
            return &k->r[i].r;
    fail_msg("no report of phase %s", bf_fit_phase_name(p));
    return NULL;
}

/* cayman (1439 samples) with a presolve of 1200: candidates and starts on the screening
 * set (1024 of the 1200), the promoted starts on the 1200, the last solve on all 1439. */
static void test_fit_reports_every_phase(void **state)
{
    (void)state;
    bf_samples *s = load(CAYMAN, "--rgb");
    assert_int_equal(s->n, 1439);
    seen k;
    seen_init(&k);
    bf_fit_result r;
    fit_seen(s, "walter", "--starts 4 --screen 16 --presolve 1200 --threads 1", &k, &r);
    assert_true(r.ok);
    assert_int_equal(r.presolve.samples, 1200);
    assert_sane(&k, "walter", &r);
    bf_fit_phase ph[8];
    assert_int_equal(phases_of(&k, ph), 5);
    assert_int_equal(ph[0], BF_PHASE_CANDIDATES);
    assert_int_equal(ph[1], BF_PHASE_SCREEN);
    assert_int_equal(ph[2], BF_PHASE_PRESOLVE);
    assert_int_equal(ph[3], BF_PHASE_DATA);
    assert_int_equal(ph[4], BF_PHASE_DONE);
    /* Every candidate, in order: 16 = the screen option (at least 4 per start). */
    const bf_progress_report *c = first_in(&k, BF_PHASE_CANDIDATES);
    assert_int_equal(c->starts, 16);
    assert_int_equal(c->starts, r.candidates);
    assert_int_equal(c->samples, BF_FIT_SCREEN_SAMPLES);
    assert_int_equal(starts_in(&k, BF_PHASE_CANDIDATES), 16);
    /* Every start the result counts, solved on the screening set (and revives after). */
    const bf_progress_report *sc = first_in(&k, BF_PHASE_SCREEN);
    assert_int_equal(sc->samples, BF_FIT_SCREEN_SAMPLES);
    assert_int_equal(r.starts, 4);
    assert_true(sc->starts >= r.starts);
    assert_true(starts_in(&k, BF_PHASE_SCREEN) >= r.starts);
    assert_int_equal(r.screen.samples, BF_FIT_SCREEN_SAMPLES);
    /* The presolve's subsample, then the whole data once. */
    assert_int_equal(first_in(&k, BF_PHASE_PRESOLVE)->samples, 1200);
    assert_true(starts_in(&k, BF_PHASE_PRESOLVE) >= 1);
    const bf_progress_report *d = first_in(&k, BF_PHASE_DATA);
    assert_int_equal(d->samples, 1439);
    assert_int_equal(d->starts, 1);
    assert_int_equal(starts_in(&k, BF_PHASE_DATA), 1);
    /* The whole set's last iteration reaches the result's cost. */
    const bf_progress_report *last = &k.r[k.n - 2].r;
    assert_int_equal(last->phase, BF_PHASE_DATA);
    ts_assert_rel(last->cost, r.solution.final_cost, 1e-12, "last reported cost");
    bf_fit_result_clear(&r);
    seen_clear(&k);
    bf_samples_free(s);
}

/* Data of at most BF_FIT_SCREEN_SAMPLES is its own screening set: candidates and starts
 * on all of it, and nothing after. */
static void test_small_data_is_the_screening_set(void **state)
{
    (void)state;
    bf_samples *s = load(CAYMAN, "--rgb --subsample 600");
    assert_int_equal(s->n, 600);
    seen k;
    seen_init(&k);
    bf_fit_result r;
    fit_seen(s, "ward_iso", "--starts 3 --screen 12 --threads 1", &k, &r);
    assert_true(r.ok);
    assert_sane(&k, "ward_iso", &r);
    bf_fit_phase ph[8];
    assert_int_equal(phases_of(&k, ph), 3);
    assert_int_equal(ph[0], BF_PHASE_CANDIDATES);
    assert_int_equal(ph[1], BF_PHASE_SCREEN);
    assert_int_equal(ph[2], BF_PHASE_DONE);
    assert_int_equal(first_in(&k, BF_PHASE_CANDIDATES)->samples, 600);
    assert_int_equal(first_in(&k, BF_PHASE_CANDIDATES)->starts, 12);
    assert_int_equal(first_in(&k, BF_PHASE_SCREEN)->samples, 600);
    bf_fit_result_clear(&r);
    seen_clear(&k);
    bf_samples_free(s);
}

/* Plain multistart (screen 0): every start on the data, numbered 0 to starts - 1. */
static void test_plain_multistart(void **state)
{
    (void)state;
    bf_samples *s = load(CAYMAN, "--rgb --subsample 600");
    seen k;
    seen_init(&k);
    bf_fit_result r;
    fit_seen(s, "ward_iso", "--starts 3 --screen 0 --threads 1", &k, &r);
    assert_true(r.ok);
    assert_sane(&k, "ward_iso", &r);
    bf_fit_phase ph[8];
    assert_int_equal(phases_of(&k, ph), 2);
    assert_int_equal(ph[0], BF_PHASE_DATA);
    assert_int_equal(ph[1], BF_PHASE_DONE);
    assert_int_equal(first_in(&k, BF_PHASE_DATA)->starts, 3);
    assert_int_equal(first_in(&k, BF_PHASE_DATA)->samples, 600);
    assert_int_equal(starts_in(&k, BF_PHASE_DATA), 3);
    assert_int_equal(k.r[k.n - 2].r.start, 2);
    bf_fit_result_clear(&r);
    seen_clear(&k);
    bf_samples_free(s);
}

/* The old callback keeps its calls (one per solver iteration) beside the reports, and
 * neither changes the fit. */
static void test_old_callback_beside_reports(void **state)
{
    (void)state;
    bf_samples *s = load(CAYMAN, "--rgb --subsample 800");
    const char *words = "--starts 3 --screen 12 --threads 1";
    bf_error err;
    bf_fit_result plain, old_only, both;
    bf_options *o = ts_options(BF_TASK_FIT, words);
    bf_fit_result_init(&plain);
    assert_int_equal(bf_fit(s, "walter", o, &plain, &err), BF_OK);

    seen a, b;
    seen_init(&a);
    seen_init(&b);
    bf_options_set_progress(o, old_progress, &a);
    bf_fit_result_init(&old_only);
    assert_int_equal(bf_fit(s, "walter", o, &old_only, &err), BF_OK);
    assert_true(a.old_calls > 0);

    bf_options_set_progress(o, old_progress, &b);
    bf_options_set_progress_report(o, record, &b);
    bf_fit_result_init(&both);
    assert_int_equal(bf_fit(s, "walter", o, &both, &err), BF_OK);
    assert_int_equal(b.old_calls, a.old_calls);
    /* One report per solver iteration, and one per candidate besides. */
    int candidates = 0;
    for (int i = 0; i < b.n; i++)
        candidates += b.r[i].r.phase == BF_PHASE_CANDIDATES;
    assert_int_equal(candidates, 12);
    assert_int_equal(b.r[b.n - 1].r.phase, BF_PHASE_DONE);
    assert_int_equal(b.n - candidates - 1, b.old_calls);
    const int P = bf_model_nvalues(plain.model);
    assert_memory_equal(plain.x, old_only.x, (size_t)P * sizeof *plain.x);
    assert_memory_equal(plain.x, both.x, (size_t)P * sizeof *plain.x);
    bf_fit_result_clear(&plain);
    bf_fit_result_clear(&old_only);
    bf_fit_result_clear(&both);
    bf_options_free(o);
    seen_clear(&a);
    seen_clear(&b);
    bf_samples_free(s);
}

/* A report returning non-zero stops the fit there (one thread: not one report after it),
 * in the candidates and in a solve. */
static void test_report_stops_the_fit(void **state)
{
    (void)state;
    bf_samples *s = load(CAYMAN, "--rgb --subsample 800");
    static const int stop_at[] = {5, 30};
    for (size_t t = 0; t < sizeof stop_at / sizeof stop_at[0]; t++) {
        seen k;
        seen_init(&k);
        k.stop_at = stop_at[t];
        bf_fit_result r;
        fit_seen(s, "walter", "--starts 3 --screen 12 --threads 1", &k, &r);
        assert_int_equal(k.n, stop_at[t]);
        assert_int_equal(k.r[k.n - 1].r.phase, t == 0 ? BF_PHASE_CANDIDATES : BF_PHASE_SCREEN); /* no DONE */
        assert_int_equal(r.solution.stop, BF_STOP_CANCELLED);
        assert_false(r.ok);
        bf_fit_result_clear(&r);
        seen_clear(&k);
    }
    bf_samples_free(s);
}

/* A comparison's reports name the material (index and name), the model and, ranked by
 * cv, the fold; every fit reports, from two jobs at once, and says once that it is done. */
static void test_compare_names_material_model_fold(void **state)
{
    (void)state;
    bf_samples *data[2] = {load(CAYMAN, "--rgb --subsample 400"),
                           load(BRDFIT_EXAMPLES "/cornell/garnet_red.brdf", "--rgb --subsample 400")};
    const char *names[2] = {"cayman", "garnet"};
    const char *specs[2] = {"lambert", "ward_iso"};
    bf_compare *c = NULL;
    bf_error err;
    assert_int_equal(bf_compare_new(2, names, 2, specs, &c, &err), BF_OK);
    bf_options *o = ts_options(BF_TASK_COMPARE, "--starts 2 --screen 8 --threads 2 --jobs 2 --rank cv --folds 2");
    seen k;
    seen_init(&k);
    bf_options_set_progress_report(o, record, &k);
    assert_int_equal(bf_compare_run(c, data, o, NULL, NULL, &err), BF_OK);
    int pairs[2][2][3] = {{{0}}}, done[2][2][3] = {{{0}}}; /* material, model, fold */
    for (int i = 0; i < k.n; i++) {
        const bf_progress_report *r = &k.r[i].r;
        assert_true(r->material >= 0 && r->material < 2);
        assert_true(r->model >= 0 && r->model < 2);
        assert_true(r->fold >= 0 && r->fold <= 2);
        assert_string_equal(k.r[i].material_name, names[r->material]);
        assert_string_equal(k.r[i].spec, specs[r->model]);
        assert_true(r->samples <= data[r->material]->n);
        pairs[r->material][r->model][r->fold]++;
        done[r->material][r->model][r->fold] += r->phase == BF_PHASE_DONE;
    }
    for (int m = 0; m < 2; m++)
        for (int j = 0; j < 2; j++)
            for (int f = 0; f < 3; f++) {
                if (!pairs[m][j][f])
                    fail_msg("no report from %s x %s, fold %d", names[m], specs[j], f);
                if (done[m][j][f] != 1)
                    fail_msg("%s x %s, fold %d: %d reports of its end", names[m], specs[j], f, done[m][j][f]);
            }
    seen_clear(&k);
    bf_options_free(o);
    bf_compare_free(c);
    bf_samples_free(data[0]);
    bf_samples_free(data[1]);
}

/* A selection's reports name the candidate (model) and no material. */
static void test_select_names_the_candidate(void **state)
{
    (void)state;
    bf_samples *data = load(CAYMAN, "--rgb --subsample 400");
    const char *specs[3] = {"lambert", "ward_iso", "walter"};
    bf_options *o = ts_options(BF_TASK_SELECT, "--starts 2 --screen 8 --threads 1");
    bf_select *s = NULL;
    bf_error err;
    assert_int_equal(bf_select_new(3, specs, data->channels, o, &s, &err), BF_OK);
    seen k;
    seen_init(&k);
    bf_options_set_progress_report(o, record, &k);
    assert_int_equal(bf_select_run(s, data, o, NULL, NULL, &err), BF_OK);
    int per[3] = {0}, done[3] = {0};
    for (int i = 0; i < k.n; i++) {
        const bf_progress_report *r = &k.r[i].r;
        assert_true(r->model >= 0 && r->model < 3);
        assert_int_equal(r->material, -1);
        assert_null(r->material_name);
        assert_string_equal(k.r[i].spec, specs[r->model]);
        per[r->model]++;
        done[r->model] += r->phase == BF_PHASE_DONE;
    }
    for (int j = 0; j < 3; j++) {
        assert_true(per[j] > 0);
        assert_int_equal(done[j], 1);
    }
    seen_clear(&k);
    bf_select_free(s);
    bf_options_free(o);
    bf_samples_free(data);
}

static void test_phase_names(void **state)
{
    (void)state;
    assert_string_equal(bf_fit_phase_name(BF_PHASE_CANDIDATES), "candidates");
    assert_string_equal(bf_fit_phase_name(BF_PHASE_SCREEN), "screen");
    assert_string_equal(bf_fit_phase_name(BF_PHASE_PRESOLVE), "presolve");
    assert_string_equal(bf_fit_phase_name(BF_PHASE_DATA), "data");
    assert_string_equal(bf_fit_phase_name(BF_PHASE_DONE), "done");
    assert_string_equal(bf_fit_phase_name((bf_fit_phase)99), "?");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fit_reports_every_phase),    cmocka_unit_test(test_small_data_is_the_screening_set),
        cmocka_unit_test(test_plain_multistart),           cmocka_unit_test(test_old_callback_beside_reports),
        cmocka_unit_test(test_report_stops_the_fit),       cmocka_unit_test(test_compare_names_material_model_fold),
        cmocka_unit_test(test_select_names_the_candidate), cmocka_unit_test(test_phase_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
