/* Values of the brady model (genBRDF model A) against closed forms at special geometry
 * and against a plain re-implementation of the docs/models.md formula from the angles. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "support.h"

#define REL 1e-12
#define assert_close(got, want, rel) ts_assert_rel((got), (want), (rel), #got)

static bf_model *make(int C)
{
    bf_error err;
    bf_model *m = NULL;
    if (bf_model_new("brady", C, &m, &err) != BF_OK)
        fail_msg("brady: %s", err.msg);
    return m;
}

/* x = rho_d, rho_s, f0, a, beta (C = 1). */
static double brady1(const double *x, double ti, double pi_, double to, double po)
{
    bf_model *m = make(1);
    assert_int_equal(bf_model_check(m, x, NULL), BF_OK);
    double v = ts_eval1(m, x, ti, pi_, to, po, 0);
    bf_model_free(m);
    return v;
}

/* At the peak tan(theta_h) = 0, so exp(-0) = 1 for every a and beta: at normal incidence
 * VH = 1 and F = f0, f = rho_d/pi + rho_s f0 / 4. */
static void test_peak_normal(void **state)
{
    (void)state;
    double x[5] = {0.3, 2.0, 0.05, 1.7, 0.2};
    const double want = 0.3 / M_PI + 2.0 * 0.05 / 4.0;
    assert_close(brady1(x, 0, 0, 0, 0), want, REL);
    x[3] = 3.0;
    x[4] = 1e-8;
    assert_close(brady1(x, 0, 0, 0, 0), want, REL);
    x[3] = 1e-9;
    x[4] = 10.0;
    assert_close(brady1(x, 0, 0, 0, 0), want, REL);
}

/* Mirror direction at 60 deg: tan(theta_h) = 0, VH = 1/2, F = f0 + (1 - f0)/32:
 * the lobe is F / 2. */
static void test_peak_mirror_60(void **state)
{
    (void)state;
    double x[5] = {0.1, 3.0, 0.2, 0.8, 0.6};
    const double F = 0.2 + 0.8 / 32.0;
    assert_close(brady1(x, 60, 25, 60, 205), 0.1 / M_PI + 3.0 * F / 2.0, REL);
}

/* Retro-reflection at 45 deg (L = V): H = L, tan(theta_h) = 1, VH = 1, F = f0: the lobe
 * is f0 exp(-(1/beta^2)^a) / 4. */
static void test_retro_45(void **state)
{
    (void)state;
    double x[5] = {0.0, 1.0, 0.5, 2.0, 1.0};
    assert_close(brady1(x, 45, 300, 45, 300), 0.5 * exp(-1.0) / 4.0, 1e-11);
    x[3] = 1.0;
    x[4] = sqrt(2.0); /* (1/2)^1 */
    assert_close(brady1(x, 45, 300, 45, 300), 0.5 * exp(-0.5) / 4.0, 1e-11);
    x[3] = 3.0;
    x[4] = sqrt(0.5); /* 2^3 */
    assert_close(brady1(x, 45, 300, 45, 300), 0.5 * exp(-8.0) / 4.0, 1e-11);
}

/* Plain re-implementation from the angles (degrees); x = rho_d[C], rho_s[C], f0, a, beta. */
static double brady_plain(int C, const double *x, int c, double ti, double pi_, double to, double po)
{
    double L[3] = {sin(ti * DEG) * cos(pi_ * DEG), sin(ti * DEG) * sin(pi_ * DEG), cos(ti * DEG)};
    double V[3] = {sin(to * DEG) * cos(po * DEG), sin(to * DEG) * sin(po * DEG), cos(to * DEG)};
    if (L[2] <= 0.0 || V[2] <= 0.0)
        return 0.0;
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double len = sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
    for (int k = 0; k < 3; k++)
        H[k] /= len;
    double vh = V[0] * H[0] + V[1] * H[1] + V[2] * H[2];
    double tan_h = sqrt(H[0] * H[0] + H[1] * H[1]) / H[2];
    double f0 = x[2 * C], a = x[2 * C + 1], beta = x[2 * C + 2];
    double F = f0 + (1.0 - f0) * pow(1.0 - vh, 5.0);
    return x[c] / M_PI + x[C + c] * F * exp(-pow(tan_h / (beta * beta), a)) / (4.0 * vh);
}

static void check_random(int C)
{
    bf_model *m = make(C);
    assert_int_equal(bf_model_nvalues(m), 2 * C + 3);
    ts_rng rng = {0xBF58476D1CE4E5B9ULL + (uint64_t)C};
    double x[16];
    for (int t = 0; t < 30; t++) {
        for (int c = 0; c < C; c++) {
            x[c] = c == 0 ? 0.0 : ts_uniform(&rng); /* channel 0: the lobe alone */
            x[C + c] = 50.0 * ts_uniform(&rng);
        }
        x[2 * C] = ts_uniform(&rng);
        x[2 * C + 1] = 0.05 + 2.95 * ts_uniform(&rng);
        x[2 * C + 2] = 0.2 + 2.0 * ts_uniform(&rng);
        assert_int_equal(bf_model_check(m, x, NULL), BF_OK);
        for (int d = 0; d < 10; d++) {
            double ti, pi_, to, po;
            ts_random_pair_deg(&rng, d % 3 == 0, &ti, &pi_, &to, &po);
            for (int c = 0; c < C; c++)
                assert_close(ts_eval1(m, x, ti, pi_, to, po, c), brady_plain(C, x, c, ti, pi_, to, po), REL);
        }
    }
    bf_model_free(m);
}

static void test_random(void **state)
{
    (void)state;
    check_random(1);
    check_random(3);
}

/* At the peak the lobe does not depend on a or beta (d/da would need ln(0) and must come
 * out as its limit 0); d/df0 = rho_s (1 - 0) / 4 and d/drho_s = f0 / 4 at normal
 * incidence. */
static void test_peak_gradient(void **state)
{
    (void)state;
    bf_model *m = make(1);
    double x[5] = {0.3, 2.0, 0.05, 1.7, 0.2};
    double z = 0.0;
    bf_geometry *g = ts_geometry_deg(1, &z, &z, &z, &z);
    double v, gr[5];
    bf_model_eval(m, x, g, &v, gr);
    assert_close(gr[0], 1.0 / M_PI, 1e-15);
    assert_close(gr[1], 0.05 / 4.0, 1e-15);
    assert_close(gr[2], 2.0 / 4.0, 1e-15);
    assert_true(gr[3] == 0.0);
    assert_true(gr[4] == 0.0);
    bf_geometry_free(g);
    bf_model_free(m);
}

/* a and beta have open lower bounds at 0. */
static void test_table(void **state)
{
    (void)state;
    bf_model *m = make(1);
    static const char *const names[] = {"rho_d", "rho_s", "f0", "a", "beta"};
    assert_int_equal(bf_model_nparams(m), 5);
    for (int i = 0; i < 5; i++)
        assert_string_equal(bf_model_param(m, i)->name, names[i]);
    const bf_param_info *a = bf_model_param(m, 3), *b = bf_model_param(m, 4);
    assert_true(a->lo == 0.0 && a->lo_open && a->hi == 3.0 && !a->hi_open);
    assert_true(b->lo == 0.0 && b->lo_open && b->hi == 10.0 && !b->hi_open);
    double x[5] = {0.5, 1.0, 0.04, 3.0, 10.0};
    assert_int_equal(bf_model_check(m, x, NULL), BF_OK);
    x[3] = 0.0;
    assert_int_equal(bf_model_check(m, x, NULL), BF_ERR_RANGE);
    x[3] = 1.0;
    x[4] = 0.0;
    assert_int_equal(bf_model_check(m, x, NULL), BF_ERR_RANGE);
    assert_false(bf_model_energy_conserving(m));
    assert_true(bf_model_reciprocal(m));
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_peak_normal), cmocka_unit_test(test_peak_mirror_60), cmocka_unit_test(test_retro_45),
        cmocka_unit_test(test_random),      cmocka_unit_test(test_peak_gradient),  cmocka_unit_test(test_table),
    };
    return cmocka_run_group_tests_name("values_brady", tests, NULL, NULL);
}
