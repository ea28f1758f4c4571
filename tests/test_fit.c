/* The fit driver on synthetic data with known answers (noiseless, so the optimum is the
 * generating parameters): recovery from the data-driven start with Ceres and with an
 * NLopt method, the start itself, multistart determinism, fixed parameters, a fit that
 * cannot succeed, the result file read back as a parameter file, and the covariance. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/fit.h"
#include "brdfit/io.h"
#include "support.h"
#include "synth.h"

#define NSAMPLES 4096

/* Noiseless samples of spec at x, uniform in solid angle. */
static bf_samples *synth(const char *spec, int C, const double *x, bf_synth_pattern pattern, size_t n)
{
    bf_model *m = ts_model(spec, C);
    bf_synth_options o;
    memset(&o, 0, sizeof o);
    o.pattern = pattern;
    o.count = n;
    o.seed = 11;
    bf_samples *s = NULL;
    bf_error err;
    if (bf_synth_generate(m, x, &o, &s, &err) != BF_OK)
        fail_msg("bf_synth_generate %s: %s", spec, err.msg);
    bf_model_free(m);
    return s;
}

static void assert_params(const bf_fit_result *r, const double *truth, double tol, const char *spec)
{
    int P = bf_model_nvalues(r->model);
    for (int k = 0; k < P; k++) {
        char what[96];
        snprintf(what, sizeof what, "%s parameter %d", spec, k);
        ts_assert_rel(r->x[k], truth[k], tol, what);
    }
}

/* ---- recovery ------------------------------------------------------------------- */

typedef struct truth_case {
    const char *spec;
    double x[8]; /* RGB: colour parameters three values each, in table order */
} truth_case;

static const truth_case cases[] = {
    {"lambert", {0.7, 0.45, 0.2}},
    {"walter", {0.5, 0.3, 0.15, 0.9, 0.85, 0.8, 0.15, 0.3}},
    {"cook_torrance", {0.4, 0.35, 0.3, 0.7, 0.6, 0.5, 0.25, 0.2}},
    {"phong", {0.3, 0.4, 0.5, 0.6, 0.6, 0.6, 40.0}},
    {"ward", {0.5, 0.4, 0.3, 0.2, 0.25, 0.3, 0.1, 0.25}},
};

static void test_recover_ceres(void **state)
{
    (void)state;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const truth_case *t = &cases[i];
        bf_samples *s = synth(t->spec, 3, t->x, BF_SYNTH_UNIFORM, NSAMPLES);
        bf_fit_options o;
        ts_fit_defaults(&o);
        bf_fit_result r;
        ts_fit_ok(s, t->spec, &o, &r);
        assert_params(&r, t->x, 1e-6, t->spec);
        assert_int_equal(r.metrics.n, 3 * NSAMPLES);
        assert_int_equal(r.metrics.k, bf_model_nvalues(r.model));
        assert_int_equal(r.samples, NSAMPLES);
        assert_int_equal(r.starts, 1);
        assert_true(r.metrics.rmse < 1e-9);
        assert_string_equal(r.solution.backend, "ceres");
        bf_fit_result_clear(&r);
        bf_samples_free(s);
    }
}

static void test_recover_nlopt(void **state)
{
    (void)state;
    const truth_case *t = &cases[1]; /* walter */
    bf_samples *s = synth(t->spec, 3, t->x, BF_SYNTH_UNIFORM, NSAMPLES);
    bf_fit_options o;
    ts_fit_defaults(&o);
    o.solver.backend = BF_BACKEND_NLOPT;
    o.solver.algorithm = "LD_LBFGS";
    o.solver.max_iterations = 20000;
    o.solver.function_tolerance = 1e-15;
    o.solver.parameter_tolerance = 1e-13;
    bf_fit_result r;
    ts_fit_ok(s, t->spec, &o, &r);
    assert_string_equal(r.solution.backend, "nlopt");
    assert_params(&r, t->x, 1e-6, t->spec);
    bf_fit_result_clear(&r);
    bf_samples_free(s);
}

/* ---- the data-driven start -------------------------------------------------------- */

static void assert_start_in_bounds(const bf_model *m, const double *x)
{
    bf_error err;
    if (bf_model_check(m, x, &err) != BF_OK)
        fail_msg("start out of bounds: %s", err.msg);
}

static void test_initial_guess_walter(void **state)
{
    (void)state;
    /* Shiny to rough lobes, dielectric and brighter Fresnel: rho_d within a factor 3
     * and alpha within a factor 2 of the truth. */
    static const double alphas[] = {0.05, 0.15, 0.4}, f0s[] = {0.04, 0.3};
    for (size_t a = 0; a < 6; a++) {
        double truth[8] = {0.5, 0.3, 0.15, 0.9, 0.85, 0.8, alphas[a % 3], f0s[a / 3]};
        bf_samples *s = synth("walter", 3, truth, BF_SYNTH_UNIFORM, 20000);
        bf_model *m = ts_model("walter", 3);
        double x[8];
        bf_error err;
        assert_int_equal(bf_fit_initial_guess(m, s, x, &err), BF_OK);
        assert_start_in_bounds(m, x);
        for (int c = 0; c < 3; c++)
            if (!(x[c] > truth[c] / 3 && x[c] < truth[c] * 3))
                fail_msg("rho_d[%d] start %g for truth %g (alpha %g, f0 %g)", c, x[c], truth[c], truth[6], truth[7]);
        if (!(x[6] > truth[6] / 2 && x[6] < truth[6] * 2))
            fail_msg("alpha start %g for truth %g (f0 %g)", x[6], truth[6], truth[7]);
        bf_model_free(m);
        bf_samples_free(s);
    }
}

/* Which colour parameters the start sets: a conductor's r and g (lobe colours that are not
 * weights) keep their defaults, where they were once scaled as weights; the lobe's rho_s
 * is scaled to the data; every colour outside the lobes starts at the diffuse level, as
 * rho_d does: Ashikhmin-Shirley's rho_s (a weight) and glTF's specular_color (an f0). */
static void start_of(const char *data_spec, const double *truth, const char *spec, double *x, bf_model **mo)
{
    bf_samples *s = synth(data_spec, 3, truth, BF_SYNTH_UNIFORM, 20000);
    *mo = ts_model(spec, 3);
    bf_error err;
    assert_int_equal(bf_fit_initial_guess(*mo, s, x, &err), BF_OK);
    assert_start_in_bounds(*mo, x);
    bf_samples_free(s);
}

static double start_value(const bf_model *m, const double *x, const char *name, int c, double *def)
{
    int i = bf_model_find_param(m, name);
    if (i < 0)
        fail_msg("no parameter %s", name);
    const bf_param_info *p = bf_model_param(m, i);
    *def = p->def;
    return x[bf_model_param_offset(m, i) + (p->color ? c : 0)];
}

static void test_initial_guess_roles(void **state)
{
    (void)state;
    const double walter_truth[8] = {0.3, 0.2, 0.1, 0.9, 0.85, 0.8, 0.15, 0.3};
    double x[32], def;
    bf_model *m;
    start_of("walter", walter_truth, "walter:fresnel=conductor", x, &m);
    for (int c = 0; c < 3; c++)
        for (int k = 0; k < 2; k++) {
            double v = start_value(m, x, k ? "g" : "r", c, &def);
            if (v != def)
                fail_msg("walter:fresnel=conductor %s[%d] starts at %g, not its default %g", k ? "g" : "r", c, v, def);
        }
    double rs = start_value(m, x, "rho_s", 0, &def);
    if (!(rs != def && rs > 0.0))
        fail_msg("walter:fresnel=conductor rho_s[0] start %g (default %g): not scaled", rs, def);
    bf_model_free(m);

    const double as_truth[7] = {0.3, 0.2, 0.1, 0.05, 0.05, 0.05, 200.0};
    const char *const outside[][3] = {{"ashikhmin_shirley_iso", "rho_d", "rho_s"},
                                      {"gltf", "base_color", "specular_color"}};
    for (size_t k = 0; k < sizeof outside / sizeof outside[0]; k++) {
        start_of(k ? "walter" : "ashikhmin_shirley_iso", k ? walter_truth : as_truth, outside[k][0], x, &m);
        for (int c = 0; c < 3; c++) {
            double d = start_value(m, x, outside[k][1], c, &def), v = start_value(m, x, outside[k][2], c, &def);
            if (!(d > 0.0 && v == d))
                fail_msg("%s starts %s[%d] %g, %s %g: not both the diffuse level", outside[k][0], outside[k][1], c, d,
                         outside[k][2], v);
        }
        bf_model_free(m);
    }
}

/* Data without a lobe, without near-specular samples, negative, or only at grazing
 * angles: a finite start inside the bounds for every model, and the Lambertian level. */
static void test_initial_guess_hard_data(void **state)
{
    (void)state;
    const double rho[3] = {0.6, 0.5, 0.4};
    bf_samples *lam = synth("lambert", 3, rho, BF_SYNTH_UNIFORM, 3000);

    /* Far from the mirror direction only: theta_h > 35 degrees. */
    bf_samples *far = synth("walter", 3, cases[1].x, BF_SYNTH_UNIFORM, 3000);
    const bf_geometry *g = NULL;
    bf_samples_geometry(far, &g, NULL);
    unsigned char *keep = malloc(far->n);
    for (size_t i = 0; i < far->n; i++)
        keep[i] = g->hz[i] < cos(35 * DEG);
    assert_int_equal(bf_samples_keep(far, keep, NULL), BF_OK);
    free(keep);

    /* Grazing only: both directions beyond 80 degrees. */
    bf_samples *graze = synth("walter", 3, cases[1].x, BF_SYNTH_UNIFORM, 40000);
    keep = malloc(graze->n);
    for (size_t i = 0; i < graze->n; i++)
        keep[i] = graze->theta_i[i] > 80 && graze->theta_o[i] > 80;
    assert_int_equal(bf_samples_keep(graze, keep, NULL), BF_OK);
    free(keep);
    assert_true(graze->n > 10);

    /* Negative and zero values. */
    bf_samples *neg = synth("lambert", 3, rho, BF_SYNTH_UNIFORM, 1000);
    for (size_t i = 0; i < neg->n * 3; i++)
        neg->value[i] = (i % 3 == 0) ? -0.01 : (i % 3 == 1 ? 0.0 : neg->value[i]);

    bf_samples *sets[] = {lam, far, graze, neg};
    char **specs;
    int ns = ts_all_specs(&specs);
    for (int k = 0; k < ns; k++) {
        bf_model *m = ts_model(specs[k], 3);
        double *x = malloc((size_t)bf_model_nvalues(m) * sizeof *x);
        for (size_t j = 0; j < sizeof sets / sizeof sets[0]; j++) {
            bf_error err;
            if (bf_fit_initial_guess(m, sets[j], x, &err) != BF_OK)
                fail_msg("%s on set %zu: %s", specs[k], j, err.msg);
            assert_start_in_bounds(m, x);
        }
        /* Lambertian data: the diffuse colour exactly, lobes small. */
        bf_error err;
        assert_int_equal(bf_fit_initial_guess(m, lam, x, &err), BF_OK);
        int id = bf_model_find_param(m, "rho_d");
        if (id >= 0)
            for (int c = 0; c < 3; c++)
                ts_assert_rel(x[bf_model_param_offset(m, id) + c], rho[c], 1e-12, "lambert rho_d start");
        free(x);
        bf_model_free(m);
    }
    ts_free_specs(specs, ns);

    /* A specular model fitted to Lambertian data converges to the Lambertian answer. */
    bf_fit_options o;
    ts_fit_defaults(&o);
    bf_fit_result r;
    ts_fit_ok(lam, "walter", &o, &r);
    for (int c = 0; c < 3; c++)
        ts_assert_near(r.x[c], rho[c], 1e-4, 0.0, "rho_d of walter on Lambertian data");
    assert_true(r.metrics.rmse < 1e-4);
    bf_fit_result_clear(&r);

    for (size_t j = 0; j < sizeof sets / sizeof sets[0]; j++)
        bf_samples_free(sets[j]);
}

/* ---- multistart, fixing, failure ------------------------------------------------------ */

static void test_multistart_deterministic(void **state)
{
    (void)state;
    const truth_case *t = &cases[2]; /* cook_torrance */
    bf_samples *s = synth(t->spec, 3, t->x, BF_SYNTH_UNIFORM, 2000);
    bf_fit_options o;
    ts_fit_defaults(&o);
    o.starts = 5;
    o.seed = 1234;
    o.solver.threads = 2;
    bf_fit_result a, b;
    ts_fit_ok(s, t->spec, &o, &a);
    ts_fit_ok(s, t->spec, &o, &b);
    assert_int_equal(a.starts, 5);
    assert_int_equal(b.starts, 5);
    assert_int_equal(a.seed, 1234);
    assert_int_equal(a.threads, 2);
    int P = bf_model_nvalues(a.model);
    assert_memory_equal(a.x, b.x, (size_t)P * sizeof *a.x);
    assert_true(a.solution.final_cost == b.solution.final_cost);
    /* The best of five is at least as good as the data-driven start alone, which
     * already finds the truth. */
    assert_params(&a, t->x, 1e-6, t->spec);
    bf_fit_result_clear(&a);
    bf_fit_result_clear(&b);
    bf_samples_free(s);
}

static void test_fix_holds(void **state)
{
    (void)state;
    const truth_case *t = &cases[1]; /* walter, f0 = 0.3 */
    bf_samples *s = synth(t->spec, 3, t->x, BF_SYNTH_UNIFORM, NSAMPLES);
    bf_override ov[2];
    bf_error err;
    assert_int_equal(bf_override_parse_fix("f0=0.3", &ov[0], &err), BF_OK);
    assert_int_equal(bf_override_parse_fix("rho_d[1]=0.3", &ov[1], &err), BF_OK);
    bf_fit_options o;
    ts_fit_defaults(&o);
    o.objective.overrides = ov;
    o.objective.noverrides = 2;
    bf_fit_result r;
    ts_fit_ok(s, t->spec, &o, &r);
    assert_true(r.x[7] == 0.3);
    assert_true(r.x[1] == 0.3);
    assert_true(r.fixed[7] && r.fixed[1] && !r.fixed[0] && !r.fixed[6]);
    assert_true(r.stderr_[7] == 0.0);
    assert_int_equal(r.metrics.k, bf_model_nvalues(r.model) - 2);
    assert_params(&r, t->x, 1e-6, "walter with f0 and rho_d[1] fixed at the truth");
    bf_fit_result_clear(&r);

    /* Fixed away from the truth: held, and the rest compensates (a worse fit). */
    assert_int_equal(bf_override_parse_fix("f0=0.9", &ov[0], &err), BF_OK);
    o.objective.noverrides = 1;
    ts_fit_ok(s, t->spec, &o, &r);
    assert_true(r.x[7] == 0.9);
    assert_true(r.metrics.rmse > 1e-6);
    bf_fit_result_clear(&r);
    bf_samples_free(s);
}

static int all_finite(const double *x, int n)
{
    for (int k = 0; k < n; k++)
        if (!isfinite(x[k]))
            return 0;
    return 1;
}

/* Values whose squares overflow: no start has a finite cost. The fit says so and
 * reports the data-driven start, which is finite. */
static void test_impossible_fit(void **state)
{
    (void)state;
    const double rho[3] = {0.5, 0.5, 0.5};
    bf_samples *s = synth("lambert", 3, rho, BF_SYNTH_UNIFORM, 500);
    for (size_t i = 0; i < s->n * 3; i++)
        s->value[i] = 1e300;
    bf_model *m = ts_model("walter", 3);
    double start[8];
    bf_error err;
    assert_int_equal(bf_fit_initial_guess(m, s, start, &err), BF_OK);
    bf_model_free(m);
    bf_fit_options o;
    ts_fit_defaults(&o);
    o.starts = 3;
    bf_fit_result r;
    assert_int_equal(bf_fit_with(s, "walter", &o, &r, &err), BF_OK);
    assert_false(r.ok);
    assert_true(r.solution.termination[0] != '\0');
    assert_true(all_finite(r.x, 8));
    assert_memory_equal(r.x, start, sizeof start);
    bf_fit_result_clear(&r);

    /* Bad specification and options: errors, not failed fits. */
    assert_int_not_equal(bf_fit_with(s, "no_such_model", &o, &r, &err), BF_OK);
    assert_non_null(strstr(err.msg, "no_such_model"));
    o.solver.algorithm = "no_such_method";
    assert_int_not_equal(bf_fit_with(s, "walter", &o, &r, &err), BF_OK);
    assert_null(strchr(err.msg, '\n'));
    bf_samples_free(s);
}

/* ---- the result file ------------------------------------------------------------------ */

static void test_result_json_round_trip(void **state)
{
    (void)state;
    /* Parameters that need all 17 digits, with two lobes so options include lobes. */
    double truth[14] = {
        0.123456789012345678, 0.3, 0.1 / 3.0, 0.7, 0.6, 0.5, 0.1 + 1e-16, 0.04, 0.2, 0.2, 0.2, 0.37, 0.5};
    const char *spec = "walter:lobes=2";
    bf_model *m = ts_model(spec, 3);
    assert_int_equal(bf_model_nvalues(m), 13);
    bf_model_free(m);
    bf_samples *s = synth(spec, 3, truth, BF_SYNTH_UNIFORM, 2000);
    bf_fit_options o;
    ts_fit_defaults(&o);
    o.start = truth; /* the fit moves off the exact truth by rounding: any 17-digit values do */
    bf_fit_result r;
    bf_error err;
    assert_int_equal(bf_fit_with(s, spec, &o, &r, &err), BF_OK);
    const char *path = ts_tmp_path("fit.json");
    assert_int_equal(bf_fit_write_json(&r, "data.csv", path, &err), BF_OK);
    bf_model *back = NULL;
    double *x = NULL;
    if (bf_params_read(path, &back, &x, &err) != BF_OK)
        fail_msg("bf_params_read: %s", err.msg);
    assert_string_equal(bf_model_spec(back), bf_model_spec(r.model));
    assert_int_equal(bf_model_channels(back), 3);
    assert_memory_equal(x, r.x, 13 * sizeof *x);
    free(x);
    bf_model_free(back);

    /* Several fits: {"fits": [...]}, which is not a parameter file. */
    const bf_fit_result *list[2] = {&r, &r};
    const char *lpath = ts_tmp_path("fits.json");
    assert_int_equal(bf_fit_write_json_list(list, 2, "data.csv", lpath, &err), BF_OK);
    assert_int_not_equal(bf_params_read(lpath, &back, &x, &err), BF_OK);
    bf_fit_result_clear(&r);
    bf_samples_free(s);
}

/* ---- covariance ------------------------------------------------------------------ */

/* Inverts the k x k matrix a in place (Gauss-Jordan with partial pivoting): the test's
 * own, independent of the library's eigen-decomposition. */
static void invert(double *a, int k)
{
    double inv[16 * 16];
    assert_true(k <= 16);
    for (int i = 0; i < k; i++)
        for (int j = 0; j < k; j++)
            inv[i * k + j] = i == j;
    for (int c = 0; c < k; c++) {
        int p = c;
        for (int i = c + 1; i < k; i++)
            if (fabs(a[i * k + c]) > fabs(a[p * k + c]))
                p = i;
        for (int j = 0; j < k; j++) {
            double t = a[c * k + j];
            a[c * k + j] = a[p * k + j], a[p * k + j] = t;
            t = inv[c * k + j];
            inv[c * k + j] = inv[p * k + j], inv[p * k + j] = t;
        }
        const double d = a[c * k + c];
        assert_true(fabs(d) > 0.0);
        for (int j = 0; j < k; j++)
            a[c * k + j] /= d, inv[c * k + j] /= d;
        for (int i = 0; i < k; i++)
            if (i != c) {
                const double f = a[i * k + c];
                for (int j = 0; j < k; j++)
                    a[i * k + j] -= f * a[c * k + j], inv[i * k + j] -= f * inv[c * k + j];
            }
    }
    memcpy(a, inv, (size_t)k * k * sizeof *a);
}

/* The covariance of a least-squares fit is s^2 (J^T J)^-1 at the solution, J the model's
 * Jacobian over the samples (its analytic gradient, tested against finite differences
 * in test_models) and s^2 the residuals' variance: against the test's own computation,
 * with a fixed parameter's row and column 0 and the diagonal the standard errors'
 * squares. */
static void test_covariance(void **state)
{
    (void)state;
    const double truth[3] = {0.3, 0.6, 40.0};
    bf_samples *s = synth("phong", 1, truth, BF_SYNTH_UNIFORM, 2000);
    for (size_t i = 0; i < s->n; i++) /* noise, so that s^2 > 0 */
        s->value[i] *= 1.0 + 0.05 * sin(12.9898 * (double)i);
    for (int with_fix = 0; with_fix < 2; with_fix++) {
        bf_fit_options o;
        ts_fit_defaults(&o);
        o.objective.solid_angle = 0;
        bf_override ov;
        bf_error err;
        if (with_fix) {
            assert_int_equal(bf_override_parse_fix("rho_d=0.3", &ov, &err), BF_OK);
            o.objective.overrides = &ov;
            o.objective.noverrides = 1;
        }
        bf_fit_result r;
        ts_fit_ok(s, "phong", &o, &r);
        const int P = bf_model_nvalues(r.model);
        assert_int_equal(P, 3);
        assert_non_null(r.covariance);
        /* J over the free entries, the residuals' sum of squares. */
        const bf_geometry *g;
        assert_int_equal(bf_samples_geometry(s, &g, &err), BF_OK);
        double *v = malloc(s->n * sizeof *v), *jac = malloc(s->n * (size_t)P * sizeof *jac);
        assert_non_null(v);
        assert_non_null(jac);
        bf_model_eval(r.model, r.x, g, v, jac);
        int free_[3], k = 0;
        for (int a = 0; a < P; a++)
            if (!r.fixed[a])
                free_[k++] = a;
        double jtj[9] = {0}, ssr = 0.0;
        for (size_t i = 0; i < s->n; i++) {
            ssr += (v[i] - s->value[i]) * (v[i] - s->value[i]);
            for (int a = 0; a < k; a++)
                for (int b = 0; b < k; b++)
                    jtj[a * k + b] += jac[i * P + free_[a]] * jac[i * P + free_[b]];
        }
        invert(jtj, k);
        const double s2 = ssr / (double)(s->n - (size_t)k);
        for (int a = 0; a < P; a++)
            for (int b = 0; b < P; b++) {
                const double got = r.covariance[a * P + b];
                assert_true(got == r.covariance[b * P + a]);
                if (r.fixed[a] || r.fixed[b]) {
                    assert_true(got == 0.0);
                    continue;
                }
                int ia = 0, ib = 0;
                while (free_[ia] != a)
                    ia++;
                while (free_[ib] != b)
                    ib++;
                char what[64];
                snprintf(what, sizeof what, "covariance[%d][%d]%s", a, b, with_fix ? " (rho_d fixed)" : "");
                ts_assert_rel(got, s2 * jtj[ia * k + ib], 1e-5, what);
            }
        for (int a = 0; a < P; a++)
            ts_assert_rel(r.covariance[a * P + a], r.stderr_[a] * r.stderr_[a], 1e-12, "the diagonal");
        assert_int_equal(k, with_fix ? 2 : 3);
        free(v);
        free(jac);
        bf_fit_result_clear(&r);
        assert_null(r.covariance);
    }
    bf_samples_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_recover_ceres),
        cmocka_unit_test(test_recover_nlopt),
        cmocka_unit_test(test_initial_guess_walter),
        cmocka_unit_test(test_initial_guess_hard_data),
        cmocka_unit_test(test_initial_guess_roles),
        cmocka_unit_test(test_multistart_deterministic),
        cmocka_unit_test(test_fix_holds),
        cmocka_unit_test(test_impossible_fit),
        cmocka_unit_test(test_result_json_round_trip),
        cmocka_unit_test(test_covariance),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
