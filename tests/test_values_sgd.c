/* Values of the sgd model (Bagher, Soler & Holzschuch 2012) against closed forms at normal
 * incidence, a plain re-implementation of the docs/models.md formula from the angles, and
 * two of the authors' published MERL fits at hand-picked directions. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "support.h"

enum { NP = 10 }; /* rho_d, rho_s, alpha, p, f0, f1, lambda, s, k, theta0 */

/* One channel's parameters in table order. */
typedef struct sgd_x {
    double rd, rs, alpha, p, f0, f1, lambda, s, k, theta0;
} sgd_x;

/* The model vector for C channels, every channel the same. */
static void fill(const sgd_x *s, int C, double *x)
{
    const double v[NP] = {s->rd, s->rs, s->alpha, s->p, s->f0, s->f1, s->lambda, s->s, s->k, s->theta0};
    for (int i = 0; i < NP; i++)
        for (int c = 0; c < C; c++)
            x[i * C + c] = v[i];
}

/* docs/models.md's G1 at polar angle th (radians), w held at 50. */
static double g1_ref(const sgd_x *s, double th)
{
    if (th <= s->theta0)
        return 1.0;
    double w = pow((th - s->theta0) / s->s, s->k);
    return 1.0 + s->lambda * (1.0 - exp(w < 50.0 ? w : 50.0));
}

/* docs/models.md, written out from the angles (degrees), nothing shared with the library. */
static double sgd_ref(const sgd_x *s, double ti, double pi_, double to, double po)
{
    double L[3], V[3];
    ts_dirs_deg(ti, pi_, to, po, L, V);
    if (L[2] <= 0.0 || V[2] <= 0.0)
        return 0.0;
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double len = sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
    for (int k = 0; k < 3; k++)
        H[k] /= len;
    double tan2 = (H[0] * H[0] + H[1] * H[1]) / (H[2] * H[2]);
    double a = s->alpha + tan2 / s->alpha;
    double D = exp(-a) / (pow(a, s->p) * M_PI * pow(H[2], 4));
    double u = L[0] * H[0] + L[1] * H[1] + L[2] * H[2];
    double F = s->f0 - s->f1 * u + (1.0 - s->f0) * pow(1.0 - u, 5);
    double G = g1_ref(s, ti * DEG) * g1_ref(s, to * DEG);
    return s->rd / M_PI + s->rs * F * D * G / (M_PI * L[2] * V[2]);
}

static void test_table(void **state)
{
    (void)state;
    bf_model *m = ts_model("sgd", 3);
    const char *names[NP] = {"rho_d", "rho_s", "alpha", "p", "f0", "f1", "lambda", "s", "k", "theta0"};
    assert_int_equal(bf_model_nparams(m), NP);
    assert_int_equal(bf_model_nvalues(m), 3 * NP);
    for (int i = 0; i < NP; i++) {
        assert_string_equal(bf_model_param(m, i)->name, names[i]);
        assert_int_equal(bf_model_param(m, i)->color, 1);
    }
    assert_true(bf_model_param(m, 7)->lo == 0.3 && bf_model_param(m, 7)->hi == M_PI);
    assert_true(bf_model_param(m, 8)->lo == 2.0 && bf_model_param(m, 8)->hi == 1e3);
    assert_int_equal(bf_model_energy_conserving(m), 0);
    assert_int_equal(bf_model_reciprocal(m), 1);
    bf_model_free(m);
}

/* L = V = N: tan(theta_h) = 0, so a = alpha, VH = 1 and both polar angles are 0:
 *   f = rho_d/pi + rho_s (f0 - f1) e^-alpha alpha^-p G1(0)^2 / pi^2. */
static void test_normal_incidence(void **state)
{
    (void)state;
    bf_model *m = ts_model("sgd", 1);
    double x[NP];
    /* alpha = 1, p = 2: D = e^-1 / pi; F = 0.9 - 0.4 = 0.5; theta0 > 0: G = 1. */
    sgd_x s = {0.2, 3.0, 1.0, 2.0, 0.9, 0.4, 5.0, 1.0, 3.0, 0.3};
    fill(&s, 1, x);
    double want = 0.2 / M_PI + 3.0 * 0.5 * exp(-1.0) / (M_PI * M_PI);
    ts_assert_rel(ts_eval1(m, x, 0.0, 0.0, 0.0, 0.0, 0), want, 1e-14, "sgd normal, G = 1");
    /* theta0 = -0.5, k = 2, s = 0.5 / sqrt(ln 2): w = ln 2, e^w = 2, G1 = 1 - lambda = 0.75. */
    s.theta0 = -0.5, s.k = 2.0, s.s = 0.5 / sqrt(log(2.0)), s.lambda = 0.25;
    fill(&s, 1, x);
    want = 0.2 / M_PI + 3.0 * 0.5 * exp(-1.0) * 0.5625 / (M_PI * M_PI);
    ts_assert_rel(ts_eval1(m, x, 0.0, 0.0, 0.0, 0.0, 0), want, 1e-13, "sgd normal, G1 = 0.75");
    bf_model_free(m);
}

/* Random parameters in the published fits' ranges, random and near-mirror directions. */
static void test_random(void **state)
{
    (void)state;
    ts_rng r = {0x5D6D0A3F1B2C4E77ULL};
    bf_model *m = ts_model("sgd", 1);
    double x[NP];
    for (int n = 0; n < 400; n++) {
        sgd_x s = {ts_uniform(&r),
                   10.0 * ts_uniform(&r),
                   1e-3 * pow(800.0, ts_uniform(&r)),
                   1.5 * ts_uniform(&r),
                   2.0 * ts_uniform(&r),
                   2.0 * ts_uniform(&r) - 0.5,
                   20.0 * ts_uniform(&r),
                   0.3 * pow(M_PI / 0.3, ts_uniform(&r)),
                   2.0 * pow(100.0, ts_uniform(&r)),
                   1.8 * ts_uniform(&r) - 0.6};
        fill(&s, 1, x);
        double ti, pi_, to, po;
        ts_random_pair_deg(&r, n % 2, &ti, &pi_, &to, &po);
        double want = sgd_ref(&s, ti, pi_, to, po);
        ts_assert_near(ts_eval1(m, x, ti, pi_, to, po, 0), want, 1e-11, 1e-14, "sgd random");
    }
    bf_model_free(m);
}

/* Below theta0 the shadowing is 1 whatever lambda, s and k; below the horizon f = 0; the
 * narrowest, steepest shadowing holds exp(w) at exp(50) (finite). */
static void test_limits(void **state)
{
    (void)state;
    bf_model *m = ts_model("sgd", 1);
    double x[NP], x0[NP];
    sgd_x s = {0.3, 2.0, 0.05, 0.5, 0.1, 0.05, 7.0, 0.76, 4.0, 1.2};
    fill(&s, 1, x);
    s.lambda = 0.0;
    fill(&s, 1, x0);
    ts_assert_rel(ts_eval1(m, x, 40.0, 0.0, 50.0, 170.0, 0), ts_eval1(m, x0, 40.0, 0.0, 50.0, 170.0, 0), 1e-15,
                  "sgd below theta0");
    assert_true(ts_eval1(m, x, 95.0, 0.0, 30.0, 180.0, 0) == 0.0);
    s.lambda = 2.0, s.s = 0.3, s.k = 1e3, s.theta0 = 0.0; /* w = (pi / 0.9)^1000 */
    fill(&s, 1, x);
    double g = 1.0 + 2.0 * (1.0 - exp(50.0));
    /* The mirror direction at 60 degrees: a = alpha, VH = 1/2, NL NV = 1/4. */
    double F = 0.1 - 0.05 * 0.5 + 0.9 / 32.0;
    double want = 0.3 / M_PI + 2.0 * F * exp(-0.05) * pow(0.05, -0.5) * g * g / (M_PI * M_PI * 0.25);
    ts_assert_rel(ts_eval1(m, x, 60.0, 0.0, 60.0, 180.0, 0), want, 1e-12, "sgd w held at 50");
    bf_model_free(m);
}

/* Two of the published fits: Bagher et al. 2012 as published in bsdfbenchmark/bbm
 * fits/bagher_sgd.fit, mapped as docs/models.md says (rho_d = the Lambertian albedo,
 * rho_s = albedo K, f0 and f1 = eta's rows, s = c^(-1/k), the rest as named). Expected
 * values from an independent implementation of bbm's Bagher model (numpy, written from
 * the paper and bbm's definitions, with its c, not from this library). */
typedef struct published {
    const char *name;
    double kd[3], albedo[3], alpha[3], p[3], f0[3], f1[3], K[3], lambda[3], c[3], k[3], theta0[3];
    double want[6][3];
} published;

static const double pub_dirs[6][4] = {{0, 0, 0, 0},     {30, 0, 30, 180}, {31, 10, 29, 192},
                                      {45, 0, 60, 135}, {85, 0, 80, 180}, {89, 0, 89, 180}};

static const published pub[] = {
    {"alum-bronze",
     {0.0478786, 0.0313514, 0.0200638},
     {0.0364976, 0.664975, 0.268836},
     {0.014832, 0.0300126, 0.0490339},
     {0.459076, 0.450056, 0.529272},
     {6.05524, 0.235756, 0.580647},
     {5.05524, 0.182842, 0.476088},
     {46.3841, 24.5961, 14.8261},
     {2.60672, 2.97371, 2.7827},
     {1.12717e-07, 1.06401e-07, 5.27952e-08},
     {47.783, 36.2767, 31.6066},
     {0.205635, 0.066289, -0.0661091},
     {{1.1832609844567741, 0.42227321042927302, 0.20470556037390453},
      {2.6270211277398894, 0.81453868389985051, 0.43216403239973022},
      {1.589162337563383, 0.68206497217828066, 0.39559842459394162},
      {0.015240241927202353, 0.010027402791532235, 0.0072385709587371927},
      {66.749077586624409, 153.27198658888085, 53.222154907820006},
      {1280.9095924913336, 3413.9324666907273, 607.81285840876376}}},
    {"chrome-steel",
     {0.0206718, 0.0240818, 0.024351},
     {0.129782, 0.109032, 0.0524555},
     {5.51292e-05, 3.13288e-05, 4.51944e-05},
     {0.207979, 0.152758, 0.325431},
     {1.18818e-12, 2.06813e-11, 0.580895},
     {-0.316807, -0.265326, -0.419105},
     {15466.8, 28628.9, 16531.2},
     {12.8988, 68.7898, 4.68237},
     {1.43049e+84, 1.63655e+109, 44.7025},
     {197.744, 257.536, 618.155},
     {1.20035, 1.2003, 0.579562},
     {{495.21633486128599, 409.13238598217657, 2279.0175553462327},
      {571.91550971397794, 472.51294204874307, 2868.1223448865876},
      {0.037663003189480182, 0.0078193583548151497, 0.014532080552897897},
      {0.0065800383052140848, 0.0076654750171008109, 0.0077511640384614871},
      {0.0065800383085540511, 0.0076654750171008109, 0.0077511640384621862},
      {4727222.6912301937, 4659296.5829600943, 7272555.3929753872}}},
};

static void test_published(void **state)
{
    (void)state;
    bf_model *m = ts_model("sgd", 3);
    for (size_t n = 0; n < sizeof pub / sizeof pub[0]; n++) {
        const published *q = &pub[n];
        double x[3 * NP];
        for (int c = 0; c < 3; c++) {
            const double v[NP] = {
                q->kd[c],     q->albedo[c] * q->K[c],       q->alpha[c], q->p[c],     q->f0[c], q->f1[c],
                q->lambda[c], exp(-log(q->c[c]) / q->k[c]), q->k[c],     q->theta0[c]};
            for (int i = 0; i < NP; i++)
                x[i * 3 + c] = v[i];
        }
        assert_int_equal(bf_model_check(m, x, NULL), BF_OK);
        for (int d = 0; d < 6; d++)
            for (int c = 0; c < 3; c++) {
                const double *a = pub_dirs[d];
                ts_assert_rel(ts_eval1(m, x, a[0], a[1], a[2], a[3], c), q->want[d][c], 1e-9, q->name);
            }
    }
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table),  cmocka_unit_test(test_normal_incidence), cmocka_unit_test(test_random),
        cmocka_unit_test(test_limits), cmocka_unit_test(test_published),
    };
    return cmocka_run_group_tests_name("values_sgd", tests, NULL, NULL);
}
