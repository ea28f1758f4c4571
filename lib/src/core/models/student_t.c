/* Student-t distribution of slopes (STD; Ribardiere, Bringier, Meneveaux & Simonot 2017):
 *   f = rho_d/pi + rho_s D G F / (4 NL NV)
 *   D = 1 / (pi alpha^2 NH^4 (1 + tan^2(theta_h) / ((gamma - 1) alpha^2))^gamma)
 *   G = G1(L) G1(V), G1 = 1 / (1 + Lambda(z)), z = 1 / (alpha tan(theta))
 *   Lambda(z) = A(z) - S(z), with a = gamma - 1,
 *     A(z) = sqrt(a) Gamma(a + 1/2) / (sqrt(pi) Gamma(a) (2a - 1) z) (1 + z^2/a)^(1/2 - a)
 *     S(z) = I_x(a, 1/2) / 2, x = a / (a + z^2)  (regularised incomplete beta)
 * gamma = 2 is GGX with Smith-GGX exactly; gamma -> infinity tends to Beckmann with its
 * exact Smith term. Lambda is the exact Smith integral of the STD slopes (not the paper's
 * fitted approximation of its hypergeometric part): so that gamma = 2 is Walter's GGX to
 * rounding and the gradient is that of the function the fit evaluates. Energy
 * conserving: D is normalised, F <= 1 and G1 is the exact Smith masking of D, which
 * satisfies the projected-area constraint. Needs gamma > 3/2 (finite mean slope). */
#include "family.h"
#include "terms.h"

#include <math.h>

/* A value and its derivative with respect to gamma. */
typedef struct dual {
    double v, d;
} dual;

/* Digamma for x > 0: the recurrence up to x >= 6, then the asymptotic series. */
static double digamma(double x)
{
    double r = 0.0;
    while (x < 6.0) {
        r -= 1.0 / x;
        x += 1.0;
    }
    double f = 1.0 / (x * x);
    double t = f * (-1.0 / 12 + f * (1.0 / 120 + f * (-1.0 / 252 + f * (1.0 / 240 + f * (-1.0 / 132)))));
    return r + log(x) - 0.5 / x + t;
}

/* The fraction of the incomplete beta I_x(p, q) = x^p (1-x)^q / (p B(p, q) T) (DLMF
 * 8.17.22): T = 1 + d1/(1 + d2/(1 + ...)), d_2m = m (q - m) x / ((p + 2m - 1)(p + 2m)),
 * d_2m+1 = -(p + m)(p + q + m) x / ((p + 2m)(p + 2m + 1)). Its coefficients do not depend
 * on x: d_2m = ce x, d_2m+1 = -co x, and 1 + d_2m+1 = ko + co (1 - x), the form without
 * cancellation near x = 1 (1 - x co cancels to O(1/p) there, at large p and z^2 ~ 1.5,
 * which cost 4 digits at gamma = 4e5). Each with its derivative in p (dp = 1) or q
 * (dq = 1). */
enum { CF_TABLE = 24 }; /* coefficients kept per gamma: the usual number of terms */
typedef struct cf_coef {
    double ce, dce, co, dco, ko, dko;
} cf_coef;

static cf_coef cf_coefficients(double p, double q, double dp, double dq, int m)
{
    cf_coef k;
    double s = p + 2 * m, t = s + 1.0, r = 1.0 / (s * t), dden = dp * (s + t);
    double u = p + m, v = p + q + m, n = m * (2.0 * p + 3.0 * m + 2.0 - q) + p * (1.0 - q);
    k.co = u * v * r;
    k.dco = ((dp * v + u * (dp + dq)) - k.co * dden) * r;
    k.ko = n * r;
    k.dko = ((dp * (2.0 * m + 1.0 - q) - dq * (m + p)) - k.ko * dden) * r;
    double te = s - 1.0, re = m > 0 ? 1.0 / (s * te) : 0.0;
    k.ce = m * (q - m) * re;
    k.dce = (m * dq - k.ce * dp * (s + te)) * re;
    return k;
}

/* One side of the incomplete beta for one gamma: its parameters and first coefficients. */
typedef struct cf_side {
    double p, q, dp, dq;
    cf_coef k[CF_TABLE];
} cf_side;

static void cf_side_init(cf_side *c, double p, double q, double dp, double dq)
{
    c->p = p, c->q = q, c->dp = dp, c->dq = dq;
    for (int m = 0; m < CF_TABLE; m++)
        c->k[m] = cf_coefficients(p, q, dp, dq, m);
}

/* T and dT by its odd convergents, through their own three-term recurrence
 * A_2m+1 = (1 + d_2m+1 + d_2m) A_2m-1 - d_2m d_2m-1 A_2m-3 (1 + d_2m+1 formed as above), with
 * no division on the chain from one term to the next (Lentz's made it the cost of a fit).
 * Converges in O(sqrt(p)) terms for x < (p + 1)/(p + q + 2), as the caller ensures. */
static dual beta_cf(const cf_side *c, double x, double y)
{
    const double eps = 2e-16;
    const int near1 = x > 0.5;
    cf_coef k = c->k[0];
    double e0 = near1 ? k.ko + y * k.co : 1.0 - x * k.co, e0d = near1 ? k.dko + y * k.dco : -x * k.dco;
    double dodd = -x * k.co, doddd = -x * k.dco; /* d_2m-1 */
    dual A0 = {1.0, 0.0}, A1 = {e0, e0d}, B0 = {0.0, 0.0}, B1 = {1.0, 0.0};
    dual R = A1;
    for (int m = 1; m < 200000; m++) {
        k = m < CF_TABLE ? c->k[m] : cf_coefficients(c->p, c->q, c->dp, c->dq, m);
        double op = near1 ? k.ko + y * k.co : 1.0 - x * k.co, op_d = near1 ? k.dko + y * k.dco : -x * k.dco;
        double dev = k.ce * x, dev_d = k.dce * x;
        double e = op + dev, ed = op_d + dev_d;
        double f = -dev * dodd, fd = -(dev_d * dodd + dev * doddd);
        dual A = {e * A1.v + f * A0.v, ed * A1.v + e * A1.d + fd * A0.v + f * A0.d};
        dual B = {e * B1.v + f * B0.v, ed * B1.v + e * B1.d + fd * B0.v + f * B0.d};
        A0 = A1, A1 = A, B0 = B1, B1 = B;
        dodd = -x * k.co, doddd = -x * k.dco;
        double rb = 1.0 / B.v;
        dual Rn = {A.v * rb, (A.d - A.v * rb * B.d) * rb};
        int done = fabs(Rn.v - R.v) <= eps * fabs(Rn.v) && fabs(Rn.d - R.d) <= eps * (fabs(Rn.d) + fabs(Rn.v));
        R = Rn;
        if (done)
            break;
        double bm = fabs(B.v);
        if (bm > 1e100 || bm < 1e-100) {          /* keep them normal numbers: only their ratio counts */
            double s = bm > 1.0 ? 1e-100 : 1e100; /* (at large p they shrink by ~1/2 a term) */
            A0.v *= s, A0.d *= s, A1.v *= s, A1.d *= s, B0.v *= s, B0.d *= s, B1.v *= s, B1.d *= s;
        }
    }
    return R;
}

/* log(1 + u) for u >= 0: log1p only where 1 + u would round away u's digits; log, about
 * twice as fast, elsewhere (it is called three times a sample). */
static inline double log_1p(double u)
{
    return u < 0.5 ? log1p(u) : log(1.0 + u);
}

/* Constants of one gamma, shared by every sample of a block. */
typedef struct std_const {
    double a;             /* gamma - 1 */
    double ib;            /* 1 / B(a, 1/2) */
    double pa;            /* psi(a + 1/2) - psi(a) */
    double isa;           /* 1 / sqrt(a) */
    double ka, dlogka;    /* A(z) z (1 + z^2/a)^(a - 1/2) and its log-derivative in gamma */
    cf_side direct, flip; /* I_x(a, 1/2) and I_(1-x)(1/2, a), derivatives in a */
} std_const;

/* log(Gamma(a + 1/2) / Gamma(a)) and psi(a + 1/2) - psi(a) - 1/(2a): from lgamma and
 * digamma, or for a >= 30 from their asymptotic series (Stirling's with the Bernoulli
 * polynomials at 1/2), which keep the digits the differences would cancel (at gamma = 1e6
 * the difference of digammas lost half of them, and dLambda/dgamma with them). */
static void gamma_ratio(double a, double *lr, double *pd)
{
    if (a < 30.0) {
        *lr = lgamma(a + 0.5) - lgamma(a);
        *pd = digamma(a + 0.5) - digamma(a) - 0.5 / a;
        return;
    }
    double f = 1.0 / a, f2 = f * f;
    *lr =
        0.5 * log(a) + f * (-1.0 / 8 + f2 * (1.0 / 192 + f2 * (-1.0 / 640 + f2 * (17.0 / 14336 - f2 * 31.0 / 18432))));
    *pd = f2 * (1.0 / 8 + f2 * (-1.0 / 64 + f2 * (1.0 / 128 + f2 * (-17.0 / 2048 + f2 * 31.0 / 2048))));
}

static std_const std_constants(double gamma)
{
    std_const c;
    c.a = gamma - 1.0;
    double lr, pd;
    gamma_ratio(c.a, &lr, &pd);
    c.ib = exp(lr) / sqrt(M_PI); /* Gamma(1/2) = sqrt(pi) */
    c.pa = pd + 0.5 / c.a;
    c.isa = 1.0 / sqrt(c.a);
    c.ka = sqrt(c.a) * c.ib / (2.0 * c.a - 1.0);
    c.dlogka = pd - 1.0 / (c.a * (2.0 * c.a - 1.0)); /* 1/(2a) + psi(a+1/2) - psi(a) - 2/(2a-1) */
    cf_side_init(&c.direct, c.a, 0.5, 1.0, 0.0);
    cf_side_init(&c.flip, 0.5, c.a, 0.0, 1.0);
    return c;
}

/* Smith Lambda of the STD slopes at z = 1 / (alpha tan(theta)) (header comment), with
 * *dz = dLambda/dz and *dg = dLambda/dgamma (dz NULL: the value alone). With w = z^2/a,
 * x = 1/(1 + w) and 1 - x = w/(1 + w), so every power of x and 1 - x is E = (1 + w)^-(a +
 * 1/2) times powers of (1 + w) and sqrt(w): one exp and one log a call. */
static double std_lambda(const std_const *c, double z, double *dz, double *dg)
{
    const double a = c->a;
    double w = z * z / a, l1w = log_1p(w);
    double E = exp(-(a + 0.5) * l1w);
    if (E == 0.0) { /* A underflows, and Lambda <= A with it: G1 = 1 */
        if (dz)
            *dz = *dg = 0.0;
        return 0.0;
    }
    double sw = z * c->isa;
    double A = c->ka / z * E * (1.0 + w);
    double dlogA = c->dlogka - l1w + (a - 0.5) * w / (a * (1.0 + w));
    double front = E * sw * c->ib; /* x^a (1 - x)^(1/2) / B(a, 1/2) */
    double x = 1.0 / (1.0 + w), y = w / (1.0 + w);
    if (!dz) { /* the value alone */
        double I = w > 1.5 / (a + 1.0) ? front / (a * beta_cf(&c->direct, x, y).v)
                                       : 1.0 - 2.0 * front / beta_cf(&c->flip, y, x).v;
        return A - 0.5 * I;
    }
    double I, dI;
    if (w > 1.5 / (a + 1.0)) { /* x < (a + 1)/(a + 2.5): I's own fraction converges */
        dual T = beta_cf(&c->direct, x, y);
        I = front / (a * T.v);
        dI = I * (c->pa - l1w - 1.0 / a - T.d / T.v);
    } else { /* I_x(a, 1/2) = 1 - I_(1-x)(1/2, a) */
        dual T = beta_cf(&c->flip, y, x);
        double r = 2.0 * front / T.v;
        I = 1.0 - r;
        dI = -r * (c->pa - l1w - T.d / T.v);
    }
    /* dS/dgamma = (dI/da + dI/dx dx/dgamma) / 2, where dI/dx dx/dgamma = E ib sqrt(w) / a. */
    double S = 0.5 * I;
    double dS = 0.5 * (dI + E * c->ib * sw / a);
    *dz = -A / z; /* d/dz (1/z) int_z^inf (q - z) P(q) dq = -(Lambda + tail) / z = -A / z */
    *dg = A * dlogA - dS;
    return A - S;
}

/* G1 of a direction at cos = cz, sin^2 = s2, and (da not NULL) its derivatives in alpha
 * and gamma. */
static double std_g1(const std_const *c, double alpha, double cz, double s2, double *da, double *dg)
{
    if (s2 <= 0.0 || cz * 1e-150 >= alpha * sqrt(s2)) { /* normal incidence: z = inf */
        if (da)
            *da = *dg = 0.0;
        return 1.0;
    }
    double z = cz / (alpha * sqrt(s2));
    double lz, lg;
    double L = std_lambda(c, z, da ? &lz : NULL, &lg);
    double G = 1.0 / (1.0 + L);
    if (da) {
        *da = G * G * lz * z / alpha; /* dz/dalpha = -z/alpha */
        *dg = -G * G * lg;
    }
    return G;
}

/* D and its derivatives in alpha and gamma; nh, sin2h as in terms.h. */
static double std_d(double nh, double sin2h, double alpha, double gamma, double *da, double *dg)
{
    double c2 = nh * nh, a2 = alpha * alpha, gm1 = gamma - 1.0;
    double u = sin2h / (c2 * gm1 * a2);
    double l1u = log_1p(u);
    double D = exp(-gamma * l1u) / (M_PI * a2 * c2 * c2);
    double r = gamma * u / (1.0 + u);
    *da = D * (2.0 * r - 2.0) / alpha;
    *dg = D * (r / gm1 - l1u);
    return D;
}

/* One lobe over a block (a bf_lobe_fn: family.h says why eight arguments). Scalars:
 * s[0] = alpha, s[1] = gamma, s[2] = f0 or ior unless fresnel=none. */
static void lobe(const bf_model *m, int k, const double *s, const bf_geometry *g, size_t i0, size_t cnt, double *S,
                 double *dS)
{
    (void)k;
    const int fk = m->opt[0];
    const double alpha = s[0], gamma = s[1], fp = fk != BF_FRESNEL_NONE ? s[2] : 0.0;
    const std_const c = std_constants(gamma);
    const double *lx = g->lx + i0, *ly = g->ly + i0, *lz = g->lz + i0;
    const double *vx = g->vx + i0, *vy = g->vy + i0, *vz = g->vz + i0;
    const double *hz = g->hz + i0, *s2h = g->sin2h + i0, *vh = g->vh + i0;
    for (size_t j = 0; j < cnt; j++) {
        if (!(lz[j] > 0.0 && vz[j] > 0.0)) {
            S[j] = 0.0;
            if (dS)
                for (int p = 0; p < 3; p++)
                    dS[p * BF_BLOCK + j] = 0.0;
            continue;
        }
        double Dda, Ddg, lda = 0.0, ldg = 0.0, vda = 0.0, vdg = 0.0, dF;
        double D = std_d(hz[j], s2h[j], alpha, gamma, &Dda, &Ddg);
        double gl = std_g1(&c, alpha, lz[j], lx[j] * lx[j] + ly[j] * ly[j], dS ? &lda : NULL, &ldg);
        double gv = std_g1(&c, alpha, vz[j], vx[j] * vx[j] + vy[j] * vy[j], dS ? &vda : NULL, &vdg);
        double F = bf_fresnel(fk, vh[j], fp, &dF);
        double inv = 0.25 / (lz[j] * vz[j]);
        double G = gl * gv;
        S[j] = D * G * F * inv;
        if (dS) {
            dS[j] = (Dda * G + D * (lda * gv + gl * vda)) * F * inv;
            dS[BF_BLOCK + j] = (Ddg * G + D * (ldg * gv + gl * vdg)) * F * inv;
            if (fk != BF_FRESNEL_NONE)
                dS[2 * BF_BLOCK + j] = D * G * dF * inv;
        }
    }
}

static bf_status configure(bf_model *m, bf_error *err)
{
    m->energy_conserving = 1; /* header comment */
    const int fk = m->opt[0];
    bf_status rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err);
    for (int k = 1; rc == BF_OK && k <= m->lobes; k++) {
        /* alpha as walter's; gamma from just above 3/2, where the mean slope and with it
         * Lambda diverge, to where STD is Beckmann to 1e-6; 2 is GGX. */
        if ((rc = bf_model_add_param(m, "rho_s", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, k, BF_ROLE_WEIGHT, err)) ||
            (rc = bf_model_add_param(m, "alpha", 0, 1e-4, 1.0, 0.12 * k, BF_SCALE_LOG, k, BF_ROLE_ROUGHNESS, err)) ||
            (rc = bf_model_add_param(m, "gamma", 0, 1.51, 1e6, 2.0, BF_SCALE_LOG, k, BF_ROLE_SHAPE, err)))
            break;
        rc = bf_model_add_fresnel_param(m, fk, k, err);
    }
    return rc;
}

static const bf_option_info options[] = {{"fresnel", bf_fresnel_values, 0}, {NULL, NULL, 0}};

const bf_family bf_family_student_t = {
    .info = {.name = "student_t",
             .summary = "Student-t slope distribution (GGX to Beckmann by gamma), exact Smith masking, Fresnel",
             .reference = "Ribardiere et al. 2017",
             .options = options,
             .lobes = 1,
             .anisotropic = 0},
    .configure = configure,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe,
};
