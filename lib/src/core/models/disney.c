/* Disney principled BRDF (Burley 2012), term for term as the reference shader of
 * Disney's BRDF Explorer (wdas/brdf, src/brdfs/disney.brdf), except that base_color is
 * taken as linear (the shader first raises it to the power 2.2):
 *
 *   f = ((1/pi) mix(Fd, ss, subsurface) Cdlin + Fsheen) (1 - metallic)
 *       + Gs Fs Ds + .25 clearcoat Gr Fr Dr
 *
 * The tint colour Ctint = Cdlin / Cdlum couples the channels through the luminance
 * Cdlum, so the Jacobian rows are dense in base_color and the family has its own
 * evaluator rather than the diffuse + lobes driver.
 *
 * Luminance: for C = 3 the shader's weights .3/.6/.1. For any other channel count there
 * is no RGB, so Cdlum is the plain mean of the channels (for C = 1, Ctint = 1). */
#include "family.h"

#include <math.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

enum { P_BASE, P_METAL, P_SUBSURF, P_SPEC, P_ROUGH, P_STINT, P_ANISO, P_SHEEN, P_SHTINT, P_CC, P_CCGLOSS, P_COUNT };

static bf_status configure(bf_model *m, bf_error *err)
{
    /* Disney's artist parameters mostly shape one term each; only the base colour, the
     * roughness and the sheen and clearcoat weights have a role the start can use. */
    static const bf_param_row tab[P_COUNT] = {
        {"base_color", 1, 0.0, 0.5, BF_ROLE_DIFFUSE},
        {"metallic", 0, 0.0, 0.0, BF_ROLE_SHAPE},
        {"subsurface", 0, 0.0, 0.0, BF_ROLE_DIFFUSE_SHAPE},
        {"specular", 0, 0.0, 0.5, BF_ROLE_SHAPE},
        {"roughness", 0, 0.0, 0.5, BF_ROLE_PERCEPTUAL_ROUGHNESS},
        {"specular_tint", 0, 0.0, 0.0, BF_ROLE_SHAPE},
        {"anisotropic", 0, 0.0, 0.0, BF_ROLE_SHAPE},
        {"sheen", 0, 0.0, 0.0, BF_ROLE_WEIGHT},
        {"sheen_tint", 0, 0.0, 0.5, BF_ROLE_SHAPE},
        {"clearcoat", 0, 0.0, 0.0, BF_ROLE_WEIGHT},
        {"clearcoat_gloss", 0, 0.0, 1.0, BF_ROLE_SHAPE},
    };
    bf_status rc = bf_model_add_rows(m, tab, P_COUNT, err);
    if (rc != BF_OK)
        return rc;
    /* Not energy conserving by design: diffuse retro-reflection (Fd90 up to 2.5), the
     * subsurface 1/(NL + NV) term, sheen and clearcoat all add energy. Reciprocal: every
     * term is symmetric in L and V (model.c's default). */
    m->energy_conserving = 0;
    return BF_OK;
}

/* SchlickFresnel(u) = clamp(1 - u, 0, 1)^5. */
static inline double schlick_weight(double u)
{
    double t = 1.0 - u;
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    double t2 = t * t;
    return t2 * t2 * t;
}

/* smithG_GGX_aniso(n, x, y, ax, ay) = 1/(n + sqrt((x ax)^2 + (y ay)^2 + n^2)), which
 * already contains the 1/(4 NL NV) of the microfacet form. *dlx, *dly: derivatives of
 * its log with respect to ax, ay. */
static inline double smith_ggx_aniso(double n, double x, double y, double ax, double ay, double *dlx, double *dly)
{
    double s = sqrt(x * x * ax * ax + y * y * ay * ay + n * n); /* >= n > 0 */
    double G = 1.0 / (n + s);
    *dlx = -G * x * x * ax / s;
    *dly = -G * y * y * ay / s;
    return G;
}

/* smithG_GGX(n, alpha) = 1/(n + sqrt(alpha^2 + n^2 - alpha^2 n^2)) (clearcoat only). */
static inline double smith_ggx(double n, double alpha)
{
    double a = alpha * alpha, b = n * n;
    return 1.0 / (n + sqrt(a + b - a * b));
}

static void eval(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1, double *values,
                 double *grad)
{
    const int C = m->channels, P = m->nfree;
    const int oB = m->offset[P_BASE];
    const double *B = x + oB;
    const double metal = x[m->offset[P_METAL]], subs = x[m->offset[P_SUBSURF]];
    const double spec = x[m->offset[P_SPEC]], rough = x[m->offset[P_ROUGH]];
    const double stint = x[m->offset[P_STINT]], aniso = x[m->offset[P_ANISO]];
    const double sheen = x[m->offset[P_SHEEN]], shtint = x[m->offset[P_SHTINT]];
    const double cc = x[m->offset[P_CC]], ccgloss = x[m->offset[P_CCGLOSS]];

    /* Luminance weights (see the header comment). */
    static const double rgb_w[3] = {0.3, 0.6, 0.1};
    const double mean_w = 1.0 / C;
#define LUM_W(c) (C == 3 ? rgb_w[c] : mean_w)
    double lum = 0.0;
    for (int c = 0; c < C; c++)
        lum += LUM_W(c) * B[c];
    const int tinted = lum > 0.0; /* else Ctint = 1, with zero gradient (branch taken) */
    const double inv_lum = tinted ? 1.0 / lum : 0.0;

    /* Specular roughness: ax = max(.001, r^2/aspect), ay = max(.001, r^2 aspect). */
    const double aspect = sqrt(1.0 - aniso * 0.9);
    const double daspect = -0.45 / aspect; /* d aspect / d anisotropic */
    const double r2 = rough * rough;
    double ax = r2 / aspect, ay = r2 * aspect;
    double dax_dr = 2.0 * rough / aspect, dax_da = -r2 * daspect / (aspect * aspect);
    double day_dr = 2.0 * rough * aspect, day_da = r2 * daspect;
    if (!(ax > 0.001)) {
        ax = 0.001;
        dax_dr = dax_da = 0.0;
    }
    if (!(ay > 0.001)) {
        ay = 0.001;
        day_dr = day_da = 0.0;
    }

    /* Clearcoat GTR1 width a = mix(.1, .001, clearcoat_gloss), in [.001, .1] in bounds. */
    const double cca = 0.1 * (1.0 - ccgloss) + 0.001 * ccgloss;
    const double cca2 = cca * cca;
    const int gtr1_flat = cca >= 1.0; /* the shader's branch; never taken in bounds */
    const double log_a2 = gtr1_flat ? 0.0 : log(cca2);
    /* d log(a^2 - 1) - d log(log a^2), with respect to a^2 (the t part is per sample). */
    const double dl_a2 = gtr1_flat ? 0.0 : 1.0 / (cca2 - 1.0) - 1.0 / (cca2 * log_a2);
    const double da2_dgloss = 2.0 * cca * (0.001 - 0.1);

    const double spec08 = spec * 0.08;
    const double iax = 1.0 / ax, iay = 1.0 / ay;
    /* The entries of a gradient row (the same for every channel). */
    const int oM = m->offset[P_METAL], oS = m->offset[P_SUBSURF], oSp = m->offset[P_SPEC];
    const int oR = m->offset[P_ROUGH], oT = m->offset[P_STINT], oA = m->offset[P_ANISO];
    const int oSh = m->offset[P_SHEEN], oShT = m->offset[P_SHTINT], oC = m->offset[P_CC];
    const int oCG = m->offset[P_CCGLOSS];

    for (size_t i = i0; i < i1; i++) {
        double *out = values + (i - i0) * (size_t)C;
        double *rows = grad ? grad + (i - i0) * (size_t)C * (size_t)P : NULL;
        if (bf_eval_skip_invalid(g, i, C, P, out, rows))
            continue;
        const double NL = g->lz[i], NV = g->vz[i], NH = g->hz[i], LH = g->vh[i];
        const double HX = g->hx[i], HY = g->hy[i];
        const double NH2 = NH * NH;

        /* Diffuse: Fresnel-like retro-reflection and the Hanrahan-Krueger-like term. */
        const double FL = schlick_weight(NL), FV = schlick_weight(NV);
        const double LH2 = LH * LH;
        const double Fd90 = 0.5 + 2.0 * LH2 * rough;
        const double mdL = (1.0 - FL) + Fd90 * FL, mdV = (1.0 - FV) + Fd90 * FV;
        const double Fd = mdL * mdV;
        const double Fss90 = LH2 * rough;
        const double msL = (1.0 - FL) + Fss90 * FL, msV = (1.0 - FV) + Fss90 * FV;
        const double Fss = msL * msV;
        const double kss = 1.0 / (NL + NV) - 0.5;
        const double ss = 1.25 * (Fss * kss + 0.5);
        const double dmix = Fd * (1.0 - subs) + ss * subs;

        /* Specular: anisotropic GTR2 (GGX) with separable Smith-GGX shadowing. */
        const double hxa = HX * iax, hya = HY * iay;
        const double q = hxa * hxa + hya * hya + NH2; /* >= NH^2 > 0 */
        const double Ds = 1.0 / (M_PI * ax * ay * q * q);
        double gLx, gLy, gVx, gVy;
        const double Gs = smith_ggx_aniso(NL, g->lx[i], g->ly[i], ax, ay, &gLx, &gLy) *
                          smith_ggx_aniso(NV, g->vx[i], g->vy[i], ax, ay, &gVx, &gVy);
        const double GD = Gs * Ds;
        const double FH = schlick_weight(LH);

        /* Clearcoat: GTR1 with t = 1 + (a^2 - 1) NH^2 = sin^2(theta_h) + a^2 NH^2. */
        const double t1 = g->sin2h[i] + cca2 * NH2;
        const double Dr = gtr1_flat ? 1.0 / M_PI : (cca2 - 1.0) / (M_PI * log_a2 * t1);
        const double Fr = 0.04 * (1.0 - FH) + FH;
        const double Gr = smith_ggx(NL, 0.25) * smith_ggx(NV, 0.25);
        const double coat = 0.25 * cc * Gr * Fr * Dr;

        /* The channel-independent parts of the gradient. Roughness enters Fd90, Fss90
         * and (above .001) ax, ay; dlax, dlay: d log(Gs Ds) / d ax and / d ay. */
        const double dFd = 2.0 * LH2 * (FL * mdV + FV * mdL);
        const double dFss = LH2 * (FL * msV + FV * msL);
        const double ddmix = (1.0 - subs) * dFd + subs * 1.25 * kss * dFss;
        const double iq = 1.0 / q;
        const double dlax = gLx + gVx - iax + 4.0 * hxa * hxa * iax * iq;
        const double dlay = gLy + gVy - iay + 4.0 * hya * hya * iay * iq;
        const double dcc = 0.25 * Gr * Fr * Dr;
        const double dccg = gtr1_flat ? 0.0 : coat * (dl_a2 - NH2 / t1) * da2_dgloss;

        for (int c = 0; c < C; c++) {
            const double ct = tinted ? B[c] * inv_lum : 1.0;
            const double tintmix = (1.0 - stint) + ct * stint;
            const double cspec0 = spec08 * tintmix * (1.0 - metal) + B[c] * metal;
            const double csheen = (1.0 - shtint) + ct * shtint;
            const double Fs = cspec0 * (1.0 - FH) + FH;
            const double front = (1.0 / M_PI) * dmix * B[c] + FH * sheen * csheen;
            out[c] = front * (1.0 - metal) + GD * Fs + coat;

            if (!rows)
                continue;
            double *row = rows + (size_t)c * (size_t)P;
            const double GD1 = GD * (1.0 - FH); /* d f / d cspec0 */

            /* base_color: diagonal through Cdlin, every channel through Ctint. */
            const double dct = (1.0 - metal) * (FH * sheen * shtint + GD1 * spec08 * stint);
            const double cross = tinted ? -dct * B[c] * inv_lum * inv_lum : 0.0;
            for (int k = 0; k < C; k++)
                row[oB + k] = cross * LUM_W(k);
            row[oB + c] += (1.0 - metal) * dmix * (1.0 / M_PI) + GD1 * metal + (tinted ? dct * inv_lum : 0.0);

            row[oM] = -front + GD1 * (B[c] - spec08 * tintmix);
            row[oS] = (1.0 - metal) * (1.0 / M_PI) * (ss - Fd) * B[c];
            row[oSp] = GD1 * 0.08 * tintmix * (1.0 - metal);
            const double FGD = Fs * GD;
            row[oR] = (1.0 - metal) * (1.0 / M_PI) * ddmix * B[c] + FGD * (dlax * dax_dr + dlay * day_dr);
            row[oT] = GD1 * spec08 * (ct - 1.0) * (1.0 - metal);
            row[oA] = FGD * (dlax * dax_da + dlay * day_da);
            row[oSh] = (1.0 - metal) * FH * csheen;
            row[oShT] = (1.0 - metal) * FH * sheen * (ct - 1.0);
            row[oC] = dcc;
            row[oCG] = dccg;
        }
    }
#undef LUM_W
}

const bf_family bf_family_disney = {
    .info = {.name = "disney",
             .summary = "Disney principled BRDF (BRDF Explorer shader, linear base_color)",
             .reference = "Burley 2012",
             .options = NULL,
             .lobes = 0,
             .anisotropic = 1},
    .configure = configure,
    .eval = eval,
};
