/* Shifted Gamma Distribution model (Bagher, Soler & Holzschuch 2012, "Accurate fitting of
 * measured reflectances using a Shifted Gamma micro-facet distribution", CGF 31(4)):
 *   f  = rho_d/pi + rho_s F D G / (pi NL NV)
 *   D  = exp(-a) / (pi a^p NH^4),  a = alpha + tan^2(theta_h) / alpha   (the SGD)
 *   F  = f0 - f1 VH + (1 - f0) (1 - VH)^5                               (their Fresnel fit)
 *   G  = G1(theta_i) G1(theta_o),
 *   G1(t) = 1 + lambda (1 - exp(w)), w = ((t - theta0) / s)^k, for t > theta0; 1 otherwise.
 * The paper writes w = c (t - theta0)^k; the width s = c^(-1/k) (radians, where w = 1) is
 * what the data pin down: c spans 1e-8 .. 1e109 over the published fits and moves with k
 * (log c = -k log s), so a search in c is ill conditioned, while s spans 0.37 .. 2.4.
 * Every lobe parameter is a colour, as the paper fits them (the driver calls the lobe once
 * per channel). The paper's normalisation K of D scales the lobe exactly as the weight
 * does, so the two are one parameter (rho_s = albedo K in bbm's names): two would make a
 * fit's normal equations singular.
 *
 * Not energy conserving: D is normalised only through rho_s, F exceeds 1 for f0 > 1 and
 * the fitted G1 is not bounded by 1 (published fits have lambda up to 1.5e7). Reciprocal:
 * F, D and G are symmetric in L and V. */
#include "family.h"
#include "terms.h"

#include <math.h>

/* exp(w) is held at exp(SGD_W_MAX) beyond it, so that G stays finite at every bound
 * ((pi / 0.3)^1000); the published fits reach w = 16.9 in the upper hemisphere. */
#define SGD_W_MAX 50.0

static bf_status configure(bf_model *m, bf_error *err)
{
    m->energy_conserving = 0;
    bf_status rc;
    /* Bounds hold all 100 published MERL fits (docs/models.md gives their ranges). */
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "rho_s", 1, 0.0, 1e4, 1.0, BF_SCALE_LOG1P, 1, BF_ROLE_WEIGHT, err)) ||
        (rc = bf_model_add_param(m, "alpha", 1, 1e-6, 2.0, 0.025, BF_SCALE_LOG, 1, BF_ROLE_SHAPE, err)) ||
        (rc = bf_model_add_param(m, "p", 1, 0.0, 3.0, 0.45, BF_SCALE_LINEAR, 1, BF_ROLE_SHAPE, err)) ||
        (rc = bf_model_add_param(m, "f0", 1, 0.0, 10.0, 1.0, BF_SCALE_LINEAR, 1, BF_ROLE_F0, err)) ||
        (rc = bf_model_add_param(m, "f1", 1, -2.0, 10.0, 0.0, BF_SCALE_LINEAR, 1, BF_ROLE_SHAPE, err)) ||
        (rc = bf_model_add_param(m, "lambda", 1, 0.0, 1e8, 1.0, BF_SCALE_LOG1P, 1, BF_ROLE_SHAPE, err)) ||
        (rc = bf_model_add_param(m, "s", 1, 0.3, M_PI, 1.5, BF_SCALE_LOG, 1, BF_ROLE_SHAPE, err)) ||
        (rc = bf_model_add_param(m, "k", 1, 2.0, 1e3, 8.0, BF_SCALE_LOG, 1, BF_ROLE_SHAPE, err)) ||
        (rc = bf_model_add_param(m, "theta0", 1, -M_PI / 2, M_PI / 2, 0.2, BF_SCALE_LINEAR, 1, BF_ROLE_SHAPE, err)))
        return rc;
    return BF_OK;
}

/* G1 at polar angle th for q = (lambda, s, k, theta0), log s in logs; d = dG1/dq. */
static inline double g1(double th, const double *q, double logs, double d[4])
{
    double x = th - q[3];
    d[0] = d[1] = d[2] = d[3] = 0.0;
    if (!(x > 0.0))
        return 1.0;
    double lr = log(x) - logs;
    double lw = q[2] * lr; /* log w: (x / s)^k neither overflows nor underflows early */
    if (lw > log(SGD_W_MAX)) {
        d[0] = -expm1(SGD_W_MAX);
        return 1.0 + q[0] * d[0];
    }
    double w = exp(lw), em1 = expm1(w);  /* e^w - 1, exact for small w */
    double le = -q[0] * (1.0 + em1) * w; /* dG1 / d(log w) */
    d[0] = -em1;
    d[1] = -le * q[2] / q[1];
    d[2] = le * lr;
    d[3] = -le * q[2] / x;
    return 1.0 + q[0] * d[0];
}

/* One lobe over a block for one channel (a bf_lobe_fn: family.h says why eight arguments).
 * Scalars s = alpha, p, f0, f1, lambda, s, k, theta0 of that channel. */
static void lobe(const bf_model *m, int k, const double *s, const bf_geometry *g, size_t i0, size_t cnt, double *S,
                 double *dS)
{
    (void)m;
    (void)k;
    const double alpha = s[0], p = s[1], f0 = s[2], f1 = s[3];
    const double *q = s + 4, logs = log(s[5]);
    /* Above 1 (nothing spared) for theta0 <= 0; the margin keeps angles a rounding above
     * theta0 on the atan2 path, where G1 - 1 is of order (1e-15 / s)^k anyway. */
    const double cos0 = q[3] > 0.0 ? cos(q[3]) * (1.0 + 1e-15) : 2.0;
    for (size_t j = 0; j < cnt; j++) {
        size_t i = i0 + j;
        double nl = g->lz[i], nv = g->vz[i], nh = g->hz[i], vh = g->vh[i];
        if (!(nl > 0.0 && nv > 0.0)) {
            S[j] = 0.0;
            for (int r = 0; dS && r < 8; r++)
                dS[r * BF_BLOCK + j] = 0.0;
            continue;
        }
        double nh2 = nh * nh;
        double t = g->sin2h[i] / nh2; /* tan^2(theta_h) */
        double a = alpha + t / alpha, la = log(a);
        double D = exp(-a - p * la) / (M_PI * nh2 * nh2);
        double mu = 1.0 - vh;
        mu = mu < 0.0 ? 0.0 : mu;
        double m5 = mu * mu * mu * mu * mu;
        double F = f0 - f1 * vh + (1.0 - f0) * m5;
        /* A polar angle at or below theta0 (its cosine at or above cos theta0) has G1 = 1:
         * the atan2 is spared there. */
        double ti = nl >= cos0 ? 0.0 : atan2(sqrt(g->lx[i] * g->lx[i] + g->ly[i] * g->ly[i]), nl);
        double to = nv >= cos0 ? 0.0 : atan2(sqrt(g->vx[i] * g->vx[i] + g->vy[i] * g->vy[i]), nv);
        double di[4], dv[4];
        double Gi = g1(ti, q, logs, di), Gv = g1(to, q, logs, dv);
        double G = Gi * Gv;
        double inv = 1.0 / (M_PI * nl * nv);
        S[j] = F * D * G * inv;
        if (!dS)
            continue;
        double FGi = F * G * inv, DGi = D * G * inv, FDi = F * D * inv;
        dS[j] = D * (-1.0 - p / a) * (1.0 - t / (alpha * alpha)) * FGi;
        dS[BF_BLOCK + j] = -la * D * FGi;
        dS[2 * BF_BLOCK + j] = (1.0 - m5) * DGi;
        dS[3 * BF_BLOCK + j] = -vh * DGi;
        for (int r = 0; r < 4; r++)
            dS[(4 + r) * BF_BLOCK + j] = FDi * (di[r] * Gv + Gi * dv[r]);
    }
}

const bf_family bf_family_sgd = {
    .info = {.name = "sgd",
             .summary = "Shifted Gamma microfacet distribution, fitted Fresnel and shadowing, per channel",
             .reference = "Bagher, Soler & Holzschuch 2012",
             .options = NULL,
             .lobes = 0,
             .anisotropic = 0},
    .configure = configure,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe,
    .channels_independent = 1, /* every parameter a colour: channel c sees only its own */
};
