/* The theta_h x theta_d image at a fixed phi_d: from a model (one batched evaluation)
 * or from a MERL table (the cell MERL's own lookup picks). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/render.h"
#include "color.h"

void bf_halfdiff_dirs(double theta_h, double theta_d, double phi_d, double L[3], double V[3])
{
    /* The same expressions as the MERL reader's cell centres (samples.h). */
    double sth = sin(theta_h), cth = cos(theta_h);
    double dx = sin(theta_d) * cos(phi_d), dy = sin(theta_d) * sin(phi_d), dz = cos(theta_d);
    L[0] = dx * cth + dz * sth;
    L[1] = dy;
    L[2] = dz * cth - dx * sth;
    V[0] = dz * sth - dx * cth;
    V[1] = -dy;
    V[2] = dz * cth + dx * sth;
}

static double pixel_angle(int i, int n)
{
    return (i + 0.5) / n * (M_PI / 2);
}

/* Columns are even in sqrt(theta_h), as MERL tables index theta_h: the highlight, a few
 * degrees wide, gets a fair share of the image instead of a few columns. */
static double column_theta_h(int i, int n)
{
    double u = (i + 0.5) / n;
    return u * u * (M_PI / 2);
}

static bf_status check_size(int width, int height, double phi_d, bf_error *err)
{
    if (width < 1 || height < 1 || width > BF_RENDER_MAX_SIDE || height > BF_RENDER_MAX_SIDE)
        return bf_fail(err, BF_ERR_ARG, "half/difference image: bad size %dx%d (each side 1 to %d)", width, height,
                       BF_RENDER_MAX_SIDE);
    if (!isfinite(phi_d))
        return bf_fail(err, BF_ERR_ARG, "half/difference image: phi_d is not finite");
    return BF_OK;
}

bf_status bf_render_halfdiff_model(const bf_model *m, const double *x, int width, int height, double phi_d, float *rgb,
                                   bf_error *err)
{
    bf_status status = check_size(width, height, phi_d, err);
    if (status != BF_OK)
        return status;
    /* In bands of rows: memory O(width x BAND) whatever the size. */
    enum { BAND = 64 };
    const int rows = height < BAND ? height : BAND;
    const size_t nb = (size_t)width * (size_t)rows;
    const int C = bf_model_channels(m);
    double *L = malloc(nb * 3 * sizeof *L), *V = malloc(nb * 3 * sizeof *V);
    double *f = malloc(nb * (size_t)C * sizeof *f);
    if (!L || !V || !f) {
        status = bf_fail(err, BF_ERR_NOMEM, "half/difference image: out of memory for %dx%d pixels", width, height);
        goto done;
    }
    const double pd = phi_d * (M_PI / 180.0);
    for (int j0 = 0; j0 < height; j0 += BAND) {
        const int j1 = j0 + BAND < height ? j0 + BAND : height;
        const size_t n = (size_t)(j1 - j0) * (size_t)width;
        for (int j = j0; j < j1; j++)
            for (int i = 0; i < width; i++) {
                size_t q = (size_t)(j - j0) * (size_t)width + (size_t)i;
                bf_halfdiff_dirs(column_theta_h(i, width), pixel_angle(j, height), pd, L + 3 * q, V + 3 * q);
            }
        bf_geometry *g;
        if ((status = bf_geometry_from_vectors(n, L, V, &g, err)) != BF_OK)
            goto done;
        bf_model_eval(m, x, g, f, NULL);
        bf_geometry_free(g);
        float *out = rgb + (size_t)j0 * (size_t)width * 3;
        for (size_t q = 0; q < n; q++) {
            double c[3];
            bf_channels_to_rgb(f + q * (size_t)C, C, c);
            for (int k = 0; k < 3; k++)
                out[3 * q + (size_t)k] = (float)c[k];
        }
    }
done:
    free(L);
    free(V);
    free(f);
    return status;
}

bf_status bf_render_halfdiff_merl(const bf_samples *s, int width, int height, double phi_d, float *rgb, bf_error *err)
{
    bf_status status = check_size(width, height, phi_d, err);
    if (status != BF_OK)
        return status;
    if (!s || !s->merl)
        return bf_fail(err, BF_ERR_ARG, "half/difference image: the data is not a MERL table as read");
    /* Which sample sits in each cell (invalid cells have none). Values come from the
     * samples, which carry MERL's channel scales already. */
    int32_t *sample_of = malloc((size_t)BF_MERL_CELLS * sizeof *sample_of);
    if (!sample_of)
        return bf_fail(err, BF_ERR_NOMEM, "half/difference image: out of memory");
    for (size_t c = 0; c < (size_t)BF_MERL_CELLS; c++)
        sample_of[c] = -1;
    for (size_t i = 0; i < s->n; i++)
        if (s->merl->cell[i] >= 0 && s->merl->cell[i] < BF_MERL_CELLS)
            sample_of[s->merl->cell[i]] = (int32_t)i;
    /* Reciprocity folds phi_d into [0, 180). */
    double pd = fmod(phi_d, 180.0);
    if (pd < 0.0)
        pd += 180.0;
    int k = (int)floor(pd / 180.0 * BF_MERL_PD);
    if (k >= BF_MERL_PD)
        k = BF_MERL_PD - 1;
    for (int j = 0; j < height; j++) {
        int jd = (int)floor(pixel_angle(j, height) / (M_PI / 2) * BF_MERL_TD);
        for (int i = 0; i < width; i++) {
            int ih = (int)floor(sqrt(column_theta_h(i, width) / (M_PI / 2)) * BF_MERL_TH);
            size_t q = (size_t)j * (size_t)width + (size_t)i;
            int32_t smp = sample_of[k + jd * BF_MERL_PD + ih * BF_MERL_PD * BF_MERL_TD];
            double c[3] = {0.0, 0.0, 0.0};
            if (smp >= 0)
                bf_channels_to_rgb(s->value + (size_t)smp * (size_t)s->channels, s->channels, c);
            for (int ch = 0; ch < 3; ch++)
                rgb[3 * q + (size_t)ch] = (float)c[ch];
        }
    }
    free(sample_of);
    return BF_OK;
}
