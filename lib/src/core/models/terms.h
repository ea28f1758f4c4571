/* Shared BRDF terms (docs/models.md, "Shared terms"), each with its derivative with
 * respect to its own parameter. Geometry arguments come from bf_geometry; everything
 * here assumes a valid sample (N.L > 0, N.V > 0). Inline so the model loops can
 * vectorise. */
#ifndef BF_TERMS_H
#define BF_TERMS_H

#include <math.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* ---- Geometry helpers ---------------------------------------------------------- */

/* log(N.H) to full relative precision: from sin^2(theta_h) near the peak, where NH
 * rounds to 1 and an exponent of 1e6 would amplify that rounding; from NH itself towards
 * the horizon, where 1 - sin2h would cancel. */
static inline double bf_log_nh(double nh, double sin2h)
{
    return sin2h < 0.5 ? 0.5 * log1p(-sin2h) : log(nh);
}

/* ---- Fresnel ---------------------------------------------------------------- */

enum { BF_FRESNEL_SCHLICK = 0, BF_FRESNEL_DIELECTRIC = 1, BF_FRESNEL_NONE = 2, BF_FRESNEL_CONDUCTOR = 3 };

/* The option values shared by every family with a `fresnel=` option (order = enum),
 * and those of the microfacet family, which adds conductor (its lobe is then coloured
 * by F, per channel: the lobe driver evaluates it channel by channel). */
extern const char *const bf_fresnel_values[];
extern const char *const bf_fresnel_metal_values[];

/* Gulbrandsen 2014 ("Artist friendly metallic Fresnel", JCGT 3(4)): the complex index
 * n + ik whose normal-incidence reflectance is r and whose edge tint is g, r in (0, 1),
 * g in (0, 1]. d[0..3] (may be NULL): dn/dr, dn/dg, dk/dr, dk/dg (k > 0). */
void bf_conductor_nk(double r, double g, double *n, double *k, double d[4]);

/* Exact unpolarised Fresnel reflectance of a conductor n + ik (from n, k = the mapping
 * above) at c = V.H; *dr, *dg (may be NULL) = dF/dr, dF/dg through the mapping. */
double bf_conductor(double c, double r, double g, double *dr, double *dg);

/* Schlick: F = f0 + (1 - f0)(1 - u)^5; *dF = dF/df0. */
static inline double bf_schlick(double u, double f0, double *dF)
{
    double m = 1.0 - u;
    m = m < 0.0 ? 0.0 : m;
    double m5 = m * m * m * m * m;
    if (dF)
        *dF = 1.0 - m5;
    return f0 + (1.0 - f0) * m5;
}

/* Upper bound of a dielectric Fresnel's index of refraction. Measured materials fitted
 * with a dielectric Fresnel, metals above all, need effective indices far above those of
 * real dielectrics: a normal reflectance F0 = ((n-1)/(n+1))^2 of 0.9 (aluminium) is
 * n = 38, and 100 is F0 = 0.961 (silver's visible F0 is about 0.95-0.97). Löw et al.
 * 2012's published MERL fits reach 10.1 (Cook-Torrance, Ashikhmin-Shirley, smooth model)
 * and 99.9996 (their microfacet model, apparently at their own bound of 100). The
 * Fresnel below and its derivative stay accurate to the bound (tests/test_terms.c);
 * the log scale gives 1.5 and 50 the same relative step. */
#define BF_IOR_MAX 100.0

/* Dielectric Fresnel (Cook & Torrance 1982) for c = V.H and index ior >= 1;
 * *dF = dF/dior. */
static inline double bf_dielectric(double c, double ior, double *dF)
{
    /* g - c written as (ior^2 - 1)/(g + c): the literal difference loses everything to
     * rounding when ior - 1 is comparable to c^2 (ior = 1 at grazing gave F ~ 1e-13
     * instead of 0, which a sharp lobe then amplified). */
    double e = (ior - 1.0) * (ior + 1.0);
    double g2 = e + c * c;
    double g = sqrt(g2 > 0.0 ? g2 : 0.0);
    double gpc = g + c;
    double gmc = gpc > 0.0 ? e / gpc : 0.0;
    double A = gpc > 0.0 ? gmc / gpc : 0.0;
    double Bn = c * gpc - 1.0, Bd = c * gmc + 1.0;
    double B = Bn / Bd;
    double F = 0.5 * A * A * (1.0 + B * B);
    if (dF) {
        if (g > 0.0 && gpc > 0.0) {
            double dA = 2.0 * c / (gpc * gpc);
            double dB = c * (2.0 - 2.0 * c * c) / (Bd * Bd);
            double dFdg = A * dA * (1.0 + B * B) + A * A * B * dB;
            *dF = dFdg * ior / g;
        } else {
            *dF = 0.0;
        }
    }
    return F;
}

/* Fresnel of the given kind with its parameter p (f0 or ior; ignored for none). */
static inline double bf_fresnel(int kind, double u, double p, double *dF)
{
    if (kind == BF_FRESNEL_SCHLICK)
        return bf_schlick(u, p, dF);
    if (kind == BF_FRESNEL_DIELECTRIC)
        return bf_dielectric(u, p, dF);
    if (dF)
        *dF = 0.0;
    return 1.0;
}

/* ---- Shadowing -------------------------------------------------------------- */

/* V-groove: min(1, 2 NH NV / VH, 2 NH NL / VH). No parameters. */
static inline double bf_g_ct(double nh, double nl, double nv, double vh)
{
    double a = 2.0 * nh * nv / vh, b = 2.0 * nh * nl / vh;
    double g = a < b ? a : b;
    return g < 1.0 ? g : 1.0;
}

/* Smith-GGX G1 = 2 / (1 + sqrt(1 + a^2 tan^2)), tan2 = tan^2(theta_w); *dG = dG1/da. */
static inline double bf_g1_ggx(double tan2, double a, double *dG)
{
    double r = sqrt(1.0 + a * a * tan2);
    double g = 2.0 / (1.0 + r);
    if (dG)
        *dG = -g / (1.0 + r) * (a * tan2 / r);
    return g;
}

/* Smith-Beckmann G1, Walter's rational fit: c = cos / (m sin); 1 for c >= 1.6.
 * cosw, sinw: cosine and sine of the direction's angle to N. *dG = dG1/dm. */
static inline double bf_g1_beckmann(double cosw, double sinw, double m, double *dG)
{
    if (m * sinw * 1.6 <= cosw) { /* c >= 1.6, also covers sinw = 0 */
        if (dG)
            *dG = 0.0;
        return 1.0;
    }
    double c = cosw / (m * sinw);
    double num = 3.535 * c + 2.181 * c * c;
    double den = 1.0 + 2.276 * c + 2.577 * c * c;
    if (dG) {
        double dGdc = ((3.535 + 4.362 * c) * den - num * (2.276 + 5.154 * c)) / (den * den);
        *dG = dGdc * (-c / m);
    }
    return num / den;
}

/* Smith-Schlick G1 = cos / (cos (1 - k) + k), k = m sqrt(2/pi). *dG = dG1/dm. */
static inline double bf_g1_schlick(double cosw, double m, double *dG)
{
    const double s = 0.79788456080286535588; /* sqrt(2/pi) */
    double k = m * s;
    double den = cosw * (1.0 - k) + k;
    if (dG)
        *dG = -cosw * (1.0 - cosw) / (den * den) * s;
    return cosw / den;
}

/* ---- Normal distributions ----------------------------------------------------- */

/* Beckmann D_b(m) = exp(-tan^2/m^2) / (pi m^2 cos^4). nh = cos(theta_h),
 * sin2h = sin^2(theta_h) (from H.X, H.Y, not 1 - nh^2). *dD = dD/dm. */
static inline double bf_d_beckmann(double nh, double sin2h, double m, double *dD)
{
    double c2 = nh * nh;
    double t2 = sin2h / c2;
    double m2 = m * m;
    double D = exp(-t2 / m2) / (M_PI * m2 * c2 * c2);
    if (dD)
        *dD = D * (2.0 * t2 / (m2 * m) - 2.0 / m);
    return D;
}

/* GGX D_g(a) = a^2 / (pi (NH^2 (a^2 - 1) + 1)^2), with the bracket written as
 * sin2h + a^2 NH^2 to avoid cancellation near the peak. *dD = dD/da. */
static inline double bf_d_ggx(double nh, double sin2h, double a, double *dD)
{
    double a2 = a * a;
    double t = sin2h + a2 * nh * nh;
    double D = a2 / (M_PI * t * t);
    if (dD)
        *dD = 2.0 * a / (M_PI * t * t) * (1.0 - 2.0 * a2 * nh * nh / t);
    return D;
}

/* Normalised Blinn D = (n+2)/(2 pi) NH^n, with NH^n = exp(n log NH) (bf_log_nh). *dD = dD/dn. */
static inline double bf_d_blinn(double nh, double sin2h, double n, double *dD)
{
    double lg = bf_log_nh(nh, sin2h);
    double p = n > 0.0 ? exp(n * lg) : 1.0; /* pow(NH, 0) = 1 */
    double D = (n + 2.0) / (2.0 * M_PI) * p;
    if (dD)
        *dD = p / (2.0 * M_PI) + D * lg;
    return D;
}

/* Gaussian highlight exp(-(theta_h/m)^2) / (pi m^2). *dD = dD/dm. */
static inline double bf_d_gaussian(double nh, double sin2h, double m, double *dD)
{
    double th = atan2(sqrt(sin2h), nh);
    double r = th / m;
    double D = exp(-r * r) / (M_PI * m * m);
    if (dD)
        *dD = D * (2.0 * r * r - 2.0) / m;
    return D;
}

#endif
