/* He, Torrance, Sillion & Greenberg 1991 (physical optics), the directional-diffuse lobe
 * as the BRDF benchmark (bbm) evaluates Ngan et al.'s 2005 fits (NganHe: Westin's
 * exponent in the series, the erratum's exponential in the shadowing, Cook-Torrance's
 * real-index Fresnel):
 *
 *   f_c = rho_d/pi + rho_s F(eta, V.H) S(L) S(V) G D_c / (pi NL NV)
 *   G   = (|L+V|^2 / (NL + NV))^2
 *   S(w) = (1 - erfc(u)/2) / (Lambda + 1), Lambda = (exp(-u^2)/(sqrt(pi) u) - erfc(u))/2,
 *          u = tau / (2 sigma tan(theta_w))
 *   sigma0 = sigma / sqrt(1 + x^2), x exp(x^2/2) = (K(L) + K(V)) / sqrt(8 pi),
 *          K(w) = tan(theta_w) erfc(u)                        (Halley, then implicit d/d.)
 *   g_c = (2 pi sigma0 (NL + NV) / lambda_c)^2,  b_c = pi^2 tau^2 |L_xy + V_xy|^2 / lambda_c^2
 *   D_c = pi^2 tau^2 / (4 lambda_c^2) ((1 - w) A_c + w R_c),  w = clamp(g_min - 18, 0, 1)
 *   A_c = sum_{m>=1} e^-g g^m / (m! m) exp(-b/m),  R_c = exp(-b/g) / g (Beckmann's rough limit)
 *
 * lambda = 0.645, 0.526, 0.444 micrometres for three channels (bbm's RGB), 0.526 for every
 * channel otherwise; tau and sigma in micrometres; g_min is the longest wavelength's g.
 * The series is summed to an absolute error below 2e-20 (A <= 1; see he_series).
 * Not energy conserving: rho_s is a free scale (Ngan's fits reach 1e4) and G grows at
 * grazing angles. Reciprocal: every factor is symmetric in L and V. */
#include "family.h"
#include "terms.h"

#include <math.h>

#define HE_EPS 1e-20          /* absolute error of each truncation of the series */
#define HE_LN_INV_EPS 46.0518 /* ln(1 / HE_EPS) = 46.05170..., rounded up: e^-46.0518 < HE_EPS */
#define HE_MAX_TERMS 160      /* never reached: for g <= 41 the last term has m <= 120 */
#define HE_LN_START 16        /* P_m0 from the recurrence up to here, in closed form above */
#define HE_BLEND_LO 18.0      /* bbm's threshold: the rough limit from g_min = 18 ... */
/* Beyond u = 6.5: S = 1, K = 0, no erfc and no exp. There erfc(u) < 4e-20 and
 * exp(-u^2) < 5e-19, so S rounds to 1; K = tan(theta) erfc(u) < 8e-16 (tan(theta) =
 * tau / (2 sigma u) < 2e4 within the bounds) moves sigma0 by under 1e-16 relative; the
 * derivatives dropped are below 2e-18 of those kept. */
#define HE_U_FLAT 6.5
#define HE_EXP_ZERO 745.2 /* exp(-q) is 0 in doubles beyond: skips glibc's slow underflow path */
#define HE_F_SERIES 1e-3  /* sigma0's equation by its series below, by Halley above */
#define HE_SQRT_PI 1.77245385090551602730

/* 1 / lambda^2 of channel c, lambda in micrometres. */
static double inv_lambda2(int C, int c)
{
    static const double rgb[3] = {0.645, 0.526, 0.444};
    double l = C == 3 ? rgb[c] : 0.526;
    return 1.0 / (l * l);
}

static bf_status configure(bf_model *m, bf_error *err)
{
    m->energy_conserving = 0; /* free scale rho_s, G ~ 1/cos^2 at grazing */
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "rho_s", 1, 0.0, 1e5, 0.5, BF_SCALE_LOG1P, 1, BF_ROLE_WEIGHT, err)) ||
        (rc = bf_model_add_param(m, "tau", 0, 1.0, 200.0, 28.0, BF_SCALE_LOG, 1, BF_ROLE_SHAPE, err)) ||
        (rc = bf_model_add_param(m, "sigma", 0, 1e-3, 20.0, 0.5, BF_SCALE_LOG, 1, BF_ROLE_SHAPE, err)) ||
        (rc = bf_model_add_param(m, "eta", 0, 1.0, 20.0, 1.5, BF_SCALE_LINEAR, 1, BF_ROLE_IOR, err)))
        return rc;
    return BF_OK;
}

/* 1/m for m = 1 .. HE_MAX_TERMS (he_inv[m - 1]), folded by the compiler: the series
 * multiplies where it would divide. */
#define HE_I4(m) 1.0 / (m + 1), 1.0 / (m + 2), 1.0 / (m + 3), 1.0 / (m + 4)
#define HE_I16(m) HE_I4(m), HE_I4(m + 4), HE_I4(m + 8), HE_I4(m + 12)
#define HE_I32(m) HE_I16(m), HE_I16(m + 16)
static const double he_inv[HE_MAX_TERMS] = {HE_I32(0), HE_I32(32), HE_I32(64), HE_I32(96), HE_I32(128)};

/* Sums over m >= 1 of T_m = P_m e^(-b/m) / m, P_m = e^-g g^m / m! (Poisson): s[0] = sum T_m,
 * s[1] = sum m T_m, s[2] = sum T_m / m. The terms below m_lo = 1 + floor(b / ln(1/HE_EPS)),
 * where e^(-b/m) < HE_EPS, are skipped (together below HE_EPS, as sum P_m <= 1), and the sum
 * stops once the Poisson tail sum_{k>m} P_k <= P_{m+1} / (1 - g/(m+2)) is at most HE_EPS:
 * each sum is then within 2 HE_EPS of the infinite series. Skipping is what makes the
 * series cheap: P_m_lo comes in closed form rather than from m_lo steps of the recurrence,
 * and when the tail from m_lo is already below HE_EPS (far from the highlight, where
 * b is large) no term is summed at all. Needs 0 < g <= 41 (the blend's range). */
static void he_series(double g, double b, double s[3])
{
    s[0] = s[1] = s[2] = 0.0;
    const double m_lo = 1.0 + floor(b / HE_LN_INV_EPS);
    double P;
    if (m_lo > 7.4 * g + 47.0) /* then ln(g/m_lo) < -2 and the test below holds: no logs */
        return;
    if (m_lo > g + 1.0) {
        /* ln P_m <= -g + m (1 + ln(g/m)), from m! >= (m/e)^m; the tail from m_lo is at
         * most P_m_lo / (1 - g/(m_lo + 1)). */
        double lt = -g + m_lo * (1.0 + log(g / m_lo)) - log1p(-g / (m_lo + 1.0));
        if (lt <= -HE_LN_INV_EPS)
            return;
    }
    if (m_lo >= HE_MAX_TERMS) /* never: for g <= 41 the test above returns from m_lo = 117 */
        return;
    const int m0 = (int)m_lo;
    if (m0 > HE_LN_START) {
        P = exp(-g + m0 * log(g)) / tgamma(m0 + 1.0);
    } else {
        P = exp(-g);
        for (int m = 1; m <= m0; m++)
            P *= g * he_inv[m - 1];
    }
    /* The Poisson weights and where the tail stops first, then the terms, then the sums:
     * loops without a division or a long chain of dependent operations. */
    double Pm[HE_MAX_TERMS], h[HE_MAX_TERMS];
    const double *inv = he_inv + (m0 - 1); /* inv[k] = 1 / (m0 + k) */
    int n = 0;
    while (n < HE_MAX_TERMS - m0) {
        Pm[n++] = P;
        /* P_{m+1} / (1 - g/(m+2)) <= HE_EPS at m = m0 + n - 1, multiplied out. */
        const double m = m0 + n - 1.0;
        if (m + 2.0 > g && P * g * (m + 2.0) <= HE_EPS * (m + 1.0) * (m + 2.0 - g))
            break;
        P *= g * inv[n];
    }
    for (int k = 0; k < n; k++)
        h[k] = Pm[k] * exp(-b * inv[k]);
    /* Even and odd k in two lanes: shorter chains of additions, and it vectorises. */
    if (n & 1)
        h[n++] = 0.0; /* within h and he_inv: n <= HE_MAX_TERMS - m0 here */
    double a0[2] = {0.0, 0.0}, a1[2] = {0.0, 0.0}, a2[2] = {0.0, 0.0};
    for (int k = 0; k < n; k += 2)
        for (int j = 0; j < 2; j++) {
            double t = h[k + j];
            a1[j] += t;
            t *= inv[k + j];
            a0[j] += t;
            a2[j] += t * inv[k + j];
        }
    s[0] = a0[0] + a0[1], s[1] = a1[0] + a1[1], s[2] = a2[0] + a2[1];
}

/* The root x >= 0 of x exp(x^2/2) = f0 and *dx = dx/df0 = 1 / ((1 + x^2) exp(x^2/2)).
 * Below HE_F_SERIES by its Lagrange inversion x = f - f^3/2 + 5 f^5/8 - 49 f^7/48 (the
 * next term is 1.9 f^9, below 2e-18 relative) and exp(x^2/2) by Taylor to y^3 (y = x^2/2
 * < 6e-7). Above by Halley's method from f0 (at most 1 and above the root) or, above 1,
 * from x^2 = L - ln(1 + L), L = 2 ln f0 (x^2 = L - ln x^2 at the root): 2 to 5 steps. The
 * convergence is cubic, so a step below 1e-11 x leaves an error far below rounding; a
 * test at rounding level (1e-16 x) could cycle where rounding makes the steps 2e-16 x. */
static double he_sigma0_root(double f0, double *dx)
{
    if (f0 < HE_F_SERIES) { /* also f0 = 0: both directions unshadowed, the usual case */
        const double f2 = f0 * f0;
        const double x = f0 * (1.0 - f2 * (0.5 - f2 * (0.625 - f2 * (49.0 / 48.0))));
        const double y = 0.5 * x * x;
        *dx = 1.0 / ((1.0 + x * x) * (1.0 + y * (1.0 + 0.5 * y * (1.0 + y / 3.0))));
        return x;
    }
    const double L = f0 <= 1.0 ? 0.0 : 2.0 * log(f0);
    double x = f0 <= 1.0 ? f0 : sqrt(L - log1p(L));
    double e = exp(0.5 * x * x);
    for (int it = 0; it < 20; it++) {
        /* f = x e - f0, f' = (1 + x^2) e, f'' = x (x^2 + 3) e; step 2 f f' / (2 f'^2 - f f''). */
        const double f = x * e - f0, d1 = (1.0 + x * x) * e, d2 = x * (x * x + 3.0) * e;
        const double d = 2.0 * f * d1 / (2.0 * d1 * d1 - f * d2);
        x -= d;
        e = exp(0.5 * x * x);
        if (!(fabs(d) > 1e-11 * x))
            break;
    }
    *dx = 1.0 / ((1.0 + x * x) * e);
    return x;
}

/* What every channel of one sample shares, with derivatives: Q = F S G / (pi NL NV) and
 * its derivatives in tau, sigma (through S) and eta (through F); sigma0 and its
 * derivatives; the geometry of g and b. */
typedef struct he_sample {
    double Q, dQ_tau, dQ_sig, dQ_eta;
    double s0, ds0_tau, ds0_sig;
    double G0, B0; /* g_c = G0 / lambda_c^2, b_c = B0 / lambda_c^2 */
    double qb, eR; /* b_c / g_c = B0 / G0 in every channel, and exp(-qb) where the rough limit is used */
} he_sample;

typedef struct he_model {
    int C, P, od, os, ot, osg, oe;
    const double *rd, *rs;
    double tau, sig, eta, lmin;    /* lmin: the smallest 1/lambda^2 */
    double itau, isig, u0, il2[3]; /* 1/tau, 1/sigma, u tan(theta), 1/lambda_c^2 */
} he_model;

/* One direction's S (header) with u dS/du, and K with dK/dtau (dK/dsigma = -(tau/sigma)
 * dK/dtau: K depends on tau/sigma only), from one erfc(u) and one exp(-u^2); S = 1 and
 * K = 0 beyond HE_U_FLAT (and at normal incidence, u infinite). */
static void he_direction(const he_model *d, double t, double out[4])
{
    const double u = t > 0.0 ? d->u0 / t : INFINITY;
    if (u > HE_U_FLAT) {
        out[0] = 1.0, out[1] = 0.0, out[2] = 0.0, out[3] = 0.0;
        return;
    }
    const double ec = erfc(u), ex = exp(-u * u);
    const double num = 1.0 - 0.5 * ec;
    const double lp1 = 0.5 * (ex / (HE_SQRT_PI * u) - ec) + 1.0;
    /* dnum/du = e^-u^2 / sqrt(pi); dLambda/du = -e^-u^2 / (2 sqrt(pi) u^2). */
    const double dnum = ex / HE_SQRT_PI, dl = -ex / (2.0 * HE_SQRT_PI * u * u);
    out[0] = num / lp1;
    out[1] = u * (dnum * lp1 - num * dl) / (lp1 * lp1);
    out[2] = t * ec;
    out[3] = -ex * d->isig / HE_SQRT_PI;
}

static void sample_terms(const he_model *d, const bf_geometry *g, size_t i, he_sample *t)
{
    const double lz = g->lz[i], vz = g->vz[i];
    const double ti = sqrt(g->lx[i] * g->lx[i] + g->ly[i] * g->ly[i]) / lz;
    const double to = sqrt(g->vx[i] * g->vx[i] + g->vy[i] * g->vy[i]) / vz;
    double di[4], dO[4]; /* S, u dS/du, K, dK/dtau */
    he_direction(d, ti, di);
    he_direction(d, to, dO);
    const double Si = di[0], uSi = di[1], Ki = di[2], dKi = di[3];
    const double So = dO[0], uSo = dO[1], Ko = dO[2], dKo = dO[3];
    const double r8pi = 1.0 / sqrt(8.0 * M_PI);
    double dx;
    const double x = he_sigma0_root((Ki + Ko) * r8pi, &dx);
    const double q = 1.0 / sqrt(1.0 + x * x);
    t->s0 = d->sig * q;
    /* Implicit: dsigma0 = sigma dq/dx dx/df0 df0, f0 a function of tau/sigma. */
    const double ds0_tau_f = -d->sig * x * q * q * q * dx * (dKi + dKo) * r8pi;
    t->ds0_tau = ds0_tau_f;
    t->ds0_sig = q - d->tau * d->isig * ds0_tau_f;

    /* u is proportional to tau / sigma: tau dS/dtau = -sigma dS/dsigma = uS_i' S_o + S_i uS_o'. */
    const double tdS = uSi * So + Si * uSo;
    double dF;
    const double F = bf_dielectric(g->vh[i], d->eta, &dF);
    const double sx = g->lx[i] + g->vx[i], sy = g->ly[i] + g->vy[i], sz = lz + vz;
    const double v2 = sx * sx + sy * sy + sz * sz;
    const double G = (v2 / sz) * (v2 / sz);
    const double Q0 = G / (M_PI * lz * vz);
    t->Q = F * Si * So * Q0;
    t->dQ_tau = F * tdS * Q0 * d->itau;
    t->dQ_sig = -F * tdS * Q0 * d->isig;
    t->dQ_eta = dF * Si * So * Q0;
    t->G0 = 4.0 * M_PI * M_PI * t->s0 * t->s0 * sz * sz;
    t->B0 = M_PI * M_PI * d->tau * d->tau * (sx * sx + sy * sy);
    t->qb = t->G0 > 0.0 ? t->B0 / t->G0 : 0.0;
    t->eR = t->G0 * d->lmin > HE_BLEND_LO && t->qb < HE_EXP_ZERO ? exp(-t->qb) : 0.0;
}

/* D_c / N_c = (1 - w) A + w R and its derivatives in g and b (dw/dg_min apart):
 * out = {value, d/dg, d/db, R - A}. */
static void he_dhat(const he_sample *t, double gc, double bc, double w, double out[4])
{
    const double ig = 1.0 / gc;
    double A = 0.0, Ag = 0.0, Ab = 0.0, R = 0.0, Rg = 0.0, Rb = 0.0;
    if (w < 1.0) {
        double s[3];
        he_series(gc, bc, s);
        A = s[0], Ag = s[1] * ig - s[0], Ab = -s[2];
    }
    if (w > 0.0) {
        R = t->eR * ig;
        Rg = R * (t->qb - 1.0) * ig, Rb = -R * ig;
    }
    out[0] = (1.0 - w) * A + w * R;
    out[1] = (1.0 - w) * Ag + w * Rg;
    out[2] = (1.0 - w) * Ab + w * Rb;
    out[3] = R - A;
}

/* Channel c's value, and its gradient row when row is not NULL. */
static void channel(const he_model *d, const he_sample *t, int c, double *out, double *row)
{
    const double il2 = d->il2[d->C == 3 ? c : 0];
    const double gc = t->G0 * il2, bc = t->B0 * il2, gmin = t->G0 * d->lmin;
    const double N = 0.25 * M_PI * M_PI * d->tau * d->tau * il2;
    const double wr = gmin - HE_BLEND_LO, w = wr <= 0.0 ? 0.0 : wr >= 1.0 ? 1.0 : wr;
    double h[4] = {0.0, 0.0, 0.0, 0.0};
    if (gc > 0.0)
        he_dhat(t, gc, bc, w, h);
    const double D = N * h[0];
    out[c] = d->rd[c] / M_PI + d->rs[c] * t->Q * D;
    if (!row)
        return;
    /* dD/dsigma0 through g_c and, inside the blend, through w(g_min). */
    const double is0 = 1.0 / t->s0, itau = d->itau;
    const double dw = (wr > 0.0 && wr < 1.0) ? 2.0 * gmin * is0 : 0.0;
    const double dD_s0 = N * (h[1] * 2.0 * gc * is0 + h[3] * dw);
    const double dD_tau = 2.0 * (D + N * h[2] * bc) * itau + dD_s0 * t->ds0_tau;
    const double dD_sig = dD_s0 * t->ds0_sig;
    const double rs = d->rs[c];
    for (int k = 0; k < d->P; k++)
        row[k] = 0.0;
    row[d->od + c] = 1.0 / M_PI;
    row[d->os + c] = t->Q * D;
    row[d->ot] = rs * (t->dQ_tau * D + t->Q * dD_tau);
    row[d->osg] = rs * (t->dQ_sig * D + t->Q * dD_sig);
    row[d->oe] = rs * t->dQ_eta * D;
}

static void eval(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1, double *values,
                 double *grad)
{
    he_model d;
    d.C = m->channels, d.P = m->nfree;
    d.od = m->offset[0], d.os = m->offset[1], d.ot = m->offset[2], d.osg = m->offset[3], d.oe = m->offset[4];
    d.rd = x + d.od, d.rs = x + d.os;
    d.tau = x[d.ot], d.sig = x[d.osg], d.eta = x[d.oe];
    d.lmin = inv_lambda2(d.C, 0); /* channel 0 has the longest wavelength */
    d.itau = 1.0 / d.tau, d.isig = 1.0 / d.sig, d.u0 = d.tau / (2.0 * d.sig);
    for (int c = 0; c < 3; c++)
        d.il2[c] = inv_lambda2(d.C, c);
    const int C = d.C, P = d.P;
    for (size_t i = i0; i < i1; i++) {
        double *out = values + (i - i0) * (size_t)C;
        double *rows = grad ? grad + (i - i0) * (size_t)C * (size_t)P : NULL;
        if (bf_eval_skip_invalid(g, i, C, P, out, rows))
            continue;
        he_sample t;
        sample_terms(&d, g, i, &t);
        for (int c = 0; c < C; c++)
            channel(&d, &t, c, out, rows ? rows + (size_t)c * (size_t)P : NULL);
    }
}

const bf_family bf_family_he = {
    .info = {.name = "he",
             .summary = "He-Torrance-Sillion-Greenberg physical optics (Ngan's fits, Westin's form)",
             .reference = "He et al. 1991; Ngan et al. 2005 as evaluated by bbm",
             .options = NULL,
             .lobes = 0,
             .anisotropic = 0},
    .configure = configure,
    .eval = eval,
};
