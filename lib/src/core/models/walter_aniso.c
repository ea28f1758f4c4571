/* Anisotropic GGX (Heitz 2014) with height-uncorrelated Smith shadowing and Schlick
 * Fresnel:
 *   f = rho_d/pi + rho_s D G1(L) G1(V) F_s(VH; f0) / (4 NL NV)
 *   D = 1 / (pi ax ay (hz^2 + hx^2/ax^2 + hy^2/ay^2)^2)
 *   G1(w) = 2 / (1 + sqrt(1 + (wx^2 ax^2 + wy^2 ay^2) / wz^2))   (projected roughness)
 * D is docs/models.md's 1/(pi ax ay NH^4 (1 + tan^2(theta_h)(cos^2 phi_h/ax^2 + ...))^2)
 * multiplied out, which needs neither tan(theta_h) nor 1 - NH^2. Energy conserving: D is
 * normalised and G1 is its exact Smith masking. */
#include "family.h"
#include "terms.h"

#include <math.h>

/* Smith G1 for a direction w with tangent-plane components (wx, wy) and wz > 0, and its
 * derivatives with respect to ax and ay. */
static inline double g1_aniso(double wx, double wy, double wz, double ax, double ay, double *dax, double *day)
{
    double iz2 = 1.0 / (wz * wz);
    double qx = wx * wx * ax * ax * iz2, qy = wy * wy * ay * ay * iz2;
    double r = sqrt(1.0 + qx + qy);
    double G = 2.0 / (1.0 + r);
    /* dG/dq = -G^2 / (4 r), dqx/dax = 2 qx / ax. */
    double k = -0.5 * G * G / r;
    *dax = k * qx / ax;
    *day = k * qy / ay;
    return G;
}

/* Scalars: s[0] = alpha_x, s[1] = alpha_y, s[2] = f0. */
/* A bf_lobe_fn (family.h: why eight arguments). */
static void lobe(const bf_model *m, int k, const double *s, const bf_geometry *g, size_t i0, size_t cnt, double *S,
                 double *dS)
{
    (void)m;
    (void)k;
    const double ax = s[0], ay = s[1], f0 = s[2];
    const double iax2 = 1.0 / (ax * ax), iay2 = 1.0 / (ay * ay);
    const double dnorm = 1.0 / (M_PI * ax * ay);
    for (size_t j = 0; j < cnt; j++) {
        size_t i = i0 + j;
        double lz = g->lz[i], vz = g->vz[i];
        double v = 0.0, dx = 0.0, dy = 0.0, df = 0.0;
        if (lz > 0.0 && vz > 0.0) {
            double hx2 = g->hx[i] * g->hx[i], hy2 = g->hy[i] * g->hy[i], hz = g->hz[i];
            double t = hz * hz + hx2 * iax2 + hy2 * iay2;
            double D = dnorm / (t * t);
            /* dD/dax = D (-1/ax + 4 hx^2 / (ax^3 t)) */
            double dDx = D * (4.0 * hx2 * iax2 / t - 1.0) / ax;
            double dDy = D * (4.0 * hy2 * iay2 / t - 1.0) / ay;
            double glx, gly, gvx, gvy;
            double gl = g1_aniso(g->lx[i], g->ly[i], lz, ax, ay, &glx, &gly);
            double gv = g1_aniso(g->vx[i], g->vy[i], vz, ax, ay, &gvx, &gvy);
            double G = gl * gv;
            double dF;
            double F = bf_schlick(g->vh[i], f0, &dF);
            double inv = 0.25 / (lz * vz);
            v = D * G * F * inv;
            dx = (dDx * G + D * (glx * gv + gl * gvx)) * F * inv;
            dy = (dDy * G + D * (gly * gv + gl * gvy)) * F * inv;
            df = D * G * dF * inv;
        }
        S[j] = v;
        if (dS) {
            dS[j] = dx;
            dS[BF_BLOCK + j] = dy;
            dS[2 * BF_BLOCK + j] = df;
        }
    }
}

static bf_status configure(bf_model *m, bf_error *err)
{
    m->energy_conserving = 1;
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "rho_s", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 1, BF_ROLE_WEIGHT, err)) ||
        (rc = bf_model_add_param(m, "alpha_x", 0, 1e-4, 1.0, 0.2, BF_SCALE_LOG, 1, BF_ROLE_ROUGHNESS, err)) ||
        (rc = bf_model_add_param(m, "alpha_y", 0, 1e-4, 1.0, 0.2, BF_SCALE_LOG, 1, BF_ROLE_ROUGHNESS, err)) ||
        (rc = bf_model_add_param(m, "f0", 0, 0.0, 1.0, 0.04, BF_SCALE_LINEAR, 1, BF_ROLE_F0, err)))
        return rc;
    return BF_OK;
}

const bf_family bf_family_walter_aniso = {
    .info = {.name = "walter_aniso",
             .summary = "anisotropic GGX with Smith shadowing and Schlick Fresnel",
             .reference = "Heitz 2014; Walter et al. 2007",
             .options = NULL,
             .lobes = 0,
             .anisotropic = 1},
    .configure = configure,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe,
};
