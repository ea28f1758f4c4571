/* Export's check and conversion fit (brdfit/export.h): a source model that is not the
 * target's native model is fitted by it on a grid of directions; the targets and the
 * writers are lib/src/report/export. */
#include "brdfit/export.h"

#include "base/sized.h"
#include "fit_impl.h"

#include <string.h>

#include "brdfit/samples.h"

BF_SIZED_INIT_ZERO(bf_export_material)

static int anisotropic(const bf_model *m)
{
    return bf_model_family(m)->anisotropic;
}

bf_status bf_export_check(const bf_export_target *t, const bf_model *src, int convert_any, bf_error *err)
{
    if (!t || !src)
        return bf_fail(err, BF_ERR_ARG, "export: no target or no model");
    const int C = bf_model_channels(src);
    if (C != 1 && C != 3)
        return bf_fail(err, BF_ERR_ARG, "%d channels; a renderer's colour needs 1 (grey) or 3 (RGB)", C);
    if (strcmp(bf_model_name(src), t->model) != 0 && !convert_any) {
        const int aniso = anisotropic(src), multi = bf_model_lobes(src) > 1;
        if (aniso || multi)
            return bf_fail(err, BF_ERR_ARG, "%s is %s; %s holds one isotropic lobe (--convert fits it anyway)",
                           bf_model_spec(src), aniso ? "anisotropic" : "multi-lobe", t->model);
    }
    return BF_OK;
}

/* The grid the conversion fits on, with the source's values. Isotropic sources need only
 * phi_i = 0. */
static bf_status source_samples(const bf_model *src, const double *xs, bf_samples **out, bf_error *err)
{
    enum { NT = 18, NPO = 36 };
    const int npi = anisotropic(src) ? 6 : 1;
    size_t n = (size_t)NT * NT * NPO * (size_t)npi, i = 0;
    bf_samples *s = NULL;
    const bf_geometry *g = NULL;
    bf_status rc = bf_samples_new(n, bf_model_channels(src), &s, err);
    if (rc != BF_OK)
        return rc;
    for (int a = 0; a < npi; a++)
        for (int ti = 0; ti < NT; ti++)
            for (int to = 0; to < NT; to++)
                for (int po = 0; po < NPO; po++, i++) {
                    s->theta_i[i] = 2.5 + 5.0 * ti;
                    s->phi_i[i] = 30.0 * a;
                    s->theta_o[i] = 2.5 + 5.0 * to;
                    s->phi_o[i] = 10.0 * po;
                }
    if ((rc = bf_samples_geometry(s, &g, err)) != BF_OK) {
        bf_samples_free(s);
        return rc;
    }
    bf_model_eval(src, xs, g, s->value, NULL);
    *out = s;
    return BF_OK;
}

/* bf_export_prepare's work, into the library's own whole material e. */
static bf_status prepare(const bf_export_target *t, const bf_model *src, const double *xs, bf_export_material *e,
                         bf_fit_result *fit, bf_error *err)
{
    e->model = src;
    e->x = xs;
    e->source = bf_model_spec(src);
    if (!strcmp(bf_model_name(src), t->model))
        return BF_OK; /* the target's own model: exact */
    bf_samples *s = NULL;
    bf_status rc = source_samples(src, xs, &s, err);
    if (rc != BF_OK)
        return rc;
    bf_fit_options o;
    bf_fit_options_init(&o);
    o.starts = 4; /* the native models have several basins (metallic against specular) */
    bf_error ferr;
    rc = bf_fit_with(s, t->model, &o, fit, &ferr);
    e->directions = s->n;
    bf_samples_free(s);
    if (rc != BF_OK || !fit->ok) {
        bf_fit_result_clear(fit);
        return bf_fail(err, rc != BF_OK ? rc : BF_ERR_RANGE, "converting %s to %s: %s", bf_model_spec(src), t->model,
                       rc != BF_OK ? ferr.msg : "the fit found no usable solution");
    }
    e->model = fit->model;
    e->x = fit->x;
    e->converted = 1;
    e->metrics = fit->metrics;
    return BF_OK;
}

bf_status bf_export_prepare(const bf_export_target *t, const bf_model *src, const double *xs, bf_export_material *e,
                            bf_fit_result *fit, bf_error *err)
{
    if (!fit || bf_sized_check(fit, sizeof *fit, "bf_fit_result", err) != BF_OK ||
        bf_sized_check(e, sizeof *e, "bf_export_material", err) != BF_OK)
        return BF_ERR_ARG;
    bf_fit_result_clear(fit);
    bf_export_material mine;
    bf_export_material_init(&mine);
    bf_status rc = !t || !src || !xs ? bf_fail(err, BF_ERR_ARG, "export: no target, model or parameters")
                                     : prepare(t, src, xs, &mine, fit, err);
    bf_sized_copy(e, &mine, sizeof mine); /* as far as the caller's size reaches (docs/api.md) */
    return rc;
}
