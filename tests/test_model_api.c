/* The model API: spec parsing, canonical specs, parameter tables and counts, bounds. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/select.h"
#include "support.h"

static void expect_error(const char *spec, int C, const char *fragment)
{
    bf_error err = {0};
    bf_model *m = NULL;
    bf_model_new(spec, C, &m, &err);
    if (m)
        fail_msg("%s accepted", spec);
    assert_int_equal(err.code, BF_ERR_ARG);
    if (!strstr(err.msg, fragment))
        fail_msg("%s: message '%s' lacks '%s'", spec, err.msg, fragment);
}

static void test_bad_specs(void **state)
{
    (void)state;
    expect_error("nosuch", 1, "unknown model 'nosuch'");
    expect_error("", 1, "empty model name");
    expect_error("lambert", 0, "channel count");
    expect_error("lambert:lobes=2", 1, "does not accept lobes");
    expect_error("walter:fresnel=metal", 1, "no value 'metal' (one of schlick|dielectric|none|conductor)");
    expect_error("walter:colour=red", 1, "has no option 'colour'");
    expect_error("walter:fresnel", 1, "is not key=value");
    expect_error("walter:fresnel=none,fresnel=none", 1, "given twice");
    expect_error("lafortune:lobes=0", 1, "lobes must be an integer from 1 to 8");
    expect_error("lafortune:lobes=9", 1, "lobes must be an integer");
    expect_error("lafortune:lobes=2x", 1, "lobes must be an integer");
}

static void test_canonical_spec(void **state)
{
    (void)state;
    bf_model *m = ts_model("walter", 3);
    assert_string_equal(bf_model_spec(m), "walter:fresnel=schlick,lobes=1");
    assert_string_equal(bf_model_option(m, "fresnel"), "schlick");
    bf_model_free(m);
    m = ts_model("microfacet:F=dielectric,lobes=2,D=beckmann", 1);
    assert_string_equal(bf_model_option(m, "D"), "beckmann");
    assert_string_equal(bf_model_option(m, "F"), "dielectric");
    assert_string_equal(bf_model_option(m, "lobes"), "2");
    assert_int_equal(bf_model_lobes(m), 2);
    /* The canonical spec configures the same model. */
    bf_model *m2 = ts_model(bf_model_spec(m), 1);
    assert_string_equal(bf_model_spec(m2), bf_model_spec(m));
    bf_model_free(m2);
    bf_model_free(m);
    m = ts_model("lambert", 1);
    assert_string_equal(bf_model_spec(m), "lambert");
    assert_null(bf_model_option(m, "lobes"));
    bf_model_free(m);
}

/* Free parameters = color_count * C + scalar_count, for C = 1, 3 and 31. */
static void test_free_parameter_counts(void **state)
{
    (void)state;
    static const struct {
        const char *spec;
        int color, scalar;
    } cases[] = {
        {"lambert", 1, 0},
        {"walter", 2, 2},
        {"walter:fresnel=none", 2, 1},
        {"cook_torrance:fresnel=dielectric", 2, 2},
        {"ashikhmin_shirley", 2, 2},
        {"disney", 1, 10},
        {"lafortune:lobes=3", 4, 9},
        {"microfacet:D=blinn,G=smith_schlick,F=none,lobes=2", 3, 2},
        {"kurt:lobes=2", 3, 6},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        int counts[3] = {1, 3, 31};
        for (int k = 0; k < 3; k++) {
            bf_model *m = ts_model(cases[i].spec, counts[k]);
            int expect = cases[i].color * counts[k] + cases[i].scalar;
            if (bf_model_nvalues(m) != expect)
                fail_msg("%s C=%d: %d free parameters, expected %d", cases[i].spec, counts[k], bf_model_nvalues(m),
                         expect);
            bf_model_free(m);
        }
    }
}

static void test_param_table(void **state)
{
    (void)state;
    bf_model *m = ts_model("walter:fresnel=dielectric", 3);
    static const char *const names[] = {"rho_d", "rho_s", "alpha", "ior"};
    static const int offsets[] = {0, 3, 6, 7};
    assert_int_equal(bf_model_nparams(m), 4);
    for (int i = 0; i < 4; i++) {
        assert_string_equal(bf_model_param(m, i)->name, names[i]);
        assert_int_equal(bf_model_param_offset(m, i), offsets[i]);
        assert_int_equal(bf_model_find_param(m, names[i]), i);
    }
    assert_int_equal(bf_model_find_param(m, "f0"), -1);
    assert_true(bf_model_param(m, 2)->lo == 1e-4 && bf_model_param(m, 2)->hi == 1.0);
    assert_true(bf_model_param(m, 3)->lo == 1.0 && bf_model_param(m, 3)->hi == 100.0);
    assert_null(bf_model_param(m, 4));
    bf_model_free(m);

    /* Lobe parameters get a lobe suffix when there is more than one lobe. */
    m = ts_model("lafortune:lobes=2", 1);
    static const char *const lnames[] = {"rho_d", "rho_s_1", "cxy_1", "cz_1", "n_1", "rho_s_2", "cxy_2", "cz_2", "n_2"};
    assert_int_equal(bf_model_nparams(m), 9);
    for (int i = 0; i < 9; i++)
        assert_string_equal(bf_model_param(m, i)->name, lnames[i]);
    assert_int_equal(bf_model_param(m, 5)->lobe, 2);
    bf_model_free(m);
}

static void test_bounds_check(void **state)
{
    (void)state;
    bf_model *m = ts_model("brady", 1);
    double *x = malloc((size_t)bf_model_nvalues(m) * sizeof *x);
    bf_model_defaults(m, x);
    bf_error err;
    assert_int_equal(bf_model_check(m, x, &err), BF_OK);
    int a = bf_model_param_offset(m, bf_model_find_param(m, "a"));
    x[a] = 0.0; /* a is in (0, 3]: the open bound itself is refused */
    assert_int_equal(bf_model_check(m, x, &err), BF_ERR_RANGE);
    assert_non_null(strstr(err.msg, "parameter a = 0 is outside (0, 3]"));
    x[a] = 3.0;
    assert_int_equal(bf_model_check(m, x, &err), BF_OK);
    x[a] = NAN;
    assert_int_equal(bf_model_check(m, x, &err), BF_ERR_RANGE);
    assert_non_null(strstr(err.msg, "parameter a is nan"));
    free(x);
    bf_model_free(m);

    m = ts_model("lambert", 3);
    double rho[3] = {0.1, 0.2, -0.1};
    assert_int_equal(bf_model_check(m, rho, &err), BF_ERR_RANGE);
    assert_non_null(strstr(err.msg, "rho_d[2] = -0.10000000000000001 is outside [0, 1]"));
    bf_model_free(m);
}

/* Defaults lie inside the bounds for every configuration. */
static void test_defaults_in_bounds(void **state)
{
    (void)state;
    char **specs;
    int n = ts_all_specs(&specs);
    assert_true(n > 0);
    for (int i = 0; i < n; i++) {
        bf_model *m = ts_model(specs[i], 3);
        double *x = malloc((size_t)bf_model_nvalues(m) * sizeof *x);
        bf_model_defaults(m, x);
        bf_error err;
        if (bf_model_check(m, x, &err) != BF_OK)
            fail_msg("%s: default %s", specs[i], err.msg);
        free(x);
        bf_model_free(m);
    }
    ts_free_specs(specs, n);
}

/* The registry is models/families.def, in its order, and every family is registered
 * under the name its symbol has (bf_family_NAME: "NAME"), which the command line, the
 * docs (cli_docs_models.sh) and every registry-walking test then use. */
static void test_registry_names(void **state)
{
    (void)state;
    static const char *const names[] = {
#define BF_FAMILY(name) #name,
#include "models/families.def"
#undef BF_FAMILY
    };
    enum { N = sizeof names / sizeof names[0] };
    assert_int_equal(bf_family_count(), N);
    for (int i = 0; i < N; i++)
        assert_string_equal(bf_family_get(i)->name, names[i]);
}

/* Evaluating a range writes only that range, and matches the whole-set evaluation. */
/* The fields renamed to one spelling keep their old names, deprecated, as the same
 * storage: programs written against them still build and read the same values. */
static void test_old_spellings(void **state)
{
    (void)state;
    bf_model *m = NULL;
    assert_int_equal(bf_model_new("walter", 3, &m, NULL), BF_OK);
    bf_select_candidate c;
    memset(&c, 0, sizeof c);
    c.colored_specular = 1;
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
#endif
    for (int i = 0; i < bf_model_nparams(m); i++)
        assert_int_equal(bf_model_param(m, i)->colour, bf_model_param(m, i)->color);
    assert_int_equal(bf_model_param(m, bf_model_find_param(m, "rho_d"))->colour, 1);
    assert_int_equal(c.coloured_specular, 1);
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif
    bf_model_free(m);
}

static void test_eval_range(void **state)
{
    (void)state;
    bf_model *m = ts_model("walter", 3);
    enum { N = 300 };
    double ti[N], pi_[N], to[N], po[N];
    ts_rng r = {42};
    ts_random_dirs(&r, N, ti, pi_, to, po);
    bf_geometry *g = NULL;
    bf_geometry_from_angles(N, ti, pi_, to, po, &g, NULL);
    int P = bf_model_nvalues(m);
    double *x = malloc((size_t)P * sizeof *x);
    bf_model_defaults(m, x);
    double *all = malloc(N * 3 * sizeof *all), *part = malloc(N * 3 * sizeof *part);
    double *ga = malloc(N * 3 * (size_t)P * sizeof *ga), *gp = malloc(N * 3 * (size_t)P * sizeof *gp);
    bf_model_eval(m, x, g, all, ga);
    for (size_t i = 0; i < N * 3; i++)
        part[i] = -1.0;
    bf_model_eval_range(m, x, g, 0, 130, part, gp);
    bf_model_eval_range(m, x, g, 130, N, part + 130 * 3, gp + 130 * 3 * (size_t)P); /* relative to i0 */
    assert_memory_equal(all, part, N * 3 * sizeof *all);
    assert_memory_equal(ga, gp, N * 3 * (size_t)P * sizeof *ga);
    free(all);
    free(part);
    free(ga);
    free(gp);
    free(x);
    bf_geometry_free(g);
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_specs),
        cmocka_unit_test(test_canonical_spec),
        cmocka_unit_test(test_free_parameter_counts),
        cmocka_unit_test(test_param_table),
        cmocka_unit_test(test_bounds_check),
        cmocka_unit_test(test_defaults_in_bounds),
        cmocka_unit_test(test_registry_names),
        cmocka_unit_test(test_eval_range),
        cmocka_unit_test(test_old_spellings),
    };
    return cmocka_run_group_tests_name("model_api", tests, NULL, NULL);
}
