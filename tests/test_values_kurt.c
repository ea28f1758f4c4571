/* Values of the kurt model against closed forms at special geometry and against a plain
 * re-implementation of the docs/models.md formula from the angles. */
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

/* x for kurt with C = 1 and one lobe: rho_d, rho_s, m, f0, alpha. */
static double kurt1(double rd, double rs, double mm, double f0, double alpha, double ti, double pi_, double to,
                    double po)
{
    bf_model *m = ts_model("kurt", 1);
    double x[5] = {rd, rs, mm, f0, alpha};
    double v = ts_eval1(m, x, ti, pi_, to, po, 0);
    bf_model_free(m);
    return v;
}

/* Normal incidence and view: H = N, VH = NL = NV = 1, F = f0, D_b = 1/(pi m^2), and
 * (NL NV)^alpha = 1 for every alpha. */
static void test_normal_incidence(void **state)
{
    (void)state;
    const double rd = 0.3, rs = 0.6, mm = 0.25, f0 = 0.05;
    const double want = rd / M_PI + rs * f0 / (4.0 * M_PI * mm * mm); /* 0.13369015... */
    assert_close(want, 0.13369015219719207, 1e-15);
    assert_close(kurt1(rd, rs, mm, f0, 0.0, 0, 0, 0, 0), want, REL);
    assert_close(kurt1(rd, rs, mm, f0, 1.0, 0, 0, 0, 0), want, REL);
    assert_close(kurt1(rd, rs, mm, f0, 0.37, 0, 0, 0, 0), want, REL);
}

/* Mirror direction at theta = 60 deg: H = N, NL = NV = VH = 1/2,
 * F = f0 + (1 - f0)/32, D_b = 1/(pi m^2); lobe F D / (4 VH (NL NV)^alpha). */
static void test_mirror_60(void **state)
{
    (void)state;
    const double rd = 0.2, rs = 0.7, mm = 0.1, f0 = 0.05;
    const double F = f0 + (1.0 - f0) / 32.0, D = 1.0 / (M_PI * mm * mm);
    /* alpha = 0: lobe = F D / 2; alpha = 1: F D / (2 * 1/4) = 2 F D. */
    assert_close(kurt1(rd, rs, mm, f0, 0.0, 60, 10, 60, 190), rd / M_PI + rs * F * D / 2.0, REL);
    assert_close(kurt1(rd, rs, mm, f0, 1.0, 60, 10, 60, 190), rd / M_PI + rs * 2.0 * F * D, REL);
    assert_close(kurt1(rd, rs, mm, f0, 0.5, 60, 10, 60, 190), rd / M_PI + rs * F * D, REL);
}

/* Retro-reflection at 45 deg (L = V): H = L, tan(theta_h) = 1, VH = 1, F = f0,
 * NL NV = 1/2, D_b(m = 1) = exp(-1) / (pi / 4). */
static void test_retro_45(void **state)
{
    (void)state;
    const double rs = 0.8, f0 = 0.3;
    const double D = 4.0 * exp(-1.0) / M_PI;
    assert_close(kurt1(0.0, rs, 1.0, f0, 0.0, 45, 30, 45, 30), rs * f0 * D / 4.0, REL);
    assert_close(kurt1(0.0, rs, 1.0, f0, 1.0, 45, 30, 45, 30), rs * f0 * D / 2.0, REL);
    /* Beckmann with m = 0.5: exp(-4) / (pi 0.25 0.25). */
    assert_close(kurt1(0.0, rs, 0.5, f0, 0.0, 45, 30, 45, 30), rs * f0 * exp(-4.0) / (M_PI * 0.0625) / 4.0, REL);
}

/* Plain re-implementation of kurt from the angles (degrees). x laid out as the model's
 * table for `lobes` lobes and C channels. */
static double kurt_plain(int lobes, int C, const double *x, int c, double ti, double pi_, double to, double po)
{
    double L[3] = {sin(ti * DEG) * cos(pi_ * DEG), sin(ti * DEG) * sin(pi_ * DEG), cos(ti * DEG)};
    double V[3] = {sin(to * DEG) * cos(po * DEG), sin(to * DEG) * sin(po * DEG), cos(to * DEG)};
    if (L[2] <= 0.0 || V[2] <= 0.0)
        return 0.0;
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double len = sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
    for (int k = 0; k < 3; k++)
        H[k] /= len;
    double nl = L[2], nv = V[2], nh = H[2], vh = V[0] * H[0] + V[1] * H[1] + V[2] * H[2];
    double tan2 = (H[0] * H[0] + H[1] * H[1]) / (nh * nh);
    double f = x[c] / M_PI;
    for (int k = 0; k < lobes; k++) {
        const double *p = x + C + k * (C + 3);
        double rs = p[c], mm = p[C], f0 = p[C + 1], alpha = p[C + 2];
        double F = f0 + (1.0 - f0) * pow(1.0 - vh, 5.0);
        double D = exp(-tan2 / (mm * mm)) / (M_PI * mm * mm * pow(nh, 4.0));
        f += rs * F * D / (4.0 * vh * pow(nl * nv, alpha));
    }
    return f;
}

static void check_random(const char *spec, int lobes, int C)
{
    bf_model *m = ts_model(spec, C);
    assert_int_equal(bf_model_nvalues(m), C + lobes * (C + 3));
    ts_rng rng = {0x853C49E6748FEA9BULL + (uint64_t)(lobes * 7 + C)};
    double x[64];
    for (int t = 0; t < 20; t++) {
        for (int c = 0; c < C; c++)
            x[c] = c == 0 ? 0.0 : ts_uniform(&rng); /* channel 0: the lobes alone */
        for (int k = 0; k < lobes; k++) {
            double *p = x + C + k * (C + 3);
            for (int c = 0; c < C; c++)
                p[c] = ts_uniform(&rng);
            p[C] = 0.05 * pow(20.0, ts_uniform(&rng));                 /* m in [0.05, 1] */
            p[C + 1] = ts_uniform(&rng);                               /* f0 */
            p[C + 2] = t == 0 ? 0.0 : t == 1 ? 1.0 : ts_uniform(&rng); /* alpha */
        }
        assert_int_equal(bf_model_check(m, x, NULL), BF_OK);
        for (int d = 0; d < 10; d++) {
            double ti, pi_, to, po;
            ts_random_pair_deg(&rng, d % 3 == 0, &ti, &pi_, &to, &po);
            for (int c = 0; c < C; c++)
                assert_close(ts_eval1(m, x, ti, pi_, to, po, c), kurt_plain(lobes, C, x, c, ti, pi_, to, po), REL);
        }
    }
    bf_model_free(m);
}

static void test_random_one_lobe(void **state)
{
    (void)state;
    check_random("kurt", 1, 1);
    check_random("kurt:lobes=1", 1, 3);
}

static void test_random_two_lobes(void **state)
{
    (void)state;
    check_random("kurt:lobes=2", 2, 1);
    check_random("kurt:lobes=2", 2, 3);
}

/* Table layout and names with two lobes; the lobes start apart. */
static void test_table(void **state)
{
    (void)state;
    bf_model *m = ts_model("kurt:lobes=2", 3);
    static const char *const names[] = {"rho_d",   "rho_s_1", "m_1",  "f0_1",   "alpha_1",
                                        "rho_s_2", "m_2",     "f0_2", "alpha_2"};
    assert_int_equal(bf_model_nparams(m), 9);
    for (int i = 0; i < 9; i++)
        assert_string_equal(bf_model_param(m, i)->name, names[i]);
    assert_true(bf_model_param(m, 2)->lo == 1e-3 && bf_model_param(m, 2)->hi == 1.0);
    assert_true(bf_model_param(m, 4)->lo == 0.0 && bf_model_param(m, 4)->hi == 1.0);
    assert_true(bf_model_param(m, 2)->def != bf_model_param(m, 6)->def);
    assert_false(bf_model_energy_conserving(m));
    assert_true(bf_model_reciprocal(m));
    bf_model_free(m);
    m = ts_model("kurt", 1);
    assert_string_equal(bf_model_param(m, 1)->name, "rho_s");
    assert_string_equal(bf_model_spec(m), "kurt:lobes=1");
    bf_model_free(m);
}

/* Grazing: the (NL NV)^-alpha factor is large but finite, values and gradients too. */
static void test_grazing(void **state)
{
    (void)state;
    bf_model *m = ts_model("kurt", 1);
    double x[5] = {0.5, 1.0, 1e-3, 1.0, 1.0};
    /* 2e-15: just above the 1e-15 the geometry takes as the horizon. */
    double L[6] = {1.0, 0.0, 2e-15, -1.0, 0.0, 2e-15};
    double V[6] = {-1.0, 0.0, 2e-15, -1.0, 1e-9, 2e-15};
    bf_geometry *g = NULL;
    bf_geometry_from_vectors(2, L, V, &g, NULL);
    double v[2], gr[10];
    bf_model_eval(m, x, g, v, gr);
    for (int i = 0; i < 2; i++)
        assert_true(isfinite(v[i]) && v[i] > 0.0);
    for (int k = 0; k < 10; k++)
        assert_true(isfinite(gr[k]));
    /* Mirror pair at grazing: H = N, lobe = F D / (4 VH NL NV), VH = NL = NV = 2e-15. */
    double F = 1.0, D = 1.0 / (M_PI * 1e-6), z = 2e-15;
    assert_close(v[0], 0.5 / M_PI + F * D / (4.0 * z * z * z), 1e-9);
    bf_geometry_free(g);
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_normal_incidence), cmocka_unit_test(test_mirror_60),
        cmocka_unit_test(test_retro_45),         cmocka_unit_test(test_random_one_lobe),
        cmocka_unit_test(test_random_two_lobes), cmocka_unit_test(test_table),
        cmocka_unit_test(test_grazing),
    };
    return cmocka_run_group_tests_name("values_kurt", tests, NULL, NULL);
}
