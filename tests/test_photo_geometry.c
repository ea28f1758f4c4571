/* The geometry of a photometric stack (photo/photo_light.c), against values worked out by
 * hand: the orthographic camera's pixel positions and view, the pinhole camera's rays
 * meeting the sample's plane, a point light's direction and 1/r^2, the camera rotation
 * both ways; and the JSON stack reader's camera and light members (stack_read.c), with
 * their errors. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/image.h"
#include "brdfit/photo.h"
#include "photo_impl.h"
#include "support.h"

/* A stack of 3 images of w x h pixels, written as 8-bit PNG codes, read from text. */
static bf_stack *read_stack(const char *json, int w, int h, bf_error *err, bf_status *rc)
{
    float *px = calloc((size_t)w * (size_t)h * 3, sizeof *px);
    assert_non_null(px);
    for (int k = 0; k < 3; k++) {
        char name[32];
        snprintf(name, sizeof name, "i%d.png", k);
        assert_int_equal(bf_image_write(ts_tmp_path(name), BF_IMAGE_PNG, w, h, 3, px, BF_IMAGE_16BIT, err), BF_OK);
    }
    free(px);
    const char *path = ts_tmp_path("stack.json");
    ts_write_file(path, json, strlen(json));
    bf_stack *s = NULL;
    *rc = bf_stack_read(path, &s, err);
    return s;
}

#define IMAGES(light0)                                                                                                 \
    "\"images\": [{\"file\": \"i0.png\", \"light\": " light0 "},"                                                      \
    "{\"file\": \"i1.png\", \"light\": {\"direction\": [0, 0, 1]}},"                                                   \
    "{\"file\": \"i2.png\", \"light\": {\"direction\": [0, 0.6, 0.8], \"intensity\": [1, 2, 3]}}]"

static void orthographic(void **state)
{
    (void)state;
    bf_error err;
    bf_status rc;
    bf_stack *s = read_stack(
        "{" IMAGES("{\"position\": [0, 0, 2], \"intensity\": 8}") ","
                                                                  "\"camera\": {\"type\": \"orthographic\", "
                                                                  "\"pixel_size\": 0.5, \"center\": [1, 0, 0]}}",
        4, 4, &err, &rc);
    assert_int_equal(rc, BF_OK);
    assert_int_equal(s->width, 4);
    assert_int_equal(s->channels, 3);
    assert_int_equal(s->transfer, BF_TRANSFER_LINEAR); /* 16-bit: linear codes */
    double l[9], e[9];
    photo_lights pl = {l, e, {0}};
    /* Pixel (0, 0): x = 1 + (0.5 - 2) 0.5 = 0.25, y = -(0.5 - 2) 0.5 = 0.75. */
    photo_lights_at(s, 0, 0, &pl);
    ts_assert_rel(pl.v[2], 1.0, 1e-15, "view z");
    double d[3] = {-0.25, -0.75, 2.0}, r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    for (int i = 0; i < 3; i++)
        ts_assert_rel(l[i], d[i] / sqrt(r2), 1e-12, "point light direction");
    for (int c = 0; c < 3; c++)
        ts_assert_rel(e[c], 8.0 / r2, 1e-12, "1/r^2 irradiance");
    /* The directional lights: unchanged; intensities per channel. */
    ts_assert_rel(l[3 + 2], 1.0, 1e-15, "directional light");
    ts_assert_rel(l[6 + 1], 0.6, 1e-12, "directional light y");
    ts_assert_rel(e[6 + 2], 3.0, 1e-15, "intensity, blue");
    bf_stack_free(s);
}

static void pinhole(void **state)
{
    (void)state;
    bf_error err;
    bf_status rc;
    /* Looking down -z from (0, 0, 2), 100 pixels per unit of focal length at 1. */
    bf_stack *s = read_stack("{" IMAGES("{\"position\": [0, 0, 1]}") ","
                                                                     "\"camera\": {\"type\": \"pinhole\", \"fx\": 100, "
                                                                     "\"fy\": 100, \"cx\": 50, \"cy\": 50,"
                                                                     " \"position\": [0, 0, 2]}}",
                             100, 100, &err, &rc);
    assert_int_equal(rc, BF_OK);
    double l[9], e[9];
    photo_lights pl = {l, e, {0}};
    /* Pixel (49, 49): the ray (-0.005, 0.005, -1) meets z = 0 at (-0.01, 0.01, 0). */
    photo_lights_at(s, 49, 49, &pl);
    double v[3] = {0.01, -0.01, 2.0}, vl = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3; i++)
        ts_assert_near(pl.v[i], v[i] / vl, 1e-12, 1e-14, "view towards the camera");
    double d[3] = {0.01, -0.01, 1.0}, r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    for (int i = 0; i < 3; i++)
        ts_assert_near(l[i], d[i] / sqrt(r2), 1e-12, 1e-14, "point light direction");
    ts_assert_rel(e[0], 1.0 / r2, 1e-12, "1/r^2");
    bf_stack_free(s);
}

static void rotation(void **state)
{
    (void)state;
    bf_error err;
    bf_status rc;
    /* The camera turned 90 degrees about z: its x axis is the world's y. */
    bf_stack *s =
        read_stack("{" IMAGES("{\"direction\": [1, 0, 0]}") ","
                                                            "\"camera\": {\"type\": \"orthographic\", \"rotation\": "
                                                            "[[0, -1, 0], [1, 0, 0], [0, 0, 1]]}}",
                   4, 4, &err, &rc);
    assert_int_equal(rc, BF_OK);
    double c[3] = {1, 0, 0}, w[3], back[3];
    photo_to_world(s, c, w);
    ts_assert_near(w[1], 1.0, 1e-15, 1e-15, "camera x is world y");
    photo_to_camera(s, w, back);
    for (int i = 0; i < 3; i++)
        ts_assert_near(back[i], c[i], 1e-15, 1e-15, "round trip");
    bf_stack_free(s);
}

/* refuse JSON WANT: the reader fails and its one-line message holds WANT. */
static void refuse(const char *json, const char *want)
{
    bf_error err;
    bf_status rc;
    bf_stack *s = read_stack(json, 4, 4, &err, &rc);
    assert_int_not_equal(rc, BF_OK);
    assert_null(s);
    if (!strstr(err.msg, want))
        fail_msg("'%s' does not say '%s'", err.msg, want);
    assert_null(strchr(err.msg, '\n'));
}

static void errors(void **state)
{
    (void)state;
    refuse("{" IMAGES("{\"direction\": [1, 0, 0]}") ", \"camera\": {\"type\": \"pinhole\", \"fx\": 1}}",
           "a pinhole camera needs fy");
    refuse("{" IMAGES("{\"direction\": [1, 0, 0]}") ", \"camera\": {\"rotation\": [[2, 0, 0], [0, 1, 0], [0, 0, 1]]}}",
           "camera/rotation: not a rotation matrix");
    refuse("{" IMAGES("{\"direction\": [1, 1, 0]}") "}", "images/0/light/direction: not a unit vector");
    refuse("{" IMAGES("{\"direction\": [0, 0, 1], \"position\": [0, 0, 1]}") "}",
           "give either a direction or a position");
    refuse("{" IMAGES("{\"direction\": [0, 0, 1], \"intensity\": -1}") "}", "is not positive");
    refuse("{" IMAGES("{\"direction\": [0, 0, 1]}") ", \"transfer\": \"gamma x\"}", "bad gamma");
    refuse("{" IMAGES("{\"direction\": [0, 0, 1]}") ", \"black_level\": 2}", "not above the black level");
    refuse("{" IMAGES("{\"direction\": [0, 0, 1]}") ", \"colour\": 1}", "unknown member 'colour'");
    refuse("{\"images\": [{\"file\": \"i0.png\", \"light\": {\"direction\": [0, 0, 1]}}]}", "a stack needs at least 3");
    refuse("{" IMAGES("{\"direction\": [0, 0, 1]}") ",\n\"mask\": 3}", "stack.json:2: mask");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(orthographic),
        cmocka_unit_test(pinhole),
        cmocka_unit_test(rotation),
        cmocka_unit_test(errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
