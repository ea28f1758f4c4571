/* The synthetic data generator: its random numbers, the direction patterns, the noise
 * models, determinism, and values equal to the model's. Statistical checks allow five
 * standard errors for the sample size used, so a correct generator fails about once in
 * a million runs per check, and the seeds are fixed, so the suite never flickers. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "brdfit/formats.h"
#include "brdfit/samples.h"
#include "support.h"
#include "synth.h"

/* |got - want| <= 5 standard errors. */
static void assert_within(double got, double want, double se, const char *what)
{
    if (!(fabs(got - want) <= 5.0 * se)) {
        fail_msg("%s: %.10g, expected %.10g +- %.3g (5 standard errors)", what, got, want, 5.0 * se);
    }
}

static void mean_var(const double *v, size_t n, size_t stride, double *mean, double *var)
{
    double s = 0.0, ss = 0.0;
    for (size_t i = 0; i < n; i++)
        s += v[i * stride];
    *mean = s / (double)n;
    for (size_t i = 0; i < n; i++)
        ss += (v[i * stride] - *mean) * (v[i * stride] - *mean);
    *var = ss / (double)(n - 1);
}

static double cosd(double deg)
{
    return cos(deg * DEG);
}

/* A Lambert model with albedo rho per channel: value rho / pi everywhere above the
 * horizon, which the noise tests need (one known mean). */
static bf_model *lambert(int C, const double *rho, double **x)
{
    bf_model *m = ts_model("lambert", C);
    *x = malloc((size_t)bf_model_nvalues(m) * sizeof **x);
    for (int c = 0; c < C; c++)
        (*x)[c] = rho[c];
    return m;
}

static bf_samples *generate(const bf_model *m, const double *x, const bf_synth_options *o)
{
    bf_samples *s = NULL;
    bf_error err;
    if (bf_synth_generate(m, x, o, &s, &err) != BF_OK)
        fail_msg("bf_synth_generate: %s", err.msg);
    return s;
}

/* ---- random numbers ------------------------------------------------------------ */

/* The documented generators, against outputs of an independent implementation of the
 * published reference code (splitmix64 state words; xoshiro256** output; after jump). */
static void test_rng_reference(void **state)
{
    (void)state;
    bf_synth_rng r;
    bf_synth_rng_seed(&r, 0);
    assert_true(r.s[0] == UINT64_C(0xe220a8397b1dcdaf));
    assert_true(r.s[1] == UINT64_C(0x6e789e6aa1b965f4));
    assert_true(r.s[2] == UINT64_C(0x06c45d188009454f));
    bf_synth_rng j = r;
    assert_true(bf_synth_next(&r) == UINT64_C(0x99ec5f36cb75f2b4));
    assert_true(bf_synth_next(&r) == UINT64_C(0xbf6e1f784956452a));
    assert_true(bf_synth_next(&r) == UINT64_C(0x1a5f849d4933e6e0));
    bf_synth_rng_jump(&j);
    assert_true(bf_synth_next(&j) == UINT64_C(0x376215edc846d62c));
    assert_true(bf_synth_next(&j) == UINT64_C(0x57c0611de8350ca7));
}

static void test_uniform_normal_below(void **state)
{
    (void)state;
    enum { N = 400000 };
    bf_synth_rng r;
    bf_synth_rng_seed(&r, 11);
    double *v = malloc(N * sizeof *v), mean, var;
    for (size_t i = 0; i < N; i++) {
        v[i] = bf_synth_uniform(&r);
        assert_true(v[i] >= 0.0 && v[i] < 1.0);
    }
    mean_var(v, N, 1, &mean, &var);
    assert_within(mean, 0.5, sqrt(1.0 / 12 / N), "uniform mean");
    assert_within(var, 1.0 / 12, sqrt((1.0 / 80 - 1.0 / 144) / N), "uniform variance");

    size_t inside = 0;
    for (size_t i = 0; i < N; i++) {
        v[i] = bf_synth_normal(&r);
        inside += fabs(v[i]) < 1.0;
    }
    mean_var(v, N, 1, &mean, &var);
    assert_within(mean, 0.0, sqrt(1.0 / N), "normal mean");
    assert_within(var, 1.0, sqrt(2.0 / N), "normal variance");
    const double p1 = erf(1.0 / sqrt(2.0));
    assert_within((double)inside / N, p1, sqrt(p1 * (1 - p1) / N), "normal P(|x| < 1)");

    /* Unbiased integers: each of 6 faces 1/6 of the time. */
    size_t count[6] = {0};
    for (size_t i = 0; i < N; i++) {
        uint64_t k = bf_synth_below(&r, 6);
        assert_true(k < 6);
        count[k]++;
    }
    for (int k = 0; k < 6; k++)
        assert_within((double)count[k] / N, 1.0 / 6, sqrt(5.0 / 36 / N), "die face frequency");
    assert_true(bf_synth_below(&r, 1) == 0);
    free(v);
}

/* Mean and variance of Poisson draws in each regime (Knuth, PTRS, normal), and the
 * probability of single counts against the exact pmf where the count is small. */
static void test_poisson(void **state)
{
    (void)state;
    enum { N = 1000000 }; /* enough to see PTRS with a wrong constant (0.3% off) */
    const double means[] = {0.3, 3.0, 9.99, 10.0, 20.0, 47.3, 1e4, 5e8, 1e10};
    bf_synth_rng r;
    bf_synth_rng_seed(&r, 5);
    double *v = malloc(N * sizeof *v);
    for (size_t q = 0; q < sizeof means / sizeof means[0]; q++) {
        const double mu = means[q];
        double hist[64] = {0};
        for (size_t i = 0; i < N; i++) {
            v[i] = bf_synth_poisson(&r, mu);
            assert_true(v[i] >= 0.0 && v[i] == floor(v[i]));
            if (v[i] < 64)
                hist[(int)v[i]]++;
        }
        double mean, var;
        mean_var(v, N, 1, &mean, &var);
        char what[64];
        snprintf(what, sizeof what, "Poisson(%g) mean", mu);
        assert_within(mean, mu, sqrt(mu / N), what);
        snprintf(what, sizeof what, "Poisson(%g) variance", mu);
        assert_within(var, mu, sqrt((mu + 2 * mu * mu) / N), what);
        for (int k = 0; k < 64 && mu < 50; k++) {
            const double p = exp(-mu + k * log(mu) - lgamma(k + 1.0));
            snprintf(what, sizeof what, "Poisson(%g) P(%d)", mu, k);
            assert_within(hist[k] / N, p, sqrt(p * (1 - p) / N) + 1e-6, what);
        }
    }
    assert_true(bf_synth_poisson(&r, 0.0) == 0.0 && bf_synth_poisson(&r, -1.0) == 0.0);
    free(v);
}

/* ---- patterns ------------------------------------------------------------------- */

static bf_samples *directions(bf_synth_pattern p, size_t n, uint64_t seed)
{
    bf_synth_rng r;
    bf_synth_rng_seed(&r, seed);
    bf_samples *s = NULL;
    bf_error err;
    if (bf_synth_directions(p, n, NULL, &r, 1, &s, &err) != BF_OK)
        fail_msg("bf_synth_directions: %s", err.msg);
    assert_int_equal(s->n, n);
    for (size_t i = 0; i < n; i++) {
        assert_true(s->theta_i[i] >= 0.0 && s->theta_i[i] < 90.0);
        assert_true(s->theta_o[i] >= 0.0 && s->theta_o[i] < 90.0);
        assert_true(s->phi_i[i] >= 0.0 && s->phi_i[i] < 360.0);
        assert_true(s->phi_o[i] >= 0.0 && s->phi_o[i] < 360.0);
    }
    return s;
}

/* Moments of cos theta (both directions) and phi against the pattern's distribution. */
static void check_moments(const bf_samples *s, double mean_cos, double var_cos, const char *name)
{
    const size_t n = s->n;
    double *c = malloc(2 * n * sizeof *c), mean, var;
    for (size_t i = 0; i < n; i++) {
        c[i] = cosd(s->theta_i[i]);
        c[n + i] = cosd(s->theta_o[i]);
    }
    char what[80];
    for (int d = 0; d < 2; d++) {
        mean_var(c + (size_t)d * n, n, 1, &mean, &var);
        snprintf(what, sizeof what, "%s: mean cos theta_%c", name, d ? 'o' : 'i');
        assert_within(mean, mean_cos, sqrt(var_cos / (double)n), what);
        snprintf(what, sizeof what, "%s: variance of cos theta_%c", name, d ? 'o' : 'i');
        /* Se of a variance: below sqrt(2 var^2 + 2 var^2) for these bounded laws. */
        assert_within(var, var_cos, 2.0 * var_cos / sqrt((double)n), what);
    }
    mean_var(s->phi_i, n, 1, &mean, &var);
    snprintf(what, sizeof what, "%s: mean phi_i", name);
    assert_within(mean, 180.0, 360.0 / sqrt(12.0 * (double)n), what);
    mean_var(s->phi_o, n, 1, &mean, &var);
    snprintf(what, sizeof what, "%s: variance of phi_o", name);
    assert_within(var, 360.0 * 360.0 / 12, 2.0 * 360.0 * 360.0 / 12 / sqrt((double)n), what);
    free(c);
}

static void test_uniform_pattern(void **state)
{
    (void)state;
    bf_samples *s = directions(BF_SYNTH_UNIFORM, 200000, 1);
    check_moments(s, 0.5, 1.0 / 12, "uniform"); /* cos theta uniform on (0, 1] */
    bf_samples_free(s);
}

static void test_cosine_pattern(void **state)
{
    (void)state;
    bf_samples *s = directions(BF_SYNTH_COSINE, 200000, 2);
    check_moments(s, 2.0 / 3, 0.5 - 4.0 / 9, "cosine"); /* pdf 2c on (0, 1] */
    bf_samples_free(s);
}

static void test_random_pattern(void **state)
{
    (void)state;
    enum { N = 200000 };
    bf_samples *s = directions(BF_SYNTH_RANDOM, N, 3);
    /* theta uniform on [0, pi/2): E cos = 2/pi, E cos^2 = 1/2. */
    check_moments(s, 2.0 / M_PI, 0.5 - 4.0 / (M_PI * M_PI), "random");
    double mean, var;
    mean_var(s->theta_o, N, 1, &mean, &var);
    assert_within(mean, 45.0, 90.0 / sqrt(12.0 * N), "random: mean theta_o");
    bf_samples_free(s);
}

static void test_stratified_pattern(void **state)
{
    (void)state;
    const size_t sizes[] = {1, 7, 360, 1000, 4096};
    const size_t want[][4] = {{1, 1, 1, 1}, {1, 7, 1, 1}, {4, 6, 3, 5}, {5, 8, 5, 5}, {8, 8, 8, 8}};
    for (size_t q = 0; q < sizeof sizes / sizeof sizes[0]; q++) {
        const size_t n = sizes[q];
        size_t dims[4];
        bf_synth_strata(n, dims);
        for (int d = 0; d < 4; d++)
            assert_int_equal(dims[d], want[q][d]);
        bf_samples *s = directions(BF_SYNTH_STRATIFIED, n, 4 + q);
        /* Every stratum exactly once: cell of cos theta (upper-closed, as drawn) and phi. */
        unsigned char *hit = calloc(n, 1);
        for (size_t i = 0; i < n; i++) {
            const double ang[4] = {s->theta_i[i], s->phi_i[i], s->theta_o[i], s->phi_o[i]};
            size_t cell = 0;
            for (int d = 0; d < 4; d++) {
                double u = d % 2 == 0 ? cosd(ang[d]) : ang[d] / 360.0;
                double k = d % 2 == 0 ? ceil(u * (double)dims[d]) - 1 : floor(u * (double)dims[d]);
                assert_true(k >= 0 && k < (double)dims[d]);
                cell = cell * dims[d] + (size_t)k;
            }
            assert_false(hit[cell]);
            hit[cell] = 1;
        }
        free(hit);
        bf_samples_free(s);
    }
    /* Large N: stratified in cos theta, so uniform in solid angle. */
    bf_samples *s = directions(BF_SYNTH_STRATIFIED, 20736, 9); /* 12^4 */
    double mean, var, c[20736];
    for (size_t i = 0; i < s->n; i++)
        c[i] = cosd(s->theta_o[i]);
    mean_var(c, s->n, 1, &mean, &var);
    /* Stratification leaves far less than the iid error: 1/12 of it is a generous bound. */
    assert_within(mean, 0.5, sqrt(1.0 / 12 / 20736) / 12, "stratified: mean cos theta_o");
    bf_samples_free(s);
}

static void check_gonio(const double *inc, int ninc, double step, const double (*want)[4], size_t nwant)
{
    bf_synth_gonio g = {inc, ninc, step};
    assert_int_equal(bf_synth_gonio_count(&g), nwant);
    bf_synth_rng r;
    bf_synth_rng_seed(&r, 0);
    bf_samples *s;
    bf_error err;
    assert_int_equal(bf_synth_directions(BF_SYNTH_GONIO, 0, &g, &r, 3, &s, &err), BF_OK);
    assert_int_equal(s->n, nwant);
    for (size_t i = 0; i < nwant; i++) {
        if (s->theta_i[i] != want[i][0] || s->phi_i[i] != want[i][1] || s->theta_o[i] != want[i][2] ||
            s->phi_o[i] != want[i][3])
            fail_msg("gonio sample %zu: (%g, %g, %g, %g), expected (%g, %g, %g, %g)", i, s->theta_i[i], s->phi_i[i],
                     s->theta_o[i], s->phi_o[i], want[i][0], want[i][1], want[i][2], want[i][3]);
    }
    bf_samples_free(s);
}

static void test_gonio_pattern(void **state)
{
    (void)state;
    /* Incidence 45 lies on the 45-degree in-plane grid: its ring leaves out phi_o 0, 180. */
    const double inc1[2] = {0, 45};
    const double want1[][4] = {{0, 0, 45, 0},    {0, 0, 0, 0},    {0, 0, 45, 180},                    /* 0: in-plane */
                               {45, 0, 45, 0},   {45, 0, 0, 0},   {45, 0, 45, 180},                   /* 45: in-plane */
                               {45, 0, 45, 45},  {45, 0, 45, 90}, {45, 0, 45, 135}, {45, 0, 45, 225}, /* 45: ring */
                               {45, 0, 45, 270}, {45, 0, 45, 315}};
    check_gonio(inc1, 2, 45, want1, sizeof want1 / sizeof want1[0]);
    /* Incidence 40 is off the 30-degree grid: the ring keeps all twelve azimuths, the
     * mirror direction (40, 180) among them. */
    const double inc2[1] = {40};
    double want2[17][4];
    for (int k = 0; k < 5; k++) {
        const double t = (k - 2) * 30.0;
        const double row[4] = {40, 0, fabs(t), t > 0 ? 180 : 0};
        memcpy(want2[k], row, sizeof row);
    }
    for (int j = 0; j < 12; j++) {
        const double row[4] = {40, 0, 40, 30.0 * j};
        memcpy(want2[5 + j], row, sizeof row);
    }
    check_gonio(inc2, 1, 30, (const double(*)[4])want2, 17);
    /* Default CLI settings: 0, 30, 60 at 5 degrees: 35 in-plane each, rings of 72 - 2. */
    const double inc3[3] = {0, 30, 60};
    bf_synth_gonio g = {inc3, 3, 5};
    assert_int_equal(bf_synth_gonio_count(&g), 3 * 35 + 2 * 70);

    /* Invalid settings. */
    const double bad_inc[1] = {90};
    bf_synth_gonio bad[3] = {{bad_inc, 1, 5}, {inc3, 3, 0}, {inc3, 0, 5}};
    bf_synth_rng r;
    bf_synth_rng_seed(&r, 0);
    for (int k = 0; k < 3; k++) {
        bf_samples *s = NULL;
        bf_error err;
        assert_int_equal(bf_synth_gonio_count(&bad[k]), 0);
        assert_int_equal(bf_synth_directions(BF_SYNTH_GONIO, 0, &bad[k], &r, 1, &s, &err), BF_ERR_ARG);
        assert_null(s);
    }
}

/* Above-horizon cells counted from MERL's definition, independently of the library:
 * D = (sin td cos pd, sin td sin pd, cos td), L = Ry(th) D, V = Ry(th) (-Dx, -Dy, Dz). */
static size_t merl_cells_above(unsigned char *above)
{
    size_t n = 0;
    for (int i = 0; i < BF_MERL_TH; i++)
        for (int j = 0; j < BF_MERL_TD; j++)
            for (int k = 0; k < BF_MERL_PD; k++) {
                const double th = pow((i + 0.5) / 90, 2) * M_PI / 2, td = (j + 0.5) / 90 * M_PI / 2;
                const double pd = (k + 0.5) / 180 * M_PI;
                const double dx = sin(td) * cos(pd), dz = cos(td);
                const double lz = dz * cos(th) - dx * sin(th), vz = dz * cos(th) + dx * sin(th);
                const size_t cell = (size_t)k + 180 * ((size_t)j + 90 * (size_t)i);
                above[cell] = lz > 1e-12 && vz > 1e-12;
                n += above[cell];
            }
    return n;
}

static void test_merl_pattern(void **state)
{
    (void)state;
    const double rho[3] = {0.8, 0.5, 0.2};
    double *x;
    bf_model *m = lambert(3, rho, &x);
    bf_synth_options o = {.pattern = BF_SYNTH_MERL, .seed = 3};
    bf_samples *s = generate(m, x, &o);

    unsigned char *above = malloc(BF_MERL_CELLS);
    const size_t n_above = merl_cells_above(above);
    assert_int_equal(s->n, n_above);
    assert_int_equal(s->n, BF_MERL_CELLS - 361784); /* the count merl.c documents */
    int32_t prev = -1;
    assert_null(s->theta_i); /* MERL cells, as a table read back */
    for (size_t i = 0; i < s->n; i++) {
        double dir[4];
        bf_samples_direction(s, i, dir);
        const int32_t cell = bf_merl_cell_of(dir[0], dir[1], dir[2], dir[3]);
        if (cell <= prev || !above[cell] || cell != s->merl->cell[i])
            fail_msg("sample %zu: cell %d after %d (above the horizon: %d)", i, cell, prev,
                     cell >= 0 ? above[cell] : -1);
        double ti, pi_, to, po;
        bf_merl_cell_directions(cell, &ti, &pi_, &to, &po);
        assert_true(ti == dir[0] && pi_ == dir[1] && to == dir[2] && po == dir[3]);
        for (int c = 0; c < 3; c++)
            ts_assert_rel(s->value[3 * i + (size_t)c], rho[c] / M_PI, 1e-15, "merl Lambert value");
        prev = cell;
    }

    /* Written and read back: the same samples and values, other cells invalid. */
    char path[] = "/tmp/test_synth_XXXXXX.binary";
    int fd = mkstemps(path, 7);
    assert_true(fd >= 0);
    close(fd);
    bf_error err;
    assert_int_equal(bf_samples_write(s, path, BF_FORMAT_AUTO, &err), BF_OK);
    bf_samples *back = NULL;
    if (bf_samples_read_merl(path, 0, &back, &err) != BF_OK)
        fail_msg("reading back: %s", err.msg);
    assert_int_equal(back->n, s->n);
    assert_memory_equal(back->value, s->value, s->n * 3 * sizeof *s->value);
    assert_memory_equal(back->merl->cell, s->merl->cell, s->n * sizeof *s->merl->cell);
    remove(path);
    bf_samples_free(back);
    bf_samples_free(s);

    /* Additive noise large enough to go negative: merl output is clamped at 0, since a
     * negative value would mark its cell invalid. */
    o.noise = (bf_synth_noise){.model = BF_NOISE_ADDITIVE, .level = 0.5};
    s = generate(m, x, &o);
    size_t zeros = 0;
    for (size_t i = 0; i < 3 * s->n; i++) {
        assert_true(s->value[i] >= 0.0);
        zeros += s->value[i] == 0.0;
    }
    assert_true(zeros > s->n / 10);
    bf_samples_free(s);

    /* A one-channel model cannot make a MERL table. */
    double *x1;
    bf_model *m1 = lambert(1, rho, &x1);
    o.noise = (bf_synth_noise){0};
    assert_int_equal(bf_synth_generate(m1, x1, &o, &s, &err), BF_ERR_ARG);
    assert_null(s);
    assert_non_null(strstr(err.msg, "3-channel"));
    bf_model_free(m1);
    free(x1);
    bf_model_free(m);
    free(x);
    free(above);
}

/* ---- values and determinism ---------------------------------------------------- */

/* Without noise every value is the model's at the sample's directions, for every
 * pattern: the generator evaluates through bf_model_eval, nothing of its own. */
static void test_values_are_the_model(void **state)
{
    (void)state;
    bf_model *m = ts_model("walter", 3);
    double *x = malloc((size_t)bf_model_nvalues(m) * sizeof *x);
    ts_rng rr = {42};
    ts_random_params(m, &rr, TS_PARAMS_MODERATE, x);
    const double inc[2] = {10, 55};
    for (int p = BF_SYNTH_UNIFORM; p <= BF_SYNTH_GONIO; p++) {
        bf_synth_options o = {.pattern = (bf_synth_pattern)p, .count = 500, .gonio = {inc, 2, 7.5}, .seed = 9};
        bf_samples *s = generate(m, x, &o);
        bf_geometry *g = ts_geometry_deg(s->n, s->theta_i, s->phi_i, s->theta_o, s->phi_o);
        double *want = ts_eval(m, x, g);
        for (size_t i = 0; i < 3 * s->n; i++)
            assert_true(s->value[i] == want[i]);
        for (size_t i = 0; i < s->n; i++) /* every pair above the horizon */
            assert_true(bf_geometry_valid(g, i));
        free(want);
        bf_geometry_free(g);
        bf_samples_free(s);
    }
    /* And against a value known without the model library: Lambert rho / pi. */
    const double rho[3] = {0.8, 0.5, 0.2};
    double *xl;
    bf_model *ml = lambert(3, rho, &xl);
    bf_synth_options o = {.pattern = BF_SYNTH_COSINE, .count = 100};
    bf_samples *s = generate(ml, xl, &o);
    for (size_t i = 0; i < s->n; i++)
        for (int c = 0; c < 3; c++)
            ts_assert_rel(s->value[3 * i + (size_t)c], rho[c] / M_PI, 1e-15, "Lambert value");
    bf_samples_free(s);
    bf_model_free(ml);
    free(xl);
    bf_model_free(m);
    free(x);
}

static int same_samples(const bf_samples *a, const bf_samples *b)
{
    return a->n == b->n && a->channels == b->channels &&
           !memcmp(a->theta_i, b->theta_i, 4 * a->n * sizeof *a->theta_i) &&
           !memcmp(a->value, b->value, a->n * (size_t)a->channels * sizeof *a->value);
}

static void test_determinism(void **state)
{
    (void)state;
    bf_model *m = ts_model("walter", 3);
    double *x = malloc((size_t)bf_model_nvalues(m) * sizeof *x);
    ts_rng rr = {7};
    ts_random_params(m, &rr, TS_PARAMS_MODERATE, x);
    const bf_synth_noise noises[] = {
        {.model = BF_NOISE_RELATIVE, .level = 0.1, .outlier_fraction = 0.05},
        {.model = BF_NOISE_ADDITIVE, .level = 0.01, .clamp = 1},
        {.model = BF_NOISE_PHOTON, .counts = 100, .outlier_fraction = 0.1, .outlier_factor = 5},
    };
    for (int p = BF_SYNTH_UNIFORM; p <= BF_SYNTH_RANDOM; p++)
        for (size_t q = 0; q < sizeof noises / sizeof noises[0]; q++) {
            bf_synth_options o = {.pattern = (bf_synth_pattern)p, .count = 2000, .seed = 1234, .noise = noises[q]};
            bf_samples *a = generate(m, x, &o), *b = generate(m, x, &o);
            assert_true(same_samples(a, b));
            o.seed = 1235;
            bf_samples *c = generate(m, x, &o);
            assert_false(memcmp(a->value, c->value, 3 * a->n * sizeof *a->value) == 0);
            for (size_t i = 0; i < a->n; i++) /* stratified too: the jitter differs */
                assert_true(a->theta_i[i] != c->theta_i[i]);
            /* The same seed without noise: the same directions, values differ. */
            o.seed = 1234;
            o.noise = (bf_synth_noise){0};
            bf_samples *d = generate(m, x, &o);
            assert_memory_equal(a->theta_i, d->theta_i, 4 * a->n * sizeof *a->theta_i);
            assert_false(memcmp(a->value, d->value, 3 * a->n * sizeof *a->value) == 0);
            bf_samples_free(a);
            bf_samples_free(b);
            bf_samples_free(c);
            bf_samples_free(d);
        }
    bf_model_free(m);
    free(x);
}

/* ---- noise ------------------------------------------------------------------------ */

enum { NN = 100000 };

/* One channel of Lambert value v at NN uniform pairs with the given noise. */
static bf_samples *lambert_noisy(double rho, const bf_synth_noise *nz, uint64_t seed)
{
    double *x;
    bf_model *m = lambert(1, &rho, &x);
    bf_synth_options o = {.pattern = BF_SYNTH_UNIFORM, .count = NN, .seed = seed, .noise = *nz};
    bf_samples *s = generate(m, x, &o);
    bf_model_free(m);
    free(x);
    return s;
}

static void test_noise_relative_additive(void **state)
{
    (void)state;
    const double rho = 0.8, v = rho / M_PI;
    double mean, var;
    /* relative: mean v, standard deviation s v */
    bf_synth_noise nz = {.model = BF_NOISE_RELATIVE, .level = 0.1};
    bf_samples *s = lambert_noisy(rho, &nz, 21);
    mean_var(s->value, NN, 1, &mean, &var);
    const double sd = 0.1 * v;
    assert_within(mean, v, sd / sqrt(NN), "relative noise: mean");
    assert_within(sqrt(var), sd, sd / sqrt(2.0 * NN), "relative noise: standard deviation");
    bf_samples_free(s);
    /* additive: mean v, standard deviation s, independent of v */
    nz = (bf_synth_noise){.model = BF_NOISE_ADDITIVE, .level = 0.03};
    s = lambert_noisy(rho, &nz, 22);
    mean_var(s->value, NN, 1, &mean, &var);
    assert_within(mean, v, 0.03 / sqrt(NN), "additive noise: mean");
    assert_within(sqrt(var), 0.03, 0.03 / sqrt(2.0 * NN), "additive noise: standard deviation");
    bf_samples_free(s);
    /* level 0 is no noise at all */
    nz.level = 0.0;
    s = lambert_noisy(rho, &nz, 22);
    for (size_t i = 0; i < NN; i++)
        assert_true(s->value[i] == v);
    bf_samples_free(s);
}

static void test_noise_photon(void **state)
{
    (void)state;
    const double rho = 0.8, v = rho / M_PI;
    const double ks[] = {20.0, 1000.0, 1e6}; /* means k v: 5 (Knuth), 255 and 2.5e5 (PTRS) */
    for (size_t q = 0; q < sizeof ks / sizeof ks[0]; q++) {
        const double k = ks[q];
        bf_synth_noise nz = {.model = BF_NOISE_PHOTON, .counts = k};
        bf_samples *s = lambert_noisy(rho, &nz, 30 + q);
        double mean, var;
        mean_var(s->value, NN, 1, &mean, &var);
        char what[64];
        snprintf(what, sizeof what, "photon k=%g: mean", k);
        assert_within(mean, v, sqrt(v / k / NN), what);
        snprintf(what, sizeof what, "photon k=%g: variance v/k", k);
        assert_within(var, v / k, sqrt((v / k / k / k + 2 * (v / k) * (v / k)) / NN), what);
        for (size_t i = 0; i < NN; i++) { /* whole counts over k */
            const double counts = s->value[i] * k;
            assert_true(fabs(counts - nearbyint(counts)) < 1e-6 && counts >= 0.0);
        }
        bf_samples_free(s);
    }
}

static void test_outliers_and_clamp(void **state)
{
    (void)state;
    const double rho[3] = {0.8, 0.5, 0.2};
    double *x;
    bf_model *m = lambert(3, rho, &x);
    /* factor: exactly round(0.03 n) samples, every channel times 10; the rest untouched */
    bf_synth_options o = {.pattern = BF_SYNTH_UNIFORM,
                          .count = 10001,
                          .seed = 40,
                          .noise = {.outlier_fraction = 0.03, .outlier_factor = 10}};
    bf_samples *s = generate(m, x, &o);
    size_t out = 0;
    for (size_t i = 0; i < s->n; i++) {
        const int hit = s->value[3 * i] != rho[0] / M_PI;
        out += hit;
        for (int c = 0; c < 3; c++)
            assert_true(s->value[3 * i + (size_t)c] == (hit ? 10.0 : 1.0) * (rho[c] / M_PI));
    }
    assert_int_equal(out, 300);
    bf_samples_free(s);

    /* random: values in [0, channel maximum), the same exact count */
    o.noise = (bf_synth_noise){.outlier_fraction = 0.1};
    o.count = 5000;
    s = generate(m, x, &o);
    size_t changed[3] = {0};
    for (size_t i = 0; i < s->n; i++)
        for (int c = 0; c < 3; c++) {
            const double vi = s->value[3 * i + (size_t)c], v = rho[c] / M_PI;
            assert_true(vi >= 0.0 && vi <= v);
            changed[c] += vi != v;
        }
    for (int c = 0; c < 3; c++)
        assert_int_equal(changed[c], 500);
    bf_samples_free(s);

    /* Outlier positions are uniform: the chosen samples' mean index is n/2. */
    o.noise = (bf_synth_noise){.outlier_fraction = 0.2, .outlier_factor = 2};
    o.count = 50000;
    s = generate(m, x, &o);
    double sum = 0;
    size_t k = 0;
    for (size_t i = 0; i < s->n; i++)
        if (s->value[3 * i] != rho[0] / M_PI) {
            sum += (double)i;
            k++;
        }
    assert_int_equal(k, 10000);
    /* without replacement: the variance of the mean carries the factor (n - k)/(n - 1) */
    assert_within(sum / (double)k, (s->n - 1) / 2.0,
                  sqrt((double)s->n * s->n / 12.0 / (double)k * (s->n - k) / (s->n - 1.0)), "outlier mean index");
    bf_samples_free(s);
    bf_model_free(m);
    free(x);

    /* clamping: additive noise past zero; clamped values are 0 as often as v + s N < 0 */
    const double v = 0.8 / M_PI, sd = 0.5;
    bf_synth_noise nz = {.model = BF_NOISE_ADDITIVE, .level = sd};
    bf_samples *raw = lambert_noisy(0.8, &nz, 50);
    nz.clamp = 1;
    bf_samples *cl = lambert_noisy(0.8, &nz, 50);
    size_t neg = 0, zero = 0;
    for (size_t i = 0; i < NN; i++) {
        neg += raw->value[i] < 0.0;
        zero += cl->value[i] == 0.0;
        assert_true(cl->value[i] == (raw->value[i] < 0.0 ? 0.0 : raw->value[i]));
    }
    const double p = 0.5 * erfc(v / sd / sqrt(2.0));
    assert_within((double)neg / NN, p, sqrt(p * (1 - p) / NN), "fraction below zero");
    assert_int_equal(zero, neg);
    bf_samples_free(raw);
    bf_samples_free(cl);
}

static void test_bad_settings(void **state)
{
    (void)state;
    const double rho = 0.5;
    double *x;
    bf_model *m = lambert(1, &rho, &x);
    const bf_synth_noise bad[] = {
        {.model = BF_NOISE_RELATIVE, .level = -0.1},
        {.model = BF_NOISE_ADDITIVE, .level = INFINITY},
        {.model = BF_NOISE_PHOTON, .counts = 0},
        {.outlier_fraction = 1.5},
        {.outlier_fraction = NAN},
        {.outlier_fraction = 0.1, .outlier_factor = -2},
        {.model = (bf_synth_noise_model)17},
    };
    for (size_t q = 0; q < sizeof bad / sizeof bad[0]; q++) {
        bf_synth_options o = {.pattern = BF_SYNTH_UNIFORM, .count = 10, .noise = bad[q]};
        bf_samples *s = NULL;
        bf_error err;
        assert_int_equal(bf_synth_generate(m, x, &o, &s, &err), BF_ERR_ARG);
        assert_null(s);
        assert_true(strlen(err.msg) > 0 && !strchr(err.msg, '\n'));
    }
    /* Settings that overflow the values: an error, not Inf in the data. */
    const bf_synth_noise huge[] = {
        {.model = BF_NOISE_RELATIVE, .level = 1e308},
        {.model = BF_NOISE_ADDITIVE, .level = 1e308},
    };
    for (size_t q = 0; q < 2; q++) {
        bf_synth_options o = {.pattern = BF_SYNTH_UNIFORM, .count = 100, .noise = huge[q]};
        bf_samples *s = NULL;
        bf_error err;
        assert_int_equal(bf_synth_generate(m, x, &o, &s, &err), BF_ERR_RANGE);
        assert_null(s);
    }
    /* Photon counts beyond the largest double: no noise, not NaN. */
    bf_synth_noise inf_counts = {.model = BF_NOISE_PHOTON, .counts = 1e308};
    bf_synth_options oc = {.pattern = BF_SYNTH_UNIFORM, .count = 10, .noise = inf_counts};
    x[0] = 1.0;
    bf_samples *sc = generate(m, x, &oc);
    for (size_t i = 0; i < sc->n; i++)
        assert_true(isfinite(sc->value[i]) && fabs(sc->value[i] - 1.0 / M_PI) < 1e-15);
    bf_samples_free(sc);
    x[0] = rho;

    bf_synth_options o = {.pattern = BF_SYNTH_STRATIFIED, .count = 0};
    bf_samples *s = NULL;
    bf_error err;
    assert_int_equal(bf_synth_generate(m, x, &o, &s, &err), BF_ERR_ARG);
    assert_null(s);
    o.pattern = (bf_synth_pattern)99;
    o.count = 10;
    assert_int_equal(bf_synth_generate(m, x, &o, &s, &err), BF_ERR_ARG);
    /* parameters out of bounds */
    x[0] = 2.0;
    o.pattern = BF_SYNTH_UNIFORM;
    assert_int_equal(bf_synth_generate(m, x, &o, &s, &err), BF_ERR_RANGE);
    assert_null(s);
    assert_int_equal(bf_synth_pattern_from_name("stratified"), BF_SYNTH_STRATIFIED);
    assert_int_equal(bf_synth_pattern_from_name("gauss"), -1);
    assert_int_equal(bf_synth_noise_model_from_name("photon"), BF_NOISE_PHOTON);
    bf_model_free(m);
    free(x);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rng_reference),
        cmocka_unit_test(test_uniform_normal_below),
        cmocka_unit_test(test_poisson),
        cmocka_unit_test(test_uniform_pattern),
        cmocka_unit_test(test_cosine_pattern),
        cmocka_unit_test(test_random_pattern),
        cmocka_unit_test(test_stratified_pattern),
        cmocka_unit_test(test_gonio_pattern),
        cmocka_unit_test(test_merl_pattern),
        cmocka_unit_test(test_values_are_the_model),
        cmocka_unit_test(test_determinism),
        cmocka_unit_test(test_noise_relative_additive),
        cmocka_unit_test(test_noise_photon),
        cmocka_unit_test(test_outliers_and_clamp),
        cmocka_unit_test(test_bad_settings),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
