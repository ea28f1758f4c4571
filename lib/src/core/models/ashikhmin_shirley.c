/* Ashikhmin & Shirley 2000 anisotropic Phong BRDF:
 *   specular  sqrt((nu+1)(nv+1))/(8 pi) NH^e / (VH max(NL, NV)) F_s(VH; rho_s),
 *             e = (nu (H.X)^2 + nv (H.Y)^2) / (1 - NH^2)
 *   diffuse   28 rho_d/(23 pi) (1 - rho_s)(1 - (1 - NL/2)^5)(1 - (1 - NV/2)^5)
 * rho_s is both the Fresnel reflectance at normal incidence and the diffuse attenuation,
 * so the model does not fit the diffuse + lobes driver: it has its own evaluator.
 * The isotropic variant is nu = nv = n, where e = n exactly. */
#include "family.h"
#include "terms.h"

#include <math.h>
#include <string.h>

/* Parameter table order (both variants): rho_d, rho_s, then nu, nv (or n). */
enum { P_RHO_D, P_RHO_S, P_NU, P_NV };

/* The family's eval (family.h's arguments) for both variants, iso saying which. */
static void eval_common(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1, double *values,
                        double *grad, int iso)
{
    const int C = m->channels, P = m->nfree;
    const double *rho_d = x + m->offset[P_RHO_D];
    const double *rho_s = x + m->offset[P_RHO_S];
    const int o_d = m->offset[P_RHO_D], o_s = m->offset[P_RHO_S];
    const int o_nu = m->offset[P_NU], o_nv = iso ? -1 : m->offset[P_NV];
    const double nu = x[o_nu], nv = iso ? nu : x[o_nv];
    const double knorm = (iso ? nu + 1.0 : sqrt((nu + 1.0) * (nv + 1.0))) / (8.0 * M_PI);
    /* d log(knorm) / d nu (and nv); for iso knorm = (n+1)/(8 pi). */
    const double dlk_nu = iso ? 1.0 / (nu + 1.0) : 0.5 / (nu + 1.0);
    const double dlk_nv = 0.5 / (nv + 1.0);
    const double kd = 28.0 / (23.0 * M_PI);

    for (size_t i = i0; i < i1; i++) {
        double *row0 = grad ? grad + (i - i0) * (size_t)C * (size_t)P : NULL;
        if (row0)
            memset(row0, 0, (size_t)C * (size_t)P * sizeof *row0);
        double nl = g->lz[i], nv_ = g->vz[i];
        if (!(nl > 0.0 && nv_ > 0.0)) {
            for (int c = 0; c < C; c++)
                values[(i - i0) * (size_t)C + (size_t)c] = 0.0;
            continue;
        }
        double s2 = g->sin2h[i], hz = g->hz[i], vh = g->vh[i];
        double lnh = bf_log_nh(hz, s2);
        /* Weights of nu and nv in e: cos^2 and sin^2 of phi_h. At H = N (s2 = 0) NH^e = 1
         * for any e; lnh = 0 there, so any finite weights do, and the exponent's
         * derivatives vanish. */
        double wx = 0.5, wy = 0.5;
        if (s2 > 0.0) {
            wx = g->hx[i] * g->hx[i] / s2;
            wy = g->hy[i] * g->hy[i] / s2;
        }
        double e = iso ? nu : nu * wx + nv * wy;
        double ph = exp(e * lnh); /* underflows cleanly to 0 for huge e */
        double den = vh * (nl > nv_ ? nl : nv_);
        double spec0 = ph > 0.0 ? knorm * ph / den : 0.0; /* specular without Fresnel */
        /* d log(spec0)/d nu, d nv: normalisation plus exponent (0 where ph underflowed,
         * where lnh may be -Inf). */
        double dl_nu = 0.0, dl_nv = 0.0;
        if (ph > 0.0) {
            dl_nu = dlk_nu + (iso ? lnh : lnh * wx);
            dl_nv = dlk_nv + lnh * wy;
        }
        double m5 = 1.0 - vh;
        m5 = m5 < 0.0 ? 0.0 : m5;
        m5 = m5 * m5 * m5 * m5 * m5; /* (1 - VH)^5 */
        double al = 1.0 - 0.5 * nl, av = 1.0 - 0.5 * nv_;
        double dl = 1.0 - al * al * al * al * al, dv = 1.0 - av * av * av * av * av;
        double diff0 = kd * dl * dv; /* diffuse per unit rho_d (1 - rho_s) */

        for (int c = 0; c < C; c++) {
            double rs = rho_s[c], rd = rho_d[c];
            double F = rs + (1.0 - rs) * m5;
            double spec = spec0 * F;
            values[(i - i0) * (size_t)C + (size_t)c] = spec + rd * (1.0 - rs) * diff0;
            if (row0) {
                double *row = row0 + (size_t)c * (size_t)P;
                row[o_d + c] = (1.0 - rs) * diff0;
                row[o_s + c] = spec0 * (1.0 - m5) - rd * diff0;
                row[o_nu] = spec * dl_nu;
                if (!iso)
                    row[o_nv] = spec * dl_nv;
            }
        }
    }
}

static void eval_aniso(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1, double *values,
                       double *grad)
{
    eval_common(m, x, g, i0, i1, values, grad, 0);
}

static void eval_iso(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1, double *values,
                     double *grad)
{
    eval_common(m, x, g, i0, i1, values, grad, 1);
}

/* Exponents: LOG1P scale, as for the other Phong-like exponents (the lower bound 1
 * keeps them away from 0 anyway). */
static bf_status configure_aniso(bf_model *m, bf_error *err)
{
    m->energy_conserving = 1;
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "rho_s", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_WEIGHT, err)) ||
        (rc = bf_model_add_param(m, "nu", 0, 1.0, 1e6, 50.0, BF_SCALE_LOG, 0, BF_ROLE_EXPONENT, err)) ||
        (rc = bf_model_add_param(m, "nv", 0, 1.0, 1e6, 50.0, BF_SCALE_LOG, 0, BF_ROLE_EXPONENT, err)))
        return rc;
    return BF_OK;
}

static bf_status configure_iso(bf_model *m, bf_error *err)
{
    m->energy_conserving = 1;
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "rho_s", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_WEIGHT, err)) ||
        (rc = bf_model_add_param(m, "n", 0, 1.0, 1e6, 50.0, BF_SCALE_LOG, 0, BF_ROLE_EXPONENT, err)))
        return rc;
    return BF_OK;
}

const bf_family bf_family_ashikhmin_shirley = {
    .info = {.name = "ashikhmin_shirley",
             .summary = "Ashikhmin-Shirley anisotropic Phong with Fresnel-coupled diffuse",
             .reference = "Ashikhmin & Shirley 2000",
             .options = NULL,
             .lobes = 0,
             .anisotropic = 1},
    .configure = configure_aniso,
    .eval = eval_aniso,
};

const bf_family bf_family_ashikhmin_shirley_iso = {
    .info = {.name = "ashikhmin_shirley_iso",
             .summary = "Ashikhmin-Shirley isotropic Phong with Fresnel-coupled diffuse",
             .reference = "Ashikhmin & Shirley 2000",
             .options = NULL,
             .lobes = 0,
             .anisotropic = 0},
    .configure = configure_iso,
    .eval = eval_iso,
};
