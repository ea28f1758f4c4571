/* The viewer's tables: tabulation on the half/difference grid of viewer_table.h and the
 * compact storage the page decodes (viewer.js, decodeTable).
 *
 * Decisions:
 *  - Logarithmic 16-bit codes: a BRDF spans decades, and a step of (hi - lo) / 65533 in
 *    the log is under 0.05% for any range a BRDF has, far below the interpolation's
 *    error, so the codes cost nothing in accuracy.
 *  - Differences along theta_h and the bytes split in two planes before deflate: smooth
 *    tables become runs of small numbers and a plane of near-constant high bytes, which
 *    deflate shrinks several times (docs/report.md gives the sizes).
 *  - zlib's deflate: the browser inflates it with its own DecompressionStream, so the page
 *    needs no script of ours for it. */
#include "html/viewer_table.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "brdfit/geometry.h"
#include "brdfit/merl.h"
#include "brdfit/render.h"
#include "io/gltf_doc.h"
#include "render/color.h"

void viewer_node_angles(int i, int j, int k, double *theta_h, double *theta_d, double *phi_d)
{
    const double u = (double)i / (VIEWER_NH - 1);
    *theta_h = u * u * (M_PI / 2);
    *theta_d = (double)j / (VIEWER_ND - 1) * (M_PI / 2);
    *phi_d = (double)k / (VIEWER_NP - 1) * (M_PI / 2);
}

/* Node q = i + NH * (j + ND * k). */
static void node_of(size_t q, int *i, int *j, int *k)
{
    *i = (int)(q % VIEWER_NH);
    *j = (int)(q / VIEWER_NH % VIEWER_ND);
    *k = (int)(q / ((size_t)VIEWER_NH * VIEWER_ND));
}

bf_status viewer_table_model(const bf_model *m, const double *x, double *v, bf_error *err)
{
    const size_t n = VIEWER_NODES;
    const int C = bf_model_channels(m);
    double *L = malloc(n * 3 * sizeof *L), *V = malloc(n * 3 * sizeof *V), *f = malloc(n * (size_t)C * sizeof *f);
    bf_geometry *g = NULL;
    bf_status rc = L && V && f ? BF_OK : bf_fail(err, BF_ERR_NOMEM, "report: out of memory");
    for (size_t q = 0; q < n && rc == BF_OK; q++) {
        int i, j, k;
        double th, td, pd;
        node_of(q, &i, &j, &k);
        viewer_node_angles(i, j, k, &th, &td, &pd);
        bf_halfdiff_dirs(th, td, pd, L + 3 * q, V + 3 * q);
    }
    if (rc == BF_OK && (rc = bf_geometry_from_vectors(n, L, V, &g, err)) == BF_OK) {
        bf_model_eval(m, x, g, f, NULL);
        for (size_t q = 0; q < n; q++) {
            double c[3];
            bf_channels_to_rgb(f + q * (size_t)C, C, c);
            for (int ch = 0; ch < 3; ch++)
                v[(size_t)ch * n + q] = bf_geometry_valid(g, q) ? c[ch] : NAN;
        }
        bf_geometry_free(g);
    }
    free(L);
    free(V);
    free(f);
    return rc;
}

/* Continuous cell index of a centre-sampled axis: lower cell and weight of the upper. */
static int cell_pair(double t, int n, double *f)
{
    double u = t * n - 0.5;
    int i0 = (int)floor(u);
    i0 = i0 < 0 ? 0 : i0 > n - 2 ? n - 2 : i0;
    *f = fmin(fmax(u - i0, 0.0), 1.0);
    return i0;
}

bf_status viewer_table_merl(const bf_samples *s, double *v, bf_error *err)
{
    const size_t n = VIEWER_NODES;
    const int C = s->channels;
    int32_t *sample_of = malloc((size_t)BF_MERL_CELLS * sizeof *sample_of);
    double *c = malloc(2 * (size_t)C * sizeof *c), *acc = c ? c + C : NULL;
    if (!sample_of || !c) {
        free(sample_of);
        free(c);
        return bf_fail(err, BF_ERR_NOMEM, "report: out of memory");
    }
    for (size_t q = 0; q < (size_t)BF_MERL_CELLS; q++)
        sample_of[q] = -1;
    for (size_t q = 0; q < s->n; q++)
        if (s->merl->cell[q] >= 0 && s->merl->cell[q] < BF_MERL_CELLS)
            sample_of[s->merl->cell[q]] = (int32_t)q;
    for (size_t q = 0; q < n; q++) {
        int i, j, k;
        double th, td, pd, fu, fv;
        node_of(q, &i, &j, &k);
        viewer_node_angles(i, j, k, &th, &td, &pd);
        /* Trilinear between the cell centres (theta_h on MERL's square-root scale, phi_d
         * periodic over 180 degrees by reciprocity), cells without a value left out: the
         * nearest cell alone would err by half a cell where the highlight falls off. */
        const int i0 = cell_pair(sqrt(th / (M_PI / 2)), BF_MERL_TH, &fu),
                  j0 = cell_pair(td / (M_PI / 2), BF_MERL_TD, &fv);
        const double w = pd / M_PI * BF_MERL_PD - 0.5, fw = w - floor(w);
        const int k0 = ((int)floor(w) + BF_MERL_PD) % BF_MERL_PD;
        double ws = 0.0;
        memset(acc, 0, (size_t)C * sizeof *acc);
        for (int corner = 0; corner < 8; corner++) {
            const int di = corner & 1, dj = corner >> 1 & 1, dk = corner >> 2;
            const double wt = (di ? fu : 1 - fu) * (dj ? fv : 1 - fv) * (dk ? fw : 1 - fw);
            const int32_t smp =
                wt > 0.0
                    ? sample_of[(k0 + dk) % BF_MERL_PD + (j0 + dj) * BF_MERL_PD + (i0 + di) * BF_MERL_PD * BF_MERL_TD]
                    : -1;
            if (smp < 0)
                continue;
            for (int ch = 0; ch < C; ch++)
                acc[ch] += wt * s->value[(size_t)smp * (size_t)C + (size_t)ch];
            ws += wt;
        }
        double rgb[3] = {NAN, NAN, NAN};
        if (ws > 1e-9) {
            for (int ch = 0; ch < C; ch++)
                c[ch] = acc[ch] / ws;
            bf_channels_to_rgb(c, C, rgb);
        }
        for (int ch = 0; ch < 3; ch++)
            v[(size_t)ch * n + q] = rgb[ch];
    }
    free(sample_of);
    free(c);
    return BF_OK;
}

/* codes (columns x count) differenced along runs, split into byte planes, deflated, as
 * a base64 data URI (malloc'd) or NULL. */
static char *pack(uint16_t *codes, size_t total, size_t run, bf_error *err)
{
    for (size_t q = total; q-- > 0;)
        if (q % run)
            codes[q] = (uint16_t)(codes[q] - codes[q - 1]);
    unsigned char *planes = malloc(2 * total);
    uLongf zn = compressBound((uLong)(2 * total));
    unsigned char *z = malloc(zn);
    char *uri = NULL;
    if (planes && z) {
        for (size_t q = 0; q < total; q++) {
            planes[q] = (unsigned char)(codes[q] >> 8);
            planes[total + q] = (unsigned char)(codes[q] & 0xff);
        }
        if (compress2(z, &zn, planes, (uLong)(2 * total), 9) == Z_OK)
            uri = bf_gltf_base64_uri(z, zn);
    }
    if (!uri)
        bf_fail(err, BF_ERR_NOMEM, "report: out of memory");
    free(planes);
    free(z);
    return uri;
}

static cJSON *with_data(cJSON *o, char *uri, bf_error *err)
{
    if (o && uri && cJSON_AddStringToObject(o, "data", uri)) {
        free(uri);
        return o;
    }
    free(uri);
    cJSON_Delete(o);
    bf_fail(err, BF_ERR_NOMEM, "report: out of memory");
    return NULL;
}

cJSON *viewer_encode(const double *v, int channels, size_t count, size_t run, bf_error *err)
{
    const size_t total = (size_t)channels * count;
    uint16_t *codes = malloc(total * sizeof *codes);
    double *lo = malloc(2 * (size_t)channels * sizeof *lo), *step = lo ? lo + channels : NULL;
    cJSON *o = cJSON_CreateObject();
    char *uri = NULL;
    if (codes && lo && o) {
        for (int c = 0; c < channels; c++) {
            const double *vc = v + (size_t)c * count;
            double a = INFINITY, b = -INFINITY;
            for (size_t q = 0; q < count; q++)
                if (vc[q] > 0.0 && isfinite(vc[q])) {
                    a = fmin(a, log(vc[q]));
                    b = fmax(b, log(vc[q]));
                }
            if (!(a <= b))
                a = b = 0.0;
            lo[c] = a;
            step[c] = b > a ? (b - a) / 65533.0 : 1.0;
            for (size_t q = 0; q < count; q++)
                codes[(size_t)c * count + q] = isnan(vc[q])   ? 0
                                               : vc[q] <= 0.0 ? 1
                                                              : (uint16_t)(2 + lround((log(vc[q]) - a) / step[c]));
        }
        cJSON_AddItemToObject(o, "lo", bf_gltf_num_array(lo, channels));
        cJSON_AddItemToObject(o, "step", bf_gltf_num_array(step, channels));
        uri = pack(codes, total, run, err);
    }
    free(codes);
    free(lo);
    return with_data(o, uri, err);
}

cJSON *viewer_encode_u16(const uint16_t *codes, int columns, size_t count, bf_error *err)
{
    const size_t total = (size_t)columns * count;
    uint16_t *copy = malloc((total ? total : 1) * sizeof *copy);
    char *uri = NULL;
    if (copy) {
        memcpy(copy, codes, total * sizeof *copy);
        uri = pack(copy, total, count ? count : 1, err);
    }
    free(copy);
    return with_data(cJSON_CreateObject(), uri, err);
}
