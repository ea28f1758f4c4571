/* Nishino & Lombardi 2011, hemispherical exponential power distribution (hemi-EPD) lobe:
 * rho_d/pi + rho_s D G_ct F / (pi NL NV), D = 1 - exp(-kappa NH^gamma).
 * Option fresnel=schlick|dielectric|none (f0, ior, nothing).
 *
 * Not energy conserving by design: D is not normalised. It tends to 1 over the whole
 * hemisphere for large kappa and small gamma, where the albedo of the lobe is 1.5 rho_s
 * at normal incidence and about 4 rho_s at grazing (f0 = 1), so rho_s absorbs the
 * normalisation and its range is wide. Reciprocal.
 */
#include "family.h"
#include "terms.h"

#include <math.h>

/* D peaks at 1 - exp(-kappa) <= 1, so measured highlights need rho_s far above 1
 * (published fits of unnormalised lobes reach thousands). */
#define NISHINO_RHO_S_MAX 1e5

static const bf_option_info options[] = {{"fresnel", bf_fresnel_values, 0}, {NULL, NULL, 0}};

static bf_status configure(bf_model *m, bf_error *err)
{
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "rho_s", 1, 0.0, NISHINO_RHO_S_MAX, 0.5, BF_SCALE_LOG1P, 1, BF_ROLE_WEIGHT, err)) ||
        (rc = bf_model_add_param(m, "kappa", 0, 1e-3, 1e3, 1.0, BF_SCALE_LOG, 1, BF_ROLE_SHAPE, err)) ||
        (rc = bf_model_add_param(m, "gamma", 0, 1e-3, 1e4, 50.0, BF_SCALE_LOG, 1, BF_ROLE_EXPONENT, err)))
        return rc;
    return bf_model_add_fresnel_param(m, bf_model_opt(m, "fresnel"), 1, err);
}

/* Scalars in table order: kappa, gamma, then f0 or ior unless fresnel=none. */
/* A bf_lobe_fn (family.h: why eight arguments). */
static void lobe(const bf_model *m, int k, const double *s, const bf_geometry *g, size_t i0, size_t cnt, double *S,
                 double *dS)
{
    (void)k;
    const int kind = m->opt[0]; /* the only option: fresnel */
    const double kappa = s[0], gamma = s[1];
    const double fp = kind == BF_FRESNEL_NONE ? 0.0 : s[2];
    for (size_t j = 0; j < cnt; j++) {
        size_t i = i0 + j;
        double nl = g->lz[i], nv = g->vz[i], nh = g->hz[i], vh = g->vh[i], s2 = g->sin2h[i];
        double dk = 0.0, dg = 0.0, df = 0.0, v = 0.0;
        if (nl > 0.0 && nv > 0.0 && vh > 0.0 && nh > 0.0) {
            double lnh = bf_log_nh(nh, s2);
            double p = exp(gamma * lnh); /* NH^gamma, underflows to 0, never overflows */
            double e = exp(-kappa * p);
            double D = -expm1(-kappa * p);
            double dF;
            double F = bf_fresnel(kind, vh, fp, &dF);
            double w = bf_g_ct(nh, nl, nv, vh) / (M_PI * nl * nv);
            v = D * F * w;
            dk = p * e * F * w;    /* dD/dkappa = NH^gamma exp(-kappa NH^gamma) */
            dg = kappa * lnh * dk; /* dD/dgamma = kappa ln(NH) NH^gamma exp(..) */
            df = D * dF * w;
        }
        S[j] = v;
        if (dS) {
            dS[j] = dk;
            dS[BF_BLOCK + j] = dg;
            if (kind != BF_FRESNEL_NONE)
                dS[2 * BF_BLOCK + j] = df;
        }
    }
}

const bf_family bf_family_nishino = {
    .info = {.name = "nishino",
             .summary = "hemispherical exponential power distribution lobe, V-groove shadowing",
             .reference = "Nishino & Lombardi 2011",
             .options = options,
             .lobes = 0,
             .anisotropic = 0},
    .configure = configure,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe,
};
