/* The warnings of a fit (bf_fit_result.warnings), each on data made to trigger it and
 * on data that must not: a parameter at a bound, parameters the data do not determine,
 * a correlated pair, an albedo above 1, a lobe narrower than the sampling, the solver's
 * iteration limit, a robust loss's undefined criteria, each with its kind
 * (bf_warning_kind); and the albedo quadrature itself against known albedos. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/fit.h"
#include "support.h"

/* n samples of model spec at x (C channels): random directions, a third of them near
 * the mirror direction unless spread (or, with max_theta_d > 0, only those whose
 * difference angle theta_d is below it), values times 1 + 0.01 sin(k) so the residuals
 * are not exactly zero. */
static bf_samples *samples_of(const char *spec, int C, const double *x, size_t n, double max_theta_d, int spread)
{
    bf_model *m = ts_model(spec, C);
    bf_samples *s = NULL;
    bf_samples_new(n, C, &s, NULL);
    assert_non_null(s);
    ts_rng r = {777};
    for (size_t i = 0; i < n;) {
        double ti, pi_, to, po;
        ts_random_pair_deg(&r, !spread && i % 3 == 0, &ti, &pi_, &to, &po);
        if (max_theta_d > 0) {
            double L[3], V[3], H[3];
            ts_dirs_deg(ti, pi_, to, po, L, V);
            double h = 0;
            for (int k = 0; k < 3; k++)
                H[k] = L[k] + V[k], h += H[k] * H[k];
            double cd = (L[0] * H[0] + L[1] * H[1] + L[2] * H[2]) / sqrt(h);
            if (acos(fmin(cd, 1.0)) / DEG > max_theta_d)
                continue;
        }
        s->theta_i[i] = ti, s->phi_i[i] = pi_, s->theta_o[i] = to, s->phi_o[i] = po;
        i++;
    }
    bf_model_eval(m, x, ts_samples_geometry(s), s->value, NULL);
    for (size_t k = 0; k < n * (size_t)C; k++)
        s->value[k] *= 1.0 + 0.01 * sin(1.3 * (double)k);
    bf_model_free(m);
    return s;
}

/* The warning holding fragment, or NULL. */
static const char *warning(const bf_fit_result *r, const char *fragment)
{
    for (int i = 0; i < r->nwarnings; i++)
        if (strstr(r->warnings[i], fragment))
            return r->warnings[i];
    return NULL;
}

/* The kind of the warning holding fragment, or -1 when none does. */
static int kind_of(const bf_fit_result *r, const char *fragment)
{
    for (int i = 0; i < r->nwarnings; i++)
        if (strstr(r->warnings[i], fragment))
            return (int)r->warning_kind[i];
    return -1;
}

static void print_warnings(const char *what, const bf_fit_result *r)
{
    for (int i = 0; i < r->nwarnings; i++)
        printf("  %s: %s\n", what, r->warnings[i]);
}

static void fit(bf_samples *s, const char *spec, const bf_fit_options *o, bf_fit_result *r)
{
    bf_error err;
    assert_int_equal(bf_fit_with(s, spec, o, r, &err), BF_OK);
}

/* A well-posed fit warns of nothing: walter with a broad lobe, densely sampled. */
static void test_clean_fit(void **state)
{
    (void)state;
    const double x[4] = {0.4, 0.5, 0.3, 0.05};
    bf_samples *s = samples_of("walter", 1, x, 3000, 0, 0);
    bf_fit_options o;
    ts_fit_defaults(&o);
    bf_fit_result r;
    fit(s, "walter", &o, &r);
    print_warnings("clean", &r);
    assert_true(r.ok);
    assert_int_equal(r.nwarnings, 0);
    bf_fit_result_clear(&r);
    bf_samples_free(s);
}

/* Lambert data in one channel of three dark: that rho_d sits at its lower bound 0. */
static void test_bound(void **state)
{
    (void)state;
    const double x[3] = {0.5, 0.0, 0.3};
    bf_samples *s = samples_of("lambert", 3, x, 500, 0, 0);
    for (size_t i = 0; i < s->n; i++)
        s->value[3 * i + 1] = -0.01; /* below zero: the bound holds it */
    bf_fit_options o;
    ts_fit_defaults(&o);
    bf_fit_result r;
    fit(s, "lambert", &o, &r);
    print_warnings("bound", &r);
    const char *w = warning(&r, "rho_d[1] = 0 is at its lower bound 0");
    assert_non_null(w);
    assert_int_equal(kind_of(&r, "rho_d[1] = 0 is at its lower bound 0"), BF_WARN_AT_BOUND);
    assert_null(warning(&r, "rho_d[0]"));
    assert_null(warning(&r, "rho_d[2]"));
    bf_fit_result_clear(&r);
    bf_samples_free(s);
}

/* Walter fitted to Lambertian data: no highlight, so its weight is at 0 and its width
 * and Fresnel are not determined by anything. */
static void test_undetermined(void **state)
{
    (void)state;
    const double x[1] = {0.6};
    bf_samples *s = samples_of("lambert", 1, x, 800, 0, 0);
    bf_fit_options o;
    ts_fit_defaults(&o);
    bf_fit_result r;
    fit(s, "walter", &o, &r);
    print_warnings("undetermined", &r);
    assert_non_null(warning(&r, "rho_s = "));
    assert_true(warning(&r, "alpha = ") || warning(&r, "f0 = "));
    assert_non_null(warning(&r, "not determined by the data"));
    assert_null(warning(&r, "rho_d"));
    for (int i = 0; i < r.nwarnings; i++) /* each by what it says */
        assert_int_equal(r.warning_kind[i], strstr(r.warnings[i], "not determined") ? BF_WARN_UNDETERMINED
                                            : strstr(r.warnings[i], "bound")        ? BF_WARN_AT_BOUND
                                            : strstr(r.warnings[i], "correlated")   ? BF_WARN_CORRELATED
                                                                                    : -1);
    bf_fit_result_clear(&r);
    bf_samples_free(s);
}

/* Fits walter (one channel) to its own values at x over n samples (as samples_of
 * draws them) and returns whether some warning of kind `kind` holds each fragment (every
 * one of them; NULL ends the list). */
static int walter_warns(const double *x, size_t n, double max_theta_d, int spread, const char *what,
                        bf_warning_kind kind, ...)
{
    bf_samples *s = samples_of("walter", 1, x, n, max_theta_d, spread);
    bf_fit_options o;
    ts_fit_defaults(&o);
    bf_fit_result r;
    fit(s, "walter", &o, &r);
    print_warnings(what, &r);
    int all = 1;
    va_list ap;
    va_start(ap, kind);
    for (const char *f; (f = va_arg(ap, const char *));)
        all &= kind_of(&r, f) == (int)kind;
    va_end(ap);
    bf_fit_result_clear(&r);
    bf_samples_free(s);
    return all;
}

/* Schlick's Fresnel is f0 wherever theta_d is small: samples only there see rho_s and
 * f0 through their product. All theta_d: the Fresnel curve separates them. */
static void test_correlated(void **state)
{
    (void)state;
    const double x[4] = {0.3, 0.5, 0.3, 0.2};
    assert_true(walter_warns(x, 1500, 30, 0, "correlated", BF_WARN_CORRELATED, "rho_s and f0 are correlated", NULL));
    assert_false(walter_warns(x, 1500, 0, 0, "uncorrelated", BF_WARN_CORRELATED, "correlated", NULL));
}

/* The same in three channels: every channel of rho_s with f0 and with each other, one
 * warning per pair of parameters (not six lines, one per pair of entries). */
static void test_correlated_channels(void **state)
{
    (void)state;
    const double x[8] = {0.3, 0.35, 0.4, 0.5, 0.5, 0.5, 0.3, 0.2};
    bf_samples *s = samples_of("walter", 3, x, 1500, 30, 0);
    bf_fit_options o;
    ts_fit_defaults(&o);
    bf_fit_result r;
    fit(s, "walter", &o, &r);
    print_warnings("correlated channels", &r);
    int correlated = 0;
    for (int i = 0; i < r.nwarnings; i++)
        correlated += strstr(r.warnings[i], "correlated") != NULL;
    assert_non_null(warning(&r, "rho_s and f0 are correlated in 3 channels (r up to -"));
    assert_non_null(warning(&r, "rho_s: its channels are correlated with each other (3 pairs, r up to "));
    assert_int_equal(correlated, 2);
    assert_int_equal(kind_of(&r, "rho_s and f0 are correlated in 3"), BF_WARN_CORRELATED);
    assert_int_equal(kind_of(&r, "rho_s: its channels are correlated"), BF_WARN_CORRELATED);
    assert_int_equal(kind_of(&r, "rho_s: channels 0, 1, 2 not determined"), BF_WARN_UNDETERMINED);
    bf_fit_result_clear(&r);
    bf_samples_free(s);
}

/* A bright diffuse and a strong highlight together reflect more than they receive. */
static void test_albedo(void **state)
{
    (void)state;
    const double bright[4] = {0.9, 0.9, 0.3, 0.9}, dim[4] = {0.5, 0.3, 0.3, 0.05};
    assert_true(walter_warns(bright, 2000, 0, 0, "albedo", BF_WARN_ALBEDO, "the albedo reaches", NULL));
    assert_false(walter_warns(dim, 2000, 0, 0, "dim", BF_WARN_ALBEDO, "albedo", NULL));
}

/* The quadrature on known albedos: Lambert's is rho_d; a sharp normalised GGX lobe
 * without Fresnel is close to rho_s at normal-ish incidence (Smith shadowing takes a
 * little at 85 degrees, so at most rho_s). */
static void test_albedo_quadrature(void **state)
{
    (void)state;
    bf_model *m = ts_model("lambert", 2);
    const double x[2] = {0.7, 0.25};
    double a, t;
    int c;
    assert_int_equal(bf_fit_max_albedo(m, x, &a, &t, &c, NULL), BF_OK);
    ts_assert_rel(a, 0.7, 1e-4, "lambert albedo"); /* well inside the warning's 1.001 */
    assert_int_equal(c, 0);
    bf_model_free(m);
    m = ts_model("walter:fresnel=none", 1);
    const double w[4] = {0.0, 0.8, 0.01, 0.0};
    assert_int_equal(bf_fit_max_albedo(m, w, &a, &t, &c, NULL), BF_OK);
    ts_assert_near(a, 0.8, 0.01, 0.0, "a sharp GGX lobe's albedo");
    bf_model_free(m);
}

/* A lobe of GGX alpha 0.02 (about 0.8 deg at half maximum) among 2000 samples spread
 * over the hemispheres: hardly any within it. A broad lobe (alpha 0.3) has plenty. */
static void test_lobe_width(void **state)
{
    (void)state;
    const double sharp[4] = {0.3, 0.5, 0.02, 0.05}, broad[4] = {0.3, 0.5, 0.3, 0.05};
    assert_true(walter_warns(sharp, 2000, 0, 1, "sharp", BF_WARN_NARROW_LOBE, "lobe 1 is ",
                             "the data do not resolve the highlight", NULL));
    assert_false(walter_warns(broad, 2000, 0, 1, "broad", BF_WARN_NARROW_LOBE, "lobe 1", NULL));
}

/* One iteration is not enough; a robust loss leaves the criteria undefined. */
static void test_limit_and_loss(void **state)
{
    (void)state;
    const double x[4] = {0.4, 0.5, 0.3, 0.05};
    bf_samples *s = samples_of("walter", 1, x, 1000, 0, 0);
    bf_fit_options o;
    ts_fit_defaults(&o);
    o.solver.max_iterations = 1;
    o.presolve = -1;
    bf_fit_result r;
    fit(s, "walter", &o, &r);
    print_warnings("limit", &r);
    assert_non_null(warning(&r, "stopped on its limit after 1 iteration,"));
    assert_int_equal(kind_of(&r, "stopped on its limit"), BF_WARN_SOLVER_LIMIT);
    assert_null(warning(&r, "robust loss"));
    assert_true(isfinite(r.metrics.bic));
    bf_fit_result_clear(&r);
    ts_fit_defaults(&o);
    o.solver.loss.kind = BF_LOSS_CAUCHY;
    o.solver.loss.scale = 0.1;
    fit(s, "walter", &o, &r);
    print_warnings("loss", &r);
    assert_non_null(warning(&r, "AIC, AICc and BIC are undefined: a robust loss"));
    assert_int_equal(kind_of(&r, "AIC, AICc and BIC are undefined"), BF_WARN_NO_CRITERIA);
    assert_null(warning(&r, "stopped on its limit"));
    assert_true(isnan(r.metrics.bic) && isnan(r.metrics.aic) && isnan(r.metrics.aicc));
    bf_fit_result_clear(&r);
    bf_samples_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_clean_fit),           cmocka_unit_test(test_bound),
        cmocka_unit_test(test_undetermined),        cmocka_unit_test(test_correlated),
        cmocka_unit_test(test_correlated_channels), cmocka_unit_test(test_albedo),
        cmocka_unit_test(test_albedo_quadrature),   cmocka_unit_test(test_lobe_width),
        cmocka_unit_test(test_limit_and_loss),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
