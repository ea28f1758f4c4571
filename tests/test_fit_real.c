/* Fits of measured data nobody synthesised (bundled: examples/cornell, tests/data/nist_ptfe):
 * Cornell "Cayman Metallic" and "Garnet Red" car paints (spectral, as RGB like
 * --rgb) and NIST sintered PTFE (f_r11, monochrome). Lambert and every other family
 * (default options) from the data-driven start: every fit converges, and every
 * non-Lambert model's error is below the Lambert fit's on each data set, but for the
 * exceptions listed at expected_worse (Oren-Nayar equal; Ashikhmin-Shirley on PTFE).
 *
 * Residual and metric: the log residual ln(1 + f cos) - ln(1 + m cos), compared through
 * the log RMSE, which is the same quantity (the samples carry no weights). Comparing
 * the objective's own metric makes the claim exact: every model here can reproduce a
 * Lambertian BRDF (a lobe weight at 0, Oren-Nayar sigma 0, Disney's lobes off), so a
 * fit that converged cannot be worse than Lambert's. The log form is also what users
 * compare for glossy data: the car paints' peaks (646 and 38 1/sr) would otherwise
 * decide a linear RMSE alone. Full data sets (1439 and 1760 samples): small enough. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/formats.h"
#include "brdfit/fit.h"
#include "brdfit/prep.h"
#include "support.h"

static int verbose(void)
{
    return getenv("BRDFIT_TEST_VERBOSE") != NULL;
}

static bf_samples *read_ptfe(void)
{
    char path[512];
    snprintf(path, sizeof path, "%s/nist_ptfe/PTFE.data.random.csv", BRDFIT_TEST_DATA);
    bf_read_options ro;
    memset(&ro, 0, sizeof ro);
    ro.format = BF_FORMAT_CSV;
    ro.csv.angle_cols[0] = "thetai";
    ro.csv.angle_cols[1] = "phi";
    ro.csv.angle_cols[2] = "thetar";
    ro.csv.angle_cols[3] = "phir";
    ro.csv.channels = "f_r11";
    bf_samples *s = NULL;
    bf_error err;
    if (bf_samples_read_with(path, &ro, &s, &err) != BF_OK)
        fail_msg("%s", err.msg);
    bf_prep p;
    memset(&p, 0, sizeof p); /* drops only what cannot be used */
    if (bf_samples_prep(s, &p, NULL, &err) != BF_OK)
        fail_msg("PTFE: %s", err.msg);
    assert_int_equal(s->channels, 1);
    assert_int_equal(s->n, 1760);
    return s;
}

/* Expected exceptions, each checked as stated so that the list stays true:
 *  - oren_nayar equals Lambert (to 1e-9) on all three sets: its sigma goes to 0, where
 *    it is Lambert; the data hold no retro-reflection for it to explain.
 *  - ashikhmin_shirley(_iso) on PTFE is worse than Lambert (log RMSE 0.0242 against
 *    0.0093): its diffuse term, rho_d 28/(23 pi)(1 - rho_s)(1 - (1 - NL/2)^5)
 *    (1 - (1 - NV/2)^5), falls towards 0 at grazing angles and is capped by
 *    rho_d <= 1, and PTFE is a near-perfect diffuser measured to 82 degrees: the fit
 *    ends with rho_d at its bound 1 and rho_s at 0 (30 seeded starts find the same).
 *    A property of the model, not of the start or the objective. */
static int expected_worse(const char *what, const char *spec)
{
    return !strcmp(what, "PTFE") && !strncmp(spec, "ashikhmin_shirley", 17);
}

static void fit_all(bf_samples *s, const char *what)
{
    bf_fit_options o;
    memset(&o, 0, sizeof o);
    bf_objective_options_init(&o.objective); /* the embedded structs carry their sizes */
    bf_solver_options_init(&o.solver);
    o.objective.residual = BF_RESIDUAL_LOG;
    o.objective.use_weights = 1;
    o.solver.backend = BF_BACKEND_CERES;
    o.starts = 1;
    bf_fit_result r;
    bf_error err;
    if (bf_fit_with(s, "lambert", &o, &r, &err) != BF_OK || !r.ok)
        fail_msg("%s: lambert: %s", what, r.ok ? err.msg : r.solution.termination);
    double lambert = r.metrics.rmse_log;
    if (verbose())
        printf("%s: n %zu, lambert log rmse %.6g\n", what, s->n, lambert);
    assert_true(isfinite(lambert) && lambert > 0.0);
    bf_fit_result_clear(&r);
    int worse = 0;
    for (int f = 0; f < bf_family_count(); f++) {
        const char *spec = bf_family_get(f)->name;
        if (!strcmp(spec, "lambert"))
            continue;
        if (bf_fit_with(s, spec, &o, &r, &err) != BF_OK)
            fail_msg("%s: %s: %s", what, spec, err.msg);
        for (int k = 0; k < bf_model_nvalues(r.model); k++)
            if (!isfinite(r.x[k]))
                fail_msg("%s: %s parameter %d is %g", what, spec, k, r.x[k]);
        if (verbose())
            printf("  %-22s ok %d log rmse %.6g (%.3f of Lambert's) it %d %.3f s %s\n", spec, r.ok, r.metrics.rmse_log,
                   r.metrics.rmse_log / lambert, r.solution.iterations, r.seconds, r.solution.termination);
        if (!r.ok) {
            print_error("%s: %s did not converge: %s\n", what, spec, r.solution.termination);
            worse++;
        } else if (!strcmp(spec, "oren_nayar")) {
            if (!(r.metrics.rmse_log <= lambert * (1.0 + 1e-9)) || !(r.x[s->channels] < 1e-6)) {
                print_error("%s: oren_nayar log rmse %.9g, sigma %g, Lambert's %.9g\n", what, r.metrics.rmse_log,
                            r.x[s->channels], lambert);
                worse++;
            }
        } else if (expected_worse(what, spec)) {
            if (!(r.metrics.rmse_log > lambert) || !(r.x[0] == 1.0)) {
                print_error("%s: %s no longer fails as listed (log rmse %.6g, rho_d %g): update the list\n", what, spec,
                            r.metrics.rmse_log, r.x[0]);
                worse++;
            }
        } else if (!(r.metrics.rmse_log < lambert)) {
            print_error("%s: %s log rmse %.6g, not below Lambert's %.6g\n", what, spec, r.metrics.rmse_log, lambert);
            worse++;
        }
        bf_fit_result_clear(&r);
    }
    assert_int_equal(worse, 0);
}

static void test_cayman(void **state)
{
    (void)state;
    bf_samples *s = ts_read_cornell_rgb("cayman.brdf");
    fit_all(s, "cayman");
    bf_samples_free(s);
}

static void test_garnet_red(void **state)
{
    (void)state;
    bf_samples *s = ts_read_cornell_rgb("garnet_red.brdf");
    fit_all(s, "garnet_red");
    bf_samples_free(s);
}

static void test_ptfe(void **state)
{
    (void)state;
    bf_samples *s = read_ptfe();
    fit_all(s, "PTFE");
    bf_samples_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cayman),
        cmocka_unit_test(test_garnet_red),
        cmocka_unit_test(test_ptfe),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
