/* Terms the renderers' principled BSDFs share (blender_principled, mitsuba_principled),
 * each with its derivative: Burley's diffuse with retro-reflection as Cycles and Mitsuba
 * write it, the specular-to-index mapping both use, and GTR1's normalisation. Assumes a
 * valid sample, as terms.h does. */
#ifndef BF_PRINCIPLED_H
#define BF_PRINCIPLED_H

#include <math.h>

#include "terms.h"

/* Schlick's weight clamp(1 - u, 0, 1)^5. */
static inline double bf_schlick_weight(double u)
{
    double t = 1.0 - u;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    double t2 = t * t;
    return t2 * t2 * t;
}

/* Diffuse shape (times base_color / pi) with retro-reflection, FL, FV the Schlick
 * weights of NL and NV, lv1 = 1 + L.V = 2 VH^2:
 *   (1 - FL/2)(1 - FV/2) + RR (FL + FV + FL FV (RR - 1)),  RR = roughness lv1.
 * *d = d / d roughness. */
static inline double bf_principled_diffuse(double FL, double FV, double lv1, double rough, double *d)
{
    double RR = rough * lv1;
    *d = lv1 * (FL + FV + FL * FV * (2.0 * RR - 1.0));
    return (1.0 - 0.5 * FL) * (1.0 - 0.5 * FV) + RR * (FL + FV + FL * FV * (RR - 1.0));
}

/* The exact dielectric Fresnel term at c = V.H for the index both renderers derive from
 * `specular`, eta = 2 / (1 - sqrt(0.08 specular)) - 1 (so F0 = 0.08 specular);
 * *d = d / d specular. At specular 0 (eta 1, F = 0) the chain rule is 0 times infinity:
 * its limit, 0.04 (1 + (2c^2 - 1)^2) / c^4, comes from F ~ q^2 (1 + B^2) / (2 c^4) with
 * q = sqrt(0.08 specular). */
static inline double bf_dielectric_of_specular(double c, double spec, double *d)
{
    double q = sqrt(0.08 * spec);
    double eta = 2.0 / (1.0 - q) - 1.0, dFe;
    double F = bf_dielectric(c, eta, &dFe);
    if (q > 0.0) {
        *d = dFe * 2.0 / ((1.0 - q) * (1.0 - q)) * 0.04 / q;
    } else {
        double b = 2.0 * c * c - 1.0, c2 = c * c;
        *d = 0.04 * (1.0 + b * b) / (c2 * c2);
    }
    return F;
}

/* GTR1's (x - 1) / ln x for x = width^2 (the D is this over pi t, t = sin^2(theta_h) +
 * x NH^2), and *d = its derivative, continued through x = 1 (where the renderers switch
 * to the limit, a flat 1/pi) by the series. */
static inline double bf_gtr1_norm(double x, double *d)
{
    double u = x - 1.0;
    if (fabs(u) < 1e-4) {
        *d = 0.5 - u / 6.0 + u * u / 8.0;
        return 1.0 + u / 2.0 - u * u / 12.0;
    }
    double l = log(x);
    *d = (l - u / x) / (l * l);
    return u / l;
}

#endif
