/* Analytic gradients of every model configuration against finite differences, at many
 * random direction pairs and parameter vectors, the bounds included. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "support.h"

enum { NDIRS = 48, TRIALS = 12 };

/* Finite-difference derivative of every value with respect to x[k]; central inside the
 * bounds, one-sided second order at a bound. h is the step. */
static void fd_column(const bf_model *m, const bf_geometry *g, double *x, int k, double lo, double hi, double h,
                      double *out)
{
    size_t n = g->n * (size_t)bf_model_channels(m);
    double x0 = x[k];
    double *a, *b;
    if (x0 - h >= lo && x0 + h <= hi) {
        x[k] = x0 + h;
        a = ts_eval(m, x, g);
        x[k] = x0 - h;
        b = ts_eval(m, x, g);
        for (size_t i = 0; i < n; i++)
            out[i] = (a[i] - b[i]) / (2.0 * h);
    } else {
        double s = x0 - h < lo ? 1.0 : -1.0; /* step into the interior */
        double *f0 = ts_eval(m, x, g);
        x[k] = x0 + s * h;
        a = ts_eval(m, x, g);
        x[k] = x0 + s * 2.0 * h;
        b = ts_eval(m, x, g);
        for (size_t i = 0; i < n; i++)
            out[i] = s * (-3.0 * f0[i] + 4.0 * a[i] - b[i]) / (2.0 * h);
        free(f0);
    }
    x[k] = x0;
    free(a);
    free(b);
}

/* The parameter entry that vector slot k belongs to. */
static const bf_param_info *slot_param(const bf_model *m, int k)
{
    for (int i = bf_model_nparams(m) - 1; i >= 0; i--)
        if (bf_model_param_offset(m, i) <= k)
            return bf_model_param(m, i);
    return NULL;
}

static void check_model(const char *spec, int C, int *checked, int *kinks)
{
    bf_error err;
    bf_model *m = NULL;
    if (bf_model_new(spec, C, &m, &err) != BF_OK)
        fail_msg("%s: %s", spec, err.msg);
    const int P = bf_model_nvalues(m);
    ts_rng rng = {0x9E3779B97F4A7C15ULL ^ (uint64_t)(strlen(spec) * 131 + (size_t)C)};
    double ti[NDIRS], pi_[NDIRS], to[NDIRS], po[NDIRS];
    ts_random_dirs(&rng, NDIRS, ti, pi_, to, po);
    bf_geometry *g = NULL;
    bf_geometry_from_angles(NDIRS, ti, pi_, to, po, &g, NULL);
    size_t nv = (size_t)NDIRS * (size_t)C;
    double *x = malloc((size_t)P * sizeof *x);
    double *val = malloc(nv * sizeof *val), *grad = malloc(nv * (size_t)P * sizeof *grad);
    double *fd = malloc(nv * sizeof *fd), *fd2 = malloc(nv * sizeof *fd2);

    for (int t = 0; t < TRIALS; t++) {
        ts_random_params(m, &rng, TS_PARAMS_ANY, x);
        assert_int_equal(bf_model_check(m, x, &err), BF_OK);
        bf_model_eval(m, x, g, val, grad);
        double fscale = 0.0;
        for (size_t i = 0; i < nv; i++) {
            if (!isfinite(val[i]))
                fail_msg("%s C=%d: value %zu is %g", spec, C, i, val[i]);
            fscale = fmax(fscale, fabs(val[i]));
        }
        for (int k = 0; k < P; k++) {
            const bf_param_info *p = slot_param(m, k);
            double lo = ts_param_lo(p), hi = ts_param_hi(p);
            double mag = p->scale == BF_SCALE_LINEAR ? fmax(fabs(x[k]), 1e-2 * (hi - lo)) : fmax(fabs(x[k]), 1e-3);
            double h = 1e-6 * mag;
            fd_column(m, g, x, k, lo, hi, h, fd);
            fd_column(m, g, x, k, lo, hi, h / 8.0, fd2);
            for (size_t i = 0; i < nv; i++) {
                double a = grad[i * (size_t)P + (size_t)k];
                if (!isfinite(a))
                    fail_msg("%s C=%d: d/d%s at value %zu is %g", spec, C, p->name, i, a);
                /* Noise floor: rounding of values of this size over a step h (plus a subnormal
                 * margin for all-zero values). */
                double floor_ = 1e-7 * (fabs(val[i]) + 1e-6 * fscale) / mag + 1e-280;
                double big = fmax(fabs(a), fabs(fd[i]));
                (*checked)++;
                if (fabs(a - fd[i]) <= 1e-4 * big + floor_)
                    continue;
                /* The smaller step has 64x less truncation error (one-sided differences at
                 * a bound where the function has a double root, e.g. dielectric at ior 1). */
                if (fabs(a - fd2[i]) <= 1e-4 * fmax(fabs(a), fabs(fd2[i])) + floor_)
                    continue;
                /* The two steps disagree: a kink (min, max, clamp) sits within h. */
                if (fabs(fd[i] - fd2[i]) > 1e-5 * fmax(fabs(fd[i]), fabs(fd2[i])) + floor_) {
                    (*kinks)++;
                    continue;
                }
                size_t s = i / (size_t)C;
                fail_msg("%s C=%d: d/d%s (slot %d = %.17g) at dirs (%.6g,%.6g,%.6g,%.6g) deg "
                         "channel %zu: analytic %.10g, finite difference %.10g (value %.10g)",
                         spec, C, p->name, k, x[k], ti[s] / DEG, pi_[s] / DEG, to[s] / DEG, po[s] / DEG, i % (size_t)C,
                         a, fd[i], val[i]);
            }
        }
    }
    free(x);
    free(val);
    free(grad);
    free(fd);
    free(fd2);
    bf_geometry_free(g);
    bf_model_free(m);
}

static void test_spec(void **state)
{
    const char *spec = *state;
    int checked = 0, kinks = 0;
    check_model(spec, 1, &checked, &kinks);
    check_model(spec, 3, &checked, &kinks);
    /* Kinks are measure-zero: only a few points may fall on one. */
    if (kinks > checked / 20)
        fail_msg("%s: %d of %d derivatives sat on a kink", spec, kinks, checked);
}

int main(void)
{
    char **specs;
    int n = ts_all_specs(&specs);
    struct CMUnitTest *tests = calloc((size_t)n, sizeof *tests);
    for (int i = 0; i < n; i++) {
        tests[i].name = specs[i];
        tests[i].test_func = test_spec;
        tests[i].initial_state = specs[i];
    }
    int rc = _cmocka_run_group_tests("gradients", tests, (size_t)n, NULL, NULL);
    free(tests);
    ts_free_specs(specs, n);
    return rc;
}
