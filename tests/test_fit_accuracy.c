/* The fit defaults (bf_fit_options_init) and the accuracy presets: names parsed and
 * refused, each preset's settings, explicit settings winning over a preset, and the
 * preset's subsample reaching the data only when none was given. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/fit.h"
#include "fit_impl.h"

static void test_defaults(void **state)
{
    (void)state;
    bf_fit_options o;
    memset(&o, 0xff, sizeof o); /* every field set, not left from a zeroed frame */
    bf_fit_options_init(&o);
    assert_int_equal(o.objective.residual, BF_RESIDUAL_LOG);
    assert_int_equal(o.objective.use_weights, 1);
    assert_int_equal(o.objective.solid_angle, 0);
    assert_null(o.objective.overrides);
    assert_int_equal(o.solver.backend, BF_BACKEND_CERES);
    assert_null(o.solver.algorithm);
    assert_int_equal(o.solver.max_iterations, 0);
    assert_int_equal(o.starts, 0); /* automatic: the screened search (search.c) */
    assert_int_equal(o.screen, BF_FIT_SCREEN);
    assert_true(o.seed == 0);
    assert_null(o.start);
    assert_int_equal(o.presolve, 0);
    assert_true(o.solver.threads >= 1);
}

static void test_names(void **state)
{
    (void)state;
    static const char *const names[] = {"fast", "balanced", "best"};
    static const bf_fit_accuracy values[] = {BF_ACCURACY_FAST, BF_ACCURACY_BALANCED, BF_ACCURACY_BEST};
    for (int k = 0; k < 3; k++) {
        bf_fit_accuracy a = BF_ACCURACY_NONE;
        bf_error err;
        assert_int_equal(bf_fit_accuracy_parse(names[k], &a, &err), BF_OK);
        assert_int_equal(a, values[k]);
        assert_string_equal(bf_fit_accuracy_name(a), names[k]);
    }
    assert_string_equal(bf_fit_accuracy_name(BF_ACCURACY_NONE), "");
    assert_string_equal(bf_fit_accuracy_name((bf_fit_accuracy)99), "unknown");
}

static void test_bad_names_refused(void **state)
{
    (void)state;
    static const char *const bad[] = {"quick", "", "Fast", "best ", "none"};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        bf_fit_accuracy a = BF_ACCURACY_BALANCED;
        bf_error err;
        assert_int_equal(bf_fit_accuracy_parse(bad[k], &a, &err), BF_ERR_ARG);
        assert_int_equal(a, BF_ACCURACY_BALANCED); /* left as it was */
        assert_non_null(strstr(err.msg, "fast, balanced, best"));
    }
    bf_fit_accuracy a = BF_ACCURACY_NONE;
    assert_int_equal(bf_fit_accuracy_parse(NULL, &a, NULL), BF_ERR_ARG);
}

static void test_presets_on_defaults(void **state)
{
    (void)state;
    bf_fit_options o;
    size_t sub = 0;
    bf_fit_options_init(&o);
    bf_fit_options_apply_accuracy(&o, BF_ACCURACY_FAST, 0, &sub);
    assert_int_equal(sub, BF_ACCURACY_FAST_SUBSAMPLE);
    assert_int_equal(o.solver.backend, BF_BACKEND_CERES);
    assert_int_equal(o.starts, 1); /* the data-driven start alone, unscreened */
    assert_int_equal(o.screen, 0);
    assert_int_equal(o.solver.max_iterations, 0);

    sub = 0;
    bf_fit_options_init(&o);
    bf_fit_options_apply_accuracy(&o, BF_ACCURACY_BALANCED, 0, &sub);
    assert_int_equal(sub, 0);
    assert_int_equal(o.starts, 0);
    assert_int_equal(o.screen, BF_FIT_SCREEN);
    assert_int_equal(o.solver.max_iterations, 0);

    bf_fit_options_init(&o);
    bf_fit_options_apply_accuracy(&o, BF_ACCURACY_BEST, 0, &sub);
    assert_int_equal(sub, 0);
    assert_int_equal(o.starts, BF_ACCURACY_BEST_STARTS);
    assert_int_equal(o.screen, BF_ACCURACY_BEST_SCREEN);
    assert_int_equal(o.solver.max_iterations, BF_ACCURACY_BEST_ITERATIONS);

    /* An explicit --screen stays. */
    bf_fit_options_init(&o);
    o.screen = 5;
    bf_fit_options_apply_accuracy(&o, BF_ACCURACY_FAST, BF_FIT_GIVEN_SCREEN, &sub);
    assert_int_equal(o.screen, 5);

    /* No preset changes nothing, and a NULL subsample is allowed. */
    bf_fit_options before, after;
    bf_fit_options_init(&before);
    before.starts = 7;
    before.solver.backend = BF_BACKEND_NLOPT;
    after = before;
    bf_fit_options_apply_accuracy(&after, BF_ACCURACY_NONE, 0, &sub);
    assert_memory_equal(&before, &after, sizeof before);
    bf_fit_options_apply_accuracy(&after, BF_ACCURACY_FAST, 0, NULL);
    assert_int_equal(after.solver.backend, BF_BACKEND_CERES);
}

static void test_explicit_settings_win(void **state)
{
    (void)state;
    bf_fit_options o;
    size_t sub = 0;
    /* --backend nlopt --starts 3 with best: both kept; NLopt's evaluation limit is not
     * Ceres's iteration count, so the preset leaves it alone. */
    bf_fit_options_init(&o);
    o.solver.backend = BF_BACKEND_NLOPT;
    o.starts = 3;
    bf_fit_options_apply_accuracy(&o, BF_ACCURACY_BEST, BF_FIT_GIVEN_BACKEND | BF_FIT_GIVEN_STARTS, &sub);
    assert_int_equal(o.solver.backend, BF_BACKEND_NLOPT);
    assert_int_equal(o.starts, 3);
    assert_int_equal(o.solver.max_iterations, 0);

    /* --algorithm alone keeps the back end it belongs to. */
    bf_fit_options_init(&o);
    o.solver.algorithm = "dogleg";
    bf_fit_options_apply_accuracy(&o, BF_ACCURACY_BEST, BF_FIT_GIVEN_ALGORITHM, &sub);
    assert_string_equal(o.solver.algorithm, "dogleg");
    assert_int_equal(o.starts, BF_ACCURACY_BEST_STARTS);

    /* --max-iterations wins; without it a preset resets a Ceres limit. */
    bf_fit_options_init(&o);
    o.solver.max_iterations = 42;
    bf_fit_options_apply_accuracy(&o, BF_ACCURACY_BEST, BF_FIT_GIVEN_MAX_ITERATIONS, &sub);
    assert_int_equal(o.solver.max_iterations, 42);
    bf_fit_options_apply_accuracy(&o, BF_ACCURACY_FAST, 0, &sub);
    assert_int_equal(o.solver.max_iterations, 0);

    /* Without the bits, the preset overrides what the options hold. */
    bf_fit_options_init(&o);
    o.solver.backend = BF_BACKEND_NLOPT;
    o.solver.algorithm = "LD_MMA";
    o.starts = 9;
    bf_fit_options_apply_accuracy(&o, BF_ACCURACY_FAST, 0, &sub);
    assert_int_equal(o.solver.backend, BF_BACKEND_CERES);
    assert_null(o.solver.algorithm);
    assert_int_equal(o.starts, 1);
}

static void test_subsample_only_when_not_given(void **state)
{
    (void)state;
    bf_fit_options o;
    bf_fit_options_init(&o);
    size_t sub = 5000; /* --subsample 5000 */
    bf_fit_options_apply_accuracy(&o, BF_ACCURACY_FAST, BF_FIT_GIVEN_SUBSAMPLE, &sub);
    assert_int_equal(sub, 5000);
    sub = 0; /* --subsample all */
    bf_fit_options_apply_accuracy(&o, BF_ACCURACY_FAST, BF_FIT_GIVEN_SUBSAMPLE, &sub);
    assert_int_equal(sub, 0);
    sub = 0; /* not given */
    bf_fit_options_apply_accuracy(&o, BF_ACCURACY_FAST, BF_FIT_GIVEN_STARTS, &sub);
    assert_int_equal(sub, BF_ACCURACY_FAST_SUBSAMPLE);
    sub = 123; /* presets without a subsample leave it as it is */
    bf_fit_options_apply_accuracy(&o, BF_ACCURACY_BEST, 0, &sub);
    assert_int_equal(sub, 123);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults),
        cmocka_unit_test(test_names),
        cmocka_unit_test(test_bad_names_refused),
        cmocka_unit_test(test_presets_on_defaults),
        cmocka_unit_test(test_explicit_settings_win),
        cmocka_unit_test(test_subsample_only_when_not_given),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
