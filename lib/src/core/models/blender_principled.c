/* Blender 3.4's Principled BSDF as Cycles evaluates its reflection (transmission 0,
 * subsurface 0, distribution "GGX", so single scattering: the multiscatter GGX variant
 * is a random walk with no closed form). Written from Cycles' svm closure setup and its
 * principled_diffuse, principled_sheen and microfacet (GGX, clearcoat) closures:
 *
 *   f = (1 - metallic) (base_color / pi Fd + sheen Csheen FH) + Fs S + coat
 *
 *   FL, FV, FH = (1 - NL)^5, (1 - NV)^5, (1 - VH)^5
 *   RR = roughness (1 + L.V)           (= 2 roughness VH^2)
 *   Fd = (1 - FL/2)(1 - FV/2) + RR (FL + FV + FL FV (RR - 1))
 *   Ctint = base_color / lum(base_color), lum with Cycles' 0.3/0.6/0.1 for the specular
 *   tint and the scene-linear luminance (Rec. 709 Y) for the sheen tint
 *   Csheen = 1 - sheen_tint + Ctint_Y sheen_tint
 *   cspec0 = 0.08 specular (1 - specular_tint + Ctint specular_tint) (1 - metallic)
 *            + base_color metallic
 *   eta = 2 / (1 - sqrt(0.08 specular)) - 1      (so that F0 = 0.08 specular)
 *   Fw = (F_diel(VH, eta) - F0) / (1 - F0),   Fs = cspec0 (1 - Fw) + Fw
 *   a = roughness^2,  S = D_GGX(a) G1(L) G1(V) / (4 NL NV)  (Smith-GGX G1)
 *   coat = 0.25 clearcoat F_diel(VH, 1.5) D_GTR1(clearcoat_roughness^2) G1'(L) G1'(V) / (4 NL NV)
 *   (G1' with the fixed a = 0.25), D_GTR1(b) = (b^2 - 1) / (pi ln(b^2) (1 + (b^2 - 1) NH^2))
 *
 * Cycles' IOR input acts only on transmission, so it is not a parameter here: the
 * reflection's index is the one above, from specular. The channels couple through the
 * luminances, so the family has its own evaluator. Reciprocal (every term is symmetric
 * in L and V); not energy conserving (the retro-reflection, sheen and coat are added,
 * not traded against the rest, as in Burley's model). */
#include "family.h"
#include "principled.h"

enum { P_BASE, P_METAL, P_SPEC, P_STINT, P_ROUGH, P_SHEEN, P_SHTINT, P_CC, P_CCR, P_COUNT };

/* Below this roughness Cycles treats the GGX lobes as a mirror (alpha^2 <= 1e-7) that
 * no finite direction sees, so a fit cannot reach it. */
#define BP_ROUGH_MIN 0.018

static bf_status configure(bf_model *m, bf_error *err)
{
    /* Blender's node ranges and defaults (base colour .8 grey). */
    static const bf_param_row tab[P_COUNT] = {
        {"base_color", 1, 0.0, 0.8, BF_ROLE_DIFFUSE},
        {"metallic", 0, 0.0, 0.0, BF_ROLE_SHAPE},
        {"specular", 0, 0.0, 0.5, BF_ROLE_SHAPE},
        {"specular_tint", 0, 0.0, 0.0, BF_ROLE_SHAPE},
        {"roughness", 0, BP_ROUGH_MIN, 0.5, BF_ROLE_PERCEPTUAL_ROUGHNESS},
        {"sheen", 0, 0.0, 0.0, BF_ROLE_WEIGHT},
        {"sheen_tint", 0, 0.0, 0.5, BF_ROLE_SHAPE},
        {"clearcoat", 0, 0.0, 0.0, BF_ROLE_WEIGHT},
        {"clearcoat_roughness", 0, BP_ROUGH_MIN, 0.03, BF_ROLE_SHAPE},
    };
    bf_status rc = bf_model_add_rows(m, tab, P_COUNT, err);
    if (rc != BF_OK)
        return rc;
    m->energy_conserving = 0;
    return BF_OK;
}

static void eval(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1, double *values,
                 double *grad)
{
    const int C = m->channels, P = m->nfree;
    const int oB = m->offset[P_BASE], oM = m->offset[P_METAL], oS = m->offset[P_SPEC];
    const int oT = m->offset[P_STINT], oR = m->offset[P_ROUGH], oSh = m->offset[P_SHEEN];
    const int oShT = m->offset[P_SHTINT], oC = m->offset[P_CC], oCR = m->offset[P_CCR];
    const double *B = x + oB;
    const double metal = x[oM], spec = x[oS], stint = x[oT], rough = x[oR];
    const double sheen = x[oSh], shtint = x[oShT], cc = x[oC], ccr = x[oCR];
    const double dw = 1.0 - metal;

    /* Luminances (3 channels: Cycles' weights; otherwise the plain mean). */
    static const double w_spec[3] = {0.3, 0.6, 0.1};
    static const double w_y[3] = {0.2126729, 0.7151522, 0.0721750};
    double lum_s = 0.0, lum_y = 0.0;
    for (int c = 0; c < C; c++) {
        lum_s += (C == 3 ? w_spec[c] : 1.0 / C) * B[c];
        lum_y += (C == 3 ? w_y[c] : 1.0 / C) * B[c];
    }
    const double ils = lum_s > 0.0 ? 1.0 / lum_s : 0.0, ily = lum_y > 0.0 ? 1.0 / lum_y : 0.0;

    /* The specular's index gives F0 = 0.08 specular (principled.h). */
    const double F0 = 0.08 * spec, iF0 = 1.0 / (1.0 - F0);
    const double a = rough * rough;
    const double xc = ccr * ccr * ccr * ccr; /* GTR1's b^2 */
    double dgx;
    const double gx = bf_gtr1_norm(xc, &dgx);

    for (size_t i = i0; i < i1; i++) {
        double *out = values + (i - i0) * (size_t)C;
        double *rows = grad ? grad + (i - i0) * (size_t)C * (size_t)P : NULL;
        if (bf_eval_skip_invalid(g, i, C, P, out, rows))
            continue;
        const double NL = g->lz[i], NV = g->vz[i], NH = g->hz[i], VH = g->vh[i];
        const double i4 = 0.25 / (NL * NV);
        const double tL = (g->lx[i] * g->lx[i] + g->ly[i] * g->ly[i]) / (NL * NL);
        const double tV = (g->vx[i] * g->vx[i] + g->vy[i] * g->vy[i]) / (NV * NV);

        /* Diffuse with retro-reflection. */
        const double FL = bf_schlick_weight(NL), FV = bf_schlick_weight(NV), FH = bf_schlick_weight(VH);
        double dFd;
        const double Fd = bf_principled_diffuse(FL, FV, 2.0 * VH * VH, rough, &dFd);

        /* Specular GGX. */
        double dD, dGL, dGV;
        const double D = bf_d_ggx(NH, g->sin2h[i], a, &dD);
        const double GL = bf_g1_ggx(tL, a, &dGL), GV = bf_g1_ggx(tV, a, &dGV);
        const double S = D * GL * GV * i4;
        const double dS = (dD * GL * GV + D * (dGL * GV + GL * dGV)) * i4 * 2.0 * rough;
        /* Fresnel weight between cspec0 and white. */
        double dFdi_ds;
        const double Fdi = bf_dielectric_of_specular(VH, spec, &dFdi_ds);
        const double Fw = (Fdi - F0) * iF0;
        const double dFw = ((dFdi_ds - 0.08) + Fw * 0.08) * iF0;

        /* Clear coat: GTR1 over t = 1 + (b^2 - 1) NH^2 = sin^2 + b^2 NH^2. */
        const double t = g->sin2h[i] + xc * NH * NH;
        const double Dc = gx / (M_PI * t);
        const double dDc = (dgx / (M_PI * t) - Dc * NH * NH / t) * 4.0 * ccr * ccr * ccr;
        const double Gc = bf_g1_ggx(tL, 0.25, NULL) * bf_g1_ggx(tV, 0.25, NULL);
        const double kc = 0.25 * bf_dielectric(VH, 1.5, NULL) * Gc * i4;
        const double coat = cc * kc * Dc;

        for (int c = 0; c < C; c++) {
            const double ct = lum_s > 0.0 ? B[c] * ils : 1.0;
            const double cty = lum_y > 0.0 ? B[c] * ily : 1.0;
            const double tm = 1.0 - stint + ct * stint;
            const double cs = 1.0 - shtint + cty * shtint;
            const double cspec0 = 0.08 * spec * tm * dw + B[c] * metal;
            const double Fs = cspec0 * (1.0 - Fw) + Fw;
            const double front = B[c] * (1.0 / M_PI) * Fd + sheen * cs * FH;
            out[c] = dw * front + Fs * S + coat;
            if (!rows)
                continue;
            double *row = rows + (size_t)c * (size_t)P;
            const double S1 = S * (1.0 - Fw); /* d f / d cspec0 */
            /* base_color: its own channel, and every channel through the luminances. */
            const double KS = lum_s > 0.0 ? S1 * 0.08 * spec * dw * stint : 0.0;
            const double KY = lum_y > 0.0 ? dw * sheen * shtint * FH : 0.0;
            const double xs = -KS * B[c] * ils * ils, xy = -KY * B[c] * ily * ily;
            for (int k = 0; k < C; k++)
                row[oB + k] = xs * (C == 3 ? w_spec[k] : 1.0 / C) + xy * (C == 3 ? w_y[k] : 1.0 / C);
            row[oB + c] += dw * Fd * (1.0 / M_PI) + S1 * metal + KS * ils + KY * ily;
            row[oM] = -front + S1 * (B[c] - 0.08 * spec * tm);
            row[oS] = S1 * 0.08 * tm * dw + S * (1.0 - cspec0) * dFw;
            row[oT] = S1 * 0.08 * spec * dw * (ct - 1.0);
            row[oR] = dw * B[c] * (1.0 / M_PI) * dFd + Fs * dS;
            row[oSh] = dw * cs * FH;
            row[oShT] = dw * sheen * (cty - 1.0) * FH;
            row[oC] = kc * Dc;
            row[oCR] = cc * kc * dDc;
        }
    }
}

const bf_family bf_family_blender_principled = {
    .info = {.name = "blender_principled",
             .summary = "Blender 3.4 Cycles Principled BSDF, reflection (GGX, no transmission)",
             .reference = "Blender 3.4 Cycles source",
             .options = NULL,
             .lobes = 0,
             .anisotropic = 0},
    .configure = configure,
    .eval = eval,
};
