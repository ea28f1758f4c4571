/* Ward 1992 anisotropic Gaussian lobe (as in Walter's 2005 notes) and its isotropic
 * special case:
 *   f = rho_d/pi + rho_s exp(-((H.X/ax)^2 + (H.Y/ay)^2) / NH^2) / (4 pi ax ay sqrt(NL NV)).
 * norm=duer divides by NL NV instead of sqrt(NL NV): Duer's 2006 normalisation as Ngan et
 * al. 2005 fitted it (bbm's WardDuer), so that their published fits evaluate exactly.
 * Both use the shared diffuse + lobe driver; the lobe shapes below are per sample.
 * Not energy conserving: 1/sqrt(NL NV) (1/(NL NV) all the more) lets the albedo exceed 1
 * at grazing. */
#include "family.h"
#include "terms.h"

#include <math.h>

enum { NORM_WARD = 0, NORM_DUER };
static const char *const norm_values[] = {"ward", "duer", NULL};
/* Quiet default: ward and ward_iso specs written before the option keep their bytes. */
static const bf_option_info options[] = {{"norm", norm_values, 1}, {NULL, NULL, 0}};

/* The lobe's cosine factor: sqrt(NL NV) as sqrt(NL) sqrt(NV), so that the product
 * cannot underflow for tiny cosines, or NL NV for norm=duer. */
static inline double cos_factor(int duer, double lz, double vz)
{
    return duer ? lz * vz : sqrt(lz) * sqrt(vz);
}

/* exp(-t) with t = tx + ty, tx = (H.X/ax)^2/NH^2. NH > 0 on every valid sample, but
 * near the horizon t can be huge or Inf: the exponential then underflows to 0 and the
 * derivatives (t-weighted) are set to 0 rather than 0 * Inf (H on the horizon has
 * H.X or H.Y nonzero, so t = Inf there). */
/* A bf_lobe_fn (family.h: why eight arguments). */
static void lobe_aniso(const bf_model *m, int lobe, const double *s, const bf_geometry *g, size_t i0, size_t cnt,
                       double *S, double *dS)
{
    (void)lobe;
    const int duer = m->opt[0] == NORM_DUER;
    const double ax = s[0], ay = s[1];
    const double iax2 = 1.0 / (ax * ax), iay2 = 1.0 / (ay * ay);
    const double norm = 1.0 / (4.0 * M_PI * ax * ay);
    for (size_t j = 0; j < cnt; j++) {
        size_t i = i0 + j;
        double hz = g->hz[i], lz = g->lz[i], vz = g->vz[i];
        double v = 0.0, dax = 0.0, day = 0.0;
        if (lz > 0.0 && vz > 0.0) {
            /* Divide by NH^2 rather than multiply by its reciprocal, which overflows
             * for NH below 1e-154 and would give 0 * Inf for H.Y = 0. */
            double hz2 = hz * hz;
            double qx = g->hx[i] * g->hx[i] * iax2, qy = g->hy[i] * g->hy[i] * iay2;
            double tx = hz2 > 0.0 ? qx / hz2 : INFINITY, ty = hz2 > 0.0 ? qy / hz2 : INFINITY;
            v = exp(-(tx + ty)) * norm / cos_factor(duer, lz, vz);
            if (v > 0.0) {
                /* d/dax: the exponent gives 2 tx / ax, the normalisation -1/ax. */
                dax = v * (2.0 * tx - 1.0) / ax;
                day = v * (2.0 * ty - 1.0) / ay;
            }
        }
        S[j] = v;
        if (dS) {
            dS[j] = dax;
            dS[BF_BLOCK + j] = day;
        }
    }
}

/* A bf_lobe_fn (family.h: why eight arguments). */
static void lobe_iso(const bf_model *m, int lobe, const double *s, const bf_geometry *g, size_t i0, size_t cnt,
                     double *S, double *dS)
{
    (void)lobe;
    const int duer = m->opt[0] == NORM_DUER;
    const double a = s[0];
    const double ia2 = 1.0 / (a * a);
    const double norm = ia2 / (4.0 * M_PI);
    for (size_t j = 0; j < cnt; j++) {
        size_t i = i0 + j;
        double hz = g->hz[i], lz = g->lz[i], vz = g->vz[i];
        double v = 0.0, da = 0.0;
        if (lz > 0.0 && vz > 0.0) {
            double t = g->sin2h[i] * ia2 / (hz * hz); /* tan^2(theta_h) / a^2 */
            v = exp(-t) * norm / cos_factor(duer, lz, vz);
            if (v > 0.0)
                da = v * (2.0 * t - 2.0) / a;
        }
        S[j] = v;
        if (dS)
            dS[j] = da;
    }
}

static bf_status configure_aniso(bf_model *m, bf_error *err)
{
    m->energy_conserving = 0; /* albedo exceeds 1 at grazing incidence */
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "rho_s", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 1, BF_ROLE_WEIGHT, err)) ||
        (rc = bf_model_add_param(m, "alpha_x", 0, 1e-3, 1.0, 0.15, BF_SCALE_LOG, 1, BF_ROLE_ROUGHNESS, err)) ||
        (rc = bf_model_add_param(m, "alpha_y", 0, 1e-3, 1.0, 0.15, BF_SCALE_LOG, 1, BF_ROLE_ROUGHNESS, err)))
        return rc;
    return BF_OK;
}

static bf_status configure_iso(bf_model *m, bf_error *err)
{
    m->energy_conserving = 0; /* albedo exceeds 1 at grazing incidence */
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "rho_s", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 1, BF_ROLE_WEIGHT, err)) ||
        (rc = bf_model_add_param(m, "alpha", 0, 1e-3, 1.0, 0.15, BF_SCALE_LOG, 1, BF_ROLE_ROUGHNESS, err)))
        return rc;
    return BF_OK;
}

const bf_family bf_family_ward = {
    .info = {.name = "ward",
             .summary = "Ward anisotropic Gaussian lobe",
             .reference = "Ward 1992, as in Walter 2005 notes",
             .options = options,
             .lobes = 0,
             .anisotropic = 1},
    .configure = configure_aniso,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe_aniso,
};

const bf_family bf_family_ward_iso = {
    .info = {.name = "ward_iso",
             .summary = "Ward isotropic Gaussian lobe",
             .reference = "Ward 1992, as in Walter 2005 notes",
             .options = options,
             .lobes = 0,
             .anisotropic = 0},
    .configure = configure_iso,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe_iso,
};
