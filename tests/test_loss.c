/* Robust losses: rho(s) and rho'(s) against Ceres' formulas (written out again here) and
 * against central differences; parsing of "name[:scale]" and its errors. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/solve.h"
#include "support.h"

/* Ceres' rho(s), independently of the library's code (soft_l1 as 2 a^2 (sqrt(1 + s/a^2)
 * - 1) rearranged to avoid cancellation at small s, cauchy through log1p). */
static double want_rho(bf_loss_kind k, double a, double s)
{
    switch (k) {
    case BF_LOSS_HUBER: return s <= a * a ? s : 2 * a * sqrt(s) - a * a;
    case BF_LOSS_CAUCHY: return a * a * log1p(s / (a * a));
    case BF_LOSS_SOFT_L1: return 2 * s / (sqrt(1 + s / (a * a)) + 1);
    case BF_LOSS_ARCTAN: return a * atan(s / a);
    default: return s;
    }
}

/* Their derivatives, by hand. */
static double want_d1(bf_loss_kind k, double a, double s)
{
    switch (k) {
    case BF_LOSS_HUBER: return s <= a * a ? 1.0 : a / sqrt(s);
    case BF_LOSS_CAUCHY: return 1.0 / (1 + s / (a * a));
    case BF_LOSS_SOFT_L1: return 1.0 / sqrt(1 + s / (a * a));
    case BF_LOSS_ARCTAN: return 1.0 / (1 + s * s / (a * a));
    default: return 1.0;
    }
}

static void test_values_and_derivatives(void **state)
{
    (void)state;
    const bf_loss_kind kinds[] = {BF_LOSS_NONE, BF_LOSS_HUBER, BF_LOSS_CAUCHY, BF_LOSS_SOFT_L1, BF_LOSS_ARCTAN};
    const double scales[] = {0.1, 1.0, 2.5};
    const double ss[] = {0.0, 1e-6, 3e-3, 0.02, 0.5, 1.0, 4.0, 37.0, 1e4};
    for (size_t ik = 0; ik < sizeof kinds / sizeof kinds[0]; ik++)
        for (size_t ia = 0; ia < 3; ia++)
            for (size_t is = 0; is < sizeof ss / sizeof ss[0]; is++) {
                const bf_loss l = {kinds[ik], scales[ia]};
                const double a = scales[ia], s = ss[is];
                char what[96];
                double d1 = -1.0;
                const double rho = bf_loss_eval(&l, s, &d1);
                snprintf(what, sizeof what, "rho kind %d a %g s %g", (int)kinds[ik], a, s);
                ts_assert_near(rho, want_rho(kinds[ik], a, s), 1e-14, 1e-300, what);
                snprintf(what, sizeof what, "rho' kind %d a %g s %g", (int)kinds[ik], a, s);
                ts_assert_rel(d1, want_d1(kinds[ik], a, s), 1e-14, what);
                /* d1 may be NULL */
                assert_true(bf_loss_eval(&l, s, NULL) == rho);
                /* central differences away from 0 and from Huber's kink at s = a^2 */
                const double h = 1e-6 * (s > 1 ? s : 1);
                if (s - h <= 0 || (kinds[ik] == BF_LOSS_HUBER && fabs(s - a * a) < 2 * h))
                    continue;
                const double fd = (bf_loss_eval(&l, s + h, NULL) - bf_loss_eval(&l, s - h, NULL)) / (2 * h);
                snprintf(what, sizeof what, "rho' vs differences kind %d a %g s %g", (int)kinds[ik], a, s);
                /* plus the rounding of the differences, ~eps rho / h */
                ts_assert_near(d1, fd, 1e-6, 1e-15 * fabs(rho) / h, what);
            }
}

/* Every loss is least squares for small residuals and bounded in its pull for large. */
static void test_shape(void **state)
{
    (void)state;
    const bf_loss_kind kinds[] = {BF_LOSS_HUBER, BF_LOSS_CAUCHY, BF_LOSS_SOFT_L1, BF_LOSS_ARCTAN};
    for (size_t ik = 0; ik < 4; ik++) {
        const bf_loss l = {kinds[ik], 0.5};
        double d1;
        ts_assert_rel(bf_loss_eval(&l, 1e-10, &d1), 1e-10, 1e-9, "rho ~ s near 0");
        ts_assert_rel(d1, 1.0, 1e-9, "rho' ~ 1 near 0");
        /* a residual of 100 scales: its weight rho' is far below 1 */
        bf_loss_eval(&l, 1e4 * 0.25, &d1);
        assert_true(d1 < 0.02);
        assert_true(d1 > 0.0);
    }
    /* Huber at the kink: both branches meet (value and slope continuous) */
    const bf_loss hub = {BF_LOSS_HUBER, 0.3};
    double dl, dr;
    const double lft = bf_loss_eval(&hub, 0.09 * (1 - 1e-12), &dl);
    const double rgt = bf_loss_eval(&hub, 0.09 * (1 + 1e-12), &dr);
    ts_assert_rel(lft, rgt, 1e-10, "huber value at the kink");
    ts_assert_rel(dl, dr, 1e-10, "huber slope at the kink");
}

static void test_parse(void **state)
{
    (void)state;
    const struct {
        const char *text;
        bf_loss_kind kind;
        double scale;
    } good[] = {
        {"none", BF_LOSS_NONE, 1.0},           {"huber", BF_LOSS_HUBER, 1.0},         {"huber:0.1", BF_LOSS_HUBER, 0.1},
        {"cauchy:2", BF_LOSS_CAUCHY, 2.0},     {"soft_l1:0.5", BF_LOSS_SOFT_L1, 0.5}, {"arctan:1", BF_LOSS_ARCTAN, 1.0},
        {"Cauchy:1e-3", BF_LOSS_CAUCHY, 1e-3}, {"soft_l1", BF_LOSS_SOFT_L1, 1.0},
    };
    for (size_t i = 0; i < sizeof good / sizeof good[0]; i++) {
        bf_loss l = {BF_LOSS_ARCTAN, -7};
        bf_error err = {0};
        assert_int_equal(bf_loss_parse(good[i].text, &l, &err), BF_OK);
        assert_int_equal(l.kind, good[i].kind);
        assert_true(l.scale == good[i].scale);
    }
    bf_loss l;
    assert_int_equal(bf_loss_parse(NULL, &l, NULL), BF_OK); /* no loss: least squares */
    assert_int_equal(l.kind, BF_LOSS_NONE);

    const struct {
        const char *text;
        const char *fragment;
    } bad[] = {
        {"", "unknown loss"},
        {"tukey", "unknown loss"},
        {"hubber:0.1", "unknown loss"},
        {"huber:0", "> 0"},
        {"huber:-1", "> 0"},
        {"cauchy:inf", "> 0"},
        {"cauchy:nan", "> 0"},
        {"huber:", "not a number"},
        {"huber:x", "not a number"},
        {"huber:0.1x", "not a number"},
        {"none:2", "no scale"},
        {"arctan:1:2", "not a number"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        bf_error err = {0};
        assert_int_equal(bf_loss_parse(bad[i].text, &l, &err), BF_ERR_ARG);
        assert_int_equal(err.code, BF_ERR_ARG);
        char quoted[64];
        snprintf(quoted, sizeof quoted, "\"%s\"", bad[i].text);
        if (!strstr(err.msg, quoted) || !strstr(err.msg, bad[i].fragment))
            fail_msg("loss \"%s\": message \"%s\" should name the text and say \"%s\"", bad[i].text, err.msg,
                     bad[i].fragment);
        assert_null(strchr(err.msg, '\n'));
    }
    /* the unknown-name message lists the known ones */
    bf_error err = {0};
    bf_loss_parse("tukey", &l, &err);
    assert_non_null(strstr(err.msg, "huber"));
    assert_non_null(strstr(err.msg, "soft_l1"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_values_and_derivatives),
        cmocka_unit_test(test_shape),
        cmocka_unit_test(test_parse),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
