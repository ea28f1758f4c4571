/* Reading a band of rows of every image (photo_impl.h): each image's rows are read on
 * their own (bf_image_read_rows), decoded to linear values and kept for the masked
 * pixels only, so memory is the masked pixels times the images, whatever the image size.
 * The images are read in parallel (one per chunk); each writes its own slots. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/parallel.h"
#include "brdfit/image.h"
#include "photo_impl.h"

void photo_band_free(photo_band *b)
{
    free(b->pixel);
    free(b->v);
    free(b->saturated);
    free(b->invalid);
    memset(b, 0, sizeof *b);
}

static double decode(const bf_stack *s, double code)
{
    switch (s->transfer) {
    case BF_TRANSFER_SRGB: return bf_srgb_decode((float)code);
    case BF_TRANSFER_GAMMA: return code > 0.0 ? pow(code, s->gamma) : 0.0;
    default: return code;
    }
}

bf_status photo_mask_load(const bf_stack *s, unsigned char **mask, bf_error *err)
{
    size_t n = (size_t)s->width * (size_t)s->height;
    unsigned char *m = malloc(n);
    if (!m)
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory for the mask", s->path);
    if (!s->mask) {
        memset(m, 1, n);
        *mask = m;
        return BF_OK;
    }
    bf_image img;
    bf_image_init(&img);
    bf_status rc = bf_image_read(s->mask, &img, err);
    if (rc != BF_OK) {
        free(m);
        return rc;
    }
    for (size_t i = 0; i < n; i++) {
        int on = 0;
        for (int c = 0; c < img.channels; c++)
            on |= img.pixels[i * (size_t)img.channels + (size_t)c] > 0.0f;
        m[i] = (unsigned char)on;
    }
    bf_image_clear(&img);
    *mask = m;
    return BF_OK;
}

typedef struct load_job {
    const bf_stack *s;
    photo_band *b;
    bf_status *rc;
    bf_error *errs;
} load_job;

static void load_image(void *ctx, size_t k)
{
    load_job *j = ctx;
    const bf_stack *s = j->s;
    photo_band *b = j->b;
    bf_image img;
    bf_image_init(&img);
    j->rc[k] = bf_image_read_rows(s->images[k].file, b->y0, b->y1, &img, &j->errs[k]);
    if (j->rc[k] != BF_OK)
        return;
    int K = s->nimages, C = s->channels, ic = img.channels;
    double inv = 1.0 / s->images[k].exposure;
    size_t sat = 0, bad = 0;
    for (size_t p = 0; p < b->npix; p++) {
        size_t x = (size_t)b->pixel[p] % (size_t)s->width, y = (size_t)b->pixel[p] / (size_t)s->width - (size_t)b->y0;
        const float *src = img.pixels + (y * (size_t)s->width + x) * (size_t)ic;
        float *dst = b->v + (p * (size_t)K + k) * (size_t)C;
        int saturated = 0, invalid = 0;
        for (int c = 0; c < C; c++) {
            double lin = decode(s, src[c]);
            if (!isfinite(lin))
                invalid = 1;
            else if (lin >= s->saturation)
                saturated = 1;
            dst[c] = (float)((lin - s->black_level) * inv);
        }
        if (saturated || invalid)
            for (int c = 0; c < C; c++)
                dst[c] = NAN;
        sat += saturated && !invalid;
        bad += invalid;
    }
    b->saturated[k] = sat;
    b->invalid[k] = bad;
    bf_image_clear(&img);
}

bf_status photo_band_load(const bf_stack *s, const photo_band_pixels *at, int threads, photo_band *b, bf_error *err)
{
    const int32_t *pixel = at->pixel;
    size_t npix = at->npix;
    memset(b, 0, sizeof *b);
    b->y0 = at->y0;
    b->y1 = at->y1;
    b->npix = npix;
    size_t K = (size_t)s->nimages;
    b->pixel = malloc((npix ? npix : 1) * sizeof *b->pixel);
    b->v = malloc((npix ? npix : 1) * K * (size_t)s->channels * sizeof *b->v);
    b->saturated = calloc(K, sizeof *b->saturated);
    b->invalid = calloc(K, sizeof *b->invalid);
    bf_status *rc = calloc(K, sizeof *rc);
    bf_error *errs = calloc(K, sizeof *errs);
    if (!b->pixel || !b->v || !b->saturated || !b->invalid || !rc || !errs) {
        free(rc);
        free(errs);
        photo_band_free(b);
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory for %zu pixels x %zu images", s->path, npix, K);
    }
    if (npix)
        memcpy(b->pixel, pixel, npix * sizeof *pixel);
    load_job j = {s, b, rc, errs};
    if (b->npix)
        bf_parallel_for(K, threads, load_image, &j);
    bf_status out = BF_OK;
    for (size_t k = 0; k < K && out == BF_OK && b->npix; k++)
        if (rc[k] != BF_OK) {
            out = rc[k];
            if (err)
                *err = errs[k];
        }
    free(rc);
    free(errs);
    if (out != BF_OK)
        photo_band_free(b);
    return out;
}
