/* Heidrich & Seidel 1998 anisotropic lobe for brushed/threaded surfaces:
 *   f = rho_d/pi + rho_s (s+2)/(2 pi) max(0, x)^s,
 *   x = sqrt(1 - (L.T)^2) sqrt(1 - (V.T)^2) - (L.T)(V.T),  T = (cos phi_t, sin phi_t, 0).
 * x = -cos(angle(L,T) + angle(V,T)): the lobe peaks on the cone of reflection around
 * the thread T, which contains the mirror direction. Through the diffuse + lobe driver.
 *
 * sqrt(1 - (L.T)^2) is computed as |L - (L.T) T| = sqrt((L.B)^2 + Lz^2), B = (-sin, cos, 0),
 * which has no cancellation and stays > 0 on every valid sample (Lz > 0).
 * s = 0 follows pow(0, 0) = 1 (the lobe is 1/pi everywhere), as in phong.
 *
 * Not energy conserving: the lobe spreads along the whole cone, so for large s the
 * albedo grows like sqrt(s) instead of staying <= rho_s. Reciprocal (x is symmetric). */
#include "family.h"
#include "terms.h"

#include <math.h>

#define INV_2PI (0.5 / M_PI)
/* Powers below exp(-665) (~1e-289) are flushed to 0 with zero derivatives (see phong.c). */
#define LOG_TINY (-665.0)

/* A bf_lobe_fn (family.h: why eight arguments). */
static void lobe_hs(const bf_model *m, int lobe, const double *sc, const bf_geometry *g, size_t i0, size_t cnt,
                    double *S, double *dS)
{
    (void)m;
    (void)lobe;
    const double s = sc[0], phi = sc[1];
    const double ct = cos(phi), st = sin(phi);
    const double norm = (s + 2.0) * INV_2PI;
    const double inv_s2 = 1.0 / (s + 2.0);
    for (size_t j = 0; j < cnt; j++) {
        size_t i = i0 + j;
        double a = g->lx[i] * ct + g->ly[i] * st;  /* L.T; d/dphi = L.B */
        double la = g->ly[i] * ct - g->lx[i] * st; /* L.B; d/dphi = -L.T */
        double b = g->vx[i] * ct + g->vy[i] * st;
        double lb = g->vy[i] * ct - g->vx[i] * st;
        double sa = sqrt(la * la + g->lz[i] * g->lz[i]);
        double sb = sqrt(lb * lb + g->vz[i] * g->vz[i]);
        /* 1 - x = ((a + b)^2 + (sa - sb)^2) / 2: no cancellation at the peak (x -> 1),
         * where s up to 1e6 would amplify the rounding of sa sb - a b. */
        double apb = a + b, smd = sa - sb;
        double delta = 0.5 * (apb * apb + smd * smd);
        double v, ds = 0.0, dphi = 0.0;
        double lg = delta < 1.0 ? log1p(-delta) : 0.0; /* log x where x > 0 */
        if (delta < 1.0 && s * lg > LOG_TINY) {
            v = norm * exp(s * lg);
            ds = v * (inv_s2 + lg);
            if (s != 0.0 && dS) {
                /* dS/dx = (s+2)/(2 pi) s x^(s-1); the exponent is capped so that for
                 * s < 1 and x near 0 (an infinite slope) the result stays finite. */
                double e = (s - 1.0) * lg;
                double dSdx = norm * s * exp(e < 600.0 ? e : 600.0);
                /* dx/dphi = -d delta/dphi, with d(L.T)/dphi = L.B, d sa/dphi = -a la/sa. */
                double dsa = sa > 0.0 ? -a * la / sa : 0.0;
                double dsb = sb > 0.0 ? -b * lb / sb : 0.0;
                double dx = -(apb * (la + lb) + smd * (dsa - dsb));
                dphi = dSdx * dx;
            }
        } else { /* x <= 0 (or x^s negligible): 0 for s > 0, 1 for s = 0 */
            v = s == 0.0 ? norm : 0.0;
        }
        S[j] = v;
        if (dS) {
            dS[j] = ds;
            dS[BF_BLOCK + j] = dphi;
        }
    }
}

static bf_status configure(bf_model *m, bf_error *err)
{
    m->energy_conserving = 0; /* albedo grows like sqrt(s) */
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "rho_s", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 1, BF_ROLE_WEIGHT, err)) ||
        (rc = bf_model_add_param(m, "s", 0, 0.0, 1e6, 50.0, BF_SCALE_LOG1P, 1, BF_ROLE_EXPONENT, err)) ||
        /* phi_t is pi-periodic (T and -T give the same lobe): start mid-range so a fit
         * is never more than pi/2 away from any thread direction. */
        (rc = bf_model_add_param_open(m, "phi_t", 0, 0.0, 0, M_PI, 1, 0.5 * M_PI, BF_SCALE_LINEAR, 1,
                                      BF_ROLE_ORIENTATION, err)))
        return rc;
    return BF_OK;
}

const bf_family bf_family_heidrich_seidel = {
    .info = {.name = "heidrich_seidel",
             .summary = "anisotropic lobe around a thread direction (brushed surfaces)",
             .reference = "Heidrich & Seidel 1998",
             .options = NULL,
             .lobes = 0,
             .anisotropic = 1},
    .configure = configure,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe_hs,
};
