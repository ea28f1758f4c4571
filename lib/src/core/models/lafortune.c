/* Lafortune 1997 generalised cosine lobes, normalised as in Ngan 2005:
 *   lafortune:       f = rho_d/pi + sum_k rho_s (n+2)/(2 pi) max(0, d)^n / cmax^n,
 *                    d = cxy (Lx Vx + Ly Vy) + cz Lz Vz,        cmax = max(|cxy|, |cz|)
 *   lafortune_aniso: d = cx Lx Vx + cy Ly Vy + cz Lz Vz,       cmax = max(|cx|, |cy|, |cz|)
 * with lobes=K (default 1). Through the diffuse + lobe driver.
 *
 * Evaluated as (n+2)/(2 pi) r^n with r = max(0, d)/cmax, so that cmax^n never
 * underflows (n up to 1e6) into 0/0. |d| <= cmax by Cauchy-Schwarz, so r <= 1 and r^n
 * cannot overflow; 1 - r is computed without cancellation (see lobe_common).
 * Conventions at the singular points:
 * - n = 0 follows pow(0, 0) = 1: the lobe is 1/pi everywhere, d <= 0 included.
 * - cxy = cz = 0 (cmax = 0): the lobe is taken as 0 for n > 0 and 1/pi at n = 0 (the
 *   d <= 0 case), with zero gradient.
 * - cmax = max(|c|) is not differentiable where two |c| tie. There the derivative of
 *   cmax is taken as 0 for each tied coefficient: the one-sided derivative in the
 *   direction that shrinks |c|, which is the only feasible one at the bounds (the
 *   default lobe cxy = -1, cz = 1 sits on such a tie).
 * - d/dn on d <= 0 is 0 (exact for n > 0; at n = 0 the one-sided value is -Inf).
 *
 * cxy = -1, cz = 1 is the normalised Phong lobe (d = R.V). Energy conserving: with
 * u = C L / cmax (|u| <= 1) the lobe is (n+2)/(2 pi) max(0, u.V)^n, whose cosine-weighted
 * integral over the hemisphere is at most that of the Phong lobe at normal incidence,
 * 1; so the albedo is <= rho_d + sum_k rho_s_k. Reciprocal (d is symmetric in L, V). */
#include "family.h"
#include "terms.h"

#include <math.h>

#define INV_2PI (0.5 / M_PI)
/* Powers below exp(-665) (~1e-289) are flushed to 0 with zero derivatives (see phong.c). */
#define LOG_TINY (-665.0)

/* (n+2)/(2 pi) max(0, r)^n for r = 1 - delta, with *dn = d/dn and *dr = d/dr. r^n as
 * exp(n log1p(-delta)) so it underflows to 0 and keeps full precision at the peak.
 * dr = (n+2)/(2 pi) n r^(n-1) is infinite at r -> 0 for n < 1; the exponent is capped
 * so it stays finite. */
static inline double power_lobe(double delta, double n, double *dn, double *dr)
{
    const double norm = (n + 2.0) * INV_2PI;
    double lg = delta < 1.0 ? log1p(-delta) : 0.0;
    if (delta < 1.0 && n * lg > LOG_TINY) {
        double v = norm * exp(n * lg);
        *dn = v * (1.0 / (n + 2.0) + lg);
        double e = (n - 1.0) * lg;
        *dr = n == 0.0 ? 0.0 : norm * n * exp(e < 600.0 ? e : 600.0);
        return v;
    }
    *dn = 0.0;
    *dr = 0.0;
    return n == 0.0 ? norm : 0.0;
}

/* max |c_q| over nc coefficients, and for each q the derivative of cmax with respect
 * to c_q: sign(c_q) where c_q is the unique maximum, else 0 (see the tie rule above). */
static inline double coef_max(const double *c, int nc, double *dmax)
{
    double cm = 0.0;
    int arg = -1, ties = 0;
    for (int q = 0; q < nc; q++) {
        double a = fabs(c[q]);
        if (a > cm) {
            cm = a;
            arg = q;
            ties = 0;
        } else if (a == cm && cm > 0.0) {
            ties = 1;
        }
    }
    for (int q = 0; q < nc; q++)
        dmax[q] = (q == arg && !ties) ? (c[q] > 0.0 ? 1.0 : -1.0) : 0.0;
    return cm;
}

/* Shared loop: nc = 2 (cxy, cz) or 3 (cx, cy, cz) coefficients, then n.
 * r = d / cmax = u.V with u = (kx Lx, ky Ly, kz Lz), k = c / cmax (|k| <= 1). For unit
 * L and V, 1 - r = (|u - V|^2 + 1 - |u|^2) / 2 and 1 - |u|^2 = sum (1 - k^2) L^2: this
 * form has no cancellation at the peak (r -> 1), where exponents up to 1e6 would
 * amplify the rounding of d. With cxy = -1, cz = 1 it is exactly phong's R.V. */
static inline void lobe_common(int nc, const double *s, const bf_geometry *g, size_t i0, size_t cnt, double *S,
                               double *dS)
{
    const double n = s[nc];
    double dmax[3];
    const double cm = coef_max(s, nc, dmax);
    if (!(cm > 0.0)) { /* cxy = cz = 0: r = 0 exactly (the formula below rounds) */
        for (size_t j = 0; j < cnt; j++) {
            S[j] = n == 0.0 ? (n + 2.0) * INV_2PI : 0.0;
            if (dS)
                for (int q = 0; q <= nc; q++)
                    dS[q * BF_BLOCK + j] = 0.0;
        }
        return;
    }
    const double inv = 1.0 / cm;
    /* k per axis (x, y, z) and 1 - k^2, exactly 0 for the largest coefficient. */
    const double kx = s[0] / cm, ky = s[nc == 2 ? 0 : 1] / cm, kz = s[nc - 1] / cm;
    const double ex = (1.0 - fabs(kx)) * (1.0 + fabs(kx));
    const double ey = (1.0 - fabs(ky)) * (1.0 + fabs(ky));
    const double ez = (1.0 - fabs(kz)) * (1.0 + fabs(kz));
    for (size_t j = 0; j < cnt; j++) {
        size_t i = i0 + j;
        double lx = g->lx[i], ly = g->ly[i], lz = g->lz[i];
        double vx = g->vx[i], vy = g->vy[i], vz = g->vz[i];
        double dx = kx * lx - vx, dy = ky * ly - vy, dz = kz * lz - vz;
        double delta = 0.5 * (dx * dx + dy * dy + dz * dz + ex * lx * lx + ey * ly * ly + ez * lz * lz);
        double dn, dr;
        S[j] = power_lobe(delta, n, &dn, &dr);
        if (dS) {
            double r = 1.0 - delta;
            double p[3];
            if (nc == 2) {
                p[0] = lx * vx + ly * vy;
                p[1] = lz * vz;
            } else {
                p[0] = lx * vx;
                p[1] = ly * vy;
                p[2] = lz * vz;
            }
            /* r = d / cmax: dr/dc_q = (p_q - r dcmax/dc_q) / cmax. */
            for (int q = 0; q < nc; q++)
                dS[q * BF_BLOCK + j] = dr * (p[q] - r * dmax[q]) * inv;
            dS[nc * BF_BLOCK + j] = dn;
        }
    }
}

/* A bf_lobe_fn (family.h: why eight arguments). */
static void lobe_iso(const bf_model *m, int lobe, const double *s, const bf_geometry *g, size_t i0, size_t cnt,
                     double *S, double *dS)
{
    (void)m;
    (void)lobe;
    lobe_common(2, s, g, i0, cnt, S, dS);
}

/* A bf_lobe_fn (family.h: why eight arguments). */
static void lobe_aniso(const bf_model *m, int lobe, const double *s, const bf_geometry *g, size_t i0, size_t cnt,
                       double *S, double *dS)
{
    (void)m;
    (void)lobe;
    lobe_common(3, s, g, i0, cnt, S, dS);
}

/* Default exponent of lobe k: lobe 1 is the Phong lobe with n = 50; the others differ
 * so that a multi-lobe fit does not start symmetric. */
static double default_n(int k)
{
    static const double ns[BF_MAX_LOBES] = {50.0, 5.0, 500.0, 1.0, 2000.0, 20.0, 200.0, 10.0};
    return ns[(k - 1) % BF_MAX_LOBES];
}

static bf_status configure_common(bf_model *m, int aniso, bf_error *err)
{
    m->energy_conserving = 1; /* albedo <= rho_d + sum rho_s (see above) */
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)))
        return rc;
    for (int k = 1; k <= m->lobes; k++) {
        if ((rc = bf_model_add_param(m, "rho_s", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, k, BF_ROLE_WEIGHT, err)))
            return rc;
        if (aniso) {
            if ((rc = bf_model_add_param(m, "cx", 0, -1.0, 1.0, -1.0, BF_SCALE_LINEAR, k, BF_ROLE_SHAPE, err)) ||
                (rc = bf_model_add_param(m, "cy", 0, -1.0, 1.0, -1.0, BF_SCALE_LINEAR, k, BF_ROLE_SHAPE, err)))
                return rc;
        } else {
            if ((rc = bf_model_add_param(m, "cxy", 0, -1.0, 1.0, -1.0, BF_SCALE_LINEAR, k, BF_ROLE_SHAPE, err)))
                return rc;
        }
        if ((rc = bf_model_add_param(m, "cz", 0, -1.0, 1.0, 1.0, BF_SCALE_LINEAR, k, BF_ROLE_SHAPE, err)) ||
            (rc = bf_model_add_param(m, "n", 0, 0.0, 1e6, default_n(k), BF_SCALE_LOG1P, k, BF_ROLE_EXPONENT, err)))
            return rc;
    }
    return BF_OK;
}

static bf_status configure_iso(bf_model *m, bf_error *err)
{
    return configure_common(m, 0, err);
}
static bf_status configure_aniso(bf_model *m, bf_error *err)
{
    return configure_common(m, 1, err);
}

const bf_family bf_family_lafortune = {
    .info = {.name = "lafortune",
             .summary = "Lafortune generalised cosine lobes (isotropic), K lobes",
             .reference = "Lafortune 1997; normalised as Ngan 2005",
             .options = NULL,
             .lobes = 1,
             .anisotropic = 0},
    .configure = configure_iso,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe_iso,
};

const bf_family bf_family_lafortune_aniso = {
    .info = {.name = "lafortune_aniso",
             .summary = "Lafortune generalised cosine lobes (anisotropic), K lobes",
             .reference = "Lafortune 1997; normalised as Ngan 2005",
             .options = NULL,
             .lobes = 1,
             .anisotropic = 1},
    .configure = configure_aniso,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe_aniso,
};
