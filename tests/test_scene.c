/* Scenes: the file format and its errors (with lines), which samples ranges keep (with
 * and without reciprocity), the kernel of explicit directions, rotation about the normal,
 * bf_scene_apply's normalisation; and weighted metrics against unweighted ones and
 * against a set with duplicated samples. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/fit.h"
#include "brdfit/metrics.h"
#include "brdfit/scene.h"
#include "support.h"

static bf_scene *parse_ok(const char *text)
{
    bf_scene *sc = NULL;
    bf_error err = {0};
    if (bf_scene_parse(text, "scene.json", &sc, &err) != BF_OK)
        fail_msg("scene rejected: %s", err.msg);
    return sc;
}

/* ---- Format ---------------------------------------------------------------------- */

static void test_defaults_and_examples(void **state)
{
    (void)state;
    bf_scene *sc = parse_ok("{}");
    assert_true(sc->light_theta.lo == 0 && sc->light_theta.hi == 90);
    assert_true(sc->view_theta.lo == 0 && sc->view_theta.hi == 90);
    assert_true(sc->radius == 5.0);
    assert_int_equal(sc->reciprocal, 1);
    assert_int_equal(sc->nlights + sc->nviews, 0);
    assert_null(sc->description);
    bf_scene_free(sc);

    bf_error err = {0};
    assert_int_equal(bf_scene_read(BRDFIT_EXAMPLES "/scenes/product_shot.json", &sc, &err), BF_OK);
    assert_true(sc->light_theta.lo == 0 && sc->light_theta.hi == 45);
    assert_true(sc->view_theta.lo == 0 && sc->view_theta.hi == 60);
    assert_non_null(sc->description);
    bf_scene_free(sc);

    assert_int_equal(bf_scene_read(BRDFIT_EXAMPLES "/scenes/turntable.json", &sc, &err), BF_OK);
    assert_int_equal(sc->nlights, 3);
    assert_int_equal(sc->nviews, 1);
    assert_true(sc->lights[0].theta == 40 && sc->lights[0].phi == 45 && sc->lights[0].weight == 3);
    assert_true(sc->lights[2].weight == 1.5);
    assert_true(sc->views[0].weight == 1.0); /* default */
    assert_true(sc->radius == 8);
    bf_scene_free(sc);

    assert_int_equal(bf_scene_read(BRDFIT_EXAMPLES "/scenes/missing.json", &sc, &err), BF_ERR_IO);
    assert_null(sc);
    assert_non_null(strstr(err.msg, "missing.json"));
}

static void test_parse_errors(void **state)
{
    (void)state;
    static const struct {
        const char *text;
        int line;
        int code;
        const char *fragment;
    } cases[] = {
        {"{\n  \"radius\": 5,,\n  \"reciprocal\": true\n}", 2, BF_ERR_PARSE, "malformed JSON"},
        {"{\n  \"radius\": 5\n", 3, BF_ERR_PARSE, "malformed JSON"},
        {"{} trailing", 1, BF_ERR_PARSE, "malformed JSON"},
        {"[1, 2]", 1, BF_ERR_PARSE, "must be a JSON object"},
        {"{\n  \"description\": \"x\",\n  \"camera\": 1\n}", 3, BF_ERR_PARSE, "unknown key \"camera\""},
        {"{\n  \"light\": {\n    \"phi\": [0, 10]\n  }\n}", 3, BF_ERR_PARSE, "\"light\": unknown key \"phi\""},
        {"{\"views\": [{\"theta\": 10},\n {\"theta\": 20, \"azimuth\": 3}]}", 2, BF_ERR_PARSE,
         "views[1]: unknown key \"azimuth\""},
        {"{\n  \"light\": [0, 45]\n}", 2, BF_ERR_PARSE, "\"light\" must be an object"},
        {"{\n  \"view\": {\"theta\": [0, 45, 60]}\n}", 2, BF_ERR_PARSE, "view.theta must be [lo, hi]"},
        {"{\n  \"view\": {\"theta\": [0, \"60\"]}\n}", 2, BF_ERR_PARSE, "view.theta upper bound must be a number"},
        {"{\n  \"radius\": \"5\"\n}", 2, BF_ERR_PARSE, "\"radius\" must be a number"},
        {"{\n\n  \"reciprocal\": 1\n}", 3, BF_ERR_PARSE, "\"reciprocal\" must be true or false"},
        {"{\"description\": 3}", 1, BF_ERR_PARSE, "\"description\" must be a string"},
        {"{\n  \"lights\": {\"theta\": 30}\n}", 2, BF_ERR_PARSE, "\"lights\" must be an array"},
        {"{\n  \"lights\": []\n}", 2, BF_ERR_PARSE, "\"lights\" is empty"},
        {"{\n  \"lights\": [30]\n}", 2, BF_ERR_PARSE, "lights[0] must be an object"},
        {"{\n  \"lights\": [{\"phi\": 30}]\n}", 2, BF_ERR_PARSE, "lights[0] has no \"theta\""},
        {"{\n  \"light\": {\"theta\": [0, 95]}\n}", 2, BF_ERR_RANGE,
         "light.theta upper bound = 95 degrees is outside [0, 90]"},
        {"{\n  \"view\": {\"theta\": [-1, 45]}\n}", 2, BF_ERR_RANGE, "outside [0, 90]"},
        /* The second entry's theta, on its own line, though "theta" appears earlier. */
        {"{\n  \"lights\": [\n    {\"theta\": 30, \"phi\": 0},\n    {\"theta\": -5}\n  ]\n}", 4, BF_ERR_RANGE,
         "lights[1].theta = -5 degrees is outside [0, 90]"},
        {"{\n  \"light\": {\"theta\": [60, 30]}\n}", 2, BF_ERR_RANGE, "light.theta: lower bound 60 > upper bound 30"},
        {"{\n  \"lights\": [{\"theta\": 30},\n             {\"theta\": 40, \"weight\": 0}]\n}", 3, BF_ERR_RANGE,
         "lights[1].weight = 0 must be > 0"},
        {"{\"views\": [{\"theta\": 30, \"weight\": -2}]}", 1, BF_ERR_RANGE, "views[0].weight = -2 must be > 0"},
        {"{\n  \"views\": [{\"theta\": 30, \"weight\": \"high\"}]\n}", 2, BF_ERR_PARSE,
         "views[0].weight must be a number"},
        {"{\n  \"views\": [{\"theta\": 30, \"phi\": null}]\n}", 2, BF_ERR_PARSE, "views[0].phi must be a number"},
        {"{\n  \"radius\": 0\n}", 2, BF_ERR_RANGE, "\"radius\" = 0 degrees must be in (0, 180]"},
        {"{\n  \"light\": {},\n  \"radius\": -3\n}", 3, BF_ERR_RANGE, "\"radius\" = -3"},
        /* A key twice: the reader used the first, a rewrite would keep both. */
        {"{\n  \"radius\": 5,\n  \"radius\": 10\n}", 2, BF_ERR_PARSE, "\"radius\" given twice"},
        {"{\"lights\": [{\"theta\": 30},\n {\"theta\": 40, \"theta\": 50}]}", 2, BF_ERR_PARSE,
         "lights[1]: \"theta\" given twice"},
        /* Content quoted in messages is escaped and shortened. */
        {"{\n  \"\x1b[2J\": 1\n}", 2, BF_ERR_PARSE, "unknown key \"\\x1b[2J\""},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        bf_scene *sc = (bf_scene *)1;
        bf_error err = {0};
        int rc = bf_scene_parse(cases[k].text, "dir/scene.json", &sc, &err);
        char where[64];
        snprintf(where, sizeof where, "dir/scene.json:%d: ", cases[k].line);
        if (rc != cases[k].code || sc != NULL || strncmp(err.msg, where, strlen(where)) != 0 ||
            !strstr(err.msg, cases[k].fragment) || strchr(err.msg, '\n'))
            fail_msg("case %zu: code %d (want %d), message '%s' (want '%s...%s')", k, rc, cases[k].code, err.msg, where,
                     cases[k].fragment);
    }
}

/* ---- Weights ----------------------------------------------------------------------- */

static bf_samples *make_samples(size_t n, const double (*dirs)[4])
{
    bf_samples *s = NULL;
    bf_samples_new(n, 1, &s, NULL);
    assert_non_null(s);
    for (size_t i = 0; i < n; i++) {
        s->theta_i[i] = dirs[i][0];
        s->phi_i[i] = dirs[i][1];
        s->theta_o[i] = dirs[i][2];
        s->phi_o[i] = dirs[i][3];
        s->value[i] = 0.1 * (double)(i + 1);
    }
    return s;
}

static void weights_of(const char *scene, bf_samples *s, double *w)
{
    bf_scene *sc = parse_ok(scene);
    bf_error err = {0};
    if (bf_scene_weights(sc, s, w, &err) != BF_OK)
        fail_msg("bf_scene_weights: %s", err.msg);
    bf_scene_free(sc);
}

static void test_ranges(void **state)
{
    (void)state;
    static const double dirs[7][4] = {
        {10, 0, 20, 180}, /* inside */
        {50, 0, 20, 180}, /* light too low; inside with light and view swapped */
        {50, 0, 70, 180}, /* outside either way */
        {30, 0, 60, 0},   /* on the view bound: inside */
        {45, 0, 61, 0},   /* view just beyond; swapped, the light is */
        {0, 0, 0, 0},     /* both at the normal */
        {70, 0, 10, 0},   /* swapped, the view is beyond 60 */
    };
    bf_samples *s = make_samples(7, dirs);
    double w[7];
    const double recip[7] = {1, 1, 0, 1, 0, 1, 0}, direct[7] = {1, 0, 0, 1, 0, 1, 0};
    weights_of("{\"light\": {\"theta\": [0, 45]}, \"view\": {\"theta\": [0, 60]}}", s, w);
    for (int i = 0; i < 7; i++)
        if (w[i] != recip[i])
            fail_msg("reciprocal: sample %d weight %g, want %g", i, w[i], recip[i]);
    weights_of("{\"light\": {\"theta\": [0, 45]}, \"view\": {\"theta\": [0, 60]}, \"reciprocal\": false}", s, w);
    for (int i = 0; i < 7; i++)
        if (w[i] != direct[i])
            fail_msg("direct: sample %d weight %g, want %g", i, w[i], direct[i]);

    /* A ranges-only scene selects: no weights appear on unweighted data. */
    bf_scene *sc = parse_ok("{\"light\": {\"theta\": [0, 45]}, \"view\": {\"theta\": [0, 60]}}");
    size_t kept = 0;
    bf_error err = {0};
    assert_int_equal(bf_scene_apply(sc, s, &kept, &err), BF_OK);
    assert_int_equal(kept, 4);
    assert_int_equal(s->n, 4);
    assert_null(s->weight);
    const double ti_kept[4] = {10, 50, 30, 0};
    for (int i = 0; i < 4; i++)
        assert_true(s->theta_i[i] == ti_kept[i]);
    assert_true(s->value[1] == 0.2 && s->value[3] == 0.1 * 6);
    bf_scene_free(sc);
    bf_samples_free(s);
}

static void test_explicit_kernel(void **state)
{
    (void)state;
    static const double dirs[][4] = {
        {30, 0, 40, 180},                        /* exactly the scene's configuration */
        {30, 0, 50, 180},                        /* view 10 degrees = 2 radius away */
        {40, 0, 40, 180},                        /* light 2 radius away */
        {30, 0, 56, 180},                        /* view beyond 3 radius */
        {46, 0, 40, 180},                        /* light beyond 3 radius */
        {40, 180, 30, 0},                        /* the configuration with light and view swapped */
        {30, 0, 40, 180 - 10.0 / sin(40 * DEG)}, /* about 2 radius away in azimuth */
    };
    const size_t n = sizeof dirs / sizeof dirs[0];
    bf_samples *s = make_samples(n, dirs);
    double w[sizeof dirs / sizeof dirs[0]];
    const char *scene = "{\"lights\": [{\"theta\": 30, \"phi\": 0, \"weight\": 2}],"
                        " \"views\": [{\"theta\": 40, \"phi\": 180}], \"radius\": 5, \"reciprocal\": %s}";
    char text[256];
    snprintf(text, sizeof text, scene, "false");
    weights_of(text, s, w);
    ts_assert_rel(w[0], 2.0, 1e-12, "at the direction");
    ts_assert_rel(w[1], 2.0 * exp(-2.0), 1e-9, "view 2 radius away");
    ts_assert_rel(w[2], 2.0 * exp(-2.0), 1e-9, "light 2 radius away");
    assert_true(w[3] == 0.0);
    assert_true(w[4] == 0.0);
    ts_assert_rel(w[5], 2.0 * exp(-4.0), 1e-9, "swapped, not reciprocal");
    /* 10 degrees of azimuth arc at theta 40 is a great-circle angle a little under 10. */
    assert_true(w[6] > 2.0 * exp(-2.0) && w[6] < 2.0 * exp(-1.9));
    snprintf(text, sizeof text, scene, "true");
    weights_of(text, s, w);
    ts_assert_rel(w[5], 2.0, 1e-12, "swapped, reciprocal");
    ts_assert_rel(w[0], 2.0, 1e-12, "at the direction, reciprocal");

    /* Lights only: the polar angle alone counts. Views only, likewise. */
    weights_of("{\"lights\": [{\"theta\": 30, \"phi\": 77}], \"reciprocal\": false}", s, w);
    ts_assert_rel(w[0], 1.0, 1e-12, "lights only");
    ts_assert_rel(w[2], exp(-2.0), 1e-9, "lights only, 2 radius");
    weights_of("{\"views\": [{\"theta\": 50, \"weight\": 0.5}], \"reciprocal\": false}", s, w);
    ts_assert_rel(w[1], 0.5, 1e-12, "views only");
    ts_assert_rel(w[0], 0.5 * exp(-2.0), 1e-9, "views only, 2 radius");

    /* Several lights add up; ranges still cut. */
    weights_of("{\"lights\": [{\"theta\": 30}, {\"theta\": 40}], \"reciprocal\": false,"
               " \"light\": {\"theta\": [0, 35]}}",
               s, w);
    ts_assert_rel(w[0], 1.0 + exp(-2.0), 1e-9, "two lights");
    assert_true(w[2] == 0.0);
    bf_samples_free(s);
}

static void test_rotation_invariance(void **state)
{
    (void)state;
    ts_rng rng = {42};
    enum { N = 64 };
    double dirs[2 * N][4];
    for (int i = 0; i < N; i++) {
        /* Near the turntable's configurations so that weights are not all 0. */
        double ti = 30 + 40 * ts_uniform(&rng), pi_ = 360 * ts_uniform(&rng);
        double to = 45 + 30 * ts_uniform(&rng), po = pi_ + 360 * ts_uniform(&rng) - 180;
        double rot = 360 * ts_uniform(&rng) - 180;
        const double a[4] = {ti, pi_, to, po}, b[4] = {ti, pi_ + rot, to, po + rot};
        memcpy(dirs[i], a, sizeof a);
        memcpy(dirs[N + i], b, sizeof b);
    }
    bf_samples *s = make_samples(2 * N, (const double(*)[4])dirs);
    bf_scene *sc = NULL;
    bf_error err = {0};
    assert_int_equal(bf_scene_read(BRDFIT_EXAMPLES "/scenes/turntable.json", &sc, &err), BF_OK);
    double w[2 * N];
    assert_int_equal(bf_scene_weights(sc, s, w, &err), BF_OK);
    int positive = 0;
    for (int i = 0; i < N; i++) {
        ts_assert_near(w[N + i], w[i], 1e-9, 1e-12, "rotated pair");
        positive += w[i] > 0;
    }
    assert_true(positive > N / 4);

    /* Rotating the scene (every light and view) changes nothing either. */
    for (int k = 0; k < sc->nlights; k++)
        sc->lights[k].phi += 123.0;
    sc->views[0].phi += 123.0;
    double w2[2 * N];
    assert_int_equal(bf_scene_weights(sc, s, w2, &err), BF_OK);
    for (int i = 0; i < 2 * N; i++)
        ts_assert_near(w2[i], w[i], 1e-9, 1e-12, "rotated scene");

    /* Mirroring the scene (every azimuth negated) changes nothing: the relative azimuth
     * is folded, as an isotropic BRDF is the same at +dphi and -dphi. */
    for (int k = 0; k < sc->nlights; k++)
        sc->lights[k].phi = -sc->lights[k].phi;
    sc->views[0].phi = -sc->views[0].phi;
    sc->reciprocal = 0;
    assert_int_equal(bf_scene_weights(sc, s, w2, &err), BF_OK);
    for (int k = 0; k < sc->nlights; k++)
        sc->lights[k].phi = -sc->lights[k].phi;
    sc->views[0].phi = -sc->views[0].phi;
    assert_int_equal(bf_scene_weights(sc, s, w, &err), BF_OK);
    for (int i = 0; i < 2 * N; i++)
        ts_assert_near(w2[i], w[i], 1e-9, 1e-12, "mirrored scene");
    bf_scene_free(sc);
    bf_samples_free(s);
}

static void test_apply(void **state)
{
    (void)state;
    static const double dirs[][4] = {
        {30, 0, 40, 180}, {30, 0, 50, 180}, {80, 0, 10, 0}, {40, 0, 40, 180}, {30, 0, 89, 180},
    };
    const char *text = "{\"lights\": [{\"theta\": 30}], \"views\": [{\"theta\": 40, \"phi\": 180}],"
                       " \"reciprocal\": false}";
    bf_samples *s = make_samples(5, dirs);
    double w[5];
    weights_of(text, s, w);
    assert_true(w[2] == 0.0 && w[4] == 0.0);
    assert_true(w[0] > 0 && w[1] > 0 && w[3] > 0);
    /* The data's own weights stay as they were; the scene's go apart. */
    assert_int_equal(bf_samples_add_weights(s, NULL), BF_OK);
    const double own[5] = {1, 3, 5, 0.5, 7};
    memcpy(s->weight, own, sizeof own);
    bf_scene *sc = parse_ok(text);
    size_t kept = 0;
    bf_error err = {0};
    assert_int_equal(bf_scene_apply(sc, s, &kept, &err), BF_OK);
    assert_int_equal(kept, 3);
    assert_int_equal(s->n, 3);
    const int from[3] = {0, 1, 3};
    double mean = (w[0] + w[1] + w[3]) / 3.0;
    for (int k = 0; k < 3; k++) {
        assert_true(s->weight[k] == own[from[k]]);
        ts_assert_rel(s->scene_weight[k], w[from[k]] / mean, 1e-12, "scene weight");
        assert_true(s->theta_o[k] == dirs[from[k]][2] && s->theta_i[k] == dirs[from[k]][0]);
    }
    bf_samples_free(s);

    /* Unweighted data gets scene weights averaging 1 over the kept samples, and no own
     * weights; a second scene multiplies the first's weights. */
    s = make_samples(5, dirs);
    assert_int_equal(bf_scene_apply(sc, s, &kept, &err), BF_OK);
    assert_null(s->weight);
    assert_non_null(s->scene_weight);
    ts_assert_rel((s->scene_weight[0] + s->scene_weight[1] + s->scene_weight[2]) / 3.0, 1.0, 1e-12, "mean weight");
    ts_assert_rel(s->scene_weight[1] / s->scene_weight[0], exp(-2.0), 1e-9, "weight ratio");
    double before[3];
    memcpy(before, s->scene_weight, sizeof before);
    assert_int_equal(bf_scene_apply(sc, s, &kept, &err), BF_OK);
    assert_int_equal(kept, 3);
    ts_assert_rel(s->scene_weight[1] / s->scene_weight[0], exp(-4.0), 1e-9, "weight ratio, twice");
    ts_assert_rel(s->scene_weight[2] / s->scene_weight[0], before[2] * before[2] / (before[0] * before[0]), 1e-9,
                  "weight ratio, twice");
    bf_scene_free(sc);
    bf_samples_free(s);

    /* Nothing in the scene: an error, and the samples untouched. */
    s = make_samples(5, dirs);
    sc = parse_ok("{\"light\": {\"theta\": [85, 90]}, \"view\": {\"theta\": [85, 90]}}");
    kept = 99;
    assert_int_equal(bf_scene_apply(sc, s, &kept, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "no sample lies in the scene"));
    assert_int_equal(kept, 0);
    assert_int_equal(s->n, 5);
    assert_null(s->weight);
    assert_null(s->scene_weight);
    bf_scene_free(sc);
    bf_samples_free(s);
}

/* ---- Weighted metrics -------------------------------------------------------------- */

/* Scene weights, all 1 (as bf_scene_apply would leave them, before the test sets them). */
static int add_scene_weights(bf_samples *s)
{
    s->scene_weight = malloc((s->n + 1) * sizeof *s->scene_weight);
    assert_non_null(s->scene_weight);
    for (size_t i = 0; i < s->n; i++)
        s->scene_weight[i] = 1.0;
    return BF_OK;
}

/* n random samples above the horizon, C = 2, values near a Lambert level with noise. */
static bf_samples *random_samples(size_t n, uint64_t seed)
{
    ts_rng rng = {seed};
    bf_samples *s = NULL;
    bf_samples_new(n, 2, &s, NULL);
    assert_non_null(s);
    for (size_t i = 0; i < n; i++) {
        s->theta_i[i] = 85 * ts_uniform(&rng);
        s->phi_i[i] = 360 * ts_uniform(&rng);
        s->theta_o[i] = 85 * ts_uniform(&rng);
        s->phi_o[i] = 360 * ts_uniform(&rng);
        s->value[2 * i] = 0.15 + 0.1 * (ts_uniform(&rng) - 0.5);
        s->value[2 * i + 1] = i % 7 == 0 ? 0.0 : 0.08 + 0.05 * (ts_uniform(&rng) - 0.5);
    }
    return s;
}

static void assert_metrics_equal(const bf_metrics *a, const bf_metrics *b)
{
    assert_int_equal(a->n, b->n);
    assert_int_equal(a->k, b->k);
    assert_true(a->rmse == b->rmse && a->rmse_cos == b->rmse_cos && a->rmse_log == b->rmse_log);
    assert_true(a->rmse_rel == b->rmse_rel && a->max_err == b->max_err);
    /* the criteria belong to the fit's objective (test_criteria.c), not compared here */
}

static void test_weighted_metrics_unit_weights(void **state)
{
    (void)state;
    bf_model *m = ts_model("lambert", 2);
    const double x[2] = {0.4, 0.25};
    bf_samples *s = random_samples(20000, 7); /* several metric chunks */
    bf_metrics plain, w0, w1;
    bf_error err = {0};
    assert_int_equal(bf_metrics_compute(m, x, s, 2, 1, &plain, &err), BF_OK);
    assert_int_equal(plain.weighted, 0);
    /* No weights: weighted = 1 changes nothing. */
    assert_int_equal(bf_metrics_compute_weighted(m, x, s, 2, 1, 1, &w0, &err), BF_OK);
    assert_metrics_equal(&w0, &plain);
    /* Weights all 1: exactly the unweighted metrics. */
    assert_int_equal(add_scene_weights(s), BF_OK);
    assert_int_equal(bf_metrics_compute_weighted(m, x, s, 2, 1, 1, &w1, &err), BF_OK);
    assert_int_equal(w1.weighted, 1);
    assert_metrics_equal(&w1, &plain);

    /* Any thread count gives the same weighted result. */
    ts_rng rng = {3};
    for (size_t i = 0; i < s->n; i++)
        s->scene_weight[i] = 4 * ts_uniform(&rng);
    bf_metrics t1, t3;
    assert_int_equal(bf_metrics_compute_weighted(m, x, s, 2, 1, 1, &t1, &err), BF_OK);
    assert_int_equal(bf_metrics_compute_weighted(m, x, s, 2, 3, 1, &t3, &err), BF_OK);
    assert_metrics_equal(&t1, &t3);
    assert_true(t1.rmse != plain.rmse);
    bf_samples_free(s);
    bf_model_free(m);
}

static void test_weighted_metrics_duplicates(void **state)
{
    (void)state;
    bf_model *m = ts_model("lambert", 2);
    const double x[2] = {0.4, 0.25};
    enum { N = 300 };
    bf_samples *s = random_samples(N, 11);
    assert_int_equal(add_scene_weights(s), BF_OK);
    size_t total = 0;
    for (size_t i = 0; i < N; i++) {
        s->scene_weight[i] = (double)(i % 4); /* 0, 1, 2, 3 */
        total += i % 4;
    }
    /* A weight-0 sample (and a negative one) with a huge error must not count. */
    s->value[0] = 50.0;
    s->scene_weight[4] = -2.0;
    s->value[8] = -40.0;
    bf_samples *d = NULL;
    bf_samples_new(total, 2, &d, NULL);
    assert_non_null(d);
    size_t j = 0;
    for (size_t i = 0; i < N; i++)
        for (int r = 0; r < (int)(s->scene_weight[i] > 0 ? s->scene_weight[i] : 0); r++, j++) {
            d->theta_i[j] = s->theta_i[i];
            d->phi_i[j] = s->phi_i[i];
            d->theta_o[j] = s->theta_o[i];
            d->phi_o[j] = s->phi_o[i];
            d->value[2 * j] = s->value[2 * i];
            d->value[2 * j + 1] = s->value[2 * i + 1];
        }
    assert_int_equal(j, total);
    bf_metrics mw, md;
    bf_error err = {0};
    assert_int_equal(bf_metrics_compute_weighted(m, x, s, 2, 1, 1, &mw, &err), BF_OK);
    assert_int_equal(bf_metrics_compute(m, x, d, 2, 1, &md, &err), BF_OK);
    ts_assert_rel(mw.rmse, md.rmse, 1e-12, "rmse");
    ts_assert_rel(mw.rmse_cos, md.rmse_cos, 1e-12, "rmse_cos");
    ts_assert_rel(mw.rmse_log, md.rmse_log, 1e-12, "rmse_log");
    ts_assert_rel(mw.rmse_rel, md.rmse_rel, 1e-12, "rmse_rel");
    assert_true(mw.max_err == md.max_err);
    assert_true(mw.max_err < 1.0); /* the huge errors carry weight 0 */
    /* n counts each value of positive weight once; AIC and BIC use that n. */
    size_t npos = 0;
    for (size_t i = 0; i < N; i++)
        npos += s->scene_weight[i] > 0;
    assert_int_equal(mw.n, 2 * npos);
    assert_true(isnan(mw.aic) && isnan(mw.bic)); /* criteria come from fits only */

    /* Every weight 0: no value to measure. */
    for (size_t i = 0; i < N; i++)
        s->scene_weight[i] = 0.0;
    assert_int_equal(bf_metrics_compute_weighted(m, x, s, 2, 1, 1, &mw, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "positive weight"));
    bf_samples_free(d);
    bf_samples_free(s);
    bf_model_free(m);
}

/* The data's own weights never enter a scene's metrics: without scene weights (a
 * ranges-only scene, or a scene keeping everything) they equal the plain metrics. */
static void test_own_weights_not_in_scene_metrics(void **state)
{
    (void)state;
    bf_samples *s = random_samples(300, 11);
    assert_int_equal(bf_samples_add_weights(s, NULL), BF_OK);
    for (size_t i = 0; i < s->n; i++)
        s->weight[i] = i % 3 == 0 ? 100.0 : 0.01;
    bf_error err;
    bf_model *m = ts_model("lambert", 2);
    const double x[2] = {0.4, 0.2};
    bf_metrics plain, w;
    assert_int_equal(bf_metrics_compute(m, x, s, 2, 1, &plain, &err), BF_OK);
    assert_int_equal(bf_metrics_compute_weighted(m, x, s, 2, 1, 1, &w, &err), BF_OK);
    assert_metrics_equal(&plain, &w);
    bf_scene *sc = parse_ok("{}");
    assert_int_equal(bf_scene_apply(sc, s, NULL, &err), BF_OK);
    assert_null(s->scene_weight);
    assert_int_equal(bf_metrics_compute_weighted(m, x, s, 2, 1, 1, &w, &err), BF_OK);
    assert_metrics_equal(&plain, &w);
    bf_scene_free(sc);
    bf_model_free(m);
    bf_samples_free(s);
}

/* bf_fit reports weighted metrics when asked, and the usual ones otherwise. */
static void test_fit_weighted_metrics(void **state)
{
    (void)state;
    bf_samples *s = random_samples(400, 5);
    assert_int_equal(add_scene_weights(s), BF_OK);
    for (size_t i = 0; i < s->n; i++)
        s->scene_weight[i] = i < 200 ? 1.0 : 0.1;
    bf_fit_options o;
    ts_fit_defaults(&o);
    o.weighted_metrics = 1;
    bf_fit_result r;
    ts_fit_ok(s, "lambert", &o, &r);
    assert_int_equal(r.metrics.weighted, 1);
    assert_true(isfinite(r.metrics.bic) && r.metrics.crit_n == 2 * s->n);
    bf_metrics want, plain;
    assert_int_equal(bf_metrics_compute_weighted(r.model, r.x, s, r.metrics.k, 1, 1, &want, NULL), BF_OK);
    assert_metrics_equal(&r.metrics, &want);
    assert_int_equal(bf_metrics_compute(r.model, r.x, s, r.metrics.k, 1, &plain, NULL), BF_OK);
    assert_true(plain.rmse != want.rmse);
    bf_fit_result_clear(&r);

    /* Samples a scene weighted are judged over its directions however the fit was asked
     * (fit.c): a program that read them with a scene and fits them later gets the
     * command's numbers. */
    o.weighted_metrics = 0;
    ts_fit_ok(s, "lambert", &o, &r);
    assert_int_equal(r.metrics.weighted, 1);
    assert_metrics_equal(&r.metrics, &want);
    bf_fit_result_clear(&r);

    /* Without a scene's weights every sample counts alike. */
    free(s->scene_weight);
    s->scene_weight = NULL;
    ts_fit_ok(s, "lambert", &o, &r);
    assert_int_equal(r.metrics.weighted, 0);
    assert_int_equal(bf_metrics_compute(r.model, r.x, s, r.metrics.k, 1, &plain, NULL), BF_OK);
    assert_metrics_equal(&r.metrics, &plain);
    bf_fit_result_clear(&r);
    bf_samples_free(s);
}

/* The kernel sum of one orientation by the formula itself, over every pair (the
 * library indexes the pairs in a grid; this is the plain sum it must equal). */
static double brute_orientation(const bf_scene *sc, double ti, double pi_, double to, double po)
{
    const double r = sc->radius * DEG, supp = 3.0 * r;
    double acc = 0.0;
    for (int a = 0; a < sc->nlights; a++)
        for (int b = 0; b < sc->nviews; b++) {
            const bf_scene_dir *l = &sc->lights[a], *v = &sc->views[b];
            const double aL = fabs(ti - l->theta) * DEG;
            /* views in the frame where the light has azimuth 0, azimuth folded */
            const double ds = (po - pi_) * DEG, dp = (v->phi - l->phi) * DEG;
            const double S[3] = {sin(to * DEG) * cos(ds), fabs(sin(to * DEG) * sin(ds)), cos(to * DEG)};
            const double P[3] = {sin(v->theta * DEG) * cos(dp), fabs(sin(v->theta * DEG) * sin(dp)),
                                 cos(v->theta * DEG)};
            double dot = S[0] * P[0] + S[1] * P[1] + S[2] * P[2];
            const double aV = acos(dot > 1.0 ? 1.0 : dot);
            if (aL <= supp && aV <= supp)
                acc += l->weight * v->weight * exp(-(aL * aL + aV * aV) / (2.0 * r * r));
        }
    return acc;
}

/* Many lights and views (the grid index at work, cells shared by many pairs): the
 * weights equal the plain sum over every pair, for both orientations. */
static void test_many_directions_match_plain_sum(void **state)
{
    (void)state;
    ts_rng r = {4242};
    char *text = malloc(200000), *p = text;
    p += sprintf(p, "{\"radius\": 7, \"reciprocal\": true, \"lights\": [");
    for (int k = 0; k < 60; k++)
        p += sprintf(p, "%s{\"theta\": %.3f, \"phi\": %.3f, \"weight\": %.3f}", k ? "," : "", 85 * ts_uniform(&r),
                     360 * ts_uniform(&r) - 180, 0.5 + ts_uniform(&r));
    p += sprintf(p, "], \"views\": [");
    for (int k = 0; k < 50; k++)
        p += sprintf(p, "%s{\"theta\": %.3f, \"phi\": %.3f}", k ? "," : "", 85 * ts_uniform(&r),
                     360 * ts_uniform(&r) - 180);
    sprintf(p, "]}");
    bf_scene *sc = parse_ok(text);
    free(text);
    bf_samples *s = random_samples(3000, 77);
    double *w = malloc(s->n * sizeof *w);
    bf_error err;
    assert_int_equal(bf_scene_weights(sc, s, w, &err), BF_OK);
    size_t nonzero = 0;
    for (size_t i = 0; i < s->n; i++) {
        const double d = brute_orientation(sc, s->theta_i[i], s->phi_i[i], s->theta_o[i], s->phi_o[i]);
        const double sw = brute_orientation(sc, s->theta_o[i], s->phi_o[i], s->theta_i[i], s->phi_i[i]);
        const double want = d > sw ? d : sw;
        ts_assert_near(w[i], want, 1e-9, 1e-12, "scene weight against the plain sum");
        nonzero += want > 0.0;
    }
    assert_true(nonzero > s->n / 4); /* the kernels reach a good share of the samples */
    free(w);
    bf_samples_free(s);
    bf_scene_free(sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults_and_examples),
        cmocka_unit_test(test_parse_errors),
        cmocka_unit_test(test_ranges),
        cmocka_unit_test(test_explicit_kernel),
        cmocka_unit_test(test_rotation_invariance),
        cmocka_unit_test(test_apply),
        cmocka_unit_test(test_weighted_metrics_unit_weights),
        cmocka_unit_test(test_weighted_metrics_duplicates),
        cmocka_unit_test(test_own_weights_not_in_scene_metrics),
        cmocka_unit_test(test_fit_weighted_metrics),
        cmocka_unit_test(test_many_directions_match_plain_sum),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
