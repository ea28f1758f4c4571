/* Mitsuba 3's `principled` BSDF as its eval() computes the reflection (spec_trans 0,
 * anisotropic 0, `specular` given rather than `eta`), written from src/bsdfs/principled.cpp
 * and principledhelpers.h; the value is Mitsuba's eval() divided by cos(theta_o):
 *
 *   f = (1 - metallic) (base_color / pi mix(Fd, ss, flatness) + sheen Csheen w)
 *       + F D G / (4 NL NV) + 0.25 clearcoat Fcc Dcc Gcc
 *
 *   w = (1 - VH)^5, FL, FV = (1 - NL)^5, (1 - NV)^5
 *   Fd = (1 - FL/2)(1 - FV/2) + RR (FL + FV + FL FV (RR - 1)),  RR = 2 roughness VH^2
 *   ss = 1.25 (Fss (1 / (NL + NV) - 0.5) + 0.5),  Fss = (1 + (RR/2 - 1) FL)(1 + (RR/2 - 1) FV)
 *   Ctint = base_color / lum(base_color)  (Mitsuba's luminance; 1 when lum = 0)
 *   Csheen = 1 - sheen_tint + Ctint sheen_tint
 *   eta = 2 / (1 - sqrt(0.08 specular)) - 1,  R0 = ((eta - 1)/(eta + 1))^2 = 0.08 specular
 *   F = (1 - metallic)(1 - spec_tint) F_diel(VH, eta) + metallic (B + (1 - B) w)
 *       + (1 - metallic) spec_tint (Ctint R0 + (1 - Ctint R0) w)
 *   D, G: GGX with a = max(0.001, roughness^2), separable Smith G1(L) G1(V)
 *   Fcc = 0.04 + 0.96 w,  Dcc = GTR1 of width mix(0.1, 0.001, clearcoat_gloss),
 *   Gcc = Smith-GGX G1(L) G1(V) with a = 0.25
 *
 * The clear coat has no 1/(4 NL NV): Mitsuba's eval() adds it that way, and this model
 * is what Mitsuba renders. The channels couple through the luminance, so the family has
 * its own evaluator. Reciprocal; not energy conserving (retro-reflection, sheen and
 * coat are added, as in Burley's model). */
#include "family.h"
#include "principled.h"

enum { P_BASE, P_METAL, P_SPEC, P_STINT, P_ROUGH, P_SHEEN, P_SHTINT, P_FLAT, P_CC, P_CCG, P_COUNT };

static bf_status configure(bf_model *m, bf_error *err)
{
    /* Mitsuba's ranges ("all parameters ... between 0.0 and 1.0") and defaults. */
    static const bf_param_row tab[P_COUNT] = {
        {"base_color", 1, 0.0, 0.5, BF_ROLE_DIFFUSE},
        {"metallic", 0, 0.0, 0.0, BF_ROLE_SHAPE},
        {"specular", 0, 0.0, 0.5, BF_ROLE_SHAPE},
        {"spec_tint", 0, 0.0, 0.0, BF_ROLE_SHAPE},
        {"roughness", 0, 0.0, 0.5, BF_ROLE_PERCEPTUAL_ROUGHNESS},
        {"sheen", 0, 0.0, 0.0, BF_ROLE_WEIGHT},
        {"sheen_tint", 0, 0.0, 0.0, BF_ROLE_SHAPE},
        {"flatness", 0, 0.0, 0.0, BF_ROLE_DIFFUSE_SHAPE},
        {"clearcoat", 0, 0.0, 0.0, BF_ROLE_WEIGHT},
        {"clearcoat_gloss", 0, 0.0, 0.0, BF_ROLE_SHAPE},
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
    const int oShT = m->offset[P_SHTINT], oF = m->offset[P_FLAT], oC = m->offset[P_CC];
    const int oCG = m->offset[P_CCG];
    const double *B = x + oB;
    const double metal = x[oM], spec = x[oS], stint = x[oT], rough = x[oR];
    const double sheen = x[oSh], shtint = x[oShT], flat = x[oF], cc = x[oC], ccg = x[oCG];
    const double dw = 1.0 - metal;

    /* Mitsuba's luminance for RGB; the plain mean for any other channel count. */
    static const double w_y[3] = {0.212671, 0.715160, 0.072169};
#define LUM_W(k) (C == 3 ? w_y[k] : 1.0 / C)
    double lum = 0.0;
    for (int c = 0; c < C; c++)
        lum += LUM_W(c) * B[c];
    const double il = lum > 0.0 ? 1.0 / lum : 0.0;

    const double R0 = 0.08 * spec;
    /* GGX width with Mitsuba's floor; roughness has no effect below it. */
    double a = rough * rough, da = 2.0 * rough;
    if (!(a > 0.001)) {
        a = 0.001;
        da = 0.0;
    }
    const double ag = 0.1 + (0.001 - 0.1) * ccg, xc = ag * ag, dxc = 2.0 * ag * (0.001 - 0.1);
    double dgx;
    const double gx = bf_gtr1_norm(xc, &dgx);

    for (size_t i = i0; i < i1; i++) {
        double *out = values + (i - i0) * (size_t)C;
        double *rows = grad ? grad + (i - i0) * (size_t)C * (size_t)P : NULL;
        if (bf_eval_skip_invalid(g, i, C, P, out, rows))
            continue;
        const double NL = g->lz[i], NV = g->vz[i], NH = g->hz[i], VH = g->vh[i];
        const double tL = (g->lx[i] * g->lx[i] + g->ly[i] * g->ly[i]) / (NL * NL);
        const double tV = (g->vx[i] * g->vx[i] + g->vy[i] * g->vy[i]) / (NV * NV);
        const double FL = bf_schlick_weight(NL), FV = bf_schlick_weight(NV), w = bf_schlick_weight(VH);

        /* Diffuse: retro-reflective Burley term blended with the fake subsurface. */
        const double lv1 = 2.0 * VH * VH;
        double dFd;
        const double Fd = bf_principled_diffuse(FL, FV, lv1, rough, &dFd);
        const double f90 = 0.5 * rough * lv1;
        const double mL = 1.0 + (f90 - 1.0) * FL, mV = 1.0 + (f90 - 1.0) * FV;
        const double kss = 1.0 / (NL + NV) - 0.5;
        const double ss = 1.25 * (mL * mV * kss + 0.5);
        const double dss = 1.25 * kss * 0.5 * lv1 * (FL * mV + FV * mL);
        const double Fmix = (1.0 - flat) * Fd + flat * ss;
        const double dFmix = (1.0 - flat) * dFd + flat * dss;

        /* Main specular: GGX, separable Smith, 1 / (4 NL NV). */
        double dD, dGL, dGV;
        const double D = bf_d_ggx(NH, g->sin2h[i], a, &dD);
        const double GL = bf_g1_ggx(tL, a, &dGL), GV = bf_g1_ggx(tV, a, &dGV);
        const double i4 = 0.25 / (NL * NV);
        const double S = D * GL * GV * i4;
        const double dS = (dD * GL * GV + D * (dGL * GV + GL * dGV)) * i4 * da;
        double dFdi;
        const double Fdi = bf_dielectric_of_specular(VH, spec, &dFdi);

        /* Clear coat, without the microfacet denominator (see the header). */
        const double t = g->sin2h[i] + xc * NH * NH;
        const double Dc = gx / (M_PI * t);
        const double dDc = (dgx / (M_PI * t) - Dc * NH * NH / t) * dxc;
        const double kc = 0.25 * (0.04 + 0.96 * w) * bf_g1_ggx(tL, 0.25, NULL) * bf_g1_ggx(tV, 0.25, NULL);

        for (int c = 0; c < C; c++) {
            const double ct = lum > 0.0 ? B[c] * il : 1.0;
            const double Fmet = B[c] + (1.0 - B[c]) * w;
            const double Ftint = ct * R0 + (1.0 - ct * R0) * w;
            const double F = dw * (1.0 - stint) * Fdi + metal * Fmet + dw * stint * Ftint;
            const double csh = 1.0 - shtint + ct * shtint;
            const double front = B[c] * (1.0 / M_PI) * Fmix + sheen * csh * w;
            out[c] = dw * front + F * S + cc * kc * Dc;
            if (!rows)
                continue;
            double *row = rows + (size_t)c * (size_t)P;
            /* base_color: its own channel, and every channel through the luminance. */
            const double K = lum > 0.0 ? dw * (stint * R0 * (1.0 - w) * S + sheen * shtint * w) : 0.0;
            const double cross = -K * B[c] * il * il;
            for (int k = 0; k < C; k++)
                row[oB + k] = cross * LUM_W(k);
            row[oB + c] += dw * Fmix * (1.0 / M_PI) + metal * (1.0 - w) * S + K * il;
            row[oM] = -front + (-(1.0 - stint) * Fdi + Fmet - stint * Ftint) * S;
            row[oS] = dw * ((1.0 - stint) * dFdi + stint * ct * 0.08 * (1.0 - w)) * S;
            row[oT] = dw * (Ftint - Fdi) * S;
            row[oR] = dw * B[c] * (1.0 / M_PI) * dFmix + F * dS;
            row[oSh] = dw * csh * w;
            row[oShT] = dw * sheen * (ct - 1.0) * w;
            row[oF] = dw * B[c] * (1.0 / M_PI) * (ss - Fd);
            row[oC] = kc * Dc;
            row[oCG] = cc * kc * dDc;
        }
    }
#undef LUM_W
}

const bf_family bf_family_mitsuba_principled = {
    .info = {.name = "mitsuba_principled",
             .summary = "Mitsuba 3 principled BSDF, reflection (isotropic, no transmission)",
             .reference = "Mitsuba 3 source (principled.cpp)",
             .options = NULL,
             .lobes = 0,
             .anisotropic = 0},
    .configure = configure,
    .eval = eval,
};
