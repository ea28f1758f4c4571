/* Each warning of a fit carries its kind (brdfit/fit.h, bf_warning_kind), and what is
 * decided on warnings is decided on kinds: the names round-trip through
 * bf_warning_kind_parse (an unknown one refused with the list), real fits give the kinds
 * their warnings say (best reached from one start, at a bound, narrow lobe, cancelled),
 * and bf_fit_result_unsure follows the kind, not the text. The kinds of the other checks
 * are asserted beside them in test_diagnostics.c. */
#include <ctype.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/fit.h"
#include "brdfit/prep.h"
#include "fit_impl.h"
#include "support.h"

/* n samples of model spec at x (C channels) in random directions, a third near the
 * mirror direction. */
static bf_samples *synth(const char *spec, int C, const double *x, size_t n, uint64_t seed)
{
    bf_samples *s = NULL;
    assert_int_equal(bf_samples_new(n, C, &s, NULL), BF_OK);
    ts_rng rng = {seed};
    for (size_t i = 0; i < n; i++)
        ts_random_pair_deg(&rng, i % 3 == 0, &s->theta_i[i], &s->phi_i[i], &s->theta_o[i], &s->phi_o[i]);
    bf_model *m = ts_model(spec, C);
    bf_model_eval(m, x, ts_samples_geometry(s), s->value, NULL);
    bf_model_free(m);
    return s;
}

/* Every kind's name is snake_case, unique and parsed back to it; files store these, so
 * a few are pinned here as they must stay. */
static void test_names(void **state)
{
    (void)state;
    for (int k = 0; k < BF_WARN_KINDS; k++) {
        const char *name = bf_warning_kind_name((bf_warning_kind)k);
        assert_true(name[0] != '\0');
        for (const char *c = name; *c; c++)
            assert_true(islower((unsigned char)*c) || *c == '_');
        for (int j = 0; j < k; j++)
            assert_string_not_equal(name, bf_warning_kind_name((bf_warning_kind)j));
        bf_warning_kind back = BF_WARN_KINDS;
        bf_error err;
        assert_int_equal(bf_warning_kind_parse(name, &back, &err), BF_OK);
        assert_int_equal(back, k);
    }
    assert_int_equal(BF_WARN_OTHER, 0);
    assert_string_equal(bf_warning_kind_name(BF_WARN_OTHER), "other");
    assert_string_equal(bf_warning_kind_name(BF_WARN_AT_BOUND), "at_bound");
    assert_string_equal(bf_warning_kind_name(BF_WARN_UNDETERMINED), "undetermined");
    assert_string_equal(bf_warning_kind_name(BF_WARN_ONE_START), "one_start");
    assert_string_equal(bf_warning_kind_name(BF_WARN_KINDS), "unknown");
    assert_string_equal(bf_warning_kind_name((bf_warning_kind)-1), "unknown");
}

static void test_parse_refuses(void **state)
{
    (void)state;
    bf_warning_kind k = BF_WARN_AT_BOUND;
    bf_error err;
    assert_int_equal(bf_warning_kind_parse("at bound", &k, &err), BF_ERR_ARG);
    assert_int_equal(k, BF_WARN_AT_BOUND); /* untouched */
    assert_non_null(strstr(err.msg, "unknown warning kind 'at bound'"));
    for (int j = 0; j < BF_WARN_KINDS; j++) /* the message lists every name */
        assert_non_null(strstr(err.msg, bf_warning_kind_name((bf_warning_kind)j)));
    assert_null(strchr(err.msg, '\n'));
    assert_int_equal(bf_warning_kind_parse("unknown", &k, &err), BF_ERR_ARG);
    assert_int_equal(bf_warning_kind_parse("", &k, &err), BF_ERR_ARG);
    assert_int_equal(bf_warning_kind_parse(NULL, &k, &err), BF_ERR_ARG);
    assert_int_equal(bf_warning_kind_parse("at_bound", &k, NULL), BF_OK); /* err may be NULL */
}

/* The warning of kind `kind` (the first), or -1. */
static int find_kind(const bf_fit_result *r, bf_warning_kind kind)
{
    for (int i = 0; i < r->nwarnings; i++)
        if (r->warning_kind[i] == kind)
            return i;
    return -1;
}

/* Cook-Torrance from 2 starts on 20 samples of the Cayman paint (tests/data), the case
 * brdfit compare marks with "?": its best optimum is reached from one of them. */
static void fit_one_start(bf_fit_result *r)
{
    bf_samples *s = ts_read_data(BRDFIT_TEST_DATA "/cornell/cayman_head20.brdf");
    bf_prep p;
    memset(&p, 0, sizeof p);
    p.color = BF_COLOR_SRGB;
    bf_error err;
    if (bf_samples_prep(s, &p, NULL, &err) != BF_OK)
        fail_msg("%s", err.msg);
    bf_fit_options o;
    bf_fit_options_init(&o);
    o.starts = 2;
    o.screen = 8;
    o.solver.threads = 1;
    ts_fit_ok(s, "cook_torrance", &o, r);
    bf_samples_free(s);
    for (int i = 0; i < r->nwarnings; i++)
        printf("  %s: %s\n", bf_warning_kind_name(r->warning_kind[i]), r->warnings[i]);
    if (!(r->starts == 2 && r->starts_at_best == 1))
        fail_msg("the case changed: %d of %d starts at the best", r->starts_at_best, r->starts);
}

static void test_one_start(void **state)
{
    (void)state;
    bf_fit_result r;
    fit_one_start(&r);
    const int w = find_kind(&r, BF_WARN_ONE_START);
    assert_true(w >= 0);
    assert_non_null(strstr(r.warnings[w], "the best optimum was reached from 1 of 2 starts"));
    assert_int_equal(find_kind(&r, BF_WARN_OTHER), -1); /* every warning here has a kind */
    const int b = find_kind(&r, BF_WARN_AT_BOUND);
    assert_true(b >= 0);
    assert_non_null(strstr(r.warnings[b], "bound"));
    assert_true(find_kind(&r, BF_WARN_NARROW_LOBE) >= 0);
    assert_true(bf_fit_result_unsure(&r));

    /* unsure() reads the kind: the same text with another kind is not unsure, and any
     * text with the one-start kind is. */
    r.warning_kind[w] = BF_WARN_OTHER;
    assert_false(bf_fit_result_unsure(&r));
    r.warning_kind[b] = BF_WARN_ONE_START;
    assert_true(bf_fit_result_unsure(&r));
    assert_false(bf_fit_result_unsure(NULL));
    bf_fit_result_clear(&r);
}

/* A fit from one start is never unsure, whatever else it warns of. */
static void test_single_start_sure(void **state)
{
    (void)state;
    const double x[3] = {0.5, 0.0, 0.3};
    bf_samples *s = synth("lambert", 3, x, 200, 11);
    for (size_t i = 0; i < s->n; i++)
        s->value[3 * i + 1] = -0.01; /* below zero: rho_d[1] held at its bound */
    bf_fit_options o;
    ts_fit_defaults(&o);
    bf_fit_result r;
    ts_fit_ok(s, "lambert", &o, &r);
    const int b = find_kind(&r, BF_WARN_AT_BOUND);
    assert_true(b >= 0);
    assert_non_null(strstr(r.warnings[b], "rho_d[1] = 0 is at its lower bound 0"));
    assert_int_equal(find_kind(&r, BF_WARN_ONE_START), -1);
    assert_false(bf_fit_result_unsure(&r));
    bf_fit_result_clear(&r);
    bf_samples_free(s);
}

/* A fit cancelled before its first solve says so, with that kind. */
static void test_cancelled(void **state)
{
    (void)state;
    const double x[4] = {0.4, 0.5, 0.3, 0.05};
    bf_samples *s = synth("walter", 1, x, 300, 5);
    static const bf_cancel_flag cancel = 1;
    bf_fit_options o;
    ts_fit_defaults(&o);
    o.solver.cancel = &cancel;
    bf_fit_result r;
    bf_error err;
    assert_int_equal(bf_fit_with(s, "walter", &o, &r, &err), BF_OK);
    assert_false(r.ok);
    assert_int_equal(r.nwarnings, 1);
    assert_int_equal(r.warning_kind[0], BF_WARN_CANCELLED);
    assert_non_null(strstr(r.warnings[0], "cancelled"));
    bf_fit_result_clear(&r);
    bf_samples_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_names),     cmocka_unit_test(test_parse_refuses),
        cmocka_unit_test(test_one_start), cmocka_unit_test(test_single_start_sure),
        cmocka_unit_test(test_cancelled),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
