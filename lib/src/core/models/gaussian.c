/* Gaussian highlight (Phong family):
 *   f = rho_d/pi + rho_s exp(-(theta_h/m)^2) / (pi m^2),  theta_h = angle(N, H).
 * The lobe is the shared Gaussian NDF applied directly as a BRDF lobe, through the
 * diffuse + lobe driver. Reciprocal (theta_h is symmetric in L and V).
 *
 * Not energy conserving: exp(-(theta_h/m)^2)/(pi m^2) integrates to ~1 over the
 * half-vector hemisphere (weighted by NH), but without the microfacet Jacobian
 * 1/(4 VH) a narrow lobe's albedo at normal incidence is ~4 rho_s. */
#include "family.h"
#include "terms.h"

#include <math.h>

/* A bf_lobe_fn (family.h: why eight arguments). */
static void lobe_gaussian(const bf_model *m, int lobe, const double *s, const bf_geometry *g, size_t i0, size_t cnt,
                          double *S, double *dS)
{
    (void)m;
    (void)lobe;
    const double mm = s[0];
    for (size_t j = 0; j < cnt; j++) {
        size_t i = i0 + j;
        double dm;
        /* theta_h from atan2(sqrt(sin2h), NH): accurate at the peak and at grazing. */
        double v = bf_d_gaussian(g->hz[i], g->sin2h[i], mm, &dm);
        /* Flush values below ~1e-289 to 0 (as the other Phong-family lobes do): they carry
         * no information and would leave subnormal gradients. */
        if (v < 1e-289)
            v = dm = 0.0;
        S[j] = v;
        if (dS)
            dS[j] = dm;
    }
}

static bf_status configure(bf_model *m, bf_error *err)
{
    m->energy_conserving = 0; /* albedo ~4 rho_s at normal incidence for narrow lobes */
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "rho_s", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 1, BF_ROLE_WEIGHT, err)) ||
        (rc = bf_model_add_param(m, "m", 0, 1e-3, 1.0, 0.2, BF_SCALE_LOG, 1, BF_ROLE_ROUGHNESS, err)))
        return rc;
    return BF_OK;
}

const bf_family bf_family_gaussian = {
    .info = {.name = "gaussian",
             .summary = "Gaussian highlight in the half-vector angle",
             .reference = "Gaussian highlight, Phong-family",
             .options = NULL,
             .lobes = 0,
             .anisotropic = 0},
    .configure = configure,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe_gaussian,
};
