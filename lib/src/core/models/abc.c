/* ABC model (Low, Kronander, Ynnerman & Unger 2012), the microfacet form:
 * rho_d/pi + rho_s D G_ct F / (pi NL NV), D = 1 / (1 + b (1 - NH))^c.
 * Option fresnel=schlick|dielectric|none (f0, ior, nothing).
 *
 * Not energy conserving by design: D is not normalised. D = 1 everywhere for b = 0 or
 * c = 0, where the albedo of the lobe is 1.5 rho_s at normal incidence and about 4 rho_s
 * at grazing (f0 = 1); rho_s carries the normalisation (the paper's A), so its range is
 * wide. Reciprocal.
 */
#include "family.h"
#include "terms.h"

#include <math.h>

/* D peaks at 1, so measured highlights need rho_s far above 1: Low et al.'s MERL fits
 * have A up to about 6e3. */
#define ABC_RHO_S_MAX 1e5

static const bf_option_info options[] = {{"fresnel", bf_fresnel_values, 0}, {NULL, NULL, 0}};

static bf_status configure(bf_model *m, bf_error *err)
{
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "rho_s", 1, 0.0, ABC_RHO_S_MAX, 0.5, BF_SCALE_LOG1P, 1, BF_ROLE_WEIGHT, err)) ||
        (rc = bf_model_add_param(m, "b", 0, 0.0, 1e7, 100.0, BF_SCALE_LOG1P, 1, BF_ROLE_FALLOFF, err)) ||
        (rc = bf_model_add_param(m, "c", 0, 0.0, 10.0, 1.0, BF_SCALE_LOG1P, 1, BF_ROLE_SHAPE, err)))
        return rc;
    return bf_model_add_fresnel_param(m, bf_model_opt(m, "fresnel"), 1, err);
}

/* Scalars in table order: b, c, then f0 or ior unless fresnel=none. */
/* A bf_lobe_fn (family.h: why eight arguments). */
static void lobe(const bf_model *m, int k, const double *s, const bf_geometry *g, size_t i0, size_t cnt, double *S,
                 double *dS)
{
    (void)k;
    const int kind = m->opt[0]; /* the only option: fresnel */
    const double b = s[0], c = s[1];
    const double fp = kind == BF_FRESNEL_NONE ? 0.0 : s[2];
    for (size_t j = 0; j < cnt; j++) {
        size_t i = i0 + j;
        double nl = g->lz[i], nv = g->vz[i], nh = g->hz[i], vh = g->vh[i];
        double db = 0.0, dc = 0.0, df = 0.0, v = 0.0;
        if (nl > 0.0 && nv > 0.0 && vh > 0.0) {
            double x = g->sin2h[i] / (1.0 + nh); /* 1 - NH without cancellation */
            double bx = b * x;
            double l = log1p(bx);
            double D = exp(-c * l); /* (1 + b x)^-c: underflows to 0, never overflows */
            double dF;
            double F = bf_fresnel(kind, vh, fp, &dF);
            double w = bf_g_ct(nh, nl, nv, vh) / (M_PI * nl * nv);
            double Fw = F * w;
            v = D * Fw;
            db = -c * x / (1.0 + bx) * D * Fw;
            dc = -l * v;
            df = D * dF * w;
        }
        S[j] = v;
        if (dS) {
            dS[j] = db;
            dS[BF_BLOCK + j] = dc;
            if (kind != BF_FRESNEL_NONE)
                dS[2 * BF_BLOCK + j] = df;
        }
    }
}

const bf_family bf_family_abc = {
    .info = {.name = "abc",
             .summary = "ABC distribution 1/(1 + b(1 - NH))^c with V-groove shadowing",
             .reference = "Low, Kronander, Ynnerman, Unger 2012",
             .options = options,
             .lobes = 0,
             .anisotropic = 0},
    .configure = configure,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe,
};
