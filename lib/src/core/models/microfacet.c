/* The composable Torrance-Sparrow family and its presets:
 *   f = rho_d/pi + sum_lobes rho_s D G F / (4 NL NV)
 * `microfacet` picks D, G and F by option; `cook_torrance` (D=beckmann, G=cook_torrance)
 * and `walter` (D=ggx, G=smith_ggx) fix D and G and keep a `fresnel=` option. All three
 * run the same lobe function, so a preset and the equivalent microfacet options agree
 * bit for bit.
 *
 * The Smith shadowing forms need a roughness: they use the D's own roughness parameter
 * (alpha for ggx, m for beckmann and gaussian); for D=blinn the exponent n is converted
 * by the standard Beckmann equivalence m = sqrt(2/(n+2)), with the chain rule into d/dn. */
#include "family.h"
#include "terms.h"

#include <math.h>

enum { D_GGX = 0, D_BECKMANN, D_BLINN, D_GAUSSIAN };
static const char *const d_values[] = {"ggx", "beckmann", "blinn", "gaussian", NULL};

enum { G_SMITH_GGX = 0, G_IMPLICIT, G_CT, G_SMITH_BECKMANN, G_SMITH_SCHLICK, G_NONE };
static const char *const g_values[] = {"smith_ggx", "implicit", "cook_torrance", "smith_beckmann", "smith_schlick",
                                       "none",      NULL};

extern const bf_family bf_family_cook_torrance;
extern const bf_family bf_family_walter;
extern const bf_family bf_family_microfacet;

typedef struct mf_cfg {
    int d, g, f;
} mf_cfg;

/* The (D, G, F) a configured model stands for. Reads the option indices directly (no
 * string lookups): microfacet's options are D, G, F in that order; the presets' only
 * option is fresnel, whose values share the BF_FRESNEL_* order. */
static mf_cfg resolve(const bf_model *m)
{
    if (m->family == &bf_family_cook_torrance)
        return (mf_cfg){D_BECKMANN, G_CT, m->opt[0]};
    if (m->family == &bf_family_walter)
        return (mf_cfg){D_GGX, G_SMITH_GGX, m->opt[0]};
    return (mf_cfg){m->opt[0], m->opt[1], m->opt[2]};
}

/* A block's D, G and F and their derivatives (dF2: a conductor's second Fresnel
 * scalar), each from its own pass with its switch outside the sample loop, so that
 * the loops stay branch-free and vectorise. */
typedef struct mf_terms {
    double D[BF_BLOCK], dD[BF_BLOCK], G[BF_BLOCK], dG[BF_BLOCK], F[BF_BLOCK], dF[BF_BLOCK], dF2[BF_BLOCK];
} mf_terms;

/* D and dD/d(roughness r) over samples [i0, i0 + cnt). */
static inline void d_pass(mf_cfg c, const bf_geometry *g, size_t i0, size_t cnt, double r, mf_terms *t)
{
    const double *hz = g->hz + i0, *s2 = g->sin2h + i0;
    switch (c.d) {
    case D_GGX:
        for (size_t j = 0; j < cnt; j++)
            t->D[j] = bf_d_ggx(hz[j], s2[j], r, &t->dD[j]);
        break;
    case D_BECKMANN:
        for (size_t j = 0; j < cnt; j++)
            t->D[j] = bf_d_beckmann(hz[j], s2[j], r, &t->dD[j]);
        break;
    case D_BLINN:
        for (size_t j = 0; j < cnt; j++)
            t->D[j] = bf_d_blinn(hz[j], s2[j], r, &t->dD[j]);
        break;
    default: /* D_GAUSSIAN */
        for (size_t j = 0; j < cnt; j++)
            t->D[j] = bf_d_gaussian(hz[j], s2[j], r, &t->dD[j]);
        break;
    }
}

/* G and dG/d(the D's roughness r). */
static inline void g_pass(mf_cfg c, const bf_geometry *g, size_t i0, size_t cnt, double r, mf_terms *t)
{
    const double *lx = g->lx + i0, *ly = g->ly + i0, *lz = g->lz + i0;
    const double *vx = g->vx + i0, *vy = g->vy + i0, *vz = g->vz + i0;
    const double *hz = g->hz + i0, *vh = g->vh + i0;
    /* Roughness seen by the Smith forms and its derivative with respect to r. For
     * blinn, m = sqrt(2/(n+2)) so dm/dn = -1/(m (n+2)^2) = -m^3/4. */
    double gm = r, dgm = 1.0;
    if (c.d == D_BLINN) {
        gm = sqrt(2.0 / (r + 2.0));
        dgm = -0.25 * gm * gm * gm;
    }
    switch (c.g) {
    case G_SMITH_GGX:
        for (size_t j = 0; j < cnt; j++) {
            double tl = (lx[j] * lx[j] + ly[j] * ly[j]) / (lz[j] * lz[j]);
            double tv = (vx[j] * vx[j] + vy[j] * vy[j]) / (vz[j] * vz[j]);
            double dl, dv;
            double gl = bf_g1_ggx(tl, gm, &dl), gv = bf_g1_ggx(tv, gm, &dv);
            t->G[j] = gl * gv;
            t->dG[j] = (dl * gv + gl * dv) * dgm;
        }
        break;
    case G_SMITH_BECKMANN:
        for (size_t j = 0; j < cnt; j++) {
            double sl = sqrt(lx[j] * lx[j] + ly[j] * ly[j]);
            double sv = sqrt(vx[j] * vx[j] + vy[j] * vy[j]);
            double dl, dv;
            double gl = bf_g1_beckmann(lz[j], sl, gm, &dl), gv = bf_g1_beckmann(vz[j], sv, gm, &dv);
            t->G[j] = gl * gv;
            t->dG[j] = (dl * gv + gl * dv) * dgm;
        }
        break;
    case G_SMITH_SCHLICK:
        for (size_t j = 0; j < cnt; j++) {
            double dl, dv;
            double gl = bf_g1_schlick(lz[j], gm, &dl), gv = bf_g1_schlick(vz[j], gm, &dv);
            t->G[j] = gl * gv;
            t->dG[j] = (dl * gv + gl * dv) * dgm;
        }
        break;
    case G_CT:
        for (size_t j = 0; j < cnt; j++) {
            t->G[j] = bf_g_ct(hz[j], lz[j], vz[j], vh[j]);
            t->dG[j] = 0.0;
        }
        break;
    default: /* G_IMPLICIT (its NL NV cancels the denominator below) and G_NONE */
        for (size_t j = 0; j < cnt; j++) {
            t->G[j] = 1.0;
            t->dG[j] = 0.0;
        }
        break;
    }
}

/* F and its derivatives with respect to the Fresnel scalars s[1] (and s[2]). */
static inline void f_pass(mf_cfg c, const bf_geometry *g, size_t i0, size_t cnt, const double *s, mf_terms *t)
{
    const double *vh = g->vh + i0;
    const double p = c.f != BF_FRESNEL_NONE ? s[1] : 0.0;
    switch (c.f) {
    case BF_FRESNEL_SCHLICK:
        for (size_t j = 0; j < cnt; j++)
            t->F[j] = bf_schlick(vh[j], p, &t->dF[j]);
        break;
    case BF_FRESNEL_DIELECTRIC:
        for (size_t j = 0; j < cnt; j++)
            t->F[j] = bf_dielectric(vh[j], p, &t->dF[j]);
        break;
    case BF_FRESNEL_CONDUCTOR:
        for (size_t j = 0; j < cnt; j++)
            t->F[j] = bf_conductor(vh[j], p, s[2], &t->dF[j], &t->dF2[j]);
        break;
    default:
        for (size_t j = 0; j < cnt; j++) {
            t->F[j] = 1.0;
            t->dF[j] = 0.0;
        }
        break;
    }
}

/* One specular lobe over a block (a bf_lobe_fn: family.h says why eight arguments).
 * Scalars: s[0] = the D's roughness (n for blinn), s[1] = f0 or ior unless F=none; for
 * F=conductor s[1] = r, s[2] = g of one channel (the driver calls the lobe per channel). */
static void lobe(const bf_model *m, int k, const double *s, const bf_geometry *g, size_t i0, size_t cnt, double *S,
                 double *dS)
{
    (void)k;
    const mf_cfg c = resolve(m);
    const double *lz = g->lz + i0, *vz = g->vz + i0;
    mf_terms t;
    d_pass(c, g, i0, cnt, s[0], &t);
    g_pass(c, g, i0, cnt, s[0], &t);
    f_pass(c, g, i0, cnt, s, &t);
    /* Samples below the horizon get 0 (the driver zeroes them too, but this keeps the
     * NaN/Inf of 1/(NL NV) and tan^2 out of the outputs). */
    const int implicit = c.g == G_IMPLICIT;
    for (size_t j = 0; j < cnt; j++) {
        int valid = lz[j] > 0.0 && vz[j] > 0.0;
        double inv = implicit ? 0.25 : 0.25 / (lz[j] * vz[j]);
        double GFi = t.G[j] * t.F[j] * inv;
        S[j] = valid ? t.D[j] * GFi : 0.0;
        if (dS) {
            dS[j] = valid ? (t.dD[j] * t.G[j] + t.D[j] * t.dG[j]) * t.F[j] * inv : 0.0;
            if (c.f != BF_FRESNEL_NONE)
                dS[BF_BLOCK + j] = valid ? t.D[j] * t.G[j] * t.dF[j] * inv : 0.0;
            if (c.f == BF_FRESNEL_CONDUCTOR)
                dS[2 * BF_BLOCK + j] = valid ? t.D[j] * t.G[j] * t.dF2[j] * inv : 0.0;
        }
    }
}

/* Energy conserving by design (albedo <= 1 whenever rho_d + sum rho_s <= 1): D
 * normalised (integral D cos(theta_h) = 1; the Gaussian integrates to less), F <= 1, and
 * G <= G1(L) for a masking term G1 that satisfies the projected-area constraint
 * integral D(h) G1(L,h) <L.h>+ dh <= NL, which bounds the albedo by 1:
 *  - smith_ggx: exact Smith masking of GGX; with Beckmann D it masks more than Beckmann's
 *    exact Smith term (GGX's Lambda is the larger at equal roughness); with Blinn (n = 0
 *    is GGX alpha = 1 exactly) and Gaussian by quadrature;
 *  - cook_torrance: the V-cavity masking is exact for the V-cavity microsurface built
 *    from any D, so it satisfies the constraint (Heitz 2014, "Understanding the
 *    masking-shadowing function"), and G_ct = min(G1(L), G1(V));
 *  - smith_beckmann with beckmann (Walter's fit of its exact Smith term) or gaussian;
 *  - smith_schlick (an approximation of Smith-Beckmann that masks more at grazing
 *    angles): by quadrature only, with every D.
 * Confirmed by half-vector quadrature over roughness 1e-3..1 and incidence 0..89.99 deg
 * (max albedo 1 + 1e-6, the quadrature error, in the smooth limit). Not conserving:
 *  - smith_beckmann with ggx (albedo 1.73 at alpha = 0.1, 89.99 deg) or blinn (1.34 at
 *    n = 0): the Beckmann masking is too weak for their heavier tails;
 *  - none (G = 1): albedo grows without bound at grazing incidence;
 *  - implicit (G = NL NV, f = D F / 4): no masking argument bounds it (a tilted peak of
 *    D exceeds 1); the four D here stay below 1 numerically, but not by design. */
static int conserving(mf_cfg c)
{
    switch (c.g) {
    case G_SMITH_GGX:
    case G_CT:
    case G_SMITH_SCHLICK: return 1;
    case G_SMITH_BECKMANN: return c.d == D_BECKMANN || c.d == D_GAUSSIAN;
    default: /* G_IMPLICIT, G_NONE */ return 0;
    }
}

/* Default roughness of lobe k: 0.12 k (doubled for lobe 2, distinct and inside the
 * bounds up to BF_MAX_LOBES); blinn gets the exponent equivalent to it. */
static double default_roughness(int d, int k)
{
    double mk = 0.12 * k;
    return d == D_BLINN ? 2.0 / (mk * mk) - 2.0 : mk;
}

static bf_status configure_cfg(bf_model *m, mf_cfg c, bf_error *err)
{
    m->energy_conserving = conserving(c);
    bf_status rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err);
    for (int k = 1; rc == BF_OK && k <= m->lobes; k++) {
        double r0 = default_roughness(c.d, k);
        rc = bf_model_add_param(m, "rho_s", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, k, BF_ROLE_WEIGHT, err);
        if (rc != BF_OK)
            break;
        switch (c.d) {
        case D_GGX:
            rc = bf_model_add_param(m, "alpha", 0, 1e-4, 1.0, r0, BF_SCALE_LOG, k, BF_ROLE_ROUGHNESS, err);
            break;
        case D_BLINN: rc = bf_model_add_param(m, "n", 0, 0.0, 1e6, r0, BF_SCALE_LOG1P, k, BF_ROLE_EXPONENT, err); break;
        default: /* beckmann, gaussian */
            rc = bf_model_add_param(m, "m", 0, 1e-3, 1.0, r0, BF_SCALE_LOG, k, BF_ROLE_ROUGHNESS, err);
            break;
        }
        if (rc == BF_OK)
            rc = bf_model_add_fresnel_param(m, c.f, k, err);
    }
    return rc;
}

static bf_status configure(bf_model *m, bf_error *err)
{
    return configure_cfg(m, resolve(m), err);
}

static const bf_option_info microfacet_options[] = {
    {"D", d_values, 0}, {"G", g_values, 0}, {"F", bf_fresnel_metal_values, 0}, {NULL, NULL, 0}};
static const bf_option_info preset_options[] = {{"fresnel", bf_fresnel_metal_values, 0}, {NULL, NULL, 0}};

const bf_family bf_family_cook_torrance = {
    .info = {.name = "cook_torrance",
             .summary = "Beckmann NDF, V-groove shadowing, Fresnel (microfacet preset)",
             .reference = "Cook & Torrance 1982",
             .options = preset_options,
             .lobes = 1,
             .anisotropic = 0},
    .configure = configure,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe,
};

const bf_family bf_family_walter = {
    .info = {.name = "walter",
             .summary = "GGX NDF, Smith-GGX shadowing, Fresnel (microfacet preset)",
             .reference = "Walter et al. 2007",
             .options = preset_options,
             .lobes = 1,
             .anisotropic = 0},
    .configure = configure,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe,
};

const bf_family bf_family_microfacet = {
    .info = {.name = "microfacet",
             .summary = "composable Torrance-Sparrow: D, G and F by option",
             .reference = "Torrance & Sparrow 1967; Cook & Torrance 1982; Walter et al. 2007",
             .options = microfacet_options,
             .lobes = 1,
             .anisotropic = 0},
    .configure = configure,
    .eval = bf_eval_diffuse_lobes,
    .lobe = lobe,
};
