/* The data-driven start: generic over models, using only the parameter table (names,
 * bounds, scale hints) and the samples; no per-model code. The rules:
 *
 *  1. Diffuse level. Over valid samples far from the specular direction (half-vector
 *     angle theta_h > 25 degrees; every valid sample if none is), per channel, the
 *     median of the lowest 30% of f pi (the 15th percentile): a Lambertian floor that
 *     a specular lobe's tail or a few dark outliers barely move. It starts every
 *     colour parameter outside the lobes (rho_d, Disney's base_color; see is_diffuse).
 *  2. Peak. The excess e = mean over channels of f minus the diffuse level / pi is
 *     averaged in log-spaced theta_h bins (1 mrad growing by 1.25x up to 60 degrees),
 *     a bin with fewer than 16 samples merged with the next ones.
 *     The peak is the largest bin mean below 25 degrees; a peak not above 5% of the
 *     diffuse level (or none: pure Lambertian data, no near-specular samples, negative
 *     data) means "no lobe seen": lobe weights start small (1% of the unit weight) and
 *     widths at their defaults.
 *  3. Width. h = the theta_h (radians) where the bin means first fall below half the
 *     peak beyond it (log-interpolated), or 1 rad if they never do. Lobe k (lobes=K)
 *     gets h 2^(k-1). h maps to each width parameter by what its name says:
 *       alpha, alpha_x, alpha_y, m (log-scale roughness: GGX, Beckmann, Ward, Gaussian)
 *                             1.4 h  (GGX halves at tan = 0.64 alpha, Beckmann at 0.83 m)
 *       n, nu, nv, s, gamma   ln 2 / (1 - cos h)   (cos^n halves there)
 *       b                     1 / (1 - cos h)      (ABC with c = 1 halves there)
 *       beta                  sqrt(tan h / ln 2)   (Brady with a = 1 halves there)
 *       roughness             sqrt(1.4 h)          (Disney: alpha = roughness^2)
 *     A scan of h over factors 1/8 .. 32 (steps of sqrt 2, up to 1.4 rad) then keeps the one whose fit
 *     in step 4 is best, which corrects a peak the samples missed or a lobe so broad
 *     that it lifted the diffuse level of step 1.
 *  4. Weights. With the diffuse colour at 0 and every lobe colour whose role is a weight
 *     (rho_s, rho_s_k) at a unit value (lobe k: 2^-(k-1)), the model's values f1 are the
 *     lobe shape; per channel, y ~ d/pi + r f1 by least squares with d, r >= 0
 *     gives the diffuse colour d and the weights' scale r (lobes are linear in their
 *     weight). Over at most 8192
 *     samples: half the nearest to the peak, half a stride over the others. A weight
 *     fitted to 0 starts at 1e-3 instead, so its lobe's gradient is not zero.
 *  5. Everything else (f0, kappa, anisotropy, shape exponents ...) at its default, and
 *     every value clamped inside its bounds (open bounds: just inside). */
#include "brdfit/fit.h"

#include "base/big_alloc.h"

#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#define DIFFUSE_MIN_THETA_H (25.0 * M_PI / 180.0)
#define NBINS 36
#define BIN0 1e-3 /* upper edge of the first bin, radians */
#define BIN_GROWTH 1.25
#define QUANTILE_CAP 65536 /* samples per channel for the diffuse quantile */
#define SHAPE_CAP 8192     /* samples for the weight and width fit */
#define MIN_GROUP 16       /* samples per theta_h group for the peak and its width */

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

typedef enum width_kind { W_NONE = 0, W_ROUGH, W_EXPONENT, W_ABC_B, W_BETA, W_DISNEY } width_kind;

/* How a lobe width h (radians) becomes this parameter's start, by its role. Kurt's
 * alpha is an exponent on NL NV, declared a shape: no width. */
static width_kind width_of(const bf_param_info *p)
{
    if (p->color)
        return W_NONE;
    switch (p->role) {
    case BF_ROLE_ROUGHNESS: return W_ROUGH;
    case BF_ROLE_EXPONENT: return W_EXPONENT;
    case BF_ROLE_FALLOFF: return W_ABC_B;
    case BF_ROLE_SLOPE_SPREAD: return W_BETA;
    case BF_ROLE_PERCEPTUAL_ROUGHNESS: return W_DISNEY;
    default: return W_NONE;
    }
}

static double clamp_param(const bf_param_info *p, double v)
{
    double span = p->hi - p->lo;
    double lo = p->lo_open ? p->lo + 1e-9 * span : p->lo;
    double hi = p->hi_open ? p->hi - 1e-9 * span : p->hi;
    if (!(v >= lo)) /* NaN goes to the lower bound too */
        v = lo;
    if (v > hi)
        v = hi;
    return v;
}

static double width_value(width_kind w, double h)
{
    if (h > 1.4)
        h = 1.4;
    double omc = 1.0 - cos(h);
    if (omc < 1e-300)
        omc = 1e-300;
    switch (w) {
    case W_ROUGH: return 1.4 * h;
    case W_EXPONENT: return log(2.0) / omc;
    case W_ABC_B: return 1.0 / omc;
    case W_BETA: return sqrt(tan(h) / log(2.0));
    case W_DISNEY: return sqrt(1.4 * h);
    default: return 0.0;
    }
}

/* The k-th smallest of q[0 .. n-1] (q is reordered): Hoare's selection with a
 * median-of-three pivot, O(n) where a sort would be O(n log n), and the same value a sort
 * would put at k. */
static double select_kth(double *q, size_t n, size_t k)
{
    size_t lo = 0, hi = n - 1;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        double a = q[lo], b = q[mid], c = q[hi];
        double pivot = a < b ? (b < c ? b : a < c ? c : a) : (a < c ? a : b < c ? c : b);
        size_t i = lo, j = hi;
        while (i <= j) {
            while (q[i] < pivot)
                i++;
            while (q[j] > pivot)
                j--;
            if (i <= j) {
                double t = q[i];
                q[i] = q[j];
                q[j] = t;
                i++;
                if (j == 0)
                    break;
                j--;
            }
        }
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            return q[k];
    }
    return q[k];
}

/* Per sample, one byte: its theta_h bin (bits 0-5) and whether it is far from the
 * specular direction (FAR); INVALID for a sample that is below the horizon or not
 * finite. */
#define FAR 0x80u
#define INVALID 0xffu

static int bin_of(double th)
{
    if (th < BIN0)
        return 0;
    int b = 1 + (int)floor(log(th / BIN0) / log(BIN_GROWTH));
    return b < NBINS ? b : NBINS - 1;
}

/* Sets every lobe's width parameters from h (lobe k: h 2^(k-1)). */
static void set_widths(const bf_model *m, double *x, double h)
{
    for (int i = 0; i < bf_model_nparams(m); i++) {
        const bf_param_info *p = bf_model_param(m, i);
        width_kind w = width_of(p);
        if (w == W_NONE)
            continue;
        int k = p->lobe > 1 ? p->lobe : 1;
        x[bf_model_param_offset(m, i)] = clamp_param(p, width_value(w, ldexp(h, k - 1)));
    }
}

/* Colour parameters, tied (mono: one value, the mean of what each channel asks) or not.
 * In a lobe, those whose role is a weight (rho_s, rho_s_k) are scaled to the data; any
 * other lobe colour (a conductor's r and g) keeps its default, where it was once scaled
 * as a weight too. Outside the lobes every colour starts at the diffuse level: rho_d and
 * base_color, but also Ashikhmin-Shirley's rho_s and glTF's specular_color, which were
 * measured both ways (docs/models.md, parameter roles): started as a weight, AS's rho_s
 * ends at 0 on pink felt (rmse_log 0.0060 against 0.0022); at its default, glTF's
 * specular_color ends at 0 when a walter fit of the Cornell cayman paint is converted
 * (rmse_log 0.0050 against 0.00084), for 5 % better on one measured material. */
static int is_colored(const bf_param_info *p)
{
    return p->color || p->mono;
}
static int is_weight(const bf_param_info *p)
{
    return is_colored(p) && p->lobe >= 1 && p->role == BF_ROLE_WEIGHT;
}
static int is_diffuse(const bf_param_info *p)
{
    return is_colored(p) && p->lobe == 0;
}

/* Channel c's value v of parameter p into its entry: a mono entry takes the mean. */
static void put_channel(const bf_model *m, int i, double *x, int c, double v)
{
    const bf_param_info *p = bf_model_param(m, i);
    double *e = x + bf_model_param_offset(m, i) + (p->color ? c : 0);
    if (p->mono)
        *e = (c ? *e : 0.0) + v / bf_model_channels(m);
    else
        *e = v;
}

/* Weighted SSR of y ~ d/pi + r f1 over n values with stride C, weights w (n). */
static double ssr_of(const double *y, const double *f1, const double *w, size_t n, int C, double d, double r)
{
    double ssr = 0.0;
    for (size_t i = 0; i < n; i++) {
        double e = w[i] * (y[i * C] - d / M_PI - r * f1[i * C]);
        ssr += e * e;
    }
    return ssr;
}

/* Least squares of y ~ d/pi + r f1 with d, r >= 0 (one channel, values at stride C). */
static double fit_two(const double *y, const double *f1, const double *w, size_t n, int C, double *d, double *r)
{
    double s1 = 0.0, sf = 0.0, sff = 0.0, sy = 0.0, syf = 0.0;
    for (size_t i = 0; i < n; i++) {
        double ww = w[i] * w[i], f = f1[i * C], v = y[i * C];
        s1 += ww, sf += ww * f, sff += ww * f * f, sy += ww * v, syf += ww * v * f;
    }
    const double u = 1.0 / M_PI;
    double a11 = s1 * u * u, a12 = u * sf, a22 = sff, b1 = u * sy, b2 = syf;
    double det = a11 * a22 - a12 * a12;
    if (det > 1e-12 * a11 * a22) {
        *d = (b1 * a22 - b2 * a12) / det;
        *r = (a11 * b2 - a12 * b1) / det;
        if (*d >= 0.0 && *r >= 0.0 && isfinite(*d) && isfinite(*r))
            return ssr_of(y, f1, w, n, C, *d, *r);
    }
    /* On a boundary: the better of lobe only and diffuse only. */
    double r1 = a22 > 0.0 && b2 > 0.0 ? b2 / a22 : 0.0, d2 = a11 > 0.0 && b1 > 0.0 ? b1 / a11 : 0.0;
    double e1 = ssr_of(y, f1, w, n, C, 0.0, r1), e2 = ssr_of(y, f1, w, n, C, d2, 0.0);
    if (isfinite(e1) && (e1 < e2 || !isfinite(e2))) {
        *d = 0.0, *r = r1;
        return e1;
    }
    *d = d2, *r = 0.0;
    return e2;
}

/* What the width scan shares: the model, step 4's samples (their geometry g and values
 * y, n*C of them), and scratch: xs, xb, xk of the model's length, f1 of n*C values. */
typedef struct scan {
    const bf_model *m;
    const bf_geometry *g;
    const double *y;
    double *xs, *xb, *xk, *f1;
} scan;

/* Steps 3-4 at width h: the lobe shapes f1 with unit weights and no diffuse part, then
 * per channel the least-squares diffuse level and weight scale. Writes widths, weights
 * and diffuse colours into x and returns the residual sum of squares; *over is the
 * largest fitted weight over its upper bound. Uses sc->xs and sc->f1. */
static double fit_at_width(const scan *sc, double *x, double h, double *over)
{
    const bf_model *m = sc->m;
    const bf_geometry *g = sc->g;
    double *xs = sc->xs, *f1 = sc->f1;
    *over = 0.0;
    const int P = bf_model_nvalues(m), C = bf_model_channels(m), np = bf_model_nparams(m);
    memcpy(xs, x, (size_t)P * sizeof *xs);
    set_widths(m, xs, h);
    for (int i = 0; i < np; i++) {
        const bf_param_info *p = bf_model_param(m, i);
        double *v = xs + bf_model_param_offset(m, i);
        for (int c = 0; c < (p->color ? C : 1); c++) {
            if (is_weight(p))
                v[c] = clamp_param(p, ldexp(1.0, 1 - p->lobe));
            else if (is_diffuse(p))
                v[c] = clamp_param(p, 0.0);
        }
    }
    bf_model_eval(m, xs, g, f1, NULL);
    set_widths(m, x, h);
    double ssr = 0.0;
    for (int c = 0; c < C; c++) {
        double d, r;
        ssr += fit_two(sc->y + c, f1 + c, g->lz, g->n, C, &d, &r);
        for (int i = 0; i < np; i++) {
            const bf_param_info *p = bf_model_param(m, i);
            int o = bf_model_param_offset(m, i) + (p->color ? c : 0);
            if (is_weight(p)) {
                put_channel(m, i, x, c, clamp_param(p, r > 0.0 ? r * xs[o] : 1e-3));
                if (r * xs[o] / p->hi > *over)
                    *over = r * xs[o] / p->hi;
            } else if (is_diffuse(p))
                put_channel(m, i, x, c, clamp_param(p, d));
        }
    }
    return isfinite(ssr) ? ssr : HUGE_VAL;
}

/* Width scan: h times 2^(j/2), j = -6 .. 10 (up to 1.4 rad), the diffuse level and
 * weights fitted at each (fit_at_width); x gets the best. Returns its SSR; *over as
 * fit_at_width's there. Uses sc->xb besides fit_at_width's scratch. */
static double scan_widths(const scan *sc, double *x, double h, double *over)
{
    const int P = bf_model_nvalues(sc->m);
    double *xb = sc->xb;
    double best = HUGE_VAL, best_h = h;
    for (int j = -6; j <= 10; j++) {
        double hj = h * pow(2.0, j / 2.0);
        if (hj > 1.4)
            break;
        memcpy(xb, x, (size_t)P * sizeof *xb);
        double ssr = fit_at_width(sc, xb, hj, over);
        if (ssr < best)
            best = ssr, best_h = hj;
    }
    return fit_at_width(sc, x, best_h, over);
}

/* What the steps share: the model, the samples, the start being built, and each
 * sample's class. */
typedef struct start {
    const bf_model *m;
    const bf_samples *s;
    const bf_geometry *g;
    double *x;
    int C, np;
    size_t n, nvalid, nfar;
    unsigned char *code; /* per sample: INVALID, or its theta_h bin | FAR */
    size_t cnt[NBINS];   /* valid samples per theta_h bin */
} start;

/* Each sample's class: invalid (geometry or a non-finite value), or its theta_h bin and
 * whether it is far from the specular direction. */
static void classify(start *st)
{
    const int C = st->C;
    bf_geometry_block gb;
    for (size_t ib = 0; ib < st->n; ib += BF_GEOMETRY_BLOCK) {
        size_t cnt = st->n - ib < BF_GEOMETRY_BLOCK ? st->n - ib : BF_GEOMETRY_BLOCK;
        const bf_geometry *gv = bf_geometry_view(st->g, ib, cnt, &gb);
        double last_s2 = NAN, last_hz = NAN, th = 0.0;
        for (size_t j = 0; j < cnt; j++) {
            size_t i = ib + j;
            int ok = bf_geometry_valid(gv, j);
            for (int c = 0; c < C && ok; c++)
                ok = isfinite(st->s->value[i * C + c]);
            if (!ok) {
                st->code[i] = INVALID;
                continue;
            }
            /* Samples in a row often share H (a MERL table runs through phi_d). */
            if (gv->sin2h[j] != last_s2 || gv->hz[j] != last_hz) {
                last_s2 = gv->sin2h[j], last_hz = gv->hz[j];
                th = atan2(sqrt(last_s2), last_hz);
            }
            int far = th > DIFFUSE_MIN_THETA_H;
            st->code[i] = (unsigned char)(bin_of(th) | (far ? FAR : 0u));
            st->nvalid++;
            st->nfar += (size_t)far;
        }
    }
}

/* Step 1: the diffuse level per channel, from a strided subset of at most QUANTILE_CAP
 * samples (q: room for them), into diffuse[] and the diffuse colours of x. */
static void diffuse_level(start *st, double *q, double *diffuse)
{
    const int C = st->C;
    const unsigned char far_mask = st->nfar > 0 ? FAR : 0u; /* none far: every valid sample */
    size_t pool = st->nfar > 0 ? st->nfar : st->nvalid, stride = (pool + QUANTILE_CAP - 1) / QUANTILE_CAP;
    for (int c = 0; c < C; c++) {
        size_t k = 0, seen = 0;
        for (size_t i = 0; i < st->n && k < QUANTILE_CAP; i++)
            if (st->code[i] != INVALID && (st->code[i] & far_mask) == far_mask && seen++ % stride == 0)
                q[k++] = st->s->value[i * C + c] * M_PI;
        diffuse[c] = select_kth(q, k, (size_t)(0.15 * (double)(k - 1) + 0.5));
    }
    for (int i = 0; i < st->np; i++) {
        if (is_diffuse(bf_model_param(st->m, i)))
            for (int c = 0; c < C; c++)
                put_channel(st->m, i, st->x, c, diffuse[c]);
    }
}

/* Steps 2 and 3: the peak of the excess over the diffuse level in theta_h groups, and
 * the half width h beyond it. 1 with *h, or 0 when no lobe is seen. Counts st->cnt. */
static int peak_width(start *st, const double *diffuse, double *h)
{
    const int C = st->C;
    double dmean = 0.0;
    for (int c = 0; c < C; c++)
        dmean += diffuse[c] / (M_PI * C);
    double sum[NBINS] = {0};
    for (size_t i = 0; i < st->n; i++) {
        if (st->code[i] == INVALID)
            continue;
        double v = 0.0;
        for (int c = 0; c < C; c++)
            v += st->s->value[i * C + c] / C;
        int b = st->code[i] & 0x3f;
        sum[b] += v - dmean;
        st->cnt[b]++;
    }
    /* Bins with few samples merge with the next ones (up to MIN_GROUP samples), so
     * that one sample's geometry (Fresnel, shadowing at grazing) is not a peak. */
    double gsum[NBINS], gt[NBINS];
    size_t gcnt[NBINS];
    int ng = 0, g0 = 0;
    for (int b = 0; b < NBINS; b++) {
        if (b == g0) {
            gsum[ng] = 0.0;
            gcnt[ng] = 0;
        }
        gsum[ng] += sum[b];
        gcnt[ng] += st->cnt[b];
        if (gcnt[ng] >= MIN_GROUP || (b == NBINS - 1 && gcnt[ng] > 0)) {
            double lo_edge = g0 == 0 ? 0.5 * BIN0 : BIN0 * pow(BIN_GROWTH, g0 - 1);
            gt[ng++] = sqrt(lo_edge * BIN0 * pow(BIN_GROWTH, b)); /* geometric centre */
            g0 = b + 1;
        }
    }
    int peak = -1;
    double pk = 0.0;
    for (int k = 0; k < ng && gt[k] < DIFFUSE_MIN_THETA_H; k++)
        if (peak < 0 || gsum[k] / gcnt[k] > pk)
            pk = gsum[k] / gcnt[k], peak = k;
    double small = 0.05 * fabs(dmean);
    if (peak < 0 || !(pk > small) || !(pk > 0.0))
        return 0;
    /* Where the group means first fall below half the peak, log-interpolated. */
    double prev_t = gt[peak], prev_v = pk;
    *h = 1.0;
    for (int k = peak + 1; k < ng; k++) {
        double v = gsum[k] / gcnt[k], t = gt[k];
        if (v < 0.5 * pk) {
            double f = (prev_v - 0.5 * pk) / (prev_v - v); /* in (0, 1] */
            *h = exp(log(prev_t) + f * (log(t) - log(prev_t)));
            break;
        }
        prev_t = t, prev_v = v;
    }
    return 1;
}

/* No lobe seen: small weights (their widths stay at the defaults). */
static void small_weights(start *st)
{
    for (int i = 0; i < st->np; i++)
        if (is_weight(bf_model_param(st->m, i)))
            for (int c = 0; c < st->C; c++)
                put_channel(st->m, i, st->x, c, 0.01);
}

/* Step 4's samples: the bins nearest the peak direction, up to SHAPE_CAP / 2 (the last
 * bin taken with a stride), and a strided subset of the others, up to SHAPE_CAP / 2,
 * which pins the diffuse level. Their directions go into L (room for 6 (SHAPE_CAP + 2)),
 * their values into ev, and their geometry into *sg (NULL when there is none). */
static bf_status shape_samples(const start *st, double *L, double *ev, bf_geometry **sg, bf_error *err)
{
    const int C = st->C;
    const size_t half = SHAPE_CAP / 2;
    size_t take = 0, last_stride = 1;
    int last = -1;
    for (int b = 0; b < NBINS; b++) {
        if (take + st->cnt[b] <= half) {
            take += st->cnt[b], last = b;
            continue;
        }
        size_t room = half - take;
        last_stride = room ? (st->cnt[b] + room - 1) / room : st->cnt[b] + 1;
        last = b;
        break;
    }
    size_t rest = 0;
    for (int b = last + 1; b < NBINS; b++)
        rest += st->cnt[b];
    size_t rest_stride = rest > half ? (rest + half - 1) / half : 1;
    double *V = L + 3 * (SHAPE_CAP + 2);
    size_t ns = 0, in_last = 0, in_rest = 0;
    bf_geometry_block gb;
    for (size_t i = 0; i < st->n && ns < SHAPE_CAP; i++) {
        if (st->code[i] == INVALID)
            continue;
        int b = st->code[i] & 0x3f;
        if (b == last ? in_last++ % last_stride != 0 : b > last && in_rest++ % rest_stride != 0)
            continue;
        const bf_geometry *gv = bf_geometry_view(st->g, i, 1, &gb);
        L[3 * ns] = gv->lx[0], L[3 * ns + 1] = gv->ly[0], L[3 * ns + 2] = gv->lz[0];
        V[3 * ns] = gv->vx[0], V[3 * ns + 1] = gv->vy[0], V[3 * ns + 2] = gv->vz[0];
        for (int c = 0; c < C; c++)
            ev[ns * C + c] = st->s->value[i * C + c];
        ns++;
    }
    return ns ? bf_geometry_from_vectors(ns, L, V, sg, err) : BF_OK;
}

/* The width scan (scan_widths). A lobe that needs a weight above its bound with f0 at its
 * default (a metal, or a highlight brighter than f0 = 0.04 allows) gets f0 raised by that
 * factor and another scan, kept while it fits better (4 at most). Uses sc->xk besides the
 * scan's scratch. */
static void scan_raising_f0(const start *st, const scan *sc, double h)
{
    const bf_model *m = st->m;
    double *x = st->x, *xk = sc->xk;
    const size_t P = (size_t)bf_model_nvalues(m);
    double over, ssr0 = scan_widths(sc, x, h, &over);
    int has_f0 = 0;
    for (int i = 0; i < st->np; i++)
        has_f0 |= bf_model_param(m, i)->role == BF_ROLE_F0;
    for (int pass = 0; pass < 4 && over > 1.0 && has_f0; pass++) {
        memcpy(xk, x, P * sizeof *xk);
        for (int i = 0; i < st->np; i++) {
            const bf_param_info *p = bf_model_param(m, i);
            if (p->role == BF_ROLE_F0) /* every channel of a colour one (a conductor's r) */
                for (int c = 0; c < (p->color ? st->C : 1); c++) {
                    double *v = x + bf_model_param_offset(m, i) + c;
                    *v = clamp_param(p, *v * over);
                }
        }
        double ssr = scan_widths(sc, x, h, &over);
        if (!(ssr < ssr0)) {
            memcpy(x, xk, P * sizeof *xk);
            break;
        }
        ssr0 = ssr;
    }
}

/* Step 5: every value inside its bounds. */
static void clamp_all(const bf_model *m, double *x)
{
    const int C = bf_model_channels(m);
    for (int i = 0; i < bf_model_nparams(m); i++) {
        const bf_param_info *p = bf_model_param(m, i);
        for (int c = 0; c < (p->color ? C : 1); c++) {
            double *v = x + bf_model_param_offset(m, i) + c;
            *v = clamp_param(p, *v);
        }
    }
}

bf_status bf_fit_initial_guess(const bf_model *m, bf_samples *s, double *x, bf_error *err)
{
    const int C = bf_model_channels(m), P = bf_model_nvalues(m), np = bf_model_nparams(m);
    if (C != s->channels)
        return bf_fail(err, BF_ERR_ARG, "model %s has %d channels, the samples %d", bf_model_spec(m), C, s->channels);
    bf_model_defaults(m, x);
    start st = {.m = m, .s = s, .x = x, .C = C, .np = np, .n = s->n};
    bf_status rc = bf_samples_geometry(s, &st.g, err);
    if (rc != BF_OK)
        return rc;

    st.code = bf_big_malloc(s->n + 1);
    double *q = malloc((QUANTILE_CAP + 1) * sizeof *q);
    double *diffuse = calloc((size_t)C, sizeof *diffuse);
    double *xs = malloc((size_t)P * sizeof *xs + 1), *xb = malloc((size_t)P * sizeof *xb + 1);
    double *xk = malloc((size_t)P * sizeof *xk + 1);
    double *L = NULL, *ev = NULL, *f1 = NULL;
    bf_geometry *sg = NULL;
    if (!st.code || !q || !diffuse || !xs || !xb || !xk) {
        rc = bf_fail(err, BF_ERR_NOMEM, "initial guess: out of memory");
        goto done;
    }
    classify(&st);
    if (st.nvalid == 0)
        goto clamp; /* nothing to learn from: defaults */
    diffuse_level(&st, q, diffuse);
    int has_weight = 0, has_width = 0;
    for (int i = 0; i < np; i++) {
        has_weight |= is_weight(bf_model_param(m, i));
        has_width |= width_of(bf_model_param(m, i)) != W_NONE;
    }
    if (!has_weight && !has_width)
        goto clamp;
    double h;
    if (!peak_width(&st, diffuse, &h)) {
        small_weights(&st);
        goto clamp;
    }
    L = malloc(6 * (SHAPE_CAP + 2) * sizeof *L);
    ev = malloc((SHAPE_CAP + 2) * (size_t)C * sizeof *ev);
    f1 = malloc((SHAPE_CAP + 2) * (size_t)C * sizeof *f1);
    if (!L || !ev || !f1) {
        rc = bf_fail(err, BF_ERR_NOMEM, "initial guess: out of memory");
        goto done;
    }
    rc = shape_samples(&st, L, ev, &sg, err);
    if (!sg) /* failed, or no sample to scan */
        goto clamp;
    if (has_weight) {
        const scan sc = {.m = m, .g = sg, .y = ev, .xs = xs, .xb = xb, .xk = xk, .f1 = f1};
        scan_raising_f0(&st, &sc, h);
    } else
        set_widths(m, x, h);
clamp:
    clamp_all(m, x);
done:
    bf_geometry_free(sg);
    free(st.code);
    free(q);
    free(diffuse);
    free(xs);
    free(xb);
    free(xk);
    free(L);
    free(ev);
    free(f1);
    return rc;
}
