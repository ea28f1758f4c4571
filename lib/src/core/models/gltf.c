/* glTF 2.0 metallic-roughness BRDF (specification, appendix B) with the
 * KHR_materials_specular and KHR_materials_ior extensions, as a renderer that implements
 * them evaluates it, so that a fit of this model is a glTF material as it stands:
 *
 *   a = roughness^2                                      (roughness is perceptual)
 *   D = a^2 / (pi (NH^2 (a^2 - 1) + 1)^2)                (GGX)
 *   Vis = 1 / ((NL + sqrt(a^2 + (1 - a^2) NL^2)) (NV + sqrt(a^2 + (1 - a^2) NV^2)))
 *   S = Vis D                                            (specular_brdf: G / (4 NL NV) D)
 *   w = (1 - VH)^5
 *   F_c = specular (min(((ior - 1)/(ior + 1))^2 specular_color_c, 1) (1 - w) + w)
 *   dielectric_c = F_c S + (1 - max_k F_k) base_color_c / pi
 *   metal_c = (base_color_c + (1 - base_color_c) w) S
 *   f_c = (1 - metallic) dielectric_c + metallic metal_c
 *
 * The max over channels is the extension's own rule for the weight left to the diffuse
 * base (so the channels are coupled and the family has its own evaluator). For C = 1 it
 * is the one channel. Reciprocal: D, Vis and w are symmetric in L and V. Not energy
 * conserving: the base's weight 1 - F(V.H) changes with the light direction, so for a
 * rough white dielectric the sum of the two terms can pass 1 at grazing view, and the
 * specification makes no claim either way. */
#include "family.h"
#include "terms.h"

#include <string.h>

enum { P_BASE, P_METAL, P_ROUGH, P_SPEC, P_SCOL, P_IOR, P_COUNT };

static bf_status configure(bf_model *m, bf_error *err)
{
    bf_status rc;
    /* Ranges are glTF's: every factor in [0, 1]; specularColorFactor has no upper
     * bound in the schema, 25 is where it lifts the default F0 of .04 to 1 (the clamp
     * holds it there); KHR_materials_ior allows any ior >= 1, 3 covers every common
     * dielectric (diamond 2.42). roughness 0 is a mirror (a delta), so it is excluded. */
    if ((rc = bf_model_add_param(m, "base_color", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "metallic", 0, 0.0, 1.0, 0.0, BF_SCALE_LINEAR, 0, BF_ROLE_SHAPE, err)) ||
        (rc = bf_model_add_param_open(m, "roughness", 0, 0.0, 1, 1.0, 0, 0.5, BF_SCALE_LINEAR, 0,
                                      BF_ROLE_PERCEPTUAL_ROUGHNESS, err)) ||
        (rc = bf_model_add_param(m, "specular", 0, 0.0, 1.0, 1.0, BF_SCALE_LINEAR, 0, BF_ROLE_WEIGHT, err)) ||
        /* A factor on F0; outside the lobes, so the start sets it to the diffuse level
         * (lib/src/fit/init.c says why). */
        (rc = bf_model_add_param(m, "specular_color", 1, 0.0, 25.0, 1.0, BF_SCALE_LINEAR, 0, BF_ROLE_F0, err)) ||
        (rc = bf_model_add_param(m, "ior", 0, 1.0, 3.0, 1.5, BF_SCALE_LINEAR, 0, BF_ROLE_IOR, err)))
        return rc;
    m->energy_conserving = 0;
    return BF_OK;
}

/* 1 / (X + sqrt(a^2 + (1 - a^2) X^2)) with s2 = 1 - X^2 = sin^2 of the direction (from
 * its x, y, no cancellation near the normal); *dl = d log / d a. */
static inline double vis1(double X, double s2, double a, double *dl)
{
    double r = sqrt(X * X + a * a * s2);
    double v = 1.0 / (X + r);
    *dl = -v * a * s2 / r;
    return v;
}

/* The dielectric F0 before the specular weight: min(f0(ior) specular_color, 1). */
static inline double f0_of(double f0i, double sc)
{
    double q = f0i * sc;
    return q < 1.0 ? q : 1.0;
}

static void eval(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1, double *values,
                 double *grad)
{
    const int C = m->channels, P = m->nfree;
    const int oB = m->offset[P_BASE], oM = m->offset[P_METAL], oR = m->offset[P_ROUGH];
    const int oS = m->offset[P_SPEC], oSC = m->offset[P_SCOL], oI = m->offset[P_IOR];
    const double *B = x + oB, *SC = x + oSC;
    const double metal = x[oM], rough = x[oR], spec = x[oS], ior = x[oI];
    const double a = rough * rough;
    const double ip1 = 1.0 / (ior + 1.0), r0 = (ior - 1.0) * ip1;
    const double f0i = r0 * r0, df0i = 4.0 * (ior - 1.0) * ip1 * ip1 * ip1;

    /* The channel of the largest dielectric F0, which is that of the largest Fresnel
     * at every angle (the first on a tie). */
    int mx = 0;
    for (int c = 1; c < C; c++)
        if (f0_of(f0i, SC[c]) > f0_of(f0i, SC[mx]))
            mx = c;
    const double qm = f0_of(f0i, SC[mx]);
    const int clamped_m = f0i * SC[mx] >= 1.0;

    for (size_t i = i0; i < i1; i++) {
        double *out = values + (i - i0) * (size_t)C;
        double *rows = grad ? grad + (i - i0) * (size_t)C * (size_t)P : NULL;
        if (bf_eval_skip_invalid(g, i, C, P, out, rows))
            continue;
        const double NL = g->lz[i], NV = g->vz[i];
        double dD, dlL, dlV;
        const double D = bf_d_ggx(g->hz[i], g->sin2h[i], a, &dD);
        const double VL = vis1(NL, g->lx[i] * g->lx[i] + g->ly[i] * g->ly[i], a, &dlL);
        const double VV = vis1(NV, g->vx[i] * g->vx[i] + g->vy[i] * g->vy[i], a, &dlV);
        const double S = VL * VV * D;
        const double dS_dr = (VL * VV * dD + S * (dlL + dlV)) * 2.0 * rough;
        double u = 1.0 - g->vh[i];
        u = u < 0.0 ? 0.0 : u;
        const double w = u * u * u * u * u;

        const double Fm = spec * (qm * (1.0 - w) + w);

        for (int c = 0; c < C; c++) {
            const double qc = f0_of(f0i, SC[c]);
            const double Fc = spec * (qc * (1.0 - w) + w);
            const double Bd = B[c] * (1.0 / M_PI);
            const double diel = Fc * S + (1.0 - Fm) * Bd;
            const double Fmet = B[c] + (1.0 - B[c]) * w;
            out[c] = (1.0 - metal) * diel + metal * Fmet * S;
            if (!rows)
                continue;
            double *row = rows + (size_t)c * (size_t)P;
            memset(row, 0, (size_t)P * sizeof *row);
            row[oB + c] = (1.0 - metal) * (1.0 - Fm) * (1.0 / M_PI) + metal * (1.0 - w) * S;
            row[oM] = Fmet * S - diel;
            row[oR] = ((1.0 - metal) * Fc + metal * Fmet) * dS_dr;
            row[oS] = (1.0 - metal) * ((qc * (1.0 - w) + w) * S - (qm * (1.0 - w) + w) * Bd);
            /* specular_color and ior act through q, zero where the clamp holds. */
            const double dq = spec * (1.0 - w) * (1.0 - metal);
            if (f0i * SC[c] < 1.0) {
                row[oSC + c] += dq * f0i * S;
                row[oI] += dq * SC[c] * df0i * S;
            }
            if (!clamped_m) {
                row[oSC + mx] -= dq * f0i * Bd;
                row[oI] -= dq * SC[mx] * df0i * Bd;
            }
        }
    }
}

const bf_family bf_family_gltf = {
    .info = {.name = "gltf",
             .summary = "glTF 2.0 metallic-roughness BRDF with KHR_materials_specular and KHR_materials_ior",
             .reference = "Khronos glTF 2.0 appendix B",
             .options = NULL,
             .lobes = 0,
             .anisotropic = 0},
    .configure = configure,
    .eval = eval,
};
