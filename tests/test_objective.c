/* The objective: residual forms at hand-computed points, the internal Jacobian against
 * central differences (several models, every form, fixed parameters and bounds, row
 * ranges that start and end mid-sample), the internal parametrisation, overrides,
 * solid-angle weights of MERL cells, the energy constraint and standard errors. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/metrics.h"
#include "brdfit/objective.h"
#include "objective_state.h"
#include "support.h"

static const bf_residual all_forms[] = {BF_RESIDUAL_LINEAR, BF_RESIDUAL_COSINE, BF_RESIDUAL_LOG, BF_RESIDUAL_CBRT,
                                        BF_RESIDUAL_RELATIVE};
#define NFORMS 5

/* n samples of C channels at random directions above the horizon (degrees). */
static bf_samples *random_samples(size_t n, int C, uint64_t seed)
{
    bf_samples *s = NULL;
    bf_samples_new(n, C, &s, NULL);
    assert_non_null(s);
    ts_rng r = {seed};
    ts_random_dirs(&r, n, s->theta_i, s->phi_i, s->theta_o, s->phi_o);
    for (size_t i = 0; i < n; i++) {
        s->theta_i[i] /= DEG;
        s->phi_i[i] /= DEG;
        s->theta_o[i] /= DEG;
        s->phi_o[i] /= DEG;
    }
    return s;
}

/* Evaluates the problem on [r0, r1) at z, into new arrays. */
static void eval_range(const bf_problem *p, const double *z, size_t r0, size_t r1, double **res, double **jac)
{
    *res = malloc((r1 - r0 + 1) * sizeof **res);
    *jac = jac ? malloc(((r1 - r0) * (size_t)p->npar + 1) * sizeof **jac) : NULL;
    assert_int_equal(p->eval(p->user, z, r0, r1, *res, jac ? *jac : NULL), 0);
}

/* The options of these tests: the defaults with form, and the samples' own weights only
 * where a test asks (the default uses them). */
static bf_objective_options objective_options(bf_residual form, int use_weights)
{
    bf_objective_options o;
    bf_objective_options_init(&o);
    o.residual = form;
    o.use_weights = use_weights;
    return o;
}

static bf_objective *make_obj(const bf_model *m, bf_samples *s, bf_residual form, const bf_override *ov, int nov)
{
    bf_objective_options o = objective_options(form, 0);
    o.overrides = ov;
    o.noverrides = nov;
    bf_error err = {0};
    bf_objective *obj = NULL;
    if (bf_objective_new(m, s, &o, &obj, &err) != BF_OK)
        fail_msg("bf_objective_new: %s", err.msg);
    return obj;
}

/* ---- Residual forms at hand-computed points ----------------------------------------- */

/* One sample at theta_i = 60 degrees (c = 1/2), Lambert (f = rho_d / pi, independent of
 * direction), C = 1: every form's value and derivative by hand. */
static void test_forms_values(void **state)
{
    (void)state;
    bf_model *m = ts_model("lambert", 1);
    bf_samples *s = NULL;
    bf_samples_new(1, 1, &s, NULL);
    s->theta_i[0] = 60;
    s->theta_o[0] = 30;
    s->phi_o[0] = 180;
    const double mm = 0.1, rho = 0.6, f = rho / M_PI, c = cos(60 * DEG);
    s->value[0] = mm;
    const double want[NFORMS] = {
        f - mm,
        (f - mm) * c,
        log(1 + f * c) - log(1 + mm * c),
        cbrt(f * c) - cbrt(mm * c),
        (f - mm) / (0.1 + 1e-3 * 0.1), /* delta = 1e-3 mean |m| */
    };
    const double dwant[NFORMS] = {
        1 / M_PI, c / M_PI, c / (1 + f * c) / M_PI, c / (3 * cbrt(f * c) * cbrt(f * c)) / M_PI, 1 / (0.1 + 1e-4) / M_PI,
    };
    for (int k = 0; k < NFORMS; k++) {
        bf_objective *obj = make_obj(m, s, all_forms[k], NULL, 0);
        const bf_problem *p = bf_objective_problem(obj);
        assert_int_equal(p->nres, 1);
        assert_int_equal(p->npar, 1);
        double x = rho, z, r, J;
        bf_objective_to_internal(obj, &x, &z);
        assert_int_equal(p->eval(p->user, &z, 0, 1, &r, &J), 0);
        ts_assert_rel(r, want[k], 1e-14, bf_residual_name(all_forms[k]));
        ts_assert_rel(J, dwant[k], 1e-14, bf_residual_name(all_forms[k]));
        bf_objective_free(obj);
    }
    bf_samples_free(s);
    bf_model_free(m);
}

/* Negative and zero measurements, a black model: every form finite; log floors 1 + m c
 * at 1e-12; cbrt's slope at f c = 0 is the documented (4/3) eps^(-2/3). */
static void test_forms_extremes(void **state)
{
    (void)state;
    bf_model *m = ts_model("lambert", 1);
    bf_samples *s = NULL;
    bf_samples_new(3, 1, &s, NULL);
    for (int i = 0; i < 3; i++) {
        s->theta_i[i] = 60;
        s->theta_o[i] = 30;
    }
    s->value[0] = -5.0; /* m c = -2.5 < -1 */
    s->value[1] = 0.0;
    s->value[2] = -1e-3;
    const double c = cos(60 * DEG);
    for (int k = 0; k < NFORMS; k++) {
        bf_objective *obj = make_obj(m, s, all_forms[k], NULL, 0);
        const bf_problem *p = bf_objective_problem(obj);
        for (int which = 0; which < 2; which++) {
            double x = which ? 0.0 : 1.0, z, r[3], J[3];
            bf_objective_to_internal(obj, &x, &z);
            assert_int_equal(p->eval(p->user, &z, 0, 3, r, J), 0);
            for (int i = 0; i < 3; i++)
                if (!isfinite(r[i]) || !isfinite(J[i]))
                    fail_msg("%s: residual %d not finite (%g, %g)", bf_residual_name(all_forms[k]), i, r[i], J[i]);
            if (all_forms[k] == BF_RESIDUAL_LOG)
                ts_assert_rel(r[0], log1p(x * c / M_PI) - log(1e-12), 1e-4, "log floor");
            if (all_forms[k] == BF_RESIDUAL_CBRT && x == 0.0) {
                ts_assert_rel(J[1], 4.0 / 3.0 * 1e6 * c / M_PI, 1e-12, "cbrt slope at 0");
                assert_true(r[1] == 0.0);
                ts_assert_rel(r[2], -cbrt(-1e-3 * c), 1e-15, "cbrt of a negative measurement");
            }
        }
        bf_objective_free(obj);
    }
    bf_samples_free(s);
    bf_model_free(m);
}

/* Sample weights (sqrt(w) on the residual) and samples below the horizon (0, zero row). */
static void test_weights_and_horizon(void **state)
{
    (void)state;
    bf_model *m = ts_model("lambert", 2);
    bf_samples *s = NULL;
    bf_samples_new(3, 2, &s, NULL);
    assert_int_equal(bf_samples_add_weights(s, NULL), BF_OK);
    for (int i = 0; i < 3; i++) {
        s->theta_i[i] = 20;
        s->theta_o[i] = 40;
        s->value[2 * i] = 0.05;
        s->value[2 * i + 1] = 0.07;
    }
    s->theta_i[1] = 95; /* below the horizon */
    s->weight[0] = 4.0;
    s->weight[2] = 0.25;
    bf_objective_options o = objective_options(BF_RESIDUAL_LINEAR, 1);
    bf_objective *obj = NULL;
    bf_objective_new(m, s, &o, &obj, NULL);
    assert_non_null(obj);
    const bf_problem *p = bf_objective_problem(obj);
    assert_int_equal(p->nres, 6);
    double x[2] = {0.3, 0.4}, z[2], r[6], J[12];
    bf_objective_to_internal(obj, x, z);
    assert_int_equal(p->eval(p->user, z, 0, 6, r, J), 0);
    ts_assert_rel(r[0], 2.0 * (0.3 / M_PI - 0.05), 1e-15, "weighted r0");
    ts_assert_rel(r[1], 2.0 * (0.4 / M_PI - 0.07), 1e-15, "weighted r1");
    assert_true(r[2] == 0.0 && r[3] == 0.0);
    for (int j = 4; j < 8; j++)
        assert_true(J[j] == 0.0);
    ts_assert_rel(r[4], 0.5 * (0.3 / M_PI - 0.05), 1e-15, "weighted r4");
    ts_assert_rel(J[0], 2.0 / M_PI, 1e-15, "weighted J");
    assert_true(J[1] == 0.0);
    bf_objective_free(obj);
    /* Without use_weights the weights are ignored. */
    o.use_weights = 0;
    bf_objective_new(m, s, &o, &obj, NULL);
    p = bf_objective_problem(obj);
    assert_int_equal(p->eval(p->user, z, 0, 2, r, NULL), 0);
    ts_assert_rel(r[0], 0.3 / M_PI - 0.05, 1e-15, "unweighted r0");
    bf_objective_free(obj);
    bf_samples_free(s);
    bf_model_free(m);
}

/* ---- The internal Jacobian against central differences ------------------------------ */

typedef struct jac_case {
    const char *spec;
    const char *fix, *bound; /* NULL or override text */
    double n_phong;          /* > 0: the exponent n set to this */
} jac_case;

/* x in the interior: each free entry at least 2% of its internal range from the bounds,
 * so that the central differences never cross a clamp. */
static void interior(const bf_objective *obj, const bf_problem *p, double *x, double *z)
{
    bf_objective_to_internal(obj, x, z);
    for (int j = 0; j < p->npar; j++) {
        double lo = p->lo[j], hi = p->hi[j], w = 0.02 * (hi - lo);
        if (z[j] < lo + w)
            z[j] = lo + w;
        if (z[j] > hi - w)
            z[j] = hi - w;
    }
    bf_objective_to_model(obj, z, x);
}

static void check_jacobian(const jac_case *jc, bf_residual form, uint64_t seed)
{
    const int C = 3;
    const size_t n = 40;
    bf_model *m = ts_model(jc->spec, C);
    bf_samples *s = random_samples(n, C, seed);
    int P = bf_model_nvalues(m);
    double *x = malloc((size_t)P * sizeof *x), *xm = malloc((size_t)P * sizeof *xm);
    ts_rng r = {seed * 7 + 1};
    /* Measurements from other parameters, some negative and some zero. */
    ts_random_params(m, &r, TS_PARAMS_MODERATE, xm);
    const bf_geometry *g = NULL;
    bf_samples_geometry(s, &g, NULL);
    bf_model_eval(m, xm, g, s->value, NULL);
    for (size_t i = 0; i < n * (size_t)C; i++) {
        double u = ts_uniform(&r);
        s->value[i] *= 0.5 + ts_uniform(&r);
        if (u < 0.1)
            s->value[i] = -0.2 * ts_uniform(&r);
        else if (u < 0.15)
            s->value[i] = 0.0;
    }
    bf_override ov[2];
    int nov = 0;
    if (jc->fix)
        assert_int_equal(bf_override_parse_fix(jc->fix, &ov[nov++], NULL), BF_OK);
    if (jc->bound)
        assert_int_equal(bf_override_parse_bound(jc->bound, &ov[nov++], NULL), BF_OK);
    bf_objective *obj = make_obj(m, s, form, ov, nov);
    const bf_problem *p = bf_objective_problem(obj);
    assert_int_equal(p->nres, n * (size_t)C);
    int nfixed = 0, want_fixed = 0;
    for (int k = 0; k < P; k++)
        nfixed += bf_objective_fixed(obj, k);
    if (jc->fix)
        want_fixed = ov[0].channel >= 0 ? 1 : bf_model_param(m, bf_model_find_param(m, ov[0].name))->color ? C : 1;
    assert_int_equal(nfixed, want_fixed);
    assert_int_equal(p->npar, P - nfixed);
    ts_random_params(m, &r, TS_PARAMS_MODERATE, x);
    if (jc->n_phong > 0)
        x[bf_model_param_offset(m, bf_model_find_param(m, "n"))] = jc->n_phong;
    int nz = p->npar;
    double *z = malloc((size_t)nz * sizeof *z), *zp = malloc((size_t)nz * sizeof *zp);
    interior(obj, p, x, z);

    /* Rows [r0, r1) starting and ending mid-sample (C = 3). */
    size_t r0 = 4, r1 = n * (size_t)C - 5, nr = r1 - r0;
    double *res, *jac;
    eval_range(p, z, r0, r1, &res, &jac);
    double *rp = malloc(nr * sizeof *rp), *rm = malloc(nr * sizeof *rm);
    for (int j = 0; j < nz; j++) {
        double h = 1e-6 * fmax(1.0, fabs(z[j]));
        memcpy(zp, z, (size_t)nz * sizeof *z);
        zp[j] = z[j] + h;
        assert_int_equal(p->eval(p->user, zp, r0, r1, rp, NULL), 0);
        zp[j] = z[j] - h;
        assert_int_equal(p->eval(p->user, zp, r0, r1, rm, NULL), 0);
        double colmax = 0.0;
        for (size_t q = 0; q < nr; q++)
            colmax = fmax(colmax, fabs(jac[q * (size_t)nz + (size_t)j]));
        for (size_t q = 0; q < nr; q++) {
            double fd = (rp[q] - rm[q]) / (2 * h), an = jac[q * (size_t)nz + (size_t)j];
            if (!isfinite(an) || fabs(fd - an) > 1e-5 * fabs(fd) + 1e-6 * colmax + 1e-9)
                fail_msg("%s, %s, fix %s, bound %s: row %zu, z[%d]: analytic %.10g, differences %.10g", jc->spec,
                         bf_residual_name(form), jc->fix ? jc->fix : "-", jc->bound ? jc->bound : "-", r0 + q, j, an,
                         fd);
        }
    }
    free(rp);
    free(rm);
    free(res);
    free(jac);
    free(z);
    free(zp);
    free(x);
    free(xm);
    bf_objective_free(obj);
    bf_samples_free(s);
    bf_model_free(m);
}

static const jac_case jac_cases[] = {
    {"lambert", NULL, NULL, 0},
    {"lambert", "rho_d[1]=0.25", NULL, 0},
    {"walter", NULL, NULL, 0},
    {"walter", "f0=0.04", "alpha=0.05:0.6", 0},
    {"walter", "rho_s[0]=0.2", "rho_d=0.1:0.9", 0},
    {"cook_torrance:lobes=2", NULL, NULL, 0},
    {"cook_torrance:lobes=2", "m_2=0.3", "rho_s_1[2]=0.1:0.5", 0},
    {"disney", NULL, NULL, 0},
    {"disney", "metallic=0.5", "roughness=0.2:0.9", 0},
    {"phong", NULL, NULL, 0},
    {"phong", NULL, NULL, 2e4},
    {"phong", "rho_d=0.2", "n=100:1e5", 3e4},
};

static void test_jacobian_fd(void **state)
{
    (void)state;
    for (size_t c = 0; c < sizeof jac_cases / sizeof jac_cases[0]; c++)
        for (int k = 0; k < NFORMS; k++)
            check_jacobian(&jac_cases[c], all_forms[k], 1000 + 17 * c + (uint64_t)k);
}

/* ---- The fused pass -------------------------------------------------------------------
 * bf_problem.normal against sums built here from eval's residuals and Jacobian rows
 * (with the loss applied as solve.h defines it): lobe models and others, mono ties,
 * fixed parameters, sample weights, MERL cells and robust losses; the same bits for
 * every thread count. */
typedef struct normal_case {
    const char *spec;
    const char *fix;
    bf_residual form;
    const char *loss;
    int weights, cells;
} normal_case;

static const normal_case normal_cases[] = {
    {"lambert", NULL, BF_RESIDUAL_LOG, NULL, 0, 0},
    {"walter", NULL, BF_RESIDUAL_LOG, NULL, 0, 0},
    {"walter", "f0=0.04", BF_RESIDUAL_LINEAR, "huber:0.01", 1, 0},
    {"walter:mono=specular", NULL, BF_RESIDUAL_LOG, NULL, 0, 1},
    {"cook_torrance:lobes=2", "m_2=0.3", BF_RESIDUAL_CBRT, "cauchy:0.1", 1, 1},
    {"lafortune:lobes=2,mono=all", NULL, BF_RESIDUAL_RELATIVE, NULL, 0, 0},
    {"disney", NULL, BF_RESIDUAL_LOG, "soft_l1:0.05", 0, 1},
    {"oren_nayar:mono=all", "sigma=0.3", BF_RESIDUAL_COSINE, NULL, 1, 0},
    {"ashikhmin_shirley", NULL, BF_RESIDUAL_LOG, NULL, 0, 1},
};

/* n samples at MERL cell centres above the horizon (cells spread over the table). */
static bf_samples *cell_samples(size_t n, uint64_t seed)
{
    bf_samples *s = NULL;
    bf_samples_new_cells(n, 3, &s, NULL);
    assert_non_null(s);
    ts_rng r = {seed};
    for (size_t i = 0; i < n;) {
        int32_t c = (int32_t)(ts_uniform(&r) * BF_MERL_CELLS);
        double d[4];
        bf_merl_cell_directions(c, &d[0], &d[1], &d[2], &d[3]);
        if (d[0] < 89.0 && d[2] < 89.0)
            s->merl->cell[i++] = c;
    }
    return s;
}

static void check_normal(const normal_case *nc, uint64_t seed)
{
    const int C = 3;
    const size_t n = 9000; /* three chunks of the pass, the last one short */
    bf_model *m = NULL;
    bf_model_new(nc->spec, C, &m, NULL);
    assert_non_null(m);
    bf_samples *s = nc->cells ? cell_samples(n, seed) : random_samples(n, C, seed);
    ts_rng r = {seed + 1};
    const int P = bf_model_nvalues(m);
    double *x = malloc((size_t)P * sizeof *x);
    ts_random_params(m, &r, TS_PARAMS_MODERATE, x);
    const bf_geometry *g = NULL;
    bf_samples_geometry(s, &g, NULL);
    assert_non_null(g);
    bf_model_eval(m, x, g, s->value, NULL); /* data from the model, then perturbed */
    for (size_t v = 0; v < n * (size_t)C; v++)
        s->value[v] *= 1.0 + 0.3 * (ts_uniform(&r) - 0.5);
    if (nc->weights) {
        assert_int_equal(bf_samples_add_weights(s, NULL), BF_OK);
        for (size_t i = 0; i < n; i++)
            s->weight[i] = 0.2 + ts_uniform(&r);
    }
    bf_override ov[1];
    int nov = 0;
    if (nc->fix)
        assert_int_equal(bf_override_parse_fix(nc->fix, &ov[nov++], NULL), BF_OK);
    bf_objective_options oo = objective_options(nc->form, 1);
    oo.overrides = ov;
    oo.noverrides = nov;
    bf_error err = {0};
    bf_objective *obj = NULL;
    if (bf_objective_new(m, s, &oo, &obj, &err) != BF_OK)
        fail_msg("%s: %s", nc->spec, err.msg);
    const bf_problem *p = bf_objective_problem(obj);
    bf_loss loss = {BF_LOSS_NONE, 1.0};
    if (nc->loss)
        assert_int_equal(bf_loss_parse(nc->loss, &loss, NULL), BF_OK);
    const int nz = p->npar;
    double *z = malloc((size_t)nz * sizeof *z);
    bf_objective_to_internal(obj, x, z);

    /* The reference, from eval. */
    double *res, *jac;
    eval_range(p, z, 0, p->nres, &res, &jac);
    double ssq = 0.0, *tr = calloc((size_t)nz, sizeof *tr), *tj = calloc((size_t)nz * (size_t)nz, sizeof *tj);
    for (size_t q = 0; q < p->nres; q++) {
        double dg, gq = bf_loss_residual(&loss, res[q], &dg);
        ssq += gq * gq;
        for (int a = 0; a < nz; a++) {
            double ja = dg * jac[q * (size_t)nz + (size_t)a];
            tr[a] += gq * ja;
            for (int b = 0; b < nz; b++)
                tj[a * nz + b] += ja * dg * jac[q * (size_t)nz + (size_t)b];
        }
    }
    double scale = 0.0;
    for (int a = 0; a < nz; a++)
        scale = fmax(scale, sqrt(fabs(tj[a * nz + a])));

    double ssq1, ssq3, ssq0, *tr1 = malloc((size_t)nz * sizeof *tr1), *tr3 = malloc((size_t)nz * sizeof *tr3);
    double *tj1 = malloc((size_t)nz * (size_t)nz * sizeof *tj1), *tj3 = malloc((size_t)nz * (size_t)nz * sizeof *tj3);
    assert_non_null(p->normal);
    assert_int_equal(bf_problem_normal(p, z, &loss, 1, &ssq1, tr1, tj1), 0);
    assert_int_equal(bf_problem_normal(p, z, &loss, 3, &ssq3, tr3, tj3), 0);
    assert_int_equal(bf_problem_normal(p, z, &loss, 2, &ssq0, NULL, NULL), 0);
    /* The same bits for every thread count, and the cost alone as with the sums. */
    assert_memory_equal(&ssq1, &ssq3, sizeof ssq1);
    assert_memory_equal(&ssq1, &ssq0, sizeof ssq1);
    assert_memory_equal(tr1, tr3, (size_t)nz * sizeof *tr1);
    assert_memory_equal(tj1, tj3, (size_t)nz * (size_t)nz * sizeof *tj1);
    ts_assert_rel(ssq1, ssq, 1e-12, nc->spec);
    for (int a = 0; a < nz; a++) {
        if (fabs(tr1[a] - tr[a]) > 1e-11 * sqrt(ssq) * scale)
            fail_msg("%s: J'g[%d] %.17g, from eval %.17g", nc->spec, a, tr1[a], tr[a]);
        for (int b = 0; b < nz; b++)
            if (fabs(tj1[a * nz + b] - tj[a * nz + b]) > 1e-11 * scale * scale)
                fail_msg("%s: J'J[%d][%d] %.17g, from eval %.17g", nc->spec, a, b, tj1[a * nz + b], tj[a * nz + b]);
    }
    free(tr), free(tj), free(tr1), free(tr3), free(tj1), free(tj3);
    free(res), free(jac), free(z), free(x);
    bf_objective_free(obj);
    bf_samples_free(s);
    bf_model_free(m);
}

static void test_normal_pass(void **state)
{
    (void)state;
    for (size_t c = 0; c < sizeof normal_cases / sizeof normal_cases[0]; c++)
        check_normal(&normal_cases[c], 5000 + 31 * c);
}

/* The end of a fit: metrics and standard errors from one pass (bf_obj_final) equal, to
 * the bit, the metrics pass and bf_objective_stderr, with and without scene weights. */
static void test_final_pass(void **state)
{
    (void)state;
    const char *const specs[] = {"walter", "disney", "lafortune:mono=specular", "oren_nayar"};
    for (size_t c = 0; c < 4; c++)
        for (int weighted = 0; weighted < 2; weighted++) {
            const size_t n = 6000;
            bf_model *m = NULL;
            bf_model_new(specs[c], 3, &m, NULL);
            bf_samples *s = c % 2 ? cell_samples(n, 70 + c) : random_samples(n, 3, 70 + c);
            ts_rng r = {80 + c};
            const int P = bf_model_nvalues(m);
            double *x = malloc((size_t)P * sizeof *x), *se1 = malloc((size_t)P * sizeof *se1);
            double *se2 = malloc((size_t)P * sizeof *se2);
            ts_random_params(m, &r, TS_PARAMS_MODERATE, x);
            bf_model_eval(m, x, ts_samples_geometry(s), s->value, NULL);
            for (size_t v = 0; v < 3 * n; v++)
                s->value[v] *= 1.0 + 0.2 * (ts_uniform(&r) - 0.5);
            if (weighted) {
                s->scene_weight = malloc(n * sizeof *s->scene_weight);
                for (size_t i = 0; i < n; i++)
                    s->scene_weight[i] = i % 7 ? ts_uniform(&r) : 0.0;
            }
            bf_objective_options oo = objective_options(BF_RESIDUAL_LOG, 0);
            oo.threads = 2;
            bf_objective *obj = NULL;
            bf_objective_new(m, s, &oo, &obj, NULL);
            assert_non_null(obj);
            bf_metrics a, b;
            bf_error err;
            assert_int_equal(bf_obj_final(obj, x, &(bf_final_want){weighted, P, NULL, NULL},
                                          &(bf_final_out){&a, se1, NULL, NULL}, &err),
                             BF_OK);
            assert_int_equal(bf_metrics_compute_weighted(m, x, s, P, 1, weighted, &b, &err), BF_OK);
            assert_int_equal(bf_objective_stderr(obj, x, se2, &err), BF_OK);
            assert_memory_equal(se1, se2, (size_t)P * sizeof *se1);
            assert_int_equal(a.n, b.n);
            assert_int_equal(a.k, b.k);
            assert_int_equal(a.weighted, b.weighted);
            assert_int_equal(a.weighted, weighted);
            const double got[5] = {a.rmse, a.rmse_cos, a.rmse_log, a.rmse_rel, a.max_err};
            const double want[5] = {b.rmse, b.rmse_cos, b.rmse_log, b.rmse_rel, b.max_err};
            /* The same sums in the same order: the same bits. */
            assert_memory_equal(got, want, sizeof got);
            /* The criteria: the metrics pass has none; the fit's come from the objective's
             * weighted sum of squares over its residuals with a positive weight (the scene's
             * weights enter the objective whatever the metrics do). */
            assert_true(isnan(b.aic) && isnan(b.bic) && isnan(b.aicc));
            const bf_problem *p = bf_objective_problem(obj);
            double z[64], wssr;
            bf_objective_to_internal(obj, x, z);
            assert_int_equal(bf_problem_normal(p, z, NULL, 1, &wssr, NULL, NULL), 0);
            size_t N = 0;
            double slw = 0.0;
            for (size_t i = 0; i < n; i++) {
                const double w = s->scene_weight ? s->scene_weight[i] : 1.0;
                if (bf_geometry_valid_at(ts_samples_geometry(s), i) && w > 0.0) {
                    N += 3;
                    slw += 3.0 * log(w);
                }
            }
            assert_int_equal(a.crit_n, N);
            const double ll = -0.5 * (double)N * (log(2 * M_PI * wssr / (double)N) + 1.0) + 0.5 * slw;
            ts_assert_rel(a.loglik, ll, 1e-9, "loglik");
            ts_assert_rel(a.aic, -2 * ll + 2 * (P + 1), 1e-9, "aic");
            ts_assert_rel(a.bic, -2 * ll + (P + 1) * log((double)N), 1e-9, "bic");
            ts_assert_rel(a.aicc, a.aic + 2.0 * (P + 1) * (P + 2) / ((double)N - P - 2), 1e-9, "aicc");
            free(x), free(se1), free(se2);
            bf_objective_free(obj);
            bf_samples_free(s);
            bf_model_free(m);
        }
}

/* Any row range gives the same residuals and Jacobian rows as the whole set. */
static void test_row_ranges(void **state)
{
    (void)state;
    const int C = 3;
    const size_t n = 700; /* spans several of the evaluator's sample chunks */
    bf_model *m = ts_model("cook_torrance:lobes=2", C);
    bf_samples *s = random_samples(n, C, 5);
    ts_rng r = {9};
    for (size_t i = 0; i < n * (size_t)C; i++)
        s->value[i] = ts_uniform(&r);
    s->theta_i[10] = 91; /* one below the horizon */
    bf_objective *obj = make_obj(m, s, BF_RESIDUAL_LOG, NULL, 0);
    const bf_problem *p = bf_objective_problem(obj);
    int P = bf_model_nvalues(m), nz = p->npar;
    assert_int_equal(nz, P);
    double *x = malloc((size_t)P * sizeof *x), *z = malloc((size_t)nz * sizeof *z);
    ts_random_params(m, &r, TS_PARAMS_MODERATE, x);
    bf_objective_to_internal(obj, x, z);
    double *res, *jac;
    eval_range(p, z, 0, p->nres, &res, &jac);
    for (size_t q = 30; q < 33; q++)
        assert_true(res[q] == 0.0); /* sample 10 */
    const size_t ranges[][2] = {{0, 1}, {1, 2}, {2, 7}, {5, 17}, {100, 1601}, {1, 2099}, {2098, 2100}, {1000, 1000}};
    for (size_t t = 0; t < sizeof ranges / sizeof ranges[0]; t++) {
        size_t r0 = ranges[t][0], r1 = ranges[t][1];
        double *rr = malloc((r1 - r0 + 1) * sizeof *rr), *jj = malloc(((r1 - r0) * (size_t)nz + 1) * sizeof *jj);
        assert_int_equal(p->eval(p->user, z, r0, r1, rr, jj), 0);
        for (size_t q = r0; q < r1; q++) {
            assert_true(rr[q - r0] == res[q]);
            assert_memory_equal(jj + (q - r0) * (size_t)nz, jac + q * (size_t)nz, (size_t)nz * sizeof *jj);
        }
        /* Residuals only. */
        assert_int_equal(p->eval(p->user, z, r0, r1, rr, NULL), 0);
        for (size_t q = r0; q < r1; q++)
            assert_true(rr[q - r0] == res[q]);
        free(rr);
        free(jj);
    }
    free(res);
    free(jac);
    free(x);
    free(z);
    bf_objective_free(obj);
    bf_samples_free(s);
    bf_model_free(m);
}

/* ---- Internal parametrisation -------------------------------------------------------- */

static void test_parametrisation(void **state)
{
    (void)state;
    bf_model *m = ts_model("walter", 3); /* rho_d[3] rho_s[3] alpha f0 */
    bf_model *ph = ts_model("phong", 3); /* rho_d[3] rho_s[3] n (LOG1P) */
    bf_samples *s = random_samples(10, 3, 3);
    bf_override ov[2];
    assert_int_equal(bf_override_parse_fix("f0=0.04", &ov[0], NULL), BF_OK);
    assert_int_equal(bf_override_parse_bound("alpha=0.01:0.5", &ov[1], NULL), BF_OK);
    bf_objective *obj = make_obj(m, s, BF_RESIDUAL_LINEAR, ov, 2);
    assert_int_equal(bf_objective_nz(obj), 7);
    const bf_problem *p = bf_objective_problem(obj);
    assert_int_equal(p->npar, 7);
    /* Internal bounds: linear for the colours, log for alpha. */
    for (int j = 0; j < 6; j++) {
        assert_true(p->lo[j] == 0.0);
        assert_true(p->hi[j] == 1.0);
    }
    ts_assert_rel(p->lo[6], log(0.01), 1e-15, "ln lo");
    ts_assert_rel(p->hi[6], log(0.5), 1e-15, "ln hi");
    for (int k = 0; k < 8; k++)
        assert_int_equal(bf_objective_fixed(obj, k), k == 7);
    double lo[8], hi[8];
    bf_objective_bounds(obj, lo, hi);
    assert_true(lo[6] == 0.01 && hi[6] == 0.5 && lo[7] == 0.04 && hi[7] == 0.04);

    double x[8] = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.07, 0.9}, z[7], x2[8];
    bf_objective_to_internal(obj, x, z);
    ts_assert_rel(z[6], log(0.07), 1e-15, "z alpha");
    assert_true(z[0] == 0.1 && z[5] == 0.6);
    bf_objective_to_model(obj, z, x2);
    for (int k = 0; k < 7; k++)
        ts_assert_rel(x2[k], x[k], 1e-15, "round trip");
    assert_true(x2[7] == 0.04); /* fixed: its value, whatever x held */
    /* to_internal clamps into the effective bounds. */
    x[6] = 0.9;
    x[0] = -1.0;
    bf_objective_to_internal(obj, x, z);
    ts_assert_rel(z[6], log(0.5), 1e-15, "clamped alpha");
    assert_true(z[0] == 0.0);
    bf_objective_free(obj);

    obj = make_obj(ph, s, BF_RESIDUAL_LINEAR, NULL, 0);
    p = bf_objective_problem(obj);
    assert_int_equal(p->npar, 7);
    assert_true(p->lo[6] == 0.0);
    ts_assert_rel(p->hi[6], log1p(1e6), 1e-15, "log1p hi");
    double xp[7] = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 12345.0}, zp[7], xp2[7];
    bf_objective_to_internal(obj, xp, zp);
    ts_assert_rel(zp[6], log1p(12345.0), 1e-15, "z n");
    bf_objective_to_model(obj, zp, xp2);
    ts_assert_rel(xp2[6], 12345.0, 1e-14, "n round trip");
    bf_objective_free(obj);
    bf_samples_free(s);
    bf_model_free(m);
    bf_model_free(ph);
}

/* An open lower bound (Brady's a in (0, 3]) is nudged in, so z never maps onto it. */
static void test_open_bounds(void **state)
{
    (void)state;
    bf_model *m = ts_model("brady", 1);
    bf_samples *s = random_samples(10, 1, 4);
    bf_objective *obj = make_obj(m, s, BF_RESIDUAL_LINEAR, NULL, 0);
    int P = bf_model_nvalues(m);
    double lo[16], hi[16];
    bf_objective_bounds(obj, lo, hi);
    int ka = bf_model_param_offset(m, bf_model_find_param(m, "a"));
    assert_true(lo[ka] > 0.0 && lo[ka] < 1e-8);
    assert_true(hi[ka] == 3.0);
    const bf_problem *p = bf_objective_problem(obj);
    double *z = malloc((size_t)p->npar * sizeof *z), *x = malloc((size_t)P * sizeof *x);
    for (int j = 0; j < p->npar; j++)
        z[j] = p->lo[j];
    bf_objective_to_model(obj, z, x);
    assert_int_equal(bf_model_check(m, x, NULL), BF_OK);
    free(z);
    free(x);
    bf_objective_free(obj);
    bf_samples_free(s);
    bf_model_free(m);
}

/* ---- Overrides ----------------------------------------------------------------------- */

static void expect_parse_error(int bound, const char *text, const char *fragment)
{
    bf_override ov;
    bf_error err = {0};
    int rc = bound ? bf_override_parse_bound(text, &ov, &err) : bf_override_parse_fix(text, &ov, &err);
    assert_int_equal(rc, BF_ERR_ARG);
    if (!strstr(err.msg, text) || !strstr(err.msg, fragment) || strchr(err.msg, '\n'))
        fail_msg("'%s': message '%s' lacks the text or '%s'", text, err.msg, fragment);
}

static void test_override_parse(void **state)
{
    (void)state;
    bf_override ov;
    assert_int_equal(bf_override_parse_fix("alpha=0.1", &ov, NULL), BF_OK);
    assert_string_equal(ov.name, "alpha");
    assert_int_equal(ov.channel, -1);
    assert_int_equal(ov.fix, 1);
    assert_true(ov.value == 0.1);
    assert_int_equal(bf_override_parse_fix("rho_d[2]=0.3", &ov, NULL), BF_OK);
    assert_string_equal(ov.name, "rho_d");
    assert_int_equal(ov.channel, 2);
    assert_true(ov.value == 0.3);
    assert_int_equal(bf_override_parse_bound("alpha=0.01:0.5", &ov, NULL), BF_OK);
    assert_string_equal(ov.name, "alpha");
    assert_int_equal(ov.fix, 0);
    assert_true(ov.lo == 0.01 && ov.hi == 0.5);
    assert_int_equal(bf_override_parse_bound("rho_s_2[0]=1e-3:2e-1", &ov, NULL), BF_OK);
    assert_string_equal(ov.name, "rho_s_2");
    assert_int_equal(ov.channel, 0);
    assert_true(ov.lo == 1e-3 && ov.hi == 2e-1);

    expect_parse_error(0, "alpha0.1", "NAME=VALUE");
    expect_parse_error(0, "=0.1", "no parameter name");
    expect_parse_error(0, "alpha=", "not a finite number");
    expect_parse_error(0, "alpha=abc", "not a finite number");
    expect_parse_error(0, "alpha=0.1x", "not a finite number");
    expect_parse_error(0, "alpha=nan", "not a finite number");
    expect_parse_error(0, "alpha=inf", "not a finite number");
    expect_parse_error(0, "rho_d[x]=1", "channel index");
    expect_parse_error(0, "rho_d[-1]=1", "channel index");
    expect_parse_error(0, "rho_d[1=1", "channel index");
    expect_parse_error(0, "rho_d[1]x=1", "channel index");
    expect_parse_error(1, "alpha=0.1", "LO:HI");
    expect_parse_error(1, "alpha=0.5:0.1", "not below");
    expect_parse_error(1, "alpha=0.5:0.5", "fix");
    expect_parse_error(1, "alpha=:0.5", "lower bound");
    expect_parse_error(1, "alpha=0.1:", "upper bound");
    expect_parse_error(1, "alpha=0.1:0.5:0.7", "upper bound");
}

/* Validation against the model in bf_objective_new: one-line errors naming the target. */
static void expect_new_error(const char *text, int bound, int code, const char *fragment)
{
    bf_model *m = ts_model("walter", 3);
    bf_samples *s = random_samples(5, 3, 1);
    bf_override ov;
    if (bound)
        assert_int_equal(bf_override_parse_bound(text, &ov, NULL), BF_OK);
    else
        assert_int_equal(bf_override_parse_fix(text, &ov, NULL), BF_OK);
    bf_objective_options o = objective_options(BF_RESIDUAL_LINEAR, 0);
    o.overrides = &ov;
    o.noverrides = 1;
    bf_error err = {0};
    bf_objective *bad;
    assert_int_equal(bf_objective_new(m, s, &o, &bad, &err), code);
    assert_null(bad);
    assert_int_equal(err.code, code);
    if (!strstr(err.msg, fragment) || !strstr(err.msg, ov.name))
        fail_msg("'%s': message '%s' lacks '%s' or the name", text, err.msg, fragment);
    bf_samples_free(s);
    bf_model_free(m);
}

static void test_override_validation(void **state)
{
    (void)state;
    expect_new_error("beta=0.1", 0, BF_ERR_ARG, "no parameter 'beta'");
    expect_new_error("rho_d[3]=0.1", 0, BF_ERR_ARG, "channel 3 out of range");
    expect_new_error("alpha[0]=0.1", 0, BF_ERR_ARG, "no channel index");
    expect_new_error("alpha=2", 0, BF_ERR_RANGE, "outside the model's bounds");
    expect_new_error("alpha=0", 0, BF_ERR_RANGE, "outside the model's bounds");
    expect_new_error("f0=-0.1", 0, BF_ERR_RANGE, "outside the model's bounds");
    expect_new_error("alpha=0:0.5", 1, BF_ERR_RANGE, "only be narrowed");
    expect_new_error("rho_s=0.1:2", 1, BF_ERR_RANGE, "only be narrowed");
    expect_new_error("rho_s[1]=0.1:inf", 1, BF_ERR_RANGE, "only be narrowed");

    /* Applied: a channel fixed, the others free; model lo kept where the bound equals
     * it. Two overrides of one entry are refused (the later would silently win). */
    bf_model *m = ts_model("walter", 3);
    bf_samples *s = random_samples(5, 3, 1);
    bf_override ov[3];
    assert_int_equal(bf_override_parse_fix("rho_d[1]=0.3", &ov[0], NULL), BF_OK);
    assert_int_equal(bf_override_parse_fix("alpha=0.2", &ov[1], NULL), BF_OK);
    assert_int_equal(bf_override_parse_bound("alpha=1e-4:0.4", &ov[2], NULL), BF_OK);
    bf_objective_options dup = objective_options(BF_RESIDUAL_LINEAR, 0);
    dup.overrides = ov;
    dup.noverrides = 3;
    bf_error derr = {0};
    bf_objective *bad;
    assert_int_equal(bf_objective_new(m, s, &dup, &bad, &derr), BF_ERR_ARG);
    assert_null(bad);
    assert_int_equal(derr.code, BF_ERR_ARG);
    assert_non_null(strstr(derr.msg, "fix alpha and bound alpha both set alpha"));
    assert_int_equal(bf_overrides_check(m, 0, ov, 3, &derr), BF_ERR_ARG);
    assert_int_equal(bf_overrides_check(m, 0, ov, 2, &derr), BF_OK);
    ov[1] = ov[2];
    bf_objective *obj = make_obj(m, s, BF_RESIDUAL_LINEAR, ov, 2);
    assert_int_equal(bf_objective_nz(obj), 7);
    double lo[8], hi[8];
    bf_objective_bounds(obj, lo, hi);
    for (int k = 0; k < 8; k++)
        assert_int_equal(bf_objective_fixed(obj, k), k == 1);
    assert_true(lo[1] == 0.3 && hi[1] == 0.3);
    assert_true(lo[0] == 0.0 && hi[0] == 1.0);
    assert_true(lo[6] == 1e-4 && hi[6] == 0.4);
    bf_objective_free(obj);
    /* Channel mismatch. */
    bf_model *m1 = ts_model("walter", 1);
    bf_error err = {0};
    assert_int_equal(bf_objective_new(m1, s, NULL, &bad, &err), BF_ERR_ARG);
    assert_null(bad);
    assert_int_equal(err.code, BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "channel"));
    bf_model_free(m1);
    bf_samples_free(s);
    bf_model_free(m);
}

static void test_residual_names(void **state)
{
    (void)state;
    for (int k = 0; k < NFORMS; k++) {
        bf_residual r;
        assert_int_equal(bf_residual_parse(bf_residual_name(all_forms[k]), &r, NULL), BF_OK);
        assert_int_equal(r, all_forms[k]);
    }
    bf_residual r;
    bf_error err = {0};
    assert_int_equal(bf_residual_parse("squared", &r, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "squared"));
    assert_non_null(strstr(err.msg, "cbrt"));
}

/* ---- Solid-angle weights -------------------------------------------------------------- */

/* The cell's measure by the midpoint rule on the raw integrand 4 cos(td) sin(th) sin(td)
 * over its extent (phi_d cells are all equal): independent of the code's closed form. */
static double cell_measure(int i, int j)
{
    double h0 = (i / 90.0) * (i / 90.0) * M_PI / 2, h1 = ((i + 1) / 90.0) * ((i + 1) / 90.0) * M_PI / 2;
    double d0 = j / 90.0 * M_PI / 2, d1 = (j + 1) / 90.0 * M_PI / 2;
    const int N = 2000;
    double sh = 0, sd = 0;
    for (int q = 0; q < N; q++) {
        double th = h0 + (q + 0.5) * (h1 - h0) / N, td = d0 + (q + 0.5) * (d1 - d0) / N;
        sh += sin(th) * (h1 - h0) / N;
        sd += 4 * cos(td) * sin(td) * (d1 - d0) / N;
    }
    return sh * sd;
}

static void test_solid_angle(void **state)
{
    (void)state;
    /* Cells (theta_h index, theta_d index) at phi_d index 90, all above the horizon. */
    static const int cells[][2] = {{0, 0},   {1, 0},  {1, 10}, {10, 5}, {30, 30},
                                   {60, 20}, {85, 1}, {88, 0}, {89, 0}, {45, 44}};
    const size_t n = sizeof cells / sizeof cells[0];
    bf_model *m = ts_model("lambert", 3);
    bf_samples *s = NULL;
    bf_samples_new(n, 3, &s, NULL);
    s->merl = calloc(1, sizeof *s->merl);
    s->merl->cell = calloc(n, sizeof *s->merl->cell);
    for (size_t q = 0; q < n; q++) {
        int32_t cell = 90 + cells[q][1] * 180 + cells[q][0] * 180 * 90;
        s->merl->cell[q] = cell;
        bf_merl_cell_directions(cell, &s->theta_i[q], &s->phi_i[q], &s->theta_o[q], &s->phi_o[q]);
    }
    const bf_geometry *g = NULL;
    bf_samples_geometry(s, &g, NULL);
    for (size_t q = 0; q < n; q++)
        assert_true(bf_geometry_valid(g, q));
    /* Measured 0 and rho_d = 1 (f = 1/pi): the linear residual is sqrt(w) / pi. */
    bf_objective_options o = objective_options(BF_RESIDUAL_LINEAR, 0);
    o.solid_angle = 1;
    bf_error err = {0};
    bf_objective *obj = NULL;
    if (bf_objective_new(m, s, &o, &obj, &err) != BF_OK)
        fail_msg("%s", err.msg);
    const bf_problem *p = bf_objective_problem(obj);
    double x[3] = {1, 1, 1}, z[3], r[3 * 10];
    bf_objective_to_internal(obj, x, z);
    assert_int_equal(p->eval(p->user, z, 0, 3 * n, r, NULL), 0);
    double w[10], sum = 0, msum = 0;
    for (size_t q = 0; q < n; q++) {
        w[q] = (r[3 * q] * M_PI) * (r[3 * q] * M_PI);
        assert_true(r[3 * q + 1] == r[3 * q] && r[3 * q + 2] == r[3 * q]);
        assert_true(w[q] > 0);
        sum += w[q];
        msum += cell_measure(cells[q][0], cells[q][1]);
    }
    ts_assert_rel(sum / (double)n, 1.0, 1e-13, "mean weight");
    for (size_t q = 0; q < n; q++)
        ts_assert_rel(w[q], cell_measure(cells[q][0], cells[q][1]) * (double)n / msum, 1e-6, "cell weight");
    /* Cells are narrow near theta_h = 0 and wide near 90: weights follow. */
    assert_true(w[8] > 50 * w[1]); /* (89, 0) against (1, 0) */
    assert_true(w[1] > 2 * w[0]);  /* (1, 0) against (0, 0) */
    bf_objective_free(obj);

    /* Samples that are not MERL cells (a copy, its cells taken away): an error. */
    bf_samples *plain = NULL;
    bf_samples_copy(s, NULL, &plain, &err);
    assert_non_null(plain);
    assert_memory_equal(plain->merl->cell, s->merl->cell, s->n * sizeof *s->merl->cell);
    free(plain->merl->cell);
    free(plain->merl);
    plain->merl = NULL;
    memset(&err, 0, sizeof err);
    bf_objective *bad;
    assert_int_equal(bf_objective_new(m, plain, &o, &bad, &err), BF_ERR_ARG);
    assert_null(bad);
    assert_int_equal(err.code, BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "MERL"));
    bf_samples_free(plain);
    bf_samples_free(s);
    bf_model_free(m);
}

/* ---- Energy constraint ------------------------------------------------------------------ */

static void test_constraint(void **state)
{
    (void)state;
    bf_model *m = ts_model("walter", 3);
    bf_samples *s = random_samples(5, 3, 2);
    bf_override ov;
    assert_int_equal(bf_override_parse_fix("rho_s[1]=0.7", &ov, NULL), BF_OK);
    bf_objective *obj = make_obj(m, s, BF_RESIDUAL_LINEAR, &ov, 1);
    const bf_problem *p = bf_objective_problem(obj);
    assert_non_null(p->constraint);
    double x[8] = {0.5, 0.2, 0.1, 0.3, 0.7, 0.1, 0.1, 0.5}, z[7], grad[7];
    bf_objective_to_internal(obj, x, z);
    /* sums 0.8, 0.9, 0.2: channel 1 rules, and only rho_d[1] is free there */
    ts_assert_rel(p->constraint(p->user, z, grad), -0.1, 1e-14, "constraint");
    for (int j = 0; j < 7; j++)
        assert_true(grad[j] == (j == 1 ? 1.0 : 0.0));
    x[3] = 0.9; /* channel 0: 1.4 */
    bf_objective_to_internal(obj, x, z);
    ts_assert_rel(p->constraint(p->user, z, grad), 0.4, 1e-14, "violated");
    for (int j = 0; j < 7; j++)
        assert_true(grad[j] == (j == 0 || j == 3 ? 1.0 : 0.0));
    bf_objective_free(obj);
    bf_samples_free(s);
    bf_model_free(m);
}

/* ---- Standard errors ----------------------------------------------------------------------- */

/* Lambert, C = 1: f = rho_d / pi everywhere, so J = 1/pi (linear) or c_i / pi (cosine), and
 * se(rho_d) = s / sqrt(sum J_i^2), s^2 = SSR / (n - 1). */
static void test_stderr_lambert(void **state)
{
    (void)state;
    const size_t n = 50;
    bf_model *m = ts_model("lambert", 1);
    bf_samples *s = random_samples(n, 1, 11);
    ts_rng r = {3};
    for (size_t i = 0; i < n; i++)
        s->value[i] = 0.1 + 0.02 * ts_uniform(&r);
    s->theta_i[7] = 100; /* below the horizon: does not count in n */
    const bf_geometry *g = NULL;
    bf_samples_geometry(s, &g, NULL);
    for (int form = 0; form < 2; form++) {
        bf_residual rf = form ? BF_RESIDUAL_COSINE : BF_RESIDUAL_LINEAR;
        bf_objective *obj = make_obj(m, s, rf, NULL, 0);
        double x = 0.35, se;
        assert_int_equal(bf_objective_stderr(obj, &x, &se, NULL), BF_OK);
        double ssr = 0, sjj = 0;
        size_t nv = 0;
        for (size_t i = 0; i < n; i++) {
            if (!bf_geometry_valid(g, i))
                continue;
            double c = form ? g->lz[i] : 1.0, res = (x / M_PI - s->value[i]) * c;
            ssr += res * res;
            sjj += (c / M_PI) * (c / M_PI);
            nv++;
        }
        assert_int_equal(nv, n - 1);
        ts_assert_rel(se, sqrt(ssr / (double)(nv - 1)) / sqrt(sjj), 1e-12, "se(rho_d)");
        bf_objective_free(obj);
    }
    bf_samples_free(s);
    bf_model_free(m);
}

/* Phong with n fixed is linear in rho_d and rho_s, with correlated columns: the
 * covariance is the inverse of a 2 x 2 J^T J per channel, computed here by hand. */
static void test_stderr_phong(void **state)
{
    (void)state;
    const size_t n = 60;
    const int C = 3;
    bf_model *m = ts_model("phong", C);
    bf_samples *s = random_samples(n, C, 12);
    ts_rng r = {4};
    for (size_t i = 0; i < n * (size_t)C; i++)
        s->value[i] = 0.05 + 0.5 * ts_uniform(&r);
    bf_override ov;
    assert_int_equal(bf_override_parse_fix("n=8", &ov, NULL), BF_OK);
    bf_objective *obj = make_obj(m, s, BF_RESIDUAL_LINEAR, &ov, 1);
    double x[7] = {0.3, 0.4, 0.5, 0.2, 0.1, 0.6, 8}, se[7];
    assert_int_equal(bf_objective_stderr(obj, x, se, NULL), BF_OK);
    assert_true(se[6] == 0.0);
    /* Columns: a_i = f(rho_d = 1, rho_s = 0), b_i = f(0, 1) (the model is linear). */
    const bf_geometry *g = NULL;
    bf_samples_geometry(s, &g, NULL);
    double xa[7] = {1, 1, 1, 0, 0, 0, 8}, xb[7] = {0, 0, 0, 1, 1, 1, 8};
    double *a = ts_eval(m, xa, g), *b = ts_eval(m, xb, g), *f = ts_eval(m, x, g);
    double ssr = 0;
    for (size_t q = 0; q < n * (size_t)C; q++)
        ssr += (f[q] - s->value[q]) * (f[q] - s->value[q]);
    double s2 = ssr / (double)(n * (size_t)C - 6);
    for (int c = 0; c < C; c++) {
        double aa = 0, ab = 0, bb = 0;
        for (size_t i = 0; i < n; i++) {
            size_t q = i * (size_t)C + (size_t)c;
            aa += a[q] * a[q];
            ab += a[q] * b[q];
            bb += b[q] * b[q];
        }
        double det = aa * bb - ab * ab;
        ts_assert_rel(se[c], sqrt(s2 * bb / det), 1e-9, "se(rho_d)");
        ts_assert_rel(se[3 + c], sqrt(s2 * aa / det), 1e-9, "se(rho_s)");
    }
    free(a);
    free(b);
    free(f);
    bf_objective_free(obj);
    bf_samples_free(s);
    bf_model_free(m);
}

/* Two identical lobes: rho_s_1 and rho_s_2 are not determined (NaN), rho_d is. A
 * parameter the residuals do not depend on (f0 of a lobe whose rho_s is 0) is NaN too. */
static void test_stderr_singular(void **state)
{
    (void)state;
    bf_model *m = ts_model("cook_torrance:lobes=2", 1); /* rho_d rho_s_1 m_1 f0_1 rho_s_2 m_2 f0_2 */
    bf_samples *s = random_samples(80, 1, 13);
    ts_rng r = {5};
    for (size_t i = 0; i < 80; i++)
        s->value[i] = 0.05 + 0.5 * ts_uniform(&r);
    bf_override ov[4];
    assert_int_equal(bf_override_parse_fix("m_1=0.2", &ov[0], NULL), BF_OK);
    assert_int_equal(bf_override_parse_fix("m_2=0.2", &ov[1], NULL), BF_OK);
    assert_int_equal(bf_override_parse_fix("f0_1=0.5", &ov[2], NULL), BF_OK);
    assert_int_equal(bf_override_parse_fix("f0_2=0.5", &ov[3], NULL), BF_OK);
    bf_objective *obj = make_obj(m, s, BF_RESIDUAL_LINEAR, ov, 4);
    double x[7] = {0.3, 0.2, 0.2, 0.5, 0.1, 0.2, 0.5}, se[7];
    assert_int_equal(bf_objective_stderr(obj, x, se, NULL), BF_OK);
    assert_true(isfinite(se[0]) && se[0] > 0);
    assert_true(isnan(se[1]) && isnan(se[4]));
    assert_true(se[2] == 0 && se[3] == 0 && se[5] == 0 && se[6] == 0);
    bf_objective_free(obj);

    /* f0_2 with rho_s_2 = 0: a zero column. */
    assert_int_equal(bf_override_parse_fix("m_2=0.05", &ov[1], NULL), BF_OK);
    obj = make_obj(m, s, BF_RESIDUAL_LINEAR, ov, 2);
    double x2[7] = {0.3, 0.2, 0.2, 0.5, 0.0, 0.05, 0.5};
    assert_int_equal(bf_objective_stderr(obj, x2, se, NULL), BF_OK);
    assert_true(isfinite(se[0]) && isfinite(se[1]) && isfinite(se[3]) && isfinite(se[4]));
    assert_true(isnan(se[6]));
    /* Out of bounds: an error, not numbers. */
    x2[0] = 2.0;
    assert_int_equal(bf_objective_stderr(obj, x2, se, NULL), BF_ERR_RANGE);
    bf_objective_free(obj);
    bf_samples_free(s);
    bf_model_free(m);
}

/* ---- The options carry their size (docs/api.md) ------------------------------------ */

/* A newer program's options: a field the library does not know at their end. */
typedef struct newer_options {
    bf_objective_options o;
    double later;
} newer_options;

static void test_options_size(void **state)
{
    (void)state;
    bf_objective_options o;
    memset(&o, 0xff, sizeof o); /* every field set, not left from a zeroed frame */
    bf_objective_options_init(&o);
    assert_int_equal(o.size, sizeof o);
    assert_int_equal(o.residual, BF_RESIDUAL_LINEAR);
    assert_int_equal(o.use_weights, 1);
    assert_int_equal(o.solid_angle, 0);
    assert_null(o.overrides);
    assert_int_equal(o.noverrides, 0);
    assert_int_equal(o.threads, 0);

    bf_model *m = ts_model("lambert", 1);
    bf_samples *s = random_samples(5, 1, 3);
    bf_objective *obj = NULL;
    bf_error err = {0};
    /* Not set up by its init (a zeroed or an older, smaller struct): refused. */
    const size_t bad[] = {0, sizeof o - 1};
    for (int k = 0; k < 2; k++) {
        o.size = bad[k];
        assert_int_equal(bf_objective_new(m, s, &o, &obj, &err), BF_ERR_ARG);
        assert_null(obj);
        char want[160];
        snprintf(want, sizeof want,
                 "bf_objective_options: size %zu is not that of a bf_objective_options (set it with its init function)",
                 bad[k]);
        assert_string_equal(err.msg, want);
    }
    /* A newer program's: the tail this library does not know zeroed, the struct taken. */
    newer_options nw;
    memset(&nw, 0xff, sizeof nw);
    bf_objective_options_init_size(&nw.o, sizeof nw);
    assert_int_equal(nw.o.size, sizeof nw);
    assert_int_equal(nw.o.use_weights, 1);
    assert_true(nw.later == 0.0);
    assert_int_equal(bf_objective_new(m, s, &nw.o, &obj, &err), BF_OK);
    bf_objective_free(obj);
    /* NULL keeps its meaning. */
    assert_int_equal(bf_objective_new(m, s, NULL, &obj, &err), BF_OK);
    bf_objective_free(obj);
    /* The problem it makes carries its size, as bf_solve wants. */
    bf_objective_options_init(&o);
    assert_int_equal(bf_objective_new(m, s, &o, &obj, &err), BF_OK);
    assert_int_equal(bf_objective_problem(obj)->size, sizeof(bf_problem));
    bf_objective_free(obj);
    bf_samples_free(s);
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_forms_values),        cmocka_unit_test(test_forms_extremes),
        cmocka_unit_test(test_weights_and_horizon), cmocka_unit_test(test_jacobian_fd),
        cmocka_unit_test(test_row_ranges),          cmocka_unit_test(test_normal_pass),
        cmocka_unit_test(test_final_pass),          cmocka_unit_test(test_parametrisation),
        cmocka_unit_test(test_open_bounds),         cmocka_unit_test(test_override_parse),
        cmocka_unit_test(test_override_validation), cmocka_unit_test(test_residual_names),
        cmocka_unit_test(test_solid_angle),         cmocka_unit_test(test_constraint),
        cmocka_unit_test(test_stderr_lambert),      cmocka_unit_test(test_stderr_phong),
        cmocka_unit_test(test_stderr_singular),     cmocka_unit_test(test_options_size),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
