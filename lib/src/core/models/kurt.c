/* Kurt, Szirmay-Kalos & Krivanek 2010: rho_d/pi + sum_k rho_s_k F_s(VH; f0_k) D_b(m_k) /
 * (4 VH (NL NV)^alpha_k). A Beckmann lobe whose 1/(NL NV) factor is softened by alpha;
 * no shadowing term. Accepts lobes=K.
 *
 * Not energy conserving by design: without a shadowing term the albedo of
 * F D_b / (4 VH (NL NV)^alpha) grows like NL^-alpha at grazing incidence (f0 = 1,
 * m = 0.3, theta_i = 89 deg: 2.1 at alpha = 0.5, 31 at alpha = 1), so rho_d + rho_s <= 1
 * does not bound it; only alpha = 0 stays below 1. Reciprocal.
 */
#include "family.h"
#include "terms.h"

#include <math.h>

/* Lobe k's default roughness: distinct per lobe so a multi-lobe fit does not start
 * symmetric (lobe 2 twice as rough as lobe 1), all inside [1e-3, 1]. */
static const double m_default[BF_MAX_LOBES] = {0.2, 0.4, 0.8, 0.1, 0.05, 0.6, 0.3, 0.025};

static bf_status configure(bf_model *m, bf_error *err)
{
    bf_status rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err);
    for (int k = 1; rc == BF_OK && k <= m->lobes; k++) {
        if ((rc = bf_model_add_param(m, "rho_s", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, k, BF_ROLE_WEIGHT, err)) ||
            (rc =
                 bf_model_add_param(m, "m", 0, 1e-3, 1.0, m_default[k - 1], BF_SCALE_LOG, k, BF_ROLE_ROUGHNESS, err)) ||
            (rc = bf_model_add_param(m, "f0", 0, 0.0, 1.0, 0.04, BF_SCALE_LINEAR, k, BF_ROLE_F0, err)) ||
            (rc = bf_model_add_param(m, "alpha", 0, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, k, BF_ROLE_SHAPE, err)))
            break;
    }
    return rc;
}

/* Scalars of a lobe, in table order: m, f0, alpha. */
/* A bf_lobe_fn (family.h: why eight arguments). */
static void lobe(const bf_model *m, int k, const double *s, const bf_geometry *g, size_t i0, size_t cnt, double *S,
                 double *dS)
{
    (void)m;
    (void)k;
    const double rough = s[0], f0 = s[1], alpha = s[2];
    for (size_t j = 0; j < cnt; j++) {
        size_t i = i0 + j;
        double nl = g->lz[i], nv = g->vz[i], vh = g->vh[i];
        /* Below the horizon, or H within 1e-70 of the horizon: there D_b's cos^4 would
         * underflow (0/0) while exp(-tan^2/m^2) is exactly 0 already. */
        if (!(nl > 0.0 && nv > 0.0 && vh > 0.0 && g->hz[i] > 1e-70)) {
            S[j] = 0.0;
            if (dS)
                dS[j] = dS[BF_BLOCK + j] = dS[2 * BF_BLOCK + j] = 0.0;
            continue;
        }
        double dF, dD;
        double F = bf_schlick(vh, f0, &dF);
        double D = bf_d_beckmann(g->hz[i], g->sin2h[i], rough, &dD);
        /* (NL NV)^-alpha from the logs of each cosine: no underflow of the product at
         * grazing, and the log is what d/dalpha needs. */
        double lg = log(nl) + log(nv);
        double w = exp(-alpha * lg) / (4.0 * vh);
        double v = F * D * w;
        S[j] = v;
        if (dS) {
            dS[j] = F * dD * w;
            dS[BF_BLOCK + j] = dF * D * w;
            dS[2 * BF_BLOCK + j] = -v * lg;
        }
    }
}

const bf_family bf_family_kurt = {
    .info = {.name = "kurt",
             .summary = "Beckmann lobes with Schlick Fresnel over 4 VH (NL NV)^alpha, no shadowing",
             .reference = "Kurt, Szirmay-Kalos, Krivanek 2010",
             .options = NULL,
             .lobes = 1,
             .anisotropic = 0},
    .configure = configure,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe,
};
