/* Löw et al.'s smooth-surface model (Low, Kronander, Ynnerman & Unger 2012, eq. 12):
 *   rho_d/pi + rho_s S(|Dp|) F(cos theta_d),  S(f) = 1 / (1 + b f^2)^c,
 * Dp = L_xy + V_xy the projected distance between V and the mirror of L (eq. 10), and
 * cos theta_d = sqrt(1 - |L_xy - V_xy|^2 / 4) (eq. 14: L.H from the projected vectors,
 * exact at the mirror and retro directions). No shadowing (G = 1) and no 1/(NL NV): the
 * lobe lives on the projected hemisphere. Option fresnel=schlick|dielectric|none as abc;
 * the paper's fits use dielectric.
 *
 * Not energy conserving by design: S is not normalised (S = 1 everywhere for b = 0 or
 * c = 0), so rho_s is the paper's A and its range is wide, as abc's. Reciprocal: both
 * projected distances are symmetric in L and V.
 */
#include "family.h"
#include "terms.h"

#include <math.h>

/* S peaks at 1, so measured highlights need rho_s far above 1: Löw et al.'s MERL fits
 * have A up to about 2.3e3 (abc's bound, for the same reason). */
#define LOW_SMOOTH_RHO_S_MAX 1e5

static const bf_option_info options[] = {{"fresnel", bf_fresnel_values, 0}, {NULL, NULL, 0}};

/* b is the falloff of S in |Dp|^2, about 8 (1 - NH) near the normal, so the start's
 * ABC-style b (BF_ROLE_FALLOFF) is about 8 times too large: one step of the log scale. */
static bf_status configure(bf_model *m, bf_error *err)
{
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "rho_s", 1, 0.0, LOW_SMOOTH_RHO_S_MAX, 0.5, BF_SCALE_LOG1P, 1, BF_ROLE_WEIGHT,
                                 err)) ||
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
        double lx = g->lx[i], ly = g->ly[i], vx = g->vx[i], vy = g->vy[i];
        double db = 0.0, dc = 0.0, df = 0.0, v = 0.0;
        if (g->lz[i] > 0.0 && g->vz[i] > 0.0) {
            double px = lx + vx, py = ly + vy, qx = lx - vx, qy = ly - vy;
            double d2 = px * px + py * py; /* |Dp|^2 */
            double cd2 = 1.0 - 0.25 * (qx * qx + qy * qy);
            double cd = sqrt(cd2 > 0.0 ? cd2 : 0.0); /* cos theta_d */
            double bd = b * d2;
            double l = log1p(bd);
            double D = exp(-c * l); /* (1 + b d2)^-c: underflows to 0, never overflows */
            double dF;
            double F = bf_fresnel(kind, cd, fp, &dF);
            v = D * F;
            db = -c * d2 / (1.0 + bd) * v;
            dc = -l * v;
            df = D * dF;
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

const bf_family bf_family_low_smooth = {
    .info = {.name = "low_smooth",
             .summary = "Low's smooth-surface model 1/(1 + b |Dp|^2)^c on the projected hemisphere",
             .reference = "Low, Kronander, Ynnerman, Unger 2012",
             .options = options,
             .lobes = 0,
             .anisotropic = 0},
    .configure = configure,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe,
};
