/* Image input and output beyond RGB pictures (image.h): 16-bit and code PNGs, 1- and
 * 4-channel EXRs written and read back exactly, bands of rows (from several threads at
 * once), what a file holds without its pixels, the sRGB decoding, and the errors: one
 * line naming the file. */
#include <math.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "brdfit/image.h"
#include "support.h"

/* A deterministic test pattern: value v of n in [0, 1], every code of 16 bits touched
 * at the ends. */
static float pattern(size_t v, size_t n)
{
    if (v == 0)
        return 0.0f;
    if (v == n - 1)
        return 1.0f;
    return (float)((v * 7919u) % 65536u) / 65535.0f;
}

static float *make_pixels(int w, int h, int c, float (*f)(size_t, size_t))
{
    size_t n = (size_t)w * (size_t)h * (size_t)c;
    float *px = malloc(n * sizeof *px);
    assert_non_null(px);
    for (size_t i = 0; i < n; i++)
        px[i] = f(i, n);
    return px;
}

/* Linear values beyond [0, 1], negative and tiny ones too: an EXR keeps them all. */
static float hdr(size_t v, size_t n)
{
    (void)n;
    return (float)(sin((double)v * 0.731) * 3.0 * (double)(v % 5)) + (v % 11 == 0 ? 1e-30f : 0.0f);
}

/* The channel names of an EXR file's header ("channels", a chlist: name, NUL, 16 bytes
 * per channel, a NUL after the last), joined with commas into buf. */
static const char *exr_channels(const char *path, char *buf, size_t size)
{
    size_t len;
    unsigned char *data = ts_read_binary(path, &len);
    static const char key[] = "channels\0chlist";
    buf[0] = '\0';
    for (size_t i = 0; i + sizeof key + 4 < len; i++) {
        if (memcmp(data + i, key, sizeof key) != 0)
            continue;
        size_t p = i + sizeof key + 4; /* past the attribute's size */
        while (p < len && data[p]) {
            const char *name = (const char *)data + p;
            size_t used = strlen(buf);
            snprintf(buf + used, size - used, "%s%s", used ? "," : "", name);
            p += strlen(name) + 1 + 16;
        }
        break;
    }
    free(data);
    return buf;
}

static void assert_same_floats(const float *got, const float *want, size_t n, const char *what)
{
    for (size_t i = 0; i < n; i++) {
        if (!(got[i] == want[i]) && !(isnan(got[i]) && isnan(want[i])))
            fail_msg("%s: value %zu is %.9g, want %.9g", what, i, (double)got[i], (double)want[i]);
    }
}

static void check_info(const char *path, int w, int h, int c, int bits, int is_float)
{
    bf_image_spec sp;
    bf_image_spec_init(&sp);
    bf_error err;
    assert_int_equal(bf_image_info(path, &sp, &err), BF_OK);
    assert_int_equal(sp.width, w);
    assert_int_equal(sp.height, h);
    assert_int_equal(sp.channels, c);
    assert_int_equal(sp.bits, bits);
    assert_int_equal(sp.is_float, is_float);
}

/* 16-bit PNG: codes as written (values k / 65535 come back exactly), with and without the
 * sRGB encoding. */
static void test_png16(void **state)
{
    (void)state;
    const int w = 13, h = 7;
    float *px = make_pixels(w, h, 3, pattern);
    const char *path = ts_tmp_path("codes16.png");
    bf_error err;
    assert_int_equal(bf_image_write(path, BF_IMAGE_BY_NAME, w, h, 3, px, BF_IMAGE_CODES | BF_IMAGE_16BIT, &err), BF_OK);
    check_info(path, w, h, 3, 16, 0);
    bf_image img;
    bf_image_init(&img);
    assert_int_equal(bf_image_read(path, &img, &err), BF_OK);
    assert_int_equal(img.width, w);
    assert_int_equal(img.height, h);
    assert_int_equal(img.channels, 3);
    for (size_t i = 0; i < (size_t)w * h * 3; i++) {
        assert_int_equal(lroundf(img.pixels[i] * 65535.0f), lroundf(px[i] * 65535.0f));
        ts_assert_near(img.pixels[i], px[i], 0, 1e-7, "16-bit code");
    }
    bf_image_clear(&img);

    /* Without BF_IMAGE_CODES: sRGB-encoded, clamped, 16 bits. */
    const float lin[6] = {0.0f, 0.2f, 0.5f, 1.0f, 3.0f, NAN};
    path = ts_tmp_path("srgb16.png");
    assert_int_equal(bf_image_write(path, BF_IMAGE_PNG, 2, 1, 3, lin, BF_IMAGE_16BIT, &err), BF_OK);
    assert_int_equal(bf_image_read(path, &img, &err), BF_OK);
    for (int i = 0; i < 6; i++)
        assert_int_equal(lroundf(img.pixels[i] * 65535.0f), lroundf(bf_srgb_encode(lin[i]) * 65535.0f));
    assert_int_equal(lroundf(img.pixels[4] * 65535.0f), 65535);
    assert_int_equal(lroundf(img.pixels[5] * 65535.0f), 0);
    bf_image_clear(&img);
    free(px);
}

/* 8-bit PNG with BF_IMAGE_CODES: no sRGB encoding, clamped, rounded; 1, 3 and 4
 * channels (a fourth is alpha, stored as given: colour under alpha 0 is kept). */
static void test_png8_codes(void **state)
{
    (void)state;
    const float v[8] = {0.0f, 1.0f / 255.0f, 0.5f, 128.0f / 255.0f, 1.0f, 1.5f, -0.25f, NAN};
    const long want[8] = {0, 1, 128, 128, 255, 255, 0, 0};
    bf_error err;
    bf_image img;
    bf_image_init(&img);
    for (int c = 1; c <= 4; c++) {
        if (c == 2)
            continue;
        char name[32];
        snprintf(name, sizeof name, "codes8_%d.png", c);
        const char *path = ts_tmp_path(name);
        const int w = 8, h = 2; /* v repeated */
        float *px = malloc((size_t)w * h * c * sizeof *px);
        for (int i = 0; i < w * h * c; i++)
            px[i] = v[i % 8];
        if (c == 4) /* alpha 0 under colour: not premultiplied away */
            px[3] = 0.0f, px[0] = px[1] = px[2] = 0.5f;
        assert_int_equal(bf_image_write(path, BF_IMAGE_BY_NAME, w, h, c, px, BF_IMAGE_CODES, &err), BF_OK);
        check_info(path, w, h, c, 8, 0);
        assert_int_equal(bf_image_read(path, &img, &err), BF_OK);
        assert_int_equal(img.channels, c);
        for (int i = 0; i < w * h * c; i++) {
            long code = lroundf(img.pixels[i] * 255.0f);
            long expect = (c == 4 && i < 4) ? (i == 3 ? 0 : 128) : want[i % 8];
            if (code != expect)
                fail_msg("%d channels: value %d has code %ld, want %ld", c, i, code, expect);
        }
        bf_image_clear(&img);
        free(px);
    }
}

/* EXR: 1 channel (Y) and 4 (RGBA) exactly as written, 3 (RGB) too; the names in the file. */
static void test_exr_channels(void **state)
{
    (void)state;
    const int w = 9, h = 5;
    const char *names[5] = {NULL, "Y", NULL, "B,G,R", "A,B,G,R"}; /* EXR sorts its channel list */
    bf_error err;
    for (int c = 1; c <= 4; c++) {
        if (c == 2)
            continue;
        float *px = make_pixels(w, h, c, hdr);
        char name[32], buf[128];
        snprintf(name, sizeof name, "ch%d.exr", c);
        const char *path = ts_tmp_path(name);
        assert_int_equal(bf_image_write(path, BF_IMAGE_BY_NAME, w, h, c, px, 0, &err), BF_OK);
        assert_string_equal(exr_channels(path, buf, sizeof buf), names[c]);
        check_info(path, w, h, c, 32, 1);
        bf_image img;
        bf_image_init(&img);
        assert_int_equal(bf_image_read(path, &img, &err), BF_OK);
        assert_int_equal(img.width, w);
        assert_int_equal(img.height, h);
        assert_int_equal(img.channels, c);
        /* Read back in the order written (R, G, B, A), not the file's sorted order. */
        assert_same_floats(img.pixels, px, (size_t)w * h * c, name);
        bf_image_clear(&img);
        free(px);
    }
}

/* bf_image_write_rgb_as is bf_image_write with 3 channels and no flags: the same bytes. */
static void test_rgb_same_bytes(void **state)
{
    (void)state;
    const int w = 11, h = 6;
    float *px = make_pixels(w, h, 3, hdr);
    bf_error err;
    const char *a = ts_tmp_path("rgb_as.png"), *b = ts_tmp_path("write.png");
    assert_int_equal(bf_image_write_rgb_as(a, BF_IMAGE_BY_NAME, w, h, px, &err), BF_OK);
    assert_int_equal(bf_image_write(b, BF_IMAGE_BY_NAME, w, h, 3, px, 0, &err), BF_OK);
    size_t na, nb;
    unsigned char *da = ts_read_binary(a, &na), *db = ts_read_binary(b, &nb);
    assert_int_equal(na, nb);
    assert_memory_equal(da, db, na);
    free(da);
    free(db);
    /* 8-bit sRGB PNG: the codes the RGB writer has always written. */
    bf_image img;
    bf_image_init(&img);
    assert_int_equal(bf_image_read(a, &img, &err), BF_OK);
    for (int i = 0; i < w * h * 3; i++)
        assert_int_equal(lroundf(img.pixels[i] * 255.0f), lroundf(bf_srgb_encode(px[i]) * 255.0f));
    bf_image_clear(&img);
    free(px);
}

/* A band of rows is those rows of the whole image, for PNG and EXR, the first, the last,
 * one row and all of them. */
static void test_read_rows(void **state)
{
    (void)state;
    const int w = 17, h = 12;
    bf_error err;
    const struct {
        const char *name;
        int c;
        unsigned flags;
    } files[] = {{"rows16.png", 3, BF_IMAGE_CODES | BF_IMAGE_16BIT},
                 {"rows8.png", 1, BF_IMAGE_CODES},
                 {"rows.exr", 4, 0},
                 {"rows1.exr", 1, 0}};
    const int bands[][2] = {{0, 12}, {0, 1}, {3, 8}, {11, 12}, {5, 6}, {0, 7}};
    for (size_t f = 0; f < sizeof files / sizeof files[0]; f++) {
        const char *path = ts_tmp_path(files[f].name);
        int c = files[f].c;
        float *px = make_pixels(w, h, c, pattern);
        assert_int_equal(bf_image_write(path, BF_IMAGE_BY_NAME, w, h, c, px, files[f].flags, &err), BF_OK);
        bf_image all;
        bf_image_init(&all);
        assert_int_equal(bf_image_read(path, &all, &err), BF_OK);
        for (size_t b = 0; b < sizeof bands / sizeof bands[0]; b++) {
            bf_image band;
            bf_image_init(&band);
            int y0 = bands[b][0], y1 = bands[b][1];
            assert_int_equal(bf_image_read_rows(path, y0, y1, &band, &err), BF_OK);
            assert_int_equal(band.width, w);
            assert_int_equal(band.height, y1 - y0);
            assert_int_equal(band.channels, c);
            size_t row = (size_t)w * c;
            assert_same_floats(band.pixels, all.pixels + row * y0, row * (size_t)(y1 - y0), files[f].name);
            bf_image_clear(&band);
            bf_image_clear(&band); /* twice is harmless */
        }
        bf_image_clear(&all);
        free(px);
    }
}

/* Errors: a bad range is BF_ERR_ARG, a file that is not there or not an image BF_ERR_IO,
 * each one line naming the file; nothing is left allocated. */
static void test_errors(void **state)
{
    (void)state;
    const int w = 4, h = 6;
    float px[4 * 6];
    for (int i = 0; i < w * h; i++)
        px[i] = (float)i;
    const char *path = ts_tmp_path("err.exr");
    bf_error err;
    assert_int_equal(bf_image_write(path, BF_IMAGE_BY_NAME, w, h, 1, px, 0, &err), BF_OK);
    const int bad[][2] = {{-1, 2}, {2, 2}, {3, 1}, {0, 7}, {6, 7}, {5, 100}};
    for (size_t b = 0; b < sizeof bad / sizeof bad[0]; b++) {
        bf_image img;
        bf_image_init(&img);
        err.msg[0] = '\0';
        assert_int_equal(bf_image_read_rows(path, bad[b][0], bad[b][1], &img, &err), BF_ERR_ARG);
        assert_int_equal(err.code, BF_ERR_ARG);
        assert_null(img.pixels);
        assert_non_null(strstr(err.msg, path));
        assert_null(strchr(err.msg, '\n'));
    }
    const char *missing = ts_tmp_path("missing.png");
    bf_image img;
    bf_image_init(&img);
    bf_image_spec sp;
    bf_image_spec_init(&sp);
    assert_int_equal(bf_image_read_rows(missing, 0, 1, &img, &err), BF_ERR_IO);
    assert_null(img.pixels);
    assert_non_null(strstr(err.msg, missing));
    assert_null(strchr(err.msg, '\n'));
    assert_int_equal(bf_image_info(missing, &sp, &err), BF_ERR_IO);
    assert_non_null(strstr(err.msg, missing));
    assert_null(strchr(err.msg, '\n'));
    /* Not an image. */
    const char *text = ts_tmp_path("text.png");
    ts_write_file(text, "not a picture\n", 14);
    assert_int_not_equal(bf_image_info(text, &sp, &err), BF_OK);
    assert_non_null(strstr(err.msg, text));
    assert_int_not_equal(bf_image_read_rows(text, 0, 1, &img, &err), BF_OK);
    assert_non_null(strstr(err.msg, text));
    assert_null(img.pixels);
    /* Writing: channels other than 1, 3, 4, unknown flags, a bad size or format. */
    const char *out = ts_tmp_path("bad.png");
    assert_int_equal(bf_image_write(out, BF_IMAGE_BY_NAME, 2, 2, 2, px, 0, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, out));
    assert_int_equal(bf_image_write(out, BF_IMAGE_BY_NAME, 2, 2, 3, px, 1u << 7, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, out));
    assert_int_equal(bf_image_write(out, BF_IMAGE_BY_NAME, 0, 2, 3, px, 0, &err), BF_ERR_ARG);
    assert_int_equal(bf_image_write(ts_tmp_path("bad.tif"), BF_IMAGE_BY_NAME, 2, 2, 3, px, 0, &err), BF_ERR_ARG);
    assert_int_equal(access(out, F_OK), -1);
    assert_int_equal(bf_image_write("/nonexistent-dir/x.png", BF_IMAGE_BY_NAME, 2, 2, 1, px, 0, &err), BF_ERR_IO);
    assert_non_null(strstr(err.msg, "/nonexistent-dir/x.png"));
}

/* decode(encode(x)) is x (to single precision), across both segments; the ends clamp. */
static void test_srgb_decode(void **state)
{
    (void)state;
    for (int i = 0; i <= 100000; i++) {
        float x = (float)i / 100000.0f;
        float back = bf_srgb_decode(bf_srgb_encode(x));
        ts_assert_near(back, x, 2e-6, 1e-9, "decode(encode(x))");
        float e = x;
        ts_assert_near(bf_srgb_encode(bf_srgb_decode(e)), e, 2e-6, 1e-9, "encode(decode(e))");
    }
    for (float x = 1e-7f; x < 1.0f; x *= 1.5f)
        ts_assert_near(bf_srgb_decode(bf_srgb_encode(x)), x, 2e-6, 0, "small x");
    assert_true(bf_srgb_decode(0.0f) == 0.0f);
    assert_true(bf_srgb_decode(1.0f) == 1.0f);
    assert_true(bf_srgb_decode(-0.5f) == 0.0f);
    assert_true(bf_srgb_decode(2.0f) == 1.0f);
    assert_true(bf_srgb_decode(NAN) == 0.0f);
    /* Known points of the standard curve. */
    ts_assert_near(bf_srgb_decode(0.5f), 0.21404114, 1e-5, 0, "decode(0.5)");
    ts_assert_near(bf_srgb_decode(0.04f), 0.04 / 12.92, 1e-6, 0, "linear segment");
    /* 8-bit codes: decoding then encoding gives the code back. */
    for (int k = 0; k <= 255; k++)
        assert_int_equal(lroundf(bf_srgb_encode(bf_srgb_decode((float)k / 255.0f)) * 255.0f), k);
}

/* Bands of different files read from several threads at once equal their serial reads. */
#define NTHREADS 6
typedef struct job {
    const char *path;
    const float *want; /* the whole image as bf_image_read gives it */
    int w, h, c;
    int failures;
} job;

static void *read_bands(void *arg)
{
    job *j = arg;
    bf_error err;
    for (int rep = 0; rep < 20; rep++) {
        for (int y0 = 0; y0 < j->h; y0 += 5) {
            int y1 = y0 + 5 < j->h ? y0 + 5 : j->h;
            bf_image band;
            bf_image_init(&band);
            if (bf_image_read_rows(j->path, y0, y1, &band, &err) != BF_OK) {
                j->failures++;
                continue;
            }
            size_t row = (size_t)j->w * j->c;
            if (band.height != y1 - y0 ||
                memcmp(band.pixels, j->want + row * y0, row * (size_t)(y1 - y0) * sizeof(float)) != 0)
                j->failures++;
            bf_image_clear(&band);
        }
    }
    return NULL;
}

static void test_read_rows_threads(void **state)
{
    (void)state;
    job jobs[NTHREADS];
    bf_image whole[NTHREADS];
    char names[NTHREADS][64];
    bf_error err;
    for (int t = 0; t < NTHREADS; t++) {
        int w = 40 + 3 * t, h = 31 + t, c = t % 2 ? 3 : 1;
        float *px = make_pixels(w, h, c, t % 3 == 0 ? hdr : pattern);
        snprintf(names[t], sizeof names[t], "thread%d.%s", t, t % 3 == 0 ? "exr" : "png");
        const char *path = ts_tmp_path(names[t]);
        snprintf(names[t], sizeof names[t], "%s", path);
        assert_int_equal(bf_image_write(names[t], BF_IMAGE_BY_NAME, w, h, c, px, BF_IMAGE_CODES | BF_IMAGE_16BIT, &err),
                         BF_OK);
        bf_image_init(&whole[t]);
        assert_int_equal(bf_image_read(names[t], &whole[t], &err), BF_OK);
        jobs[t] = (job){names[t], whole[t].pixels, w, h, c, 0};
        free(px);
    }
    pthread_t th[NTHREADS];
    for (int t = 0; t < NTHREADS; t++)
        assert_int_equal(pthread_create(&th[t], NULL, read_bands, &jobs[t]), 0);
    for (int t = 0; t < NTHREADS; t++) {
        pthread_join(th[t], NULL);
        assert_int_equal(jobs[t].failures, 0);
        bf_image_clear(&whole[t]);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_png16),        cmocka_unit_test(test_png8_codes),
        cmocka_unit_test(test_exr_channels), cmocka_unit_test(test_rgb_same_bytes),
        cmocka_unit_test(test_read_rows),    cmocka_unit_test(test_errors),
        cmocka_unit_test(test_srgb_decode),  cmocka_unit_test(test_read_rows_threads),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
