/* Spectral reflectance to XYZ, sRGB or ACEScg (brdfit/color.h).
 *
 * Decisions where color.h leaves room:
 * - Integration is the CIE 015 weighted sum over the 5 nm table (360-830 nm); the data
 *   spectrum is interpolated onto it by the cubic Lagrange polynomial through the four
 *   nearest measured wavelengths (quadratic or linear where fewer exist: next to the
 *   ends, or with 2-3 channels), which CIE 015:2018 (7.2.2) lists among the accepted
 *   methods and which, unlike Sprague's, needs no even spacing; and held constant past
 *   its ends (the CIE 015 / ASTM E308 advice for truncated data: repeat the end values).
 *   Linear interpolation would move the chromaticity of saturated ColorChecker
 *   patches by up to 8e-4 from BabelColor's published values; the cubic stays within
 *   6e-5, their rounding.
 * - The white that RGB is adapted from is the one the same weights give a flat spectrum,
 *   not a rounded chromaticity, so a flat spectrum lands on (1, 1, 1) to rounding for
 *   every illuminant: a grey paint is grey whatever it was integrated under.
 * - Chromatic adaptation is Bradford (Lam 1985), as ICC and most colour software use. */
#include "brdfit/color.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "cie_tables.h"

static const char *const color_names[] = {"none", "srgb", "acescg", "xyz"};
static const char *const illuminant_names[] = {"d65", "e", "a", "d50"};

const char *bf_color_name(bf_color c)
{
    return (unsigned)c < 4 ? color_names[c] : "unknown";
}

const char *bf_illuminant_name(bf_illuminant i)
{
    return (unsigned)i < 4 ? illuminant_names[i] : "unknown";
}

bf_status bf_color_parse(const char *name, bf_color *out, bf_error *err)
{
    for (int k = 1; name && k < 4; k++)
        if (!strcasecmp(name, color_names[k])) {
            *out = (bf_color)k;
            return BF_OK;
        }
    return bf_fail(err, BF_ERR_ARG, "unknown colour space '%s' (srgb, acescg, xyz)", name ? name : "");
}

bf_status bf_illuminant_parse(const char *name, bf_illuminant *out, bf_error *err)
{
    for (int k = 0; name && k < 4; k++)
        if (!strcasecmp(name, illuminant_names[k])) {
            *out = (bf_illuminant)k;
            return BF_OK;
        }
    return bf_fail(err, BF_ERR_ARG, "unknown illuminant '%s' (d65, e, a, d50)", name ? name : "");
}

int bf_color_from_name(const char *name)
{
    bf_color c;
    return bf_color_parse(name, &c, NULL) == BF_OK ? (int)c : -1;
}

int bf_illuminant_from_name(const char *name)
{
    bf_illuminant i;
    return bf_illuminant_parse(name, &i, NULL) == BF_OK ? (int)i : -1;
}

static double illuminant(bf_illuminant ill, const bf_cie_row *r)
{
    switch (ill) {
    case BF_ILLUMINANT_E: return 100.0;
    case BF_ILLUMINANT_A: return bf_cie_illuminant_a(r->nm);
    case BF_ILLUMINANT_D50: return r->d50;
    default: return r->d65;
    }
}

/* ---- 3x3 matrices, row-major ------------------------------------------------------ */

static void mat_mul(const double a[9], const double b[9], double out[9])
{
    double t[9];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            t[3 * i + j] = a[3 * i] * b[j] + a[3 * i + 1] * b[3 + j] + a[3 * i + 2] * b[6 + j];
    memcpy(out, t, sizeof t);
}

static void mat_vec(const double a[9], const double v[3], double out[3])
{
    double t[3];
    for (int i = 0; i < 3; i++)
        t[i] = a[3 * i] * v[0] + a[3 * i + 1] * v[1] + a[3 * i + 2] * v[2];
    memcpy(out, t, sizeof t);
}

static void mat_inv(const double a[9], double out[9])
{
    double c[9] = {a[4] * a[8] - a[5] * a[7], a[2] * a[7] - a[1] * a[8], a[1] * a[5] - a[2] * a[4],
                   a[5] * a[6] - a[3] * a[8], a[0] * a[8] - a[2] * a[6], a[2] * a[3] - a[0] * a[5],
                   a[3] * a[7] - a[4] * a[6], a[1] * a[6] - a[0] * a[7], a[0] * a[4] - a[1] * a[3]};
    double det = a[0] * c[0] + a[1] * c[3] + a[2] * c[6];
    for (int i = 0; i < 9; i++)
        out[i] = c[i] / det;
}

/* XYZ -> RGB for primaries xy[0..5] (r, g, b) and white wx, wy (Y = 1 maps to 1, 1, 1). */
static void xyz_to_rgb(const double xy[6], double wx, double wy, double out[9])
{
    double P[9], Pi[9], W[3] = {wx / wy, 1.0, (1.0 - wx - wy) / wy}, S[3];
    for (int j = 0; j < 3; j++) {
        double x = xy[2 * j], y = xy[2 * j + 1];
        P[j] = x / y;
        P[3 + j] = 1.0;
        P[6 + j] = (1.0 - x - y) / y;
    }
    mat_inv(P, Pi);
    mat_vec(Pi, W, S);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            P[3 * i + j] *= S[j];
    mat_inv(P, out);
}

/* Bradford adaptation from white ws to white wd (XYZ). */
static void bradford(const double ws[3], const double wd[3], double out[9])
{
    static const double B[9] = {0.8951, 0.2664, -0.1614, -0.7502, 1.7135, 0.0367, 0.0389, -0.0685, 1.0296};
    double Bi[9], s[3], d[3], D[9] = {0};
    mat_vec(B, ws, s);
    mat_vec(B, wd, d);
    for (int i = 0; i < 3; i++)
        D[4 * i] = d[i] / s[i];
    mat_inv(B, Bi);
    mat_mul(D, B, out);
    mat_mul(Bi, out, out);
}

/* XYZ (relative to white w, Y = 1) -> the RGB space c. */
static void rgb_matrix(bf_color c, const double w[3], double out[9])
{
    static const double srgb[6] = {0.64, 0.33, 0.30, 0.60, 0.15, 0.06};
    static const double ap1[6] = {0.713, 0.293, 0.165, 0.830, 0.128, 0.044};
    const double *xy = c == BF_COLOR_SRGB ? srgb : ap1;
    const double wx = c == BF_COLOR_SRGB ? 0.3127 : 0.32168, wy = c == BF_COLOR_SRGB ? 0.3290 : 0.33767;
    double M[9], A[9], wd[3] = {wx / wy, 1.0, (1.0 - wx - wy) / wy};
    xyz_to_rgb(xy, wx, wy, M);
    bradford(w, wd, A);
    mat_mul(M, A, out);
}

/* ---- Spectrum to XYZ ------------------------------------------------------------- */

static bf_status check_wavelengths(const double *wl, int n, int *order, bf_error *err)
{
    if (n < 2)
        return bf_fail(err, BF_ERR_ARG, "colorimetry needs at least 2 wavelengths, got %d", n);
    for (int i = 0; i < n; i++) {
        if (!(isfinite(wl[i]) && wl[i] > 0.0))
            return bf_fail(err, BF_ERR_ARG, "wavelength %g nm is not a positive number", wl[i]);
        order[i] = i;
    }
    for (int i = 1; i < n; i++) /* insertion sort: spectra have tens of channels */
        for (int j = i; j > 0 && wl[order[j]] < wl[order[j - 1]]; j--) {
            int t = order[j];
            order[j] = order[j - 1];
            order[j - 1] = t;
        }
    for (int i = 1; i < n; i++)
        if (wl[order[i]] == wl[order[i - 1]])
            return bf_fail(err, BF_ERR_ARG, "wavelength %g nm appears twice", wl[order[i]]);
    double lo = wl[order[0]], hi = wl[order[n - 1]];
    if (hi < bf_cie_table[0].nm || lo > bf_cie_table[BF_CIE_ROWS - 1].nm)
        return bf_fail(err, BF_ERR_ARG, "wavelengths %g-%g nm lie outside the visible 360-830 nm", lo, hi);
    return BF_OK;
}

/* Lagrange weights at x of the sorted nodes order[lo..hi] (at most 4). */
static void lagrange(const double *wl, const int *order, int lo, int hi, double x, double *wt)
{
    for (int a = lo; a <= hi; a++) {
        double w = 1.0;
        for (int b = lo; b <= hi; b++)
            if (b != a)
                w *= (x - wl[order[b]]) / (wl[order[a]] - wl[order[b]]);
        wt[a - lo] = w;
    }
}

/* T[k * n + i]: XYZ weights of channel i, normalised so that a flat 1 gives Y = 1. */
static void xyz_weights(const double *wl, int n, const int *order, bf_illuminant ill, double *T)
{
    memset(T, 0, 3 * (size_t)n * sizeof *T);
    double norm = 0.0;
    int seg = 0; /* order[seg] <= the table wavelength < order[seg + 1] */
    for (int j = 0; j < BF_CIE_ROWS; j++) {
        const bf_cie_row *r = &bf_cie_table[j];
        double S = illuminant(ill, r), a[3] = {S * r->xbar, S * r->ybar, S * r->zbar};
        norm += a[1];
        int lo, hi;
        double wt[4] = {1.0, 0.0, 0.0, 0.0};
        if (r->nm <= wl[order[0]]) {
            lo = hi = 0;
        } else if (r->nm >= wl[order[n - 1]]) {
            lo = hi = n - 1;
        } else {
            while (wl[order[seg + 1]] <= r->nm)
                seg++;
            lo = seg > 0 ? seg - 1 : 0;
            hi = seg + 2 < n ? seg + 2 : n - 1;
            lagrange(wl, order, lo, hi, r->nm, wt);
        }
        for (int q = lo; q <= hi; q++)
            for (int k = 0; k < 3; k++)
                T[k * n + order[q]] += a[k] * wt[q - lo];
    }
    for (int q = 0; q < 3 * n; q++)
        T[q] /= norm;
}

bf_status bf_color_weights(const double *wavelength, int n, bf_color c, bf_illuminant ill, double *w, bf_error *err)
{
    if (c != BF_COLOR_SRGB && c != BF_COLOR_ACESCG && c != BF_COLOR_XYZ)
        return bf_fail(err, BF_ERR_ARG, "no colour space to convert to");
    if ((unsigned)ill > BF_ILLUMINANT_D50)
        return bf_fail(err, BF_ERR_ARG, "unknown illuminant %d", (int)ill);
    int *order = malloc((size_t)(n > 0 ? n : 1) * sizeof *order);
    if (!order)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    bf_status rc = check_wavelengths(wavelength, n, order, err);
    if (rc == BF_OK)
        xyz_weights(wavelength, n, order, ill, w);
    free(order);
    if (rc != BF_OK || c == BF_COLOR_XYZ)
        return rc;
    double white[3] = {0, 0, 0}, M[9];
    for (int k = 0; k < 3; k++)
        for (int i = 0; i < n; i++)
            white[k] += w[k * n + i];
    rgb_matrix(c, white, M);
    for (int i = 0; i < n; i++) {
        double v[3] = {w[i], w[n + i], w[2 * n + i]};
        mat_vec(M, v, v);
        for (int k = 0; k < 3; k++)
            w[k * n + i] = v[k];
    }
    return BF_OK;
}
