/* Ashikhmin & Shirley 2000 anisotropic Phong BRDF:
 *   specular  sqrt((nu+1)(nv+1))/(8 pi) NH^e / (VH max(NL, NV)) F_s(VH; rho_s),
 *             e = (nu (H.X)^2 + nv (H.Y)^2) / (1 - NH^2)
 *   diffuse   28 rho_d/(23 pi) (1 - rho_s)(1 - (1 - NL/2)^5)(1 - (1 - NV/2)^5)
 * rho_s is both the Fresnel reflectance at normal incidence and the diffuse attenuation,
 * so the model does not fit the diffuse + lobes driver: it has its own evaluator.
 * The isotropic variant is nu = nv = n, where e = n exactly.
 * diffuse=lambert (Ngan et al. 2005's variant, for their published fits) decouples them:
 *   f = rho_d/pi + rho_s sqrt((nu+1)(nv+1))/(8 pi) NH^e / (VH max(NL, NV)) F_s(VH; f0),
 * rho_s a weight, f0 Schlick's reflectance at normal incidence. Energy conserving in both
 * forms: the lobe without F is AS's half-vector density p(H) / (4 VH) times
 * NL / max(NL, NV) <= 1, so its albedo is at most rho_s.
 * fresnel=dielectric (Löw et al. 2012's fits, as bbm's LowAshikhminShirley) puts the
 * dielectric F_d(VH; ior) in place of Schlick's, rho_s then weighing the lobe in both
 * forms (coupled: rho_s F_d <= rho_s <= F_s(VH; rho_s), so still conserving). */
#include "family.h"
#include "terms.h"

#include <math.h>
#include <string.h>

/* Parameter table order (both variants): rho_d, rho_s, then nu, nv (or n), then f0 with
 * diffuse=lambert. */
enum { P_RHO_D, P_RHO_S, P_NU, P_NV };

enum { DIFFUSE_COUPLED = 0, DIFFUSE_LAMBERT };
static const char *const diffuse_values[] = {"coupled", "lambert", NULL};
/* Quiet default: specs written before the option keep their bytes. */
static const char *const fresnel_values[] = {"schlick", "dielectric", NULL}; /* BF_FRESNEL_* order */
static const bf_option_info options[] = {
    {"diffuse", diffuse_values, 1}, {"fresnel", fresnel_values, 1}, {NULL, NULL, 0}};

/* The lobe's exponents and normalisation knorm, with d log(knorm)/d nu, d nv. */
typedef struct as_shape {
    double nu, nv, knorm, dlk_nu, dlk_nv;
    int iso;
} as_shape;

static as_shape shape_of(double nu, double nv, int iso)
{
    as_shape k = {nu, nv, 0.0, 0.0, 0.0, iso};
    k.knorm = (iso ? nu + 1.0 : sqrt((nu + 1.0) * (nv + 1.0))) / (8.0 * M_PI);
    /* For iso knorm = (n+1)/(8 pi). */
    k.dlk_nu = iso ? 1.0 / (nu + 1.0) : 0.5 / (nu + 1.0);
    k.dlk_nv = 0.5 / (nv + 1.0);
    return k;
}

/* The specular lobe without Fresnel at valid sample i, knorm NH^e / (VH max(NL, NV)),
 * with *dl_nu, *dl_nv = its d log / d nu, d nv. */
static inline double spec_unit(const as_shape *k, const bf_geometry *g, size_t i, double *dl_nu, double *dl_nv)
{
    double nl = g->lz[i], nv_ = g->vz[i];
    double s2 = g->sin2h[i], hz = g->hz[i], vh = g->vh[i];
    double lnh = bf_log_nh(hz, s2);
    /* Weights of nu and nv in e: cos^2 and sin^2 of phi_h. At H = N (s2 = 0) NH^e = 1
     * for any e; lnh = 0 there, so any finite weights do, and the exponent's
     * derivatives vanish. */
    double wx = 0.5, wy = 0.5;
    if (s2 > 0.0) {
        wx = g->hx[i] * g->hx[i] / s2;
        wy = g->hy[i] * g->hy[i] / s2;
    }
    double e = k->iso ? k->nu : k->nu * wx + k->nv * wy;
    double ph = exp(e * lnh); /* underflows cleanly to 0 for huge e */
    double den = vh * (nl > nv_ ? nl : nv_);
    /* 0 where ph underflowed, where lnh may be -Inf. */
    *dl_nu = ph > 0.0 ? k->dlk_nu + (k->iso ? lnh : lnh * wx) : 0.0;
    *dl_nv = ph > 0.0 ? k->dlk_nv + lnh * wy : 0.0;
    return ph > 0.0 ? k->knorm * ph / den : 0.0;
}

/* The family's eval (family.h's arguments) for both variants, iso saying which. */
static void eval_common(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1, double *values,
                        double *grad, int iso)
{
    const int C = m->channels, P = m->nfree;
    const int lambert = m->opt[0] == DIFFUSE_LAMBERT, diel = m->opt[1] == BF_FRESNEL_DIELECTRIC;
    const double *rho_d = x + m->offset[P_RHO_D];
    const double *rho_s = x + m->offset[P_RHO_S];
    const int o_d = m->offset[P_RHO_D], o_s = m->offset[P_RHO_S];
    const int o_nu = m->offset[P_NU], o_nv = iso ? -1 : m->offset[P_NV];
    /* diffuse=lambert: f0 follows the exponents; fresnel=dielectric: ior does. */
    const int o_f0 = lambert || diel ? m->offset[iso ? P_NV : P_NV + 1] : -1;
    const double f0 = o_f0 >= 0 ? x[o_f0] : 0.0;
    const as_shape k = shape_of(x[o_nu], iso ? x[o_nu] : x[o_nv], iso);
    const double kd = lambert ? 1.0 / M_PI : 28.0 / (23.0 * M_PI);

    for (size_t i = i0; i < i1; i++) {
        double *row0 = grad ? grad + (i - i0) * (size_t)C * (size_t)P : NULL;
        if (row0)
            memset(row0, 0, (size_t)C * (size_t)P * sizeof *row0);
        double nl = g->lz[i], nv_ = g->vz[i];
        if (!(nl > 0.0 && nv_ > 0.0)) {
            for (int c = 0; c < C; c++)
                values[(i - i0) * (size_t)C + (size_t)c] = 0.0;
            continue;
        }
        double dl_nu, dl_nv;
        double spec0 = spec_unit(&k, g, i, &dl_nu, &dl_nv); /* specular without Fresnel */
        double m5 = 1.0 - g->vh[i];
        m5 = m5 < 0.0 ? 0.0 : m5;
        m5 = m5 * m5 * m5 * m5 * m5; /* (1 - VH)^5 */
        double diff0 = kd;           /* diffuse per unit rho_d: Lambert's, or (1 - rho_s) times */
        if (!lambert) {
            double al = 1.0 - 0.5 * nl, av = 1.0 - 0.5 * nv_;
            diff0 *= (1.0 - al * al * al * al * al) * (1.0 - av * av * av * av * av);
        }

        for (int c = 0; c < C; c++) {
            double rs = rho_s[c], rd = rho_d[c];
            /* coupled: rho_s is Schlick's F0 and attenuates the diffuse; lambert: rho_s
             * weighs the lobe, f0 is Schlick's F0, the diffuse is plain. */
            double dFd = 0.0;
            double F = diel ? bf_dielectric(g->vh[i], f0, &dFd) : lambert ? f0 + (1.0 - f0) * m5 : rs + (1.0 - rs) * m5;
            double w = lambert || diel ? rs : 1.0, att = lambert ? 1.0 : 1.0 - rs;
            double spec = w * spec0 * F;
            values[(i - i0) * (size_t)C + (size_t)c] = spec + rd * att * diff0;
            if (row0) {
                double *row = row0 + (size_t)c * (size_t)P;
                row[o_d + c] = att * diff0;
                row[o_s + c] = lambert ? spec0 * F : (diel ? spec0 * F : spec0 * (1.0 - m5)) - rd * diff0;
                row[o_nu] = spec * dl_nu;
                if (!iso)
                    row[o_nv] = spec * dl_nv;
                if (o_f0 >= 0)
                    row[o_f0] += rs * spec0 * (diel ? dFd : 1.0 - m5);
            }
        }
    }
}

static void eval_aniso(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1, double *values,
                       double *grad)
{
    eval_common(m, x, g, i0, i1, values, grad, 0);
}

static void eval_iso(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1, double *values,
                     double *grad)
{
    eval_common(m, x, g, i0, i1, values, grad, 1);
}

/* diffuse=lambert: Schlick's F0 as a parameter of its own, outside the colours;
 * fresnel=dielectric: the index of refraction instead (either diffuse form). */
static bf_status add_f0(bf_model *m, bf_error *err)
{
    if (m->opt[1] == BF_FRESNEL_DIELECTRIC)
        return bf_model_add_fresnel_param(m, BF_FRESNEL_DIELECTRIC, 0, err);
    return m->opt[0] == DIFFUSE_LAMBERT ? bf_model_add_fresnel_param(m, BF_FRESNEL_SCHLICK, 0, err) : BF_OK;
}

/* Exponents: [1, 1e6] on a log scale for the coupled form (the lower bound keeps them
 * away from 0); diffuse=lambert reaches down to 0 (Ngan's published fits go to 0.5; the
 * lobe is finite there), on the LOG1P scale as the other Phong-like exponents. */
static bf_status add_exponent(bf_model *m, const char *name, bf_error *err)
{
    if (m->opt[0] == DIFFUSE_LAMBERT)
        return bf_model_add_param(m, name, 0, 0.0, 1e6, 50.0, BF_SCALE_LOG1P, 0, BF_ROLE_EXPONENT, err);
    return bf_model_add_param(m, name, 0, 1.0, 1e6, 50.0, BF_SCALE_LOG, 0, BF_ROLE_EXPONENT, err);
}

static bf_status configure_aniso(bf_model *m, bf_error *err)
{
    m->energy_conserving = 1; /* both diffuse forms: docs/models.md */
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "rho_s", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_WEIGHT, err)) ||
        (rc = add_exponent(m, "nu", err)) || (rc = add_exponent(m, "nv", err)))
        return rc;
    return add_f0(m, err);
}

static bf_status configure_iso(bf_model *m, bf_error *err)
{
    m->energy_conserving = 1; /* both diffuse forms: docs/models.md */
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "rho_s", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_WEIGHT, err)) ||
        (rc = add_exponent(m, "n", err)))
        return rc;
    return add_f0(m, err);
}

const bf_family bf_family_ashikhmin_shirley = {
    .info = {.name = "ashikhmin_shirley",
             .summary = "Ashikhmin-Shirley anisotropic Phong, Fresnel-coupled (or Lambertian) diffuse",
             .reference = "Ashikhmin & Shirley 2000",
             .options = options,
             .lobes = 0,
             .anisotropic = 1},
    .configure = configure_aniso,
    .eval = eval_aniso,
};

const bf_family bf_family_ashikhmin_shirley_iso = {
    .info = {.name = "ashikhmin_shirley_iso",
             .summary = "Ashikhmin-Shirley isotropic Phong, Fresnel-coupled (or Lambertian) diffuse",
             .reference = "Ashikhmin & Shirley 2000",
             .options = options,
             .lobes = 0,
             .anisotropic = 0},
    .configure = configure_iso,
    .eval = eval_iso,
};
