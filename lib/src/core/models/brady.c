/* Brady, Lawrence, Peers & Weimer 2014 (genBRDF), model A:
 * rho_d/pi + rho_s F_s(VH; f0) exp(-(tan(theta_h)/beta^2)^a) / (4 VH).
 *
 * Not energy conserving by design: the lobe is not normalised (it tends to 1/(4 VH) over
 * the whole hemisphere as beta grows; albedo 1.3 rho_s at theta_i = 89 deg for f0 = 1,
 * a = 1, beta = 10), so rho_s absorbs the normalisation and its range is wide.
 * Reciprocal.
 */
#include "family.h"
#include "terms.h"

#include <math.h>

/* The lobe peaks at F / (4 VH) <= 1/4 at normal incidence, so measured highlights need
 * rho_s far above 1. */
#define BRADY_RHO_S_MAX 1e5

static bf_status configure(bf_model *m, bf_error *err)
{
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "rho_s", 1, 0.0, BRADY_RHO_S_MAX, 0.5, BF_SCALE_LOG1P, 1, BF_ROLE_WEIGHT, err)) ||
        (rc = bf_model_add_param(m, "f0", 0, 0.0, 1.0, 0.04, BF_SCALE_LINEAR, 1, BF_ROLE_F0, err)) ||
        (rc = bf_model_add_param_open(m, "a", 0, 0.0, 1, 3.0, 0, 1.0, BF_SCALE_LOG1P, 1, BF_ROLE_SHAPE, err)))
        return rc;
    return bf_model_add_param_open(m, "beta", 0, 0.0, 1, 10.0, 0, 0.5, BF_SCALE_LOG1P, 1, BF_ROLE_SLOPE_SPREAD, err);
}

/* Scalars in table order: f0, a, beta. */
/* A bf_lobe_fn (family.h: why eight arguments). */
static void lobe(const bf_model *m, int k, const double *s, const bf_geometry *g, size_t i0, size_t cnt, double *S,
                 double *dS)
{
    (void)m;
    (void)k;
    const double f0 = s[0], a = s[1], beta = s[2];
    const double ib2 = 1.0 / (beta * beta);
    for (size_t j = 0; j < cnt; j++) {
        size_t i = i0 + j;
        double nl = g->lz[i], nv = g->vz[i], nh = g->hz[i], vh = g->vh[i], s2 = g->sin2h[i];
        double df = 0.0, da = 0.0, db = 0.0, v = 0.0;
        if (nl > 0.0 && nv > 0.0 && vh > 0.0 && nh > 0.0) {
            double t = sqrt(s2) / nh;
            double u = t > 0.0 ? t * ib2 : 0.0; /* tan(theta_h) / beta^2; no 0 * inf */
            double q = pow(u, a);               /* 0 at the peak (a > 0) */
            double E = exp(-q) / (4.0 * vh);
            double dF;
            double F = bf_schlick(vh, f0, &dF);
            v = F * E;
            df = dF * E;
            /* d/da = -v q ln u and d/dbeta = v q 2a / beta; both vanish where q = 0
             * (u^a ln u -> 0 at the peak, where ln u would be -inf) or v = 0. */
            if (q > 0.0 && v > 0.0) {
                da = -v * q * log(u);
                db = v * q * 2.0 * a / beta;
            }
        }
        S[j] = v;
        if (dS) {
            dS[j] = df;
            dS[BF_BLOCK + j] = da;
            dS[2 * BF_BLOCK + j] = db;
        }
    }
}

const bf_family bf_family_brady = {
    .info = {.name = "brady",
             .summary = "genBRDF model A: exp(-(tan(theta_h)/beta^2)^a) lobe with Schlick Fresnel",
             .reference = "Brady, Lawrence, Peers, Weimer 2014",
             .options = NULL,
             .lobes = 0,
             .anisotropic = 0},
    .configure = configure,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe,
};
