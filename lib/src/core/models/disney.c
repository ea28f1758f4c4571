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

/* What every sample of one evaluation shares: the parameters, the tint's luminance,
 * the specular widths and the clearcoat width, with their derivatives, and where each
 * parameter sits in a gradient row. */
typedef struct disney_model {
    int C, P;
    int oB, oM, oS, oSp, oR, oT, oA, oSh, oShT, oC, oCG;
    const double *B;
    double metal, subs, rough, stint, sheen, shtint, cc;
    double mean_w, inv_lum;
    int tinted;
    double ax, ay, dax_dr, dax_da, day_dr, day_da, iax, iay, spec08;
    double cca2, log_a2, dl_a2, da2_dgloss;
    int gtr1_flat;
} disney_model;

/* One sample's terms, the same for every channel: the diffuse mix, the specular and
 * clearcoat products, and the channel-independent parts of the gradient. */
typedef struct disney_sample {
    double FH, Fd, ss, dmix, GD, coat;
    double ddmix, dlax, dlay, dcc, dccg;
} disney_sample;

/* Luminance weights (see the header comment). */
static inline double lum_w(const disney_model *d, int c)
{
    static const double rgb_w[3] = {0.3, 0.6, 0.1};
    return d->C == 3 ? rgb_w[c] : d->mean_w;
}

static void model_terms(const bf_model *m, const double *x, disney_model *d)
{
    d->C = m->channels;
    d->P = m->nfree;
    d->oB = m->offset[P_BASE];
    d->oM = m->offset[P_METAL], d->oS = m->offset[P_SUBSURF], d->oSp = m->offset[P_SPEC];
    d->oR = m->offset[P_ROUGH], d->oT = m->offset[P_STINT], d->oA = m->offset[P_ANISO];
    d->oSh = m->offset[P_SHEEN], d->oShT = m->offset[P_SHTINT], d->oC = m->offset[P_CC];
    d->oCG = m->offset[P_CCGLOSS];
    d->B = x + d->oB;
    d->metal = x[d->oM], d->subs = x[d->oS];
    const double spec = x[d->oSp];
    d->rough = x[d->oR];
    d->stint = x[d->oT];
    const double aniso = x[d->oA];
    d->sheen = x[d->oSh], d->shtint = x[d->oShT];
    d->cc = x[d->oC];
    const double ccgloss = x[d->oCG];

    d->mean_w = 1.0 / d->C;
    double lum = 0.0;
    for (int c = 0; c < d->C; c++)
        lum += lum_w(d, c) * d->B[c];
    d->tinted = lum > 0.0; /* else Ctint = 1, with zero gradient (branch taken) */
    d->inv_lum = d->tinted ? 1.0 / lum : 0.0;

    /* Specular roughness: ax = max(.001, r^2/aspect), ay = max(.001, r^2 aspect). */
    const double aspect = sqrt(1.0 - aniso * 0.9);
    const double daspect = -0.45 / aspect; /* d aspect / d anisotropic */
    const double r2 = d->rough * d->rough;
    d->ax = r2 / aspect, d->ay = r2 * aspect;
    d->dax_dr = 2.0 * d->rough / aspect, d->dax_da = -r2 * daspect / (aspect * aspect);
    d->day_dr = 2.0 * d->rough * aspect, d->day_da = r2 * daspect;
    if (!(d->ax > 0.001)) {
        d->ax = 0.001;
        d->dax_dr = d->dax_da = 0.0;
    }
    if (!(d->ay > 0.001)) {
        d->ay = 0.001;
        d->day_dr = d->day_da = 0.0;
    }

    /* Clearcoat GTR1 width a = mix(.1, .001, clearcoat_gloss), in [.001, .1] in bounds. */
    const double cca = 0.1 * (1.0 - ccgloss) + 0.001 * ccgloss;
    d->cca2 = cca * cca;
    d->gtr1_flat = cca >= 1.0; /* the shader's branch; never taken in bounds */
    d->log_a2 = d->gtr1_flat ? 0.0 : log(d->cca2);
    /* d log(a^2 - 1) - d log(log a^2), with respect to a^2 (the t part is per sample). */
    d->dl_a2 = d->gtr1_flat ? 0.0 : 1.0 / (d->cca2 - 1.0) - 1.0 / (d->cca2 * d->log_a2);
    d->da2_dgloss = 2.0 * cca * (0.001 - 0.1);

    d->spec08 = spec * 0.08;
    d->iax = 1.0 / d->ax, d->iay = 1.0 / d->ay;
}

static void sample_terms(const disney_model *d, const bf_geometry *g, size_t i, disney_sample *t)
{
    const double NL = g->lz[i], NV = g->vz[i], NH = g->hz[i], LH = g->vh[i];
    const double HX = g->hx[i], HY = g->hy[i];
    const double NH2 = NH * NH;

    /* Diffuse: Fresnel-like retro-reflection and the Hanrahan-Krueger-like term. */
    const double FL = schlick_weight(NL), FV = schlick_weight(NV);
    const double LH2 = LH * LH;
    const double Fd90 = 0.5 + 2.0 * LH2 * d->rough;
    const double mdL = (1.0 - FL) + Fd90 * FL, mdV = (1.0 - FV) + Fd90 * FV;
    t->Fd = mdL * mdV;
    const double Fss90 = LH2 * d->rough;
    const double msL = (1.0 - FL) + Fss90 * FL, msV = (1.0 - FV) + Fss90 * FV;
    const double Fss = msL * msV;
    const double kss = 1.0 / (NL + NV) - 0.5;
    t->ss = 1.25 * (Fss * kss + 0.5);
    t->dmix = t->Fd * (1.0 - d->subs) + t->ss * d->subs;

    /* Specular: anisotropic GTR2 (GGX) with separable Smith-GGX shadowing. */
    const double hxa = HX * d->iax, hya = HY * d->iay;
    const double q = hxa * hxa + hya * hya + NH2; /* >= NH^2 > 0 */
    const double Ds = 1.0 / (M_PI * d->ax * d->ay * q * q);
    double gLx, gLy, gVx, gVy;
    const double Gs = smith_ggx_aniso(NL, g->lx[i], g->ly[i], d->ax, d->ay, &gLx, &gLy) *
                      smith_ggx_aniso(NV, g->vx[i], g->vy[i], d->ax, d->ay, &gVx, &gVy);
    t->GD = Gs * Ds;
    t->FH = schlick_weight(LH);

    /* Clearcoat: GTR1 with t = 1 + (a^2 - 1) NH^2 = sin^2(theta_h) + a^2 NH^2. */
    const double t1 = g->sin2h[i] + d->cca2 * NH2;
    const double Dr = d->gtr1_flat ? 1.0 / M_PI : (d->cca2 - 1.0) / (M_PI * d->log_a2 * t1);
    const double Fr = 0.04 * (1.0 - t->FH) + t->FH;
    const double Gr = smith_ggx(NL, 0.25) * smith_ggx(NV, 0.25);
    t->coat = 0.25 * d->cc * Gr * Fr * Dr;

    /* The channel-independent parts of the gradient. Roughness enters Fd90, Fss90
     * and (above .001) ax, ay; dlax, dlay: d log(Gs Ds) / d ax and / d ay. */
    const double dFd = 2.0 * LH2 * (FL * mdV + FV * mdL);
    const double dFss = LH2 * (FL * msV + FV * msL);
    t->ddmix = (1.0 - d->subs) * dFd + d->subs * 1.25 * kss * dFss;
    const double iq = 1.0 / q;
    t->dlax = gLx + gVx - d->iax + 4.0 * hxa * hxa * d->iax * iq;
    t->dlay = gLy + gVy - d->iay + 4.0 * hya * hya * d->iay * iq;
    t->dcc = 0.25 * Gr * Fr * Dr;
    t->dccg = d->gtr1_flat ? 0.0 : t->coat * (d->dl_a2 - NH2 / t1) * d->da2_dgloss;
}

/* Channel c's value, and its gradient row when row is not NULL. */
static void channel(const disney_model *d, const disney_sample *t, int c, double *out, double *row)
{
    const double *B = d->B;
    const double metal = d->metal, stint = d->stint, sheen = d->sheen, shtint = d->shtint, FH = t->FH;
    const double ct = d->tinted ? B[c] * d->inv_lum : 1.0;
    const double tintmix = (1.0 - stint) + ct * stint;
    const double cspec0 = d->spec08 * tintmix * (1.0 - metal) + B[c] * metal;
    const double csheen = (1.0 - shtint) + ct * shtint;
    const double Fs = cspec0 * (1.0 - FH) + FH;
    const double front = (1.0 / M_PI) * t->dmix * B[c] + FH * sheen * csheen;
    out[c] = front * (1.0 - metal) + t->GD * Fs + t->coat;

    if (!row)
        return;
    const double GD1 = t->GD * (1.0 - FH); /* d f / d cspec0 */

    /* base_color: diagonal through Cdlin, every channel through Ctint. */
    const double dct = (1.0 - metal) * (FH * sheen * shtint + GD1 * d->spec08 * stint);
    const double cross = d->tinted ? -dct * B[c] * d->inv_lum * d->inv_lum : 0.0;
    for (int k = 0; k < d->C; k++)
        row[d->oB + k] = cross * lum_w(d, k);
    row[d->oB + c] += (1.0 - metal) * t->dmix * (1.0 / M_PI) + GD1 * metal + (d->tinted ? dct * d->inv_lum : 0.0);

    row[d->oM] = -front + GD1 * (B[c] - d->spec08 * tintmix);
    row[d->oS] = (1.0 - metal) * (1.0 / M_PI) * (t->ss - t->Fd) * B[c];
    row[d->oSp] = GD1 * 0.08 * tintmix * (1.0 - metal);
    const double FGD = Fs * t->GD;
    row[d->oR] = (1.0 - metal) * (1.0 / M_PI) * t->ddmix * B[c] + FGD * (t->dlax * d->dax_dr + t->dlay * d->day_dr);
    row[d->oT] = GD1 * d->spec08 * (ct - 1.0) * (1.0 - metal);
    row[d->oA] = FGD * (t->dlax * d->dax_da + t->dlay * d->day_da);
    row[d->oSh] = (1.0 - metal) * FH * csheen;
    row[d->oShT] = (1.0 - metal) * FH * sheen * (ct - 1.0);
    row[d->oC] = t->dcc;
    row[d->oCG] = t->dccg;
}

static void eval(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1, double *values,
                 double *grad)
{
    disney_model d;
    model_terms(m, x, &d);
    const int C = d.C, P = d.P;
    for (size_t i = i0; i < i1; i++) {
        double *out = values + (i - i0) * (size_t)C;
        double *rows = grad ? grad + (i - i0) * (size_t)C * (size_t)P : NULL;
        if (bf_eval_skip_invalid(g, i, C, P, out, rows))
            continue;
        disney_sample t;
        sample_terms(&d, g, i, &t);
        for (int c = 0; c < C; c++)
            channel(&d, &t, c, out, rows ? rows + (size_t)c * (size_t)P : NULL);
    }
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
