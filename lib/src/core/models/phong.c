/* The Phong family: normalised Phong and Blinn-Phong.
 *   phong:       f = rho_d/pi + rho_s (n+2)/(2 pi) max(0, R.V)^n,  R = 2 NL N - L
 *   blinn_phong: f = rho_d/pi + rho_s (n+2)(n+4) / (8 pi (2^(-n/2) + n)) NH^n
 * Both use the shared diffuse + lobe driver.
 *
 * n = 0 follows pow(0, 0) = 1: the Phong lobe is then the constant 1/pi over the whole
 * hemisphere, R.V <= 0 included (max(0, R.V)^0 = 1). For n > 0 the lobe is 0 wherever
 * R.V <= 0 and locally constant there, so d/dn = 0; at n = 0 exactly on R.V <= 0 the
 * value jumps (1/pi -> 0), and d/dn is reported as 0 rather than the one-sided -Inf.
 *
 * Energy: both are energy conserving. Normalised Phong's albedo is largest at normal
 * incidence, where the lobe integrates to exactly 1 (Lewis 1994). Blinn-Phong's exact
 * normalisation likewise makes the albedo exactly 1 at normal incidence, and (checked
 * by quadrature for n from 0 to 1000, theta_i up to 89.99 degrees) it only decreases
 * towards grazing (Blinn-Phong is often named as a model that is not energy conserving
 * at grazing; for this formula the quadrature says otherwise: docs/models.md). */
#include "family.h"
#include "terms.h"

#include <math.h>

#define INV_2PI (0.5 / M_PI)
/* Powers below exp(-665) (~1e-289) are flushed to 0 with zero derivatives: they carry
 * no information, and letting them decay through subnormals is slow and leaves
 * gradients that no finite difference can resolve. */
#define LOG_TINY (-665.0)

/* Phong: R.V = 1 - |R - V|^2 / 2 for unit R, V, with R = (-Lx, -Ly, Lz); written this
 * way 1 - R.V keeps full relative precision near the mirror direction, where huge
 * exponents need it. The power is exp(n log(R.V)) so it underflows to 0, never 0 * Inf. */
/* A bf_lobe_fn (family.h: why eight arguments). */
static void lobe_phong(const bf_model *m, int lobe, const double *s, const bf_geometry *g, size_t i0, size_t cnt,
                       double *S, double *dS)
{
    (void)m;
    (void)lobe;
    const double n = s[0];
    const double norm = (n + 2.0) * INV_2PI;
    const double inv_n2 = 1.0 / (n + 2.0);
    for (size_t j = 0; j < cnt; j++) {
        size_t i = i0 + j;
        double ax = g->lx[i] + g->vx[i], ay = g->ly[i] + g->vy[i], az = g->lz[i] - g->vz[i];
        double d = 0.5 * (ax * ax + ay * ay + az * az); /* 1 - R.V, in [0, 2] */
        double v, dn;
        if (d < 1.0) {
            double lg = log1p(-d); /* log(R.V) */
            double t = n * lg;
            v = t > LOG_TINY ? norm * exp(t) : 0.0;
            dn = v * (inv_n2 + lg);
        } else { /* R.V <= 0 */
            v = n == 0.0 ? norm : 0.0;
            dn = 0.0;
        }
        S[j] = v;
        if (dS)
            dS[j] = dn;
    }
}

/* Blinn-Phong normalisation N(n) = (n+2)(n+4) / (8 pi (2^(-n/2) + n)) (exact at normal
 * incidence) and d log N / dn. 2^(-n/2) underflows harmlessly for large n. */
static double blinn_norm(double n, double *dlog)
{
    double e = exp2(-0.5 * n);
    double den = e + n;
    *dlog = 1.0 / (n + 2.0) + 1.0 / (n + 4.0) - (1.0 - 0.5 * M_LN2 * e) / den;
    return (n + 2.0) * (n + 4.0) / (8.0 * M_PI * den);
}

/* A bf_lobe_fn (family.h: why eight arguments). */
static void lobe_blinn(const bf_model *m, int lobe, const double *s, const bf_geometry *g, size_t i0, size_t cnt,
                       double *S, double *dS)
{
    (void)m;
    (void)lobe;
    const double n = s[0];
    double dlog;
    const double norm = blinn_norm(n, &dlog);
    for (size_t j = 0; j < cnt; j++) {
        size_t i = i0 + j;
        double nh = g->hz[i], s2 = g->sin2h[i];
        double v = 0.0, dn = 0.0;
        if (nh > 0.0) { /* always so on valid samples */
            double lg = bf_log_nh(nh, s2);
            double t = n * lg;
            v = t > LOG_TINY ? norm * exp(t) : 0.0;
            dn = v * (dlog + lg);
        }
        S[j] = v;
        if (dS)
            dS[j] = dn;
    }
}

static bf_status add_params(bf_model *m, bf_error *err)
{
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "rho_s", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 1, BF_ROLE_WEIGHT, err)) ||
        (rc = bf_model_add_param(m, "n", 0, 0.0, 1e6, 50.0, BF_SCALE_LOG1P, 1, BF_ROLE_EXPONENT, err)))
        return rc;
    return BF_OK;
}

static bf_status configure_phong(bf_model *m, bf_error *err)
{
    m->energy_conserving = 1; /* Lewis 1994: albedo <= rho_s, equality at normal incidence */
    return add_params(m, err);
}

static bf_status configure_blinn(bf_model *m, bf_error *err)
{
    m->energy_conserving = 1; /* albedo <= rho_s, equality at normal incidence */
    return add_params(m, err);
}

const bf_family bf_family_phong = {
    .info = {.name = "phong",
             .summary = "normalised Phong lobe around the mirror direction",
             .reference = "Phong 1975; Lewis 1994 normalisation",
             .options = NULL,
             .lobes = 0,
             .anisotropic = 0},
    .configure = configure_phong,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe_phong,
};

const bf_family bf_family_blinn_phong = {
    .info = {.name = "blinn_phong",
             .summary = "normalised Blinn-Phong half-vector lobe",
             .reference = "Blinn 1977; exact normalisation",
             .options = NULL,
             .lobes = 0,
             .anisotropic = 0},
    .configure = configure_blinn,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe_blinn,
};
