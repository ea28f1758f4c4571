/* Preprocessing before a fit: channel selection, spectral to RGB or to one channel,
 * dropping what cannot be used, and a seeded stratified subsample.
 *
 * Decisions where prep.h leaves room:
 * - Channel selection: each comma-separated item is first looked up as a channel name,
 *   then (all digits) as a 0-based index, so "550" on spectral data means 550 nm when a
 *   channel has that name. A channel selected twice is an error. Selecting every
 *   channel in its own order changes nothing (a MERL origin is kept).
 * - color: brdfit/color.h's weights on the channels' wavelengths (s->wavelength, or
 *   channel names that are numbers as below); channels r, g, b (sRGB, ACEScg) or X, Y,
 *   Z. It needs a wavelength for every channel: index groups are the bands' fallback
 *   only, and a colour computed from guessed wavelengths would be wrong.
 * - to_bands with wavelengths (s->wavelength, or channel names that are all numbers,
 *   optionally with "nm", as in a CSV with wavelength headers): b = mean of the
 *   channels in [400, 500) nm, g = [500, 600), r = [600, 700]; channels outside are
 *   ignored; a band without a channel is an error. Without wavelengths (more than 3
 *   channels): three index groups [0, C/3), [C/3, 2C/3), [2C/3, C) (integer division),
 *   taken as b, g, r, assuming channels run from short to long wavelengths as spectral
 *   files list them. Output order r, g, b.
 * - to_luminance: 3 channels named r, g, b (any order, any case) give Rec. 709
 *   luminance 0.2126 r + 0.7152 g + 0.0722 b (channel "luminance"); spectral channels
 *   with a wavelength each give CIE Y under the illuminant, the Y of color = XYZ, so a
 *   flat spectrum v gives v (channel "luminance"; that is what Rec. 709's weights are
 *   for sRGB primaries); anything else the unweighted mean of the channels (channel
 *   "mean"). With both set, to_bands or color runs first.
 * - Drops count each sample once, under the first reason that applies in this order:
 *   non-finite angle or value (nonfinite), below the horizon, above max_theta, then a
 *   negative value. So `negative` counts the negative samples among those that passed
 *   the other filters: the ones dropped, clamped or kept (before subsampling).
 * - Subsampling to N >= the samples left keeps them all (subsampled_out = 0): "at most
 *   N", so one option suits every file of a batch. */
#include "samples/prep_options.h"
#include "brdfit/prep.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/big_alloc.h"
#include "io/merl_cells.h"
#include "base/rng.h"

/* ---- Channels ---------------------------------------------------------------- */

/* New channel arrays for n samples and K channels; names zeroed. */
static bf_status alloc_channels(size_t n, int K, double **vals, char ***names, bf_error *err)
{
    *vals = bf_big_calloc(n * (size_t)K + 1, sizeof **vals);
    *names = calloc((size_t)K, sizeof **names);
    if (!*vals || !*names) {
        free(*vals);
        free(*names);
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for %zu samples of %d channels", n, K);
    }
    return BF_OK;
}

static void free_names(char **names, int K)
{
    for (int c = 0; names && c < K; c++)
        free(names[c]);
    free(names);
}

/* New arrays for three output channels with the given names (to_bands, to_color). */
static bf_status alloc_three(size_t n, const char *const name[3], double **vals, char ***names, bf_error *err)
{
    bf_status rc = alloc_channels(n, 3, vals, names, err);
    for (int k = 0; rc == BF_OK && k < 3; k++)
        if (!((*names)[k] = strdup(name[k]))) {
            free(*vals);
            free_names(*names, 3);
            rc = bf_fail(err, BF_ERR_NOMEM, "out of memory");
        }
    return rc;
}

/* Replaces the channels of s (taking ownership). The MERL origin no longer describes
 * the data, so it goes. */
static void set_channels(bf_samples *s, int K, double *vals, char **names, double *wl)
{
    free_names(s->channel_names, s->channels);
    free(s->value);
    free(s->wavelength);
    s->channels = K;
    s->value = vals;
    s->channel_names = names;
    s->wavelength = wl;
    bf_samples_drop_origin(s);
}

/* "r, g, b" (or as many as fit), for error messages. */
static const char *list_names(const bf_samples *s, char *buf, size_t size)
{
    size_t len = 0;
    buf[0] = '\0';
    for (int c = 0; c < s->channels; c++) {
        int w = snprintf(buf + len, size - len, "%s%s", c ? ", " : "", s->channel_names[c]);
        if (w < 0 || (size_t)w >= size - len) {
            snprintf(buf + (size > 4 ? size - 4 : 0), size > 4 ? 4 : size, "...");
            break;
        }
        len += (size_t)w;
    }
    return buf;
}

static int find_channel(const bf_samples *s, const char *tok)
{
    for (int c = 0; c < s->channels; c++)
        if (strcmp(s->channel_names[c], tok) == 0)
            return c;
    size_t len = strlen(tok);
    if (len == 0 || len > 9 || strspn(tok, "0123456789") != len)
        return -1;
    long idx = strtol(tok, NULL, 10);
    return idx < s->channels ? (int)idx : -1;
}

static bf_status select_channels(bf_samples *s, const char *spec, bf_error *err)
{
    char listbuf[200];
    int K = 1;
    for (const char *p = spec; *p; p++)
        K += *p == ',';
    char *copy = strdup(spec);
    int *idx = malloc((size_t)K * sizeof *idx);
    bf_status rc = BF_OK;
    if (!copy || !idx) {
        rc = bf_fail(err, BF_ERR_NOMEM, "out of memory");
        goto done;
    }
    char *p = copy;
    for (int k = 0; k < K; k++) {
        char *comma = strchr(p, ',');
        if (comma)
            *comma = '\0';
        while (isspace((unsigned char)*p))
            p++;
        for (char *e = p + strlen(p); e > p && isspace((unsigned char)e[-1]);)
            *--e = '\0';
        if (!*p) {
            rc = bf_fail(err, BF_ERR_ARG, "empty item in the channel list '%s'", spec);
            goto done;
        }
        if ((idx[k] = find_channel(s, p)) < 0) {
            rc = bf_fail(err, BF_ERR_ARG, "unknown channel '%s' (the data has %d: %s; or 0-based indices)", p,
                         s->channels, list_names(s, listbuf, sizeof listbuf));
            goto done;
        }
        for (int j = 0; j < k; j++)
            if (idx[j] == idx[k]) {
                rc = bf_fail(err, BF_ERR_ARG, "channel '%s' is selected twice in '%s'", s->channel_names[idx[k]], spec);
                goto done;
            }
        p = comma ? comma + 1 : p + strlen(p);
    }
    int identity = K == s->channels;
    for (int k = 0; identity && k < K; k++)
        identity = idx[k] == k;
    if (identity)
        goto done;

    double *vals, *wl = NULL;
    char **names;
    if ((rc = alloc_channels(s->n, K, &vals, &names, err)) != BF_OK)
        goto done;
    if (s->wavelength && !(wl = malloc((size_t)K * sizeof *wl)))
        goto nomem;
    for (int k = 0; k < K; k++) {
        if (!(names[k] = strdup(s->channel_names[idx[k]])))
            goto nomem;
        if (wl)
            wl[k] = s->wavelength[idx[k]];
    }
    const size_t C = (size_t)s->channels;
    for (size_t i = 0; i < s->n; i++)
        for (int k = 0; k < K; k++)
            vals[i * (size_t)K + (size_t)k] = s->value[i * C + (size_t)idx[k]];
    set_channels(s, K, vals, names, wl);
    goto done;
nomem:
    free(vals);
    free(wl);
    free_names(names, K);
    rc = bf_fail(err, BF_ERR_NOMEM, "out of memory");
done:
    free(copy);
    free(idx);
    return rc;
}

/* A channel name that is a wavelength: a positive number, optionally followed by "nm". */
static int name_wavelength(const char *name, double *w)
{
    char *end;
    *w = strtod(name, &end);
    if (end == name)
        return 0;
    while (isspace((unsigned char)*end))
        end++;
    if (!strcasecmp(end, "nm"))
        end += 2;
    return *end == '\0' && isfinite(*w) && *w > 0.0;
}

/* Output band (0 r, 1 g, 2 b) of a wavelength; -1 outside 400-700 nm. */
static int band_of(double w)
{
    if (w >= 400.0 && w < 500.0)
        return 2;
    if (w >= 500.0 && w < 600.0)
        return 1;
    if (w >= 600.0 && w <= 700.0)
        return 0;
    return -1;
}

/* The wavelength of every channel into wl (from s->wavelength, else from numeric
 * channel names); 0 when some channel has none. */
static int channel_wavelengths(const bf_samples *s, double *wl)
{
    for (int c = 0; c < s->channels; c++) {
        if (s->wavelength)
            wl[c] = s->wavelength[c];
        else if (!name_wavelength(s->channel_names[c], &wl[c]))
            return 0;
    }
    return 1;
}

static bf_status to_bands(bf_samples *s, bf_error *err)
{
    const int C = s->channels;
    int *band = malloc((size_t)C * sizeof *band);
    double *wl = malloc((size_t)C * sizeof *wl);
    if (!band || !wl) {
        free(band);
        free(wl);
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    }
    int have_wl = channel_wavelengths(s, wl);
    double wlo = INFINITY, whi = -INFINITY;
    char listbuf[200];
    bf_status rc = BF_OK;
    if (have_wl) {
        for (int c = 0; c < C; c++) {
            band[c] = band_of(wl[c]);
            wlo = fmin(wlo, wl[c]);
            whi = fmax(whi, wl[c]);
        }
        static const char *const band_name[3] = {"600-700 nm (r)", "500-600 nm (g)", "400-500 nm (b)"};
        for (int b = 0; b < 3; b++) {
            int found = 0;
            for (int c = 0; c < C; c++)
                found |= band[c] == b;
            if (!found) {
                rc = bf_fail(err, BF_ERR_ARG, "cannot make RGB: no channel in %s (wavelengths %g-%g nm)", band_name[b],
                             wlo, whi);
                goto done;
            }
        }
    } else if (C > 3) {
        for (int c = 0; c < C; c++) /* index groups, short wavelengths first: b, g, r */
            band[c] = c < C / 3 ? 2 : c < 2 * C / 3 ? 1 : 0;
    } else {
        rc = bf_fail(err, BF_ERR_ARG,
                     "cannot make RGB: it needs spectral data (wavelengths, or more than 3 channels); the "
                     "data has %d channel%s (%s)",
                     C, C == 1 ? "" : "s", list_names(s, listbuf, sizeof listbuf));
        goto done;
    }
    int count[3] = {0, 0, 0};
    for (int c = 0; c < C; c++)
        if (band[c] >= 0)
            count[band[c]]++;
    double *vals;
    char **names;
    static const char *const rgb[3] = {"r", "g", "b"};
    if ((rc = alloc_three(s->n, rgb, &vals, &names, err)) != BF_OK)
        goto done;
    for (size_t i = 0; i < s->n; i++) {
        const double *v = s->value + i * (size_t)C;
        double *o = vals + 3 * i;
        for (int c = 0; c < C; c++)
            if (band[c] >= 0)
                o[band[c]] += v[c];
        for (int b = 0; b < 3; b++)
            o[b] /= count[b];
    }
    set_channels(s, 3, vals, names, NULL);
done:
    free(band);
    free(wl);
    return rc;
}

/* Spectral channels to the three of a colour space (brdfit/color.h). */
static bf_status to_color(bf_samples *s, bf_color space, bf_illuminant ill, bf_error *err)
{
    const int C = s->channels;
    char listbuf[200];
    double *wl = malloc((size_t)C * sizeof *wl), *w = malloc(3 * (size_t)C * sizeof *w);
    double *vals = NULL;
    char **names = NULL;
    bf_status rc = BF_OK;
    if (!wl || !w) {
        rc = bf_fail(err, BF_ERR_NOMEM, "out of memory");
        goto done;
    }
    if (!channel_wavelengths(s, wl)) {
        rc = bf_fail(err, BF_ERR_ARG,
                     "cannot make %s: it needs spectral data with a wavelength for every channel; the data has "
                     "%d channel%s (%s)",
                     space == BF_COLOR_XYZ ? "XYZ" : "RGB", C, C == 1 ? "" : "s",
                     list_names(s, listbuf, sizeof listbuf));
        goto done;
    }
    static const char *const rgb[3] = {"r", "g", "b"}, *const xyz[3] = {"X", "Y", "Z"};
    if ((rc = bf_color_weights(wl, C, space, ill, w, err)) != BF_OK ||
        (rc = alloc_three(s->n, space == BF_COLOR_XYZ ? xyz : rgb, &vals, &names, err)) != BF_OK)
        goto done;
    for (size_t i = 0; i < s->n; i++) {
        const double *v = s->value + i * (size_t)C;
        for (int k = 0; k < 3; k++) {
            double sum = 0.0;
            for (int c = 0; c < C; c++)
                sum += w[k * C + c] * v[c];
            vals[3 * i + (size_t)k] = sum;
        }
    }
    set_channels(s, 3, vals, names, NULL);
done:
    free(wl);
    free(w);
    return rc;
}

/* The CIE Y weights of spectral channels into y[0..C-1], *have 1; *have 0 when some
 * channel has no wavelength. */
static bf_status luminance_weights(const bf_samples *s, bf_illuminant ill, double *y, int *have, bf_error *err)
{
    const int C = s->channels;
    double *wl = malloc((size_t)C * sizeof *wl), *w = malloc(3 * (size_t)C * sizeof *w);
    bf_status rc = wl && w ? BF_OK : bf_fail(err, BF_ERR_NOMEM, "out of memory");
    *have = rc == BF_OK && channel_wavelengths(s, wl);
    if (*have && (rc = bf_color_weights(wl, C, BF_COLOR_XYZ, ill, w, err)) == BF_OK)
        memcpy(y, w + C, (size_t)C * sizeof *y); /* the Y row */
    free(wl);
    free(w);
    return rc;
}

static bf_status to_luminance(bf_samples *s, bf_illuminant ill, bf_error *err)
{
    const int C = s->channels;
    const char *no_ill = "an illuminant (%s) applies only to a colour conversion or the luminance of spectral data "
                         "with a wavelength per channel";
    if (C == 1)
        return ill == BF_ILLUMINANT_D65 ? BF_OK : bf_fail(err, BF_ERR_ARG, no_ill, bf_illuminant_name(ill));
    /* Rec. 709 weights by channel name, so b,g,r order works too. */
    double w[3] = {0, 0, 0};
    int rgb = C == 3;
    for (int c = 0; rgb && c < 3; c++) {
        const char *nm = s->channel_names[c];
        if (!strcasecmp(nm, "r"))
            w[c] = 0.2126;
        else if (!strcasecmp(nm, "g"))
            w[c] = 0.7152;
        else if (!strcasecmp(nm, "b"))
            w[c] = 0.0722;
        else
            rgb = 0;
    }
    rgb = rgb && w[0] != w[1] && w[1] != w[2] && w[0] != w[2];
    /* Spectral channels: CIE Y. */
    int spectral = 0;
    double *y = rgb ? NULL : malloc((size_t)C * sizeof *y);
    bf_status st = !rgb && !y ? bf_fail(err, BF_ERR_NOMEM, "out of memory") : BF_OK;
    if (y && (st = luminance_weights(s, ill, y, &spectral, err)) == BF_OK && !spectral && ill != BF_ILLUMINANT_D65)
        st = bf_fail(err, BF_ERR_ARG, no_ill, bf_illuminant_name(ill));
    if (rgb && ill != BF_ILLUMINANT_D65)
        st = bf_fail(err, BF_ERR_ARG, no_ill, bf_illuminant_name(ill));
    if (st != BF_OK) {
        free(y);
        return st;
    }
    double *vals;
    char **names;
    bf_status rc = alloc_channels(s->n, 1, &vals, &names, err);
    if (rc == BF_OK && !(names[0] = strdup(rgb || spectral ? "luminance" : "mean"))) {
        free(vals);
        free(names);
        rc = bf_fail(err, BF_ERR_NOMEM, "out of memory");
    }
    if (rc != BF_OK) {
        free(y);
        return rc;
    }
    for (size_t i = 0; i < s->n; i++) {
        const double *v = s->value + i * (size_t)C;
        double sum = 0.0;
        if (rgb) {
            sum = w[0] * v[0] + w[1] * v[1] + w[2] * v[2];
        } else if (spectral) {
            for (int c = 0; c < C; c++)
                sum += y[c] * v[c];
        } else {
            for (int c = 0; c < C; c++)
                sum += v[c];
            sum /= C;
        }
        vals[i] = sum;
    }
    free(y);
    set_channels(s, 1, vals, names, NULL);
    return BF_OK;
}

/* ---- Drops ----------------------------------------------------------------------- */

/* Below or on the horizon exactly as bf_geometry_from_angles decides it (a cosine
 * under 1e-15 is the horizon), so prep and the models agree sample for sample. */
static int below_horizon(double theta_deg)
{
    return theta_deg >= 90.0 || !(cos(theta_deg * (M_PI / 180.0)) >= 1e-15);
}

/* ---- Stratified subsample -------------------------------------------------------- */

enum { STRATA_H = 16, STRATA_D = 8 };

/* Stratum of a direction pair: theta_h in 16 bins of sqrt(theta_h / 90 deg) (dense
 * near the specular peak, like MERL's table), theta_d in 8 linear bins over 0-90 deg. */
static int stratum_of_half(double th, double td)
{
    int ih = (int)(sqrt(fmax(th, 0.0) / (M_PI / 2)) * STRATA_H);
    int id = (int)(td / (M_PI / 2) * STRATA_D);
    ih = ih < 0 ? 0 : ih >= STRATA_H ? STRATA_H - 1 : ih;
    id = id < 0 ? 0 : id >= STRATA_D ? STRATA_D - 1 : id;
    return ih * STRATA_D + id;
}

static int stratum_of(double ti, double pi_, double to, double po)
{
    const double d = M_PI / 180.0;
    double L[3] = {sin(ti * d) * cos(pi_ * d), sin(ti * d) * sin(pi_ * d), cos(ti * d)};
    double V[3] = {sin(to * d) * cos(po * d), sin(to * d) * sin(po * d), cos(to * d)};
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double len = sqrt(H[0] * H[0] + H[1] * H[1] + H[2] * H[2]);
    if (!(len > 0.0))
        return 0;
    for (int k = 0; k < 3; k++)
        H[k] /= len;
    double th = atan2(hypot(H[0], H[1]), H[2]);
    double td = acos(fmin(1.0, fmax(-1.0, L[0] * H[0] + L[1] * H[1] + L[2] * H[2])));
    return stratum_of_half(th, td);
}

/* The strata of MERL cells by (theta_h, theta_d) row, from the centres' angles: a
 * table's million cells then cost a lookup each. */
static void cell_strata(unsigned char table[BF_MERL_TH * BF_MERL_TD])
{
    for (int i = 0; i < BF_MERL_TH; i++)
        for (int j = 0; j < BF_MERL_TD; j++)
            table[i * BF_MERL_TD + j] =
                (unsigned char)stratum_of_half(bf_merl_centre_theta_h(i), bf_merl_centre_theta_d(j));
}

/* Every sample's stratum into st (n bytes) and each stratum's count. */
static void strata(const bf_samples *s, unsigned char *st, size_t count[STRATA_H * STRATA_D])
{
    unsigned char rows[BF_MERL_TH * BF_MERL_TD];
    if (!s->theta_i)
        cell_strata(rows);
    for (size_t i = 0; i < s->n; i++) {
        st[i] = (unsigned char)(s->theta_i ? stratum_of(s->theta_i[i], s->phi_i[i], s->theta_o[i], s->phi_o[i])
                                           : rows[s->merl->cell[i] / BF_MERL_PD]);
        count[st[i]]++;
    }
}

/* Quotas summing to N exactly: when N allows, every non-empty stratum first gets one
 * sample (a highlight held by a handful of samples must not vanish from a small
 * subsample), then the rest goes in proportion to the samples each stratum has left
 * (largest remainder, ties to the lower stratum); inside each stratum Knuth's selection sampling
 * (TAOCP 3.4.2, Algorithm S) walks the samples in order, keeping each with probability
 * (still needed) / (still to see): a uniform random subset of exactly the quota, in the
 * original order, from one splitmix64 stream seeded with `seed`. */
bf_status bf_samples_subsample_mask(const bf_samples *s, size_t N, uint64_t seed, unsigned char *keep, bf_error *err)
{
    enum { K = STRATA_H * STRATA_D };
    const size_t n = s->n;
    if (n > UINT32_MAX) /* N * count must fit in 64 bits */
        return bf_fail(err, BF_ERR_ARG, "too many samples (%zu) to subsample", n);
    if (N >= n)
        return bf_fail(err, BF_ERR_ARG, "subsample of %zu from %zu samples: nothing to choose", N, n);
    unsigned char *st = bf_big_malloc(n + 1);
    if (!st)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for subsampling %zu samples", n);
    size_t count[K] = {0}, quota[K], seen[K] = {0};
    uint64_t rem[K];
    strata(s, st, count);
    size_t nonempty = 0;
    for (int k = 0; k < K; k++)
        nonempty += count[k] > 0;
    size_t base = N >= nonempty ? 1 : 0, left_n = n - base * nonempty, left_N = N - base * nonempty;
    size_t assigned = 0;
    for (int k = 0; k < K; k++) {
        size_t first = count[k] > 0 ? base : 0;
        uint64_t p = left_n ? (uint64_t)left_N * (count[k] - first) : 0;
        quota[k] = first + (size_t)(left_n ? p / left_n : 0);
        rem[k] = left_n ? p % left_n : 0;
        assigned += quota[k];
    }
    /* The remainders sum to (N - assigned) left_n, each below left_n: enough non-zero ones. */
    for (size_t left = N - assigned; left > 0; left--) {
        int best = -1;
        for (int k = 0; k < K; k++)
            if (rem[k] > 0 && (best < 0 || rem[k] > rem[best]))
                best = k;
        quota[best]++;
        rem[best] = 0;
    }
    uint64_t state = seed;
    for (size_t i = 0; i < n; i++) {
        int k = st[i];
        size_t need = quota[k], to_see = count[k] - seen[k];
        keep[i] = need > 0 && bf_uniform01(&state) * (double)to_see < (double)need;
        quota[k] -= keep[i];
        seen[k]++;
    }
    free(st);
    return BF_OK;
}

bf_status bf_samples_folds(const bf_samples *s, int K, uint64_t seed, unsigned char *fold, bf_error *err)
{
    enum { NS = STRATA_H * STRATA_D, MAXK = 255 };
    if (K < 2 || K > MAXK)
        return bf_fail(err, BF_ERR_ARG, "folds: %d folds (2 to %d)", K, MAXK);
    unsigned char *st = bf_big_malloc(s->n + 1);
    unsigned char *perm = malloc((size_t)NS * MAXK);
    if (!st || !perm) {
        free(st);
        free(perm);
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for the folds of %zu samples", s->n);
    }
    size_t count[NS] = {0}, dealt[NS] = {0};
    strata(s, st, count);
    uint64_t state = seed;
    for (size_t i = 0; i < s->n; i++) {
        const int k = st[i];
        unsigned char *p = perm + (size_t)k * MAXK;
        const size_t r = dealt[k]++ % (size_t)K;
        if (r == 0) { /* a new round: a fresh random order of the folds (Fisher-Yates) */
            for (int a = 0; a < K; a++)
                p[a] = (unsigned char)a;
            for (int a = K - 1; a > 0; a--) {
                int b = (int)(bf_uniform01(&state) * (double)(a + 1));
                b = b > a ? a : b;
                unsigned char t = p[a];
                p[a] = p[b];
                p[b] = t;
            }
        }
        fold[i] = p[r];
    }
    free(st);
    free(perm);
    return BF_OK;
}

static bf_status subsample(bf_samples *s, size_t N, uint64_t seed, bf_error *err)
{
    unsigned char *keep = bf_big_malloc(s->n + 1);
    if (!keep)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for subsampling %zu samples", s->n);
    bf_status rc = bf_samples_subsample_mask(s, N, seed, keep, err);
    if (rc == BF_OK)
        rc = bf_samples_keep(s, keep, err);
    free(keep);
    return rc;
}

/* ---- The whole step ---------------------------------------------------------------- */

bf_status bf_samples_prep(bf_samples *s, const bf_prep *p, bf_prep_report *report, bf_error *err)
{
    static const bf_prep none = {0};
    bf_prep_report r = {0};
    if (!p)
        p = &none;
    r.read = s->n;
    bf_status rc;
    if (p->channels && (rc = select_channels(s, p->channels, err)) != BF_OK)
        return rc;
    if (p->to_bands && p->color != BF_COLOR_NONE)
        return bf_fail(err, BF_ERR_ARG, "three bands and a colour space exclude each other");
    if (p->color == BF_COLOR_NONE && !p->to_luminance && p->illuminant != BF_ILLUMINANT_D65)
        return bf_fail(err, BF_ERR_ARG, "an illuminant (%s) applies only to a colour conversion",
                       bf_illuminant_name(p->illuminant));
    if (p->to_bands && (rc = to_bands(s, err)) != BF_OK)
        return rc;
    if (p->color != BF_COLOR_NONE && (rc = to_color(s, p->color, p->illuminant, err)) != BF_OK)
        return rc;
    if (p->to_luminance &&
        (rc = to_luminance(s, p->color == BF_COLOR_NONE ? p->illuminant : BF_ILLUMINANT_D65, err)) != BF_OK)
        return rc;

    const size_t C = (size_t)s->channels;
    unsigned char *keep = bf_big_malloc(s->n + 1);
    if (!keep)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for %zu samples", s->n);
    size_t kept = 0;
    const bf_merl_trig *trig = s->theta_i ? NULL : bf_merl_trig_get();
    for (size_t i = 0; i < s->n; i++) {
        double *v = s->value + i * C;
        double ti = 0.0, to = 0.0;
        int finite = 1, below;
        if (s->theta_i) {
            ti = s->theta_i[i], to = s->theta_o[i];
            finite = isfinite(ti) && isfinite(to) && isfinite(s->phi_i[i]) && isfinite(s->phi_o[i]);
            below = below_horizon(ti) || below_horizon(to);
        } else { /* a cell centre: the horizon as its generated geometry decides it */
            double L[3], V[3], H[3], vh, s2h;
            bf_merl_cell_vectors(trig, s->merl->cell[i], L, V, H, &vh, &s2h);
            below = !(L[2] > 0.0 && V[2] > 0.0);
            if (!below && p->max_theta > 0.0) {
                double dir[4];
                bf_samples_direction(s, i, dir);
                ti = dir[0], to = dir[2];
            }
        }
        int negative = 0;
        for (size_t c = 0; c < C; c++) {
            finite &= isfinite(v[c]) != 0;
            negative |= v[c] < 0.0;
        }
        keep[i] = 0;
        if (!finite)
            r.nonfinite++;
        else if (below)
            r.below_horizon++;
        else if (p->max_theta > 0.0 && (ti > p->max_theta || to > p->max_theta))
            r.above_max_theta++;
        else {
            keep[i] = 1;
            if (negative) {
                r.negative++;
                if (p->negative == BF_NEGATIVE_DROP)
                    keep[i] = 0;
                else if (p->negative == BF_NEGATIVE_CLAMP)
                    for (size_t c = 0; c < C; c++)
                        v[c] = v[c] < 0.0 ? 0.0 : v[c];
            }
        }
        kept += keep[i];
    }
    rc = kept < s->n ? bf_samples_keep(s, keep, err) : BF_OK;
    free(keep);
    if (rc != BF_OK)
        return rc;
    if (s->n == 0)
        return bf_fail(err, BF_ERR_RANGE,
                       "no sample left: %zu read, %zu below the horizon, %zu with NaN or Inf, %zu above "
                       "max theta, %zu negative%s",
                       r.read, r.below_horizon, r.nonfinite, r.above_max_theta, r.negative,
                       p->negative == BF_NEGATIVE_DROP ? " (dropped)" : "");
    if (p->subsample > 0 && p->subsample < s->n) {
        r.subsampled_out = s->n - p->subsample;
        if ((rc = subsample(s, p->subsample, p->seed, err)) != BF_OK)
            return rc;
    }
    r.kept = s->n;
    if (report)
        *report = r;
    return BF_OK;
}
