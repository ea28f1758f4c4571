/* Model selection: the order of preference on hand-made candidates, and on synthetic
 * data where the right answer is known (Lambert data selects lambert, isotropic GGX
 * data no anisotropic model, two-lobe data two lobes, a white highlight mono), and a
 * scene that hides the highlight changes the choice. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>
#include <cmocka.h>

#include "brdfit/scene.h"
#include "brdfit/select.h"
#include "select/select_run.h"
#include "compare/compare_impl.h"
#include "support.h"

/* Select options from command-line words; the last set made is kept until the next. */
static const bf_options *ts_select_options(const char *words)
{
    static bf_options *last;
    bf_options_free(last);
    last = ts_options(BF_TASK_SELECT, words);
    return last;
}

/* ---- The order of preference, without fitting ------------------------------------- */

static void set_error(bf_select *s, int i, bf_compare_state state, double e)
{
    s->c[i].state = state;
    if (!s->c[i].result) { /* freed by bf_select_clear, as a fit's would be */
        s->c[i].result = malloc(sizeof *s->c[i].result);
        assert_non_null(s->c[i].result);
        bf_fit_result_init(s->c[i].result);
    }
    s->c[i].result->metrics.rmse_log = e;
}

static void test_choose_order(void **state)
{
    (void)state;
    const char *specs[] = {"walter", "walter:mono=specular", "walter_aniso:mono=specular", "lambert",
                           "walter:lobes=2,mono=specular"};
    bf_select s;
    bf_error err;
    assert_int_equal(bf_select_init(&s, 5, specs, 3, ts_select_options("--tolerance 0.05 --abs-tolerance 0.0"), &err),
                     BF_OK);
    assert_int_equal(s.c[0].k, 8);
    assert_int_equal(s.c[1].k, 6);
    assert_int_equal(s.c[2].k, 7);
    assert_int_equal(s.c[3].k, 3);
    assert_int_equal(s.c[2].anisotropic, 1);
    assert_int_equal(s.c[4].lobes, 2);
    assert_int_equal(s.c[0].colored_specular, 1);
    assert_int_equal(s.c[1].colored_specular, 0);

    /* Lambert far off; the others within 5% of the best (walter, 0.100). */
    set_error(&s, 0, BF_CMP_OK, 0.100);
    set_error(&s, 1, BF_CMP_OK, 0.104);
    set_error(&s, 2, BF_CMP_OK, 0.1001);
    set_error(&s, 3, BF_CMP_OK, 0.5);
    set_error(&s, 4, BF_CMP_OK, 0.1002);
    bf_select_choose(&s);
    assert_int_equal(s.best, 0);
    assert_int_equal(s.chosen, 1); /* fewest parameters among those within */
    assert_false(s.c[3].within);
    assert_true(s.c[1].within);

    /* Just outside the tolerance: the next simplest. */
    set_error(&s, 1, BF_CMP_OK, 0.1051);
    bf_select_choose(&s);
    assert_int_equal(s.chosen, 2);

    /* A failed fit is never chosen, however good its error looks. */
    set_error(&s, 2, BF_CMP_FAILED, 0.01);
    bf_select_choose(&s);
    assert_int_equal(s.best, 0);
    assert_int_equal(s.chosen, 0); /* walter (8) before walter:lobes=2,mono (9) */

    /* An absolute tolerance makes near-equal tiny errors equal. */
    set_error(&s, 3, BF_CMP_OK, 3e-15);
    set_error(&s, 0, BF_CMP_OK, 1e-16);
    bf_select_choose(&s);
    assert_int_equal(s.chosen, 0); /* relative alone: only the luckiest rounding */
    s.abs_tolerance = 1e-9;
    bf_select_choose(&s);
    assert_int_equal(s.chosen, 3);

    /* The order for tables: k first. */
    int order[5];
    bf_select_order(&s, order);
    assert_int_equal(order[0], 3);
    assert_int_equal(s.c[order[4]].k, 9);
    bf_select_clear(&s);

    /* Nothing fitted: no choice. */
    const char *one[] = {"lambert"};
    assert_int_equal(
        bf_select_init(&s, 1, one, 1, ts_select_options("--error rmse --tolerance 0.05 --abs-tolerance 0.0"), &err),
        BF_OK);
    set_error(&s, 0, BF_CMP_ERROR, NAN);
    bf_select_choose(&s);
    assert_int_equal(s.chosen, -1);
    assert_int_equal(s.best, -1);
    bf_select_clear(&s);
}

/* Equal k: isotropic before anisotropic, one lobe before two, mono before colour. */
static int choose_between(const char *a, const char *b, int C, int k)
{
    const char *specs[] = {a, b};
    bf_select s;
    bf_error err;
    assert_int_equal(bf_select_init(&s, 2, specs, C, ts_select_options("--tolerance 0.05 --abs-tolerance 0.0"), &err),
                     BF_OK);
    assert_int_equal(s.c[0].k, k);
    assert_int_equal(s.c[1].k, k);
    set_error(&s, 0, BF_CMP_OK, 0.1);
    set_error(&s, 1, BF_CMP_OK, 0.1);
    bf_select_choose(&s);
    int chosen = s.chosen;
    bf_select_clear(&s);
    return chosen;
}

static void test_tie_breaks(void **state)
{
    (void)state;
    /* Isotropic before anisotropic: cook_torrance and ward, 4 parameters on one channel. */
    assert_int_equal(choose_between("ward", "cook_torrance", 1, 4), 1);
    /* ... even when the isotropic one has two lobes (9 each on RGB). */
    assert_int_equal(choose_between("walter_aniso", "walter:lobes=2,mono=specular", 3, 9), 1);
    /* One lobe before two (9 each). */
    assert_int_equal(choose_between("walter:lobes=2,mono=specular", "lafortune", 3, 9), 1);
    /* A monochrome highlight before a coloured one (7 each). */
    assert_int_equal(choose_between("ashikhmin_shirley_iso", "lafortune:mono=specular", 3, 7), 1);
    /* All equal: the lower error, then the earlier candidate. */
    assert_int_equal(choose_between("walter", "cook_torrance", 3, 8), 0);

    /* A bad spec is refused up front. */
    const char *bad[] = {"walter", "nonesuch"};
    bf_select s;
    bf_error err;
    assert_int_equal(bf_select_init(&s, 2, bad, 3, ts_select_options("--tolerance 0.05 --abs-tolerance 0.0"), &err),
                     BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "nonesuch"));
}

/* ---- Synthetic data ----------------------------------------------------------------- */

enum { NSAMPLES = 3000 };

/* NSAMPLES samples of model spec at x (3 channels), a third near the mirror direction,
 * with 1% multiplicative noise. */
static bf_samples *synth(const char *spec, const double *x, uint64_t seed)
{
    bf_error err;
    bf_samples *s = NULL;
    bf_samples_new(NSAMPLES, 3, &s, &err);
    assert_non_null(s);
    ts_rng r = {seed};
    for (size_t i = 0; i < NSAMPLES; i++)
        ts_random_pair_deg(&r, i % 3 == 0, &s->theta_i[i], &s->phi_i[i], &s->theta_o[i], &s->phi_o[i]);
    bf_model *m = ts_model(spec, 3);
    const bf_geometry *g = NULL;
    bf_samples_geometry(s, &g, &err);
    assert_non_null(g);
    bf_model_eval(m, x, g, s->value, NULL);
    for (size_t k = 0; k < NSAMPLES * 3; k++)
        s->value[k] *= 1.0 + 0.02 * (ts_uniform(&r) - 0.5);
    bf_model_free(m);
    return s;
}

static bf_fit_options fit_options(void)
{
    bf_fit_options o;
    memset(&o, 0, sizeof o);
    bf_objective_options_init(&o.objective); /* the embedded structs carry their sizes */
    bf_solver_options_init(&o.solver);
    o.objective.residual = BF_RESIDUAL_LOG;
    o.objective.use_weights = 1;
    o.solver.backend = BF_BACKEND_CERES;
    o.solver.threads = 1;
    o.starts = 1;
    return o;
}

static const bf_select_candidate *select_on(bf_samples *data, int n, const char *const *specs, bf_select *s,
                                            int weighted)
{
    bf_error err;
    assert_int_equal(
        bf_select_init(s, n, specs, data->channels, ts_select_options("--tolerance 0.05 --abs-tolerance 1e-6"), &err),
        BF_OK);
    bf_fit_options o = fit_options();
    o.weighted_metrics = weighted;
    assert_int_equal(select_run_with(s, data, &o, 1, NULL, &err), BF_OK);
    assert_true(s->chosen >= 0);
    return &s->c[s->chosen];
}

static void test_lambert_data_selects_lambert(void **state)
{
    (void)state;
    const double x[] = {0.7, 0.4, 0.2};
    bf_samples *data = synth("lambert", x, 1);
    const char **specs;
    int n = bf_select_default_candidates(3, &specs);
    assert_true(n > 10);
    bf_select s;
    const bf_select_candidate *c = select_on(data, n, specs, &s, 0);
    assert_string_equal(c->spec, "lambert");
    /* Every richer model fits it as well (the noise floor), and none is chosen. */
    assert_true(s.c[s.best].error > 0.0);
    free(specs);
    bf_select_clear(&s);
    bf_samples_free(data);
}

static const char *const single_lobe_candidates[] = {
    "lambert",
    "walter:mono=specular",
    "walter",
    "walter_aniso:mono=specular",
    "walter_aniso",
    "ward:mono=specular",
    "walter:lobes=2,mono=specular",
    "walter:lobes=2",
};
enum { NSINGLE = sizeof single_lobe_candidates / sizeof single_lobe_candidates[0] };

static void test_isotropic_ggx_selects_isotropic_mono(void **state)
{
    (void)state;
    /* walter: rho_d, rho_s (white), alpha, f0 */
    const double x[] = {0.5, 0.3, 0.1, 0.6, 0.6, 0.6, 0.12, 0.05};
    bf_samples *data = synth("walter", x, 2);
    bf_select s;
    const bf_select_candidate *c = select_on(data, NSINGLE, single_lobe_candidates, &s, 0);
    assert_false(c->anisotropic);
    assert_int_equal(c->lobes, 1);
    assert_string_equal(c->spec, "walter:mono=specular");
    /* The anisotropic model fits as well, with alpha_x = alpha_y. */
    assert_true(s.c[3].within);
    bf_select_clear(&s);
    bf_samples_free(data);
}

static void test_colored_highlight_needs_color(void **state)
{
    (void)state;
    const double x[] = {0.1, 0.1, 0.1, 0.2, 0.5, 0.9, 0.12, 0.05};
    bf_samples *data = synth("walter", x, 3);
    bf_select s;
    const bf_select_candidate *c = select_on(data, NSINGLE, single_lobe_candidates, &s, 0);
    assert_string_equal(c->spec, "walter");
    assert_true(c->colored_specular);
    assert_false(s.c[1].within); /* the white highlight cannot follow it */
    bf_select_clear(&s);
    bf_samples_free(data);
}

static void test_two_lobe_data_selects_two_lobes(void **state)
{
    (void)state;
    /* walter:lobes=2: rho_d, rho_s_1, alpha_1, f0_1, rho_s_2, alpha_2, f0_2 */
    const double x[] = {0.3, 0.2, 0.1, 0.5, 0.5, 0.5, 0.04, 0.05, 0.5, 0.5, 0.5, 0.35, 0.05};
    bf_samples *data = synth("walter:lobes=2", x, 4);
    bf_select s;
    const bf_select_candidate *c = select_on(data, NSINGLE, single_lobe_candidates, &s, 0);
    assert_int_equal(c->lobes, 2);
    assert_string_equal(c->spec, "walter:lobes=2,mono=specular");
    bf_select_clear(&s);
    bf_samples_free(data);
}

/* A diffuse base with a sharp highlight: the whole data set needs the lobe; a scene
 * whose camera never sees the mirror direction (lights near the normal, views beyond
 * 50 degrees) is served by lambert, and the error is reported over that scene. */
static void test_scene_changes_the_choice(void **state)
{
    (void)state;
    const double x[] = {0.5, 0.4, 0.3, 0.8, 0.8, 0.8, 0.05, 0.05};
    static const char *const specs[] = {"lambert", "walter:mono=specular", "walter"};
    bf_samples *data = synth("walter", x, 5);
    bf_select s;
    const bf_select_candidate *c = select_on(data, 3, specs, &s, 0);
    assert_string_equal(c->spec, "walter:mono=specular");
    assert_false(s.c[0].within);
    bf_select_clear(&s);

    bf_scene *scene;
    bf_error err;
    static const char text[] = "{\"light\": {\"theta\": [0, 20]}, \"view\": {\"theta\": [50, 85]},"
                               " \"reciprocal\": false}";
    assert_int_equal(bf_scene_parse(text, "scene.json", &scene, &err), BF_OK);
    size_t kept = 0;
    assert_int_equal(bf_scene_apply(scene, data, &kept, &err), BF_OK);
    assert_true(kept > 50 && kept < NSAMPLES / 4);
    c = select_on(data, 3, specs, &s, 1);
    assert_string_equal(c->spec, "lambert");
    assert_int_equal(s.c[0].result->metrics.n, kept * 3);
    bf_select_clear(&s);
    bf_scene_free(scene);
    bf_samples_free(data);
}

static void test_json(void **state)
{
    (void)state;
    const double x[] = {0.7, 0.4, 0.2};
    bf_samples *data = synth("lambert", x, 6);
    static const char *const specs[] = {"lambert", "walter", "nishino:fresnel=none"};
    bf_select s;
    select_on(data, 3, specs, &s, 0);
    bf_error err;
    const char *path = ts_tmp_path("select.json");
    assert_int_equal(bf_select_write_json(&s, "data.csv", path, &err), BF_OK);
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    char buf[65536];
    size_t len = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[len] = '\0';
    cJSON *root = cJSON_Parse(buf);
    assert_non_null(root);
    assert_string_equal(cJSON_GetObjectItem(root, "chosen")->valuestring, "lambert");
    assert_string_equal(cJSON_GetObjectItem(root, "data")->valuestring, "data.csv");
    cJSON *list = cJSON_GetObjectItem(root, "candidates");
    assert_int_equal(cJSON_GetArraySize(list), 3);
    cJSON *first = cJSON_GetArrayItem(list, 0);
    assert_true(cJSON_IsTrue(cJSON_GetObjectItem(first, "chosen")));
    assert_int_equal(cJSON_GetObjectItem(first, "k")->valueint, 3);
    assert_non_null(cJSON_GetObjectItem(cJSON_GetObjectItem(first, "params"), "rho_d"));
    assert_non_null(cJSON_GetObjectItem(cJSON_GetObjectItem(first, "metrics"), "rmse_log"));
    cJSON_Delete(root);
    bf_select_clear(&s);
    bf_samples_free(data);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_choose_order),
        cmocka_unit_test(test_tie_breaks),
        cmocka_unit_test(test_lambert_data_selects_lambert),
        cmocka_unit_test(test_isotropic_ggx_selects_isotropic_mono),
        cmocka_unit_test(test_colored_highlight_needs_color),
        cmocka_unit_test(test_two_lobe_data_selects_two_lobes),
        cmocka_unit_test(test_scene_changes_the_choice),
        cmocka_unit_test(test_json),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
