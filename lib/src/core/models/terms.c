#include "terms.h"

#include <complex.h>
#include <math.h>
#include <stddef.h>

#include "family.h"

const char *const bf_fresnel_values[] = {"schlick", "dielectric", "none", NULL};
const char *const bf_fresnel_metal_values[] = {"schlick", "dielectric", "none", "conductor", NULL};

bf_status bf_model_add_fresnel_param(bf_model *m, int kind, int lobe, bf_error *err)
{
    if (kind == BF_FRESNEL_SCHLICK)
        return bf_model_add_param(m, "f0", 0, 0.0, 1.0, 0.04, BF_SCALE_LINEAR, lobe, BF_ROLE_F0, err);
    if (kind == BF_FRESNEL_DIELECTRIC) /* BF_IOR_MAX (terms.h) says why 100 */
        return bf_model_add_param(m, "ior", 0, 1.0, BF_IOR_MAX, 1.5, BF_SCALE_LOG, lobe, BF_ROLE_IOR, err);
    if (kind == BF_FRESNEL_CONDUCTOR) { /* per channel: the metal's colour is in F */
        bf_status rc = bf_model_add_param(m, "r", 1, 1e-3, 0.99, 0.9, BF_SCALE_LINEAR, lobe, BF_ROLE_F0, err);
        return rc != BF_OK
                   ? rc
                   : bf_model_add_param(m, "g", 1, 1e-3, 1.0, 0.9, BF_SCALE_LINEAR, lobe, BF_ROLE_EDGE_TINT, err);
    }
    return BF_OK;
}

/* ---- Conductor Fresnel ------------------------------------------------------------ */

void bf_conductor_nk(double r, double g, double *n, double *k, double d[4])
{
    /* n runs from the index of a dielectric with reflectance r, (1 + sqrt r)/(1 - sqrt r)
     * (g = 0, k = 0), to (1 - r)/(1 + r) (g = 1); k is then what keeps the normal
     * reflectance ((n-1)^2 + k^2)/((n+1)^2 + k^2) at r. */
    double q = sqrt(r);
    double nmin = (1.0 - r) / (1.0 + r), nmax = (1.0 + q) / (1.0 - q);
    double nn = g * nmin + (1.0 - g) * nmax;
    double K = (r * (nn + 1.0) * (nn + 1.0) - (nn - 1.0) * (nn - 1.0)) / (1.0 - r);
    double kk = sqrt(K > 0.0 ? K : 0.0);
    *n = nn;
    *k = kk;
    if (d) {
        double dn_dr = -2.0 * g / ((1.0 + r) * (1.0 + r)) + (1.0 - g) / (q * (1.0 - q) * (1.0 - q));
        double dn_dg = nmin - nmax;
        double dK_dn = 2.0 * (r * (nn + 1.0) - (nn - 1.0)) / (1.0 - r);
        double dK_dr = 4.0 * nn / ((1.0 - r) * (1.0 - r)) + dK_dn * dn_dr;
        double inv2k = kk > 0.0 ? 0.5 / kk : 0.0; /* k = 0 only at g = 0, outside the bounds */
        d[0] = dn_dr;
        d[1] = dn_dg;
        d[2] = dK_dr * inv2k;
        d[3] = dK_dn * dn_dg * inv2k;
    }
}

double bf_conductor(double c, double r, double g, double *dr, double *dg)
{
    double n, k, d[4];
    bf_conductor_nk(r, g, &n, &k, d);
    /* With eta = n + ik and w = sqrt(eta^2 - sin^2): r_s = (c - w)/(c + w), r_p =
     * (eta^2 c - w)/(eta^2 c + w), F = (|r_s|^2 + |r_p|^2)/2. Both are analytic in eta,
     * so dF/dn = Re(A) and dF/dk = -Im(A) with A = conj(r_s) r_s' + conj(r_p) r_p'. */
    /* n + k*I, not CMPLX: clang's glibc headers lack CMPLX, and n, k are finite here. */
    double complex eta = n + k * I, e2 = eta * eta;
    double complex w = csqrt(e2 - (1.0 - c * c));
    double complex rs = (c - w) / (c + w), u = e2 * c, rp = (u - w) / (u + w);
    double F = 0.5 * (creal(rs * conj(rs)) + creal(rp * conj(rp)));
    if (dr || dg) {
        double complex dw = eta / w, du = 2.0 * eta * c;
        double complex drs = -2.0 * c * dw / ((c + w) * (c + w));
        double complex drp = 2.0 * (du * w - u * dw) / ((u + w) * (u + w));
        double complex A = conj(rs) * drs + conj(rp) * drp;
        double dFdn = creal(A), dFdk = -cimag(A);
        if (dr)
            *dr = dFdn * d[0] + dFdk * d[2];
        if (dg)
            *dg = dFdn * d[1] + dFdk * d[3];
    }
    return F;
}
