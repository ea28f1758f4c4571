/* Fits at the extremes: each must converge to sensible parameters (ok = 1) or fail
 * clearly (ok = 0 with a termination text), and never return NaN parameters.
 * Near-mirror lobes (walter alpha 1e-3, cook_torrance m 1e-3) on a fine goniometer
 * sweep through the peak; Phong exponents 1e4 and 1e5; Lambertian data fitted with
 * specular models; data only at grazing angles; f0 near 1 (metals); data with zeros
 * and small negative values, kept, clamped or dropped. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/fit.h"
#include "brdfit/prep.h"
#include "support.h"
#include "synth.h"

#define NCH 3

static int verbose(void)
{
    return getenv("BRDFIT_TEST_VERBOSE") != NULL;
}

static bf_samples *generate(const char *spec, const double *x, const bf_synth_options *o)
{
    bf_model *m = ts_model(spec, NCH);
    bf_samples *s = NULL;
    bf_error err;
    if (bf_synth_generate(m, x, o, &s, &err) != BF_OK)
        fail_msg("bf_synth_generate %s: %s", spec, err.msg);
    bf_model_free(m);
    return s;
}

/* A goniometer sweep at three incidences with a fine step (degrees): in-plane through
 * the mirror direction and the out-of-plane cone through it. */
static bf_samples *gonio(const char *spec, const double *x, double step)
{
    static const double inc[] = {15.0, 40.0, 65.0};
    bf_synth_options o;
    memset(&o, 0, sizeof o);
    o.pattern = BF_SYNTH_GONIO;
    o.gonio.incidence = inc;
    o.gonio.n_incidence = 3;
    o.gonio.step = step;
    o.seed = 3;
    return generate(spec, x, &o);
}

static bf_samples *stratified(const char *spec, const double *x, size_t n)
{
    bf_synth_options o;
    memset(&o, 0, sizeof o);
    o.pattern = BF_SYNTH_STRATIFIED;
    o.count = n;
    o.seed = 4;
    return generate(spec, x, &o);
}

/* Runs the fit; fails the test on an error, on NaN parameters or metrics, or on a
 * failed fit without a reason. Returns r->ok. */
static int fit(bf_samples *s, const char *spec, const bf_fit_options *o, bf_fit_result *r, const char *what)
{
    bf_error err;
    if (bf_fit_with(s, spec, o, r, &err) != BF_OK)
        fail_msg("%s: bf_fit %s: %s", what, spec, err.msg);
    int P = bf_model_nvalues(r->model);
    for (int k = 0; k < P; k++)
        if (!isfinite(r->x[k]))
            fail_msg("%s: %s parameter %d is %g", what, spec, k, r->x[k]);
    if (!r->ok && !r->solution.termination[0])
        fail_msg("%s: %s failed without saying why", what, spec);
    if (r->ok && !isfinite(r->metrics.rmse))
        fail_msg("%s: %s rmse %g", what, spec, r->metrics.rmse);
    bf_error cerr;
    if (bf_model_check(r->model, r->x, &cerr) != BF_OK)
        fail_msg("%s: %s result out of bounds: %s", what, spec, cerr.msg);
    if (verbose()) {
        printf("%s: %s ok=%d n=%zu rmse=%.3g it=%d %s\n  x =", what, spec, r->ok, r->samples, r->metrics.rmse,
               r->solution.iterations, r->solution.termination);
        for (int k = 0; k < P; k++)
            printf(" %.9g", r->x[k]);
        printf("\n");
    }
    return r->ok;
}

static double max_value(const bf_samples *s)
{
    double v = 0.0;
    for (size_t i = 0; i < s->n * (size_t)s->channels; i++)
        v = fmax(v, s->value[i]);
    return v;
}

static void expect_rel(const bf_fit_result *r, int k, double want, double tol, const char *what)
{
    char msg[128];
    snprintf(msg, sizeof msg, "%s: parameter %d", what, k);
    ts_assert_rel(r->x[k], want, tol, msg);
}

/* ---- near-mirror ------------------------------------------------------------------- */

static void test_near_mirror(void **state)
{
    (void)state;
    static const struct {
        const char *spec;
        double x[8];
        int width; /* index of alpha / m */
    } cases[] = {
        {"walter", {0.5, 0.3, 0.15, 0.9, 0.85, 0.8, 1e-3, 0.1}, 6},
        {"cook_torrance", {0.4, 0.35, 0.3, 0.7, 0.6, 0.5, 1e-3, 0.2}, 6},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        bf_samples *s = gonio(cases[i].spec, cases[i].x, 0.01);
        bf_fit_options o;
        ts_fit_defaults(&o);
        bf_fit_result r;
        if (fit(s, cases[i].spec, &o, &r, "near-mirror")) {
            /* Noiseless: the peak is resolved, so the truth itself. */
            for (int k = 0; k < 8; k++)
                expect_rel(&r, k, cases[i].x[k], 1e-6, cases[i].spec);
            assert_true(r.metrics.rmse < 1e-9 * max_value(s));
        } else {
            fail_msg("near-mirror %s did not converge: %s", cases[i].spec, r.solution.termination);
        }
        bf_fit_result_clear(&r);
        bf_samples_free(s);
    }
}

/* ---- large exponents ----------------------------------------------------------------- */

static void test_large_exponents(void **state)
{
    (void)state;
    static const struct {
        const char *spec;
        double n;
    } cases[] = {{"phong", 1e4}, {"phong", 1e5}, {"blinn_phong", 1e4}, {"blinn_phong", 1e5}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        double x[7] = {0.3, 0.4, 0.5, 0.5, 0.55, 0.6, cases[i].n};
        bf_samples *s = gonio(cases[i].spec, x, 0.01);
        bf_fit_options o;
        ts_fit_defaults(&o);
        bf_fit_result r;
        if (!fit(s, cases[i].spec, &o, &r, "large exponent"))
            fail_msg("%s n = %g did not converge: %s", cases[i].spec, cases[i].n, r.solution.termination);
        for (int k = 0; k < 7; k++)
            expect_rel(&r, k, x[k], 1e-6, cases[i].spec);
        bf_fit_result_clear(&r);
        bf_samples_free(s);
    }
}

/* ---- Lambertian data, specular models --------------------------------------------------- */

static void test_lambertian_data(void **state)
{
    (void)state;
    const double rho[3] = {0.6, 0.5, 0.4};
    bf_samples *s = stratified("lambert", rho, 2401);
    static const char *const specs[] = {"walter", "cook_torrance", "phong"};
    for (size_t i = 0; i < sizeof specs / sizeof specs[0]; i++) {
        bf_fit_options o;
        ts_fit_defaults(&o);
        bf_fit_result r;
        if (!fit(s, specs[i], &o, &r, "lambertian data"))
            fail_msg("%s on Lambertian data did not converge: %s", specs[i], r.solution.termination);
        /* The lobe vanishes (its weight to ~0, or its shape flat enough to act as
         * diffuse: then rho_d + lobe is the Lambertian level); the values are exact. */
        assert_true(r.metrics.rmse < 1e-4 * rho[2] / M_PI);
        for (int c = 0; c < 3; c++) {
            if (!(r.x[3 + c] < 1e-3))
                fail_msg("%s rho_s[%d] = %g on Lambertian data", specs[i], c, r.x[3 + c]);
            ts_assert_near(r.x[c], rho[c], 2e-3, 0.0, "rho_d on Lambertian data");
        }
        bf_fit_result_clear(&r);
    }
    bf_samples_free(s);
}

/* ---- grazing angles only ---------------------------------------------------------------- */

static void test_grazing_only(void **state)
{
    (void)state;
    const double truth[8] = {0.5, 0.3, 0.15, 0.9, 0.85, 0.8, 0.2, 0.1};
    bf_samples *s = stratified("walter", truth, 160000);
    unsigned char *keep = malloc(s->n);
    for (size_t i = 0; i < s->n; i++)
        keep[i] = s->theta_i[i] > 75.0 && s->theta_o[i] > 75.0;
    assert_int_equal(bf_samples_keep(s, keep, NULL), BF_OK);
    free(keep);
    if (verbose())
        printf("grazing: %zu samples\n", s->n);
    assert_true(s->n > 500);
    /* Lambert first: every specular model must do at least as well (it contains it). */
    static const char *const specs[] = {"lambert", "walter", "cook_torrance", "phong", "ward"};
    double lambert_rmse = 0.0;
    for (size_t i = 0; i < sizeof specs / sizeof specs[0]; i++) {
        bf_fit_options o;
        ts_fit_defaults(&o);
        bf_fit_result r;
        int ok = fit(s, specs[i], &o, &r, "grazing only");
        if (!ok)
            fail_msg("%s on grazing data: %s", specs[i], r.solution.termination);
        if (i == 0)
            lambert_rmse = r.metrics.rmse;
        else if (!(r.metrics.rmse < lambert_rmse))
            fail_msg("%s on grazing data: rmse %g, Lambert's %g", specs[i], r.metrics.rmse, lambert_rmse);
        if (!strcmp(specs[i], "walter")) {
            /* The generating model: noiseless data, so the truth. */
            for (int k = 0; k < 8; k++)
                expect_rel(&r, k, truth[k], 1e-6, "walter on grazing data");
        }
        bf_fit_result_clear(&r);
    }
    bf_samples_free(s);
}

/* ---- f0 near 1: metals -------------------------------------------------------------------- */

static void test_f0_near_one(void **state)
{
    (void)state;
    static const struct {
        const char *spec;
        double x[8];
    } cases[] = {
        {"walter", {0.05, 0.04, 0.03, 0.95, 0.64, 0.54, 0.15, 0.98}}, /* copper-like */
        {"walter", {0.02, 0.02, 0.02, 0.9, 0.9, 0.9, 0.05, 1.0 - 1e-6}},
        {"cook_torrance", {0.02, 0.02, 0.02, 0.9, 0.8, 0.5, 0.2, 0.97}}, /* gold-like */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        bf_samples *s = stratified(cases[i].spec, cases[i].x, 4096);
        bf_fit_options o;
        ts_fit_defaults(&o);
        bf_fit_result r;
        if (!fit(s, cases[i].spec, &o, &r, "f0 near 1"))
            fail_msg("%s with f0 %g: %s", cases[i].spec, cases[i].x[7], r.solution.termination);
        for (int k = 0; k < 8; k++)
            expect_rel(&r, k, cases[i].x[k], 1e-6, cases[i].spec);
        bf_fit_result_clear(&r);
        bf_samples_free(s);
    }
}

/* ---- zeros and small negative values ---------------------------------------------------------- */

static void test_zeros_and_negatives(void **state)
{
    (void)state;
    /* A dark glossy material with additive noise: the dark off-specular values go
     * negative (about a quarter of them); plus exact zeros. */
    const double truth[8] = {0.02, 0.015, 0.01, 0.5, 0.5, 0.5, 0.15, 0.1};
    for (int mode = 0; mode < 3; mode++) {
        bf_synth_options so;
        memset(&so, 0, sizeof so);
        so.pattern = BF_SYNTH_STRATIFIED;
        so.count = 4096;
        so.seed = 9;
        so.noise.model = BF_NOISE_ADDITIVE;
        so.noise.level = 0.004;
        bf_samples *s = generate("walter", truth, &so);
        size_t nneg = 0;
        for (size_t i = 0; i < s->n * NCH; i++) {
            if (i % 97 == 0)
                s->value[i] = 0.0;
            nneg += s->value[i] < 0.0;
        }
        assert_true(nneg > s->n / 10);
        bf_prep p;
        memset(&p, 0, sizeof p);
        p.negative = mode == 0 ? BF_NEGATIVE_KEEP : mode == 1 ? BF_NEGATIVE_CLAMP : BF_NEGATIVE_DROP;
        bf_prep_report rep;
        bf_error err;
        assert_int_equal(bf_samples_prep(s, &p, &rep, &err), BF_OK);
        assert_true(rep.negative > 0);
        static const char *const specs[] = {"walter", "lambert", "phong"};
        for (size_t j = 0; j < sizeof specs / sizeof specs[0]; j++) {
            for (int res = 0; res < 2; res++) {
                bf_fit_options o;
                ts_fit_defaults(&o);
                /* log and cbrt residuals of a negative value: ln(1 + m c) and cbrt(m c)
                 * are defined for m c > -1; they must stay finite. */
                o.objective.residual = res == 0 ? BF_RESIDUAL_LINEAR : BF_RESIDUAL_LOG;
                bf_fit_result r;
                char what[64];
                snprintf(what, sizeof what, "negatives mode %d residual %d", mode, res);
                if (!fit(s, specs[j], &o, &r, what))
                    fail_msg("%s, %s: %s", what, specs[j], r.solution.termination);
                if (!strcmp(specs[j], "walter") && mode == 0 && res == 0) {
                    /* Kept negatives are unbiased data: the lobe within its noise. */
                    ts_assert_rel(r.x[6], truth[6], 0.02, "alpha with negatives kept");
                    for (int c = 0; c < 3; c++)
                        ts_assert_rel(r.x[3 + c], truth[3 + c], 0.05, "rho_s with negatives kept");
                }
                bf_fit_result_clear(&r);
            }
        }
        bf_samples_free(s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_near_mirror),     cmocka_unit_test(test_large_exponents),
        cmocka_unit_test(test_lambertian_data), cmocka_unit_test(test_grazing_only),
        cmocka_unit_test(test_f0_near_one),     cmocka_unit_test(test_zeros_and_negatives),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
