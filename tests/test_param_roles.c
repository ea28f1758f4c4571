/* Parameter roles (model.h): every family declares one for every parameter, under every
 * option value and with several lobes; the roles the start and mono=specular rely on
 * are where they must be. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdio.h>
#include <string.h>

#include "brdfit/model.h"

/* Checks one configuration; returns the number of parameters seen. */
static int check_spec(const char *spec)
{
    bf_error err;
    bf_model *m = NULL;
    if (bf_model_new(spec, 3, &m, &err) != BF_OK)
        fail_msg("%s: %s", spec, err.msg);
    int diffuse = 0, weights[BF_MAX_LOBES + 1] = {0};
    for (int i = 0; i < bf_model_nparams(m); i++) {
        const bf_param_info *p = bf_model_param(m, i);
        if (p->role == BF_ROLE_NONE)
            fail_msg("%s: parameter %s has no role", spec, p->name);
        assert_string_not_equal(bf_param_role_name(p->role), "none");
        diffuse += p->role == BF_ROLE_DIFFUSE;
        if (p->role == BF_ROLE_WEIGHT && p->lobe >= 1)
            weights[p->lobe]++;
        /* A diffuse colour is a colour outside the lobes; widths are scalars. */
        if (p->role == BF_ROLE_DIFFUSE && (!p->color || p->lobe != 0))
            fail_msg("%s: %s is diffuse but not a colour outside the lobes", spec, p->name);
        if ((p->role == BF_ROLE_ROUGHNESS || p->role == BF_ROLE_EXPONENT) && p->color)
            fail_msg("%s: width %s is a colour", spec, p->name);
    }
    if (diffuse != 1)
        fail_msg("%s: %d diffuse parameters, expected 1", spec, diffuse);
    for (int k = 1; k <= bf_model_lobes(m); k++)
        if (strstr(spec, "lobes=") && weights[k] == 0)
            fail_msg("%s: lobe %d has no weight", spec, k);
    int n = bf_model_nparams(m);
    bf_model_free(m);
    return n;
}

static void test_every_parameter_has_a_role(void **state)
{
    (void)state;
    int specs = 0;
    for (int f = 0; f < bf_family_count(); f++) {
        const bf_family_info *fi = bf_family_get(f);
        char spec[256];
        check_spec(fi->name);
        specs++;
        for (int k = 0; fi->options && fi->options[k].name; k++)
            for (int v = 0; fi->options[k].values[v]; v++) {
                snprintf(spec, sizeof spec, "%s:%s=%s", fi->name, fi->options[k].name, fi->options[k].values[v]);
                check_spec(spec);
                specs++;
            }
        if (fi->lobes) {
            snprintf(spec, sizeof spec, "%s:lobes=3", fi->name);
            check_spec(spec);
            specs++;
        }
    }
    assert_true(specs > 40);
}

static void test_roles_of_known_parameters(void **state)
{
    (void)state;
    static const struct {
        const char *spec, *param;
        bf_param_role role;
    } cases[] = {
        {"walter", "rho_d", BF_ROLE_DIFFUSE},
        {"walter", "rho_s", BF_ROLE_WEIGHT},
        {"walter", "alpha", BF_ROLE_ROUGHNESS},
        {"walter", "f0", BF_ROLE_F0},
        {"walter:fresnel=dielectric", "ior", BF_ROLE_IOR},
        {"phong", "n", BF_ROLE_EXPONENT},
        {"kurt", "alpha", BF_ROLE_SHAPE}, /* an exponent on NL NV, not a width */
        {"abc", "b", BF_ROLE_FALLOFF},
        {"brady", "beta", BF_ROLE_SLOPE_SPREAD},
        {"disney", "base_color", BF_ROLE_DIFFUSE},
        {"disney", "roughness", BF_ROLE_PERCEPTUAL_ROUGHNESS},
        {"oren_nayar", "sigma", BF_ROLE_DIFFUSE_SHAPE},
        {"microfacet:lobes=2", "rho_s_2", BF_ROLE_WEIGHT},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        bf_model *m = NULL;
        bf_model_new(cases[i].spec, 1, &m, NULL);
        assert_non_null(m);
        int k = bf_model_find_param(m, cases[i].param);
        assert_true(k >= 0);
        if (bf_model_param(m, k)->role != cases[i].role)
            fail_msg("%s %s: role %s, expected %s", cases[i].spec, cases[i].param,
                     bf_param_role_name(bf_model_param(m, k)->role), bf_param_role_name(cases[i].role));
        bf_model_free(m);
    }
}

/* mono=specular ties every colour parameter but the diffuse one. */
static void test_mono_specular_by_role(void **state)
{
    (void)state;
    bf_model *m = NULL;
    bf_model_new("disney:mono=specular", 3, &m, NULL);
    assert_null(m); /* Disney's only colour parameter is its base colour: nothing to tie */
    bf_model_new("microfacet:lobes=2,mono=specular", 3, &m, NULL);
    assert_non_null(m);
    for (int i = 0; i < bf_model_nparams(m); i++) {
        const bf_param_info *p = bf_model_param(m, i);
        if (p->role == BF_ROLE_DIFFUSE)
            assert_true(p->color && !p->mono);
        if (p->role == BF_ROLE_WEIGHT)
            assert_true(!p->color && p->mono);
    }
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_parameter_has_a_role),
        cmocka_unit_test(test_roles_of_known_parameters),
        cmocka_unit_test(test_mono_specular_by_role),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
