/* bf_photo_options as the library defines it (photo.h): the defaults, the ranges that
 * bf_photo_options_check refuses with their messages in both spellings, the parsers of
 * tile, normals and scale, bf_photo_fit refusing bad options before any work, and
 * bf_photo_result_json: the text fit.json holds, of a small Lambertian plane whose
 * answer is known. */
#include <cjson/cJSON.h>
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
#include "support.h"

/* check(o) fails with msg; again with keywords, failing with kmsg. */
static void refused(bf_photo_options *o, const char *msg, const char *kmsg)
{
    bf_error err;
    o->spelling = BF_SPELL_COMMAND_LINE;
    assert_int_equal(bf_photo_options_check(o, &err), BF_ERR_ARG);
    assert_string_equal(err.msg, msg);
    o->spelling = BF_SPELL_KEYWORD;
    assert_int_equal(bf_photo_options_check(o, &err), BF_ERR_ARG);
    assert_string_equal(err.msg, kmsg);
    bf_photo_options_init(o);
}

static void test_defaults_pass(void **state)
{
    (void)state;
    bf_photo_options o;
    bf_photo_options_init(&o);
    assert_int_equal(o.size, sizeof o);
    assert_string_equal(o.model, "walter");
    assert_int_equal(o.relit_images, 3);
    assert_int_equal(o.normals, BF_NORMALS_FIT);
    assert_true(o.clusters == 0 && o.threads == 0 && o.tile_count == 0 && !o.scale_given && o.seed == 0);
    assert_int_equal(o.spelling, BF_SPELL_COMMAND_LINE);
    bf_error err;
    assert_int_equal(bf_photo_options_check(&o, &err), BF_OK);
    /* Every end of every range. */
    o.clusters = BF_PHOTO_MAX_CLUSTERS;
    o.threads = BF_PHOTO_MAX_THREADS;
    o.relit_images = 0;
    o.scale_given = 1;
    o.scale = 1e30;
    o.tile_index = BF_PHOTO_MAX_TILES - 1;
    o.tile_count = BF_PHOTO_MAX_TILES;
    o.share = "alpha,rho_d";
    assert_int_equal(bf_photo_options_check(&o, &err), BF_OK);
}

static void test_check_ranges_and_messages(void **state)
{
    (void)state;
    bf_photo_options o;
    bf_photo_options_init(&o);
    o.model = "nope";
    refused(&o, "-m: unknown model 'nope' (see brdfit models)", "model: unknown model 'nope' (see brdfit models)");
    o.model = "lambert";
    o.share = "rho_d,alpha";
    refused(&o, "--share: lambert has no parameter 'alpha' (brdfit models)",
            "share: lambert has no parameter 'alpha' (brdfit models)");
    o.normals = BF_NORMALS_FILE;
    refused(&o, "--normals: no file", "normals: no file");
    o.clusters = 65;
    refused(&o, "--clusters needs an integer from 1 to 64, got '65'",
            "clusters needs an integer from 1 to 64, got '65'");
    o.clusters = -1;
    refused(&o, "--clusters needs an integer from 1 to 64, got '-1'",
            "clusters needs an integer from 1 to 64, got '-1'");
    o.scale_given = 1;
    o.scale = -1;
    refused(&o, "bad value '-1' for --scale (auto or a positive number)",
            "bad value '-1' for scale (auto or a positive number)");
    o.scale_given = 1;
    o.scale = NAN;
    refused(&o, "bad value 'nan' for --scale (auto or a positive number)",
            "bad value 'nan' for scale (auto or a positive number)");
    o.tile_index = 2;
    o.tile_count = 2;
    refused(&o, "bad value '3/2' for --tile (I/N with 1 <= I <= N)", "bad value '3/2' for tile (I/N with 1 <= I <= N)");
    o.tile_index = -1;
    o.tile_count = 4;
    refused(&o, "bad value '0/4' for --tile (I/N with 1 <= I <= N)", "bad value '0/4' for tile (I/N with 1 <= I <= N)");
    o.threads = 1025;
    refused(&o, "--threads needs an integer from 1 to 1024 (0: every core), got '1025'",
            "threads needs an integer from 1 to 1024 (0: every core), got '1025'");
    o.relit_images = 9;
    refused(&o, "--relit needs an integer from 0 to 8, got '9'", "relit needs an integer from 0 to 8, got '9'");
    /* A scale not given is not read; 0 given is the automatic one. */
    o.scale = -5;
    bf_error err;
    assert_int_equal(bf_photo_options_check(&o, &err), BF_OK);
    o.scale_given = 1;
    o.scale = 0;
    assert_int_equal(bf_photo_options_check(&o, &err), BF_OK);
    /* A size never set; the first version's size (before spelling): taken, spelling not read. */
    o.size = 0;
    assert_int_equal(bf_photo_options_check(&o, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "bf_photo_options: size 0"));
    bf_photo_options_init(&o);
    o.spelling = BF_SPELL_KEYWORD;
    o.size = offsetof(bf_photo_options, spelling);
    o.relit_images = 9;
    assert_int_equal(bf_photo_options_check(&o, &err), BF_ERR_ARG);
    assert_string_equal(err.msg, "--relit needs an integer from 0 to 8, got '9'");
    assert_int_equal(bf_photo_options_check(NULL, &err), BF_ERR_ARG);
}

static void test_parsers(void **state)
{
    (void)state;
    bf_photo_options o;
    bf_photo_options_init(&o);
    bf_error err;
    assert_int_equal(bf_photo_options_set_tile(&o, "2/3", &err), BF_OK);
    assert_true(o.tile_index == 1 && o.tile_count == 3);
    assert_int_equal(bf_photo_options_set_tile(&o, "1000000/1000000", &err), BF_OK);
    static const char *const bad_tiles[] = {"1/",  "/2",  "2",    "1/2/3",     " 1/2",
                                            "0/2", "3/2", "+1/2", "1/1000001", "12345678901234567890123456789012345/40",
                                            ""};
    for (size_t k = 0; k < sizeof bad_tiles / sizeof *bad_tiles; k++) {
        bf_photo_options_init(&o);
        assert_int_equal(bf_photo_options_set_tile(&o, bad_tiles[k], &err), BF_ERR_ARG);
        char want[128];
        snprintf(want, sizeof want, "bad value '%s' for --tile (I/N with 1 <= I <= N)", bad_tiles[k]);
        assert_string_equal(err.msg, want);
        assert_true(o.tile_index == 0 && o.tile_count == 0); /* unchanged */
    }
    o.spelling = BF_SPELL_KEYWORD;
    assert_int_equal(bf_photo_options_set_tile(&o, "3/2", &err), BF_ERR_ARG);
    assert_string_equal(err.msg, "bad value '3/2' for tile (I/N with 1 <= I <= N)");

    const char *file = "n.exr";
    assert_int_equal(bf_photo_options_set_normals(&o, file, &err), BF_OK);
    assert_true(o.normals == BF_NORMALS_FILE && o.normals_file == file); /* the pointer kept */
    assert_int_equal(bf_photo_options_set_normals(&o, "flat", &err), BF_OK);
    assert_true(o.normals == BF_NORMALS_FLAT && !o.normals_file);
    assert_int_equal(bf_photo_options_set_normals(&o, "fit", &err), BF_OK);
    assert_int_equal(o.normals, BF_NORMALS_FIT);
    assert_int_equal(bf_photo_options_set_normals(&o, NULL, &err), BF_ERR_ARG);

    assert_int_equal(bf_photo_options_set_scale(&o, "2.5", &err), BF_OK);
    assert_true(o.scale_given == 1 && o.scale == 2.5);
    assert_int_equal(bf_photo_options_set_scale(&o, "auto", &err), BF_OK);
    assert_true(o.scale_given == 1 && o.scale == 0.0);
    o.scale_given = 0;
    static const char *const bad_scales[] = {"0", "-1", "nan", "inf", "1e31", "abc", "", "1e-31"};
    for (size_t k = 0; k < sizeof bad_scales / sizeof *bad_scales; k++) {
        assert_int_equal(bf_photo_options_set_scale(&o, bad_scales[k], &err), BF_ERR_ARG);
        char want[128];
        snprintf(want, sizeof want, "bad value '%s' for scale (auto or a positive number)", bad_scales[k]);
        assert_string_equal(err.msg, want);
        assert_int_equal(o.scale_given, 0);
    }
}

/* A flat Lambertian square (W x H, albedo 0.5, 0.4, 0.3) under six lights as a JSON stack
 * of EXR images. */
enum { W = 8, H = 6, K = 6 };
static const double ALBEDO[3] = {0.5, 0.4, 0.3};

static bf_stack *plane_stack(void)
{
    static const double dirs[K][3] = {{0, 0, 1},     {0.6, 0, 0.8},  {-0.6, 0, 0.8},
                                      {0, 0.6, 0.8}, {0, -0.6, 0.8}, {0.48, 0.36, 0.8}};
    char json[2048] = "{\"images\": [";
    float px[W * H * 3];
    bf_error err;
    for (int k = 0; k < K; k++) {
        for (int p = 0; p < W * H; p++)
            for (int c = 0; c < 3; c++)
                px[3 * p + c] = (float)(ALBEDO[c] / M_PI * dirs[k][2]);
        char name[32], entry[160];
        snprintf(name, sizeof name, "plane%d.exr", k);
        if (bf_image_write(ts_tmp_path(name), BF_IMAGE_EXR, W, H, 3, px, 0, &err) != BF_OK)
            fail_msg("%s", err.msg);
        snprintf(entry, sizeof entry, "%s{\"file\": \"%s\", \"light\": {\"direction\": [%g, %g, %g]}}", k ? ", " : "",
                 name, dirs[k][0], dirs[k][1], dirs[k][2]);
        strcat(json, entry);
    }
    strcat(json, "]}");
    const char *path = ts_tmp_path("plane.json");
    ts_write_file(path, json, strlen(json));
    bf_stack *s = NULL;
    if (bf_stack_read(path, &s, &err) != BF_OK)
        fail_msg("%s", err.msg);
    return s;
}

static void test_fit_refuses_bad_options_first(void **state)
{
    (void)state;
    bf_stack *s = plane_stack();
    bf_photo_options o;
    bf_photo_options_init(&o);
    o.scale_given = 1;
    o.scale = NAN; /* ran, and gave garbage, before the check */
    bf_photo_result *r = (bf_photo_result *)s;
    bf_error err;
    assert_int_equal(bf_photo_fit(s, &o, &r, &err), BF_ERR_ARG);
    assert_null(r);
    assert_string_equal(err.msg, "bad value 'nan' for --scale (auto or a positive number)");
    bf_photo_options_init(&o);
    o.spelling = BF_SPELL_KEYWORD;
    o.share = "zz";
    assert_int_equal(bf_photo_fit(s, &o, &r, &err), BF_ERR_ARG);
    assert_string_equal(err.msg, "share: walter has no parameter 'zz' (brdfit models)");
    /* The tile against the image: only the fit knows its rows. */
    bf_photo_options_init(&o);
    assert_int_equal(bf_photo_options_set_tile(&o, "3/40", &err), BF_OK);
    assert_int_equal(bf_photo_fit(s, &o, &r, &err), BF_ERR_ARG);
    assert_string_equal(err.msg, "--tile 3/40: out of range (the image has 6 rows)");
    o.spelling = BF_SPELL_KEYWORD;
    assert_int_equal(bf_photo_fit(s, &o, &r, &err), BF_ERR_ARG);
    assert_string_equal(err.msg, "tile 3/40: out of range (the image has 6 rows)");
    /* A program built before `spelling`: its shorter struct (allocated at that size, so
     * the sanitizers see a read past it) is taken, and read no further. */
    const size_t old_size = offsetof(bf_photo_options, spelling);
    bf_photo_options_init(&o);
    o.size = old_size;
    o.model = "lambert";
    o.threads = 1;
    o.relit_images = 0;
    void *old = malloc(old_size);
    assert_non_null(old);
    memcpy(old, &o, old_size);
    assert_int_equal(bf_photo_fit(s, old, &r, &err), BF_OK);
    assert_int_equal(r->counts.pixels, W * H);
    bf_photo_result_free(r);
    free(old);
    bf_stack_free(s);
}

static void test_result_json_is_fit_json(void **state)
{
    (void)state;
    bf_stack *s = plane_stack();
    bf_photo_options o;
    bf_photo_options_init(&o);
    o.model = "lambert";
    o.threads = 1;
    o.relit_images = 2;
    bf_error err;
    assert_int_equal(bf_photo_options_set_normals(&o, "flat", &err), BF_OK);
    bf_photo_result *r = NULL;
    if (bf_photo_fit(s, &o, &r, &err) != BF_OK)
        fail_msg("%s", err.msg);
    char *text = NULL;
    assert_int_equal(bf_photo_result_json(r, s, &o, "brdfit fit-images plane.json", &text, &err), BF_OK);
    /* What bf_photo_write puts in fit.json, byte for byte. */
    const char *dir = ts_tmp_path("plane_out");
    assert_int_equal(bf_photo_write(r, s, &o, dir, "brdfit fit-images plane.json", &err), BF_OK);
    char file[512];
    snprintf(file, sizeof file, "%s/fit.json", dir);
    assert_string_equal(text, ts_read_file(file));
    cJSON *root = cJSON_Parse(text);
    assert_non_null(root);
    assert_string_equal(cJSON_GetObjectItem(root, "command")->valuestring, "brdfit fit-images plane.json");
    assert_string_equal(cJSON_GetObjectItem(root, "model")->valuestring, "lambert");
    const cJSON *opt = cJSON_GetObjectItem(root, "options");
    assert_string_equal(cJSON_GetObjectItem(opt, "normals")->valuestring, "flat");
    assert_true(cJSON_GetObjectItem(opt, "scale")->valuedouble == 1.0);
    const cJSON *counts = cJSON_GetObjectItem(root, "counts");
    assert_int_equal(cJSON_GetObjectItem(counts, "pixels")->valuedouble, W * H);
    assert_int_equal(cJSON_GetObjectItem(counts, "samples_used")->valuedouble, W * H * K);
    /* The files: those bf_photo_write wrote, in its order. */
    const char *want[] = {"normals.exr",        "rho_d.exr",     "error.exr",     "lambert_normals.exr",
                          "lambert_albedo.exr", "normals.png",   "albedo.png",    "relit_000.png",
                          "relit_000.exr",      "relit_005.png", "relit_005.exr", "mask.png"};
    const cJSON *files = cJSON_GetObjectItem(root, "files");
    assert_int_equal(cJSON_GetArraySize(files), sizeof want / sizeof *want);
    for (int i = 0; i < cJSON_GetArraySize(files); i++) {
        assert_string_equal(cJSON_GetArrayItem(files, i)->valuestring, want[i]);
        char path[512];
        snprintf(path, sizeof path, "%s/%s", dir, want[i]);
        FILE *fp = fopen(path, "rb");
        assert_non_null(fp);
        fclose(fp);
    }
    /* The albedo recovered: rho_d of a pixel is the truth. */
    for (int c = 0; c < 3; c++)
        ts_assert_rel(r->params[(2 * W + 3) * r->nvalues + c], ALBEDO[c], 1e-4, "rho_d");
    assert_true(r->relit_rms < 1e-5);
    cJSON_Delete(root);
    bf_free(text);
    /* A cancelled fit has no summary; nothing in, nothing out. */
    r->cancelled = 1;
    assert_int_equal(bf_photo_result_json(r, s, &o, NULL, &text, &err), BF_ERR_ARG);
    assert_null(text);
    assert_string_equal(err.msg, "fit-images: the fit was cancelled: it has no summary");
    assert_int_equal(bf_photo_result_json(NULL, s, &o, NULL, &text, &err), BF_ERR_ARG);
    bf_photo_result_free(r);
    bf_stack_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults_pass),
        cmocka_unit_test(test_check_ranges_and_messages),
        cmocka_unit_test(test_parsers),
        cmocka_unit_test(test_fit_refuses_bad_options_first),
        cmocka_unit_test(test_result_json_is_fit_json),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
