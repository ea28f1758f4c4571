/* The registry as JSON (bf_models_json, model.h): what brdfit models --json prints and
 * the Python package's brdfit.models() returns. */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>

#include "brdfit/model.h"

static const char *scale_name(bf_scale s)
{
    return s == BF_SCALE_LOG ? "log" : s == BF_SCALE_LOG1P ? "log1p" : "linear";
}

static cJSON *param_json(const bf_param_info *p)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "name", p->name);
    cJSON_AddStringToObject(o, "kind", p->color ? "colour" : "scalar");
    cJSON_AddNumberToObject(o, "lower", p->lo);
    cJSON_AddNumberToObject(o, "upper", p->hi);
    cJSON_AddBoolToObject(o, "lower_open", p->lo_open);
    cJSON_AddBoolToObject(o, "upper_open", p->hi_open);
    cJSON_AddNumberToObject(o, "default", p->def);
    cJSON_AddStringToObject(o, "scale", scale_name(p->scale));
    cJSON_AddStringToObject(o, "role", bf_param_role_name(p->role));
    return o;
}

/* The parameter names of `family:option=value`. */
static cJSON *variant_params(const char *family, const char *option, const char *value)
{
    char spec[160];
    snprintf(spec, sizeof spec, "%s:%s=%s", family, option, value);
    bf_model *m = NULL;
    bf_model_new(spec, 1, &m, NULL);
    cJSON *a = cJSON_CreateArray();
    for (int i = 0; m && i < bf_model_nparams(m); i++)
        cJSON_AddItemToArray(a, cJSON_CreateString(bf_model_param(m, i)->name));
    bf_model_free(m);
    return a;
}

/* A family's default model for 1 and for 3 channels; 0 (nothing made) when out of memory,
 * the only way a registered family's defaults can fail. */
static int family_models(const bf_family_info *fi, bf_model **m1, bf_model **m3)
{
    *m3 = NULL;
    if (bf_model_new(fi->name, 1, m1, NULL) == BF_OK && bf_model_new(fi->name, 3, m3, NULL) == BF_OK)
        return 1;
    bf_model_free(*m1);
    *m1 = NULL;
    return 0;
}

static cJSON *family_json(const bf_family_info *fi)
{
    bf_model *m1, *m3;
    if (!family_models(fi, &m1, &m3))
        return NULL;
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "name", fi->name);
    cJSON_AddStringToObject(o, "summary", fi->summary);
    cJSON_AddStringToObject(o, "reference", fi->reference);
    cJSON_AddBoolToObject(o, "anisotropic", fi->anisotropic);
    cJSON_AddBoolToObject(o, "lobes", fi->lobes);
    cJSON_AddBoolToObject(o, "reciprocal", bf_model_reciprocal(m1));
    cJSON_AddBoolToObject(o, "energy_conserving", bf_model_energy_conserving(m1));
    cJSON *params = cJSON_AddArrayToObject(o, "params");
    for (int i = 0; i < bf_model_nparams(m1); i++)
        cJSON_AddItemToArray(params, param_json(bf_model_param(m1, i)));
    cJSON *opts = cJSON_AddArrayToObject(o, "options");
    for (int k = 0; fi->options && fi->options[k].name; k++) {
        cJSON *opt = cJSON_CreateObject();
        cJSON_AddStringToObject(opt, "name", fi->options[k].name);
        cJSON_AddStringToObject(opt, "default", fi->options[k].values[0]);
        cJSON *vals = cJSON_AddArrayToObject(opt, "values");
        for (int v = 0; fi->options[k].values[v]; v++) {
            cJSON *val = cJSON_CreateObject();
            cJSON_AddStringToObject(val, "value", fi->options[k].values[v]);
            cJSON_AddItemToObject(val, "params",
                                  variant_params(fi->name, fi->options[k].name, fi->options[k].values[v]));
            cJSON_AddItemToArray(vals, val);
        }
        cJSON_AddItemToArray(opts, opt);
    }
    cJSON *nfree = cJSON_AddObjectToObject(o, "free_params");
    cJSON_AddNumberToObject(nfree, "1", bf_model_nvalues(m1));
    cJSON_AddNumberToObject(nfree, "3", bf_model_nvalues(m3));
    bf_model_free(m1);
    bf_model_free(m3);
    return o;
}

char *bf_models_json(void)
{
    cJSON *root = cJSON_CreateObject();
    cJSON *arr = cJSON_AddArrayToObject(root, "models");
    cJSON_AddStringToObject(root, "mono",
                            "every model accepts mono=specular|all|NAME[+NAME...]: the named colour "
                            "parameters take one value for all channels");
    int ok = arr != NULL;
    for (int f = 0; ok && f < bf_family_count(); f++) {
        cJSON *o = family_json(bf_family_get(f));
        ok = o != NULL;
        cJSON_AddItemToArray(arr, o);
    }
    char *s = ok ? cJSON_Print(root) : NULL;
    cJSON_Delete(root);
    return s;
}
