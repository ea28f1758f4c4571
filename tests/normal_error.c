/* normal_error A.exr B.exr [MASK]: the angle between two normal maps (RGB = unit xyz)
 * over the pixels where both are non-zero (and MASK, an image, is non-zero): prints
 * "mean M median D max X pixels N" in degrees. A test support program for fit-images. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "brdfit/image.h"

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double len3(const float *v)
{
    return sqrt((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]);
}

int main(int argc, char **argv)
{
    if (argc < 3 || argc > 4) {
        fprintf(stderr, "usage: normal_error A.exr B.exr [MASK]\n");
        return 2;
    }
    bf_image a, b, m;
    bf_image_init(&a);
    bf_image_init(&b);
    bf_image_init(&m);
    bf_error err;
    if (bf_image_read(argv[1], &a, &err) != BF_OK || bf_image_read(argv[2], &b, &err) != BF_OK ||
        (argc == 4 && bf_image_read(argv[3], &m, &err) != BF_OK)) {
        fprintf(stderr, "normal_error: %s\n", err.msg);
        return 1;
    }
    if (a.width != b.width || a.height != b.height || a.channels < 3 || b.channels < 3 ||
        (argc == 4 && (m.width != a.width || m.height != a.height))) {
        fprintf(stderr, "normal_error: the images differ in size or lack 3 channels\n");
        return 1;
    }
    size_t n = (size_t)a.width * (size_t)a.height, k = 0;
    double *ang = malloc(n * sizeof *ang), sum = 0.0;
    for (size_t i = 0; ang && i < n; i++) {
        const float *p = a.pixels + i * (size_t)a.channels, *q = b.pixels + i * (size_t)b.channels;
        double lp = len3(p), lq = len3(q);
        if (!(lp > 0.5 && lq > 0.5) || (argc == 4 && !(m.pixels[i * (size_t)m.channels] > 0.0f)))
            continue;
        double d = ((double)p[0] * q[0] + (double)p[1] * q[1] + (double)p[2] * q[2]) / (lp * lq);
        ang[k] = acos(fmax(-1.0, fmin(1.0, d))) * 180.0 / M_PI;
        sum += ang[k++];
    }
    if (!k) {
        fprintf(stderr, "normal_error: no pixel to compare\n");
        return 1;
    }
    qsort(ang, k, sizeof *ang, cmp);
    printf("mean %.4f median %.4f max %.4f pixels %zu\n", sum / (double)k, ang[k / 2], ang[k - 1], k);
    free(ang);
    bf_image_clear(&a);
    bf_image_clear(&b);
    bf_image_clear(&m);
    return 0;
}
