/* bf_photo_options (photo.h): the defaults, the ranges and their messages, and the
 * options brdfit fit-images takes as text (tile, normals, scale), in one place for the
 * command and every front end. Messages name an option as o->spelling says. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/sized.h"
#include "brdfit/tool.h"
#include "photo_impl.h"

#define SCALE_MIN 1e-30 /* a scale outside these is a typing error, not a choice */
#define SCALE_MAX 1e30
#define TILE_TEXT "I/N with 1 <= I <= N"

/* bf_photo_options with the library's defaults (a whole struct of this version). */
static void photo_options_defaults(bf_photo_options *o)
{
    o->model = "walter";
    o->relit_images = 3;
}

BF_SIZED_INIT(bf_photo_options, photo_options_defaults)

const char *photo_option_name(const bf_photo_options *o, const char *keyword)
{
    static const struct {
        const char *keyword, *command_line;
    } names[] = {{"model", "-m"},         {"normals", "--normals"}, {"share", "--share"}, {"clusters", "--clusters"},
                 {"scale", "--scale"},    {"tile", "--tile"},       {"relit", "--relit"}, {"seed", "--seed"},
                 {"threads", "--threads"}};
    const int keywords = o && o->size >= PHOTO_OPTIONS_SPELLING_SIZE && o->spelling == BF_SPELL_KEYWORD;
    for (size_t i = 0; i < sizeof names / sizeof *names; i++)
        if (!strcmp(names[i].keyword, keyword))
            return keywords ? names[i].keyword : names[i].command_line;
    return keyword;
}

static bf_status bad_tile(const bf_photo_options *o, const char *text, bf_error *err)
{
    return bf_fail(err, BF_ERR_ARG, "bad value '%s' for %s (" TILE_TEXT ")", text, photo_option_name(o, "tile"));
}

static bf_status bad_scale(const bf_photo_options *o, const char *text, bf_error *err)
{
    return bf_fail(err, BF_ERR_ARG, "bad value '%s' for %s (auto or a positive number)", text,
                   photo_option_name(o, "scale"));
}

/* An integer option out of its range, as the command line's parser says it. */
static bf_status bad_int(const bf_photo_options *o, const char *keyword, int lo, int hi, const char *note, int v,
                         bf_error *err)
{
    return bf_fail(err, BF_ERR_ARG, "%s needs an integer from %d to %d%s, got '%d'", photo_option_name(o, keyword), lo,
                   hi, note, v);
}

/* The model spec and the shared names against it: what is usage before any image. */
static bf_status check_model(const bf_photo_options *o, bf_error *err)
{
    bf_model *m = NULL;
    bf_error e;
    if (bf_model_new(o->model, 3, &m, &e) != BF_OK)
        return bf_fail(err, BF_ERR_ARG, "%s: %s", photo_option_name(o, "model"), e.msg);
    bf_status rc = BF_OK;
    char *names = o->share ? strdup(o->share) : NULL;
    if (o->share && !names)
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", photo_option_name(o, "share"));
    for (char *save = NULL, *t = names ? strtok_r(names, ",", &save) : NULL; t && rc == BF_OK;
         t = strtok_r(NULL, ",", &save))
        if (bf_model_find_param(m, t) < 0)
            rc = bf_fail(err, BF_ERR_ARG, "%s: %s has no parameter '%s' (brdfit models)", photo_option_name(o, "share"),
                         bf_model_name(m), t);
    free(names);
    bf_model_free(m);
    return rc;
}

bf_status bf_photo_options_check(const bf_photo_options *o, bf_error *err)
{
    if (!o)
        return bf_fail(err, BF_ERR_ARG, "fit-images: no options");
    if (bf_sized_check(o, PHOTO_OPTIONS_MIN_SIZE, "bf_photo_options", err) != BF_OK)
        return BF_ERR_ARG;
    if (!o->model)
        return bf_fail(err, BF_ERR_ARG, "%s: no model", photo_option_name(o, "model"));
    bf_status rc = check_model(o, err);
    if (rc != BF_OK)
        return rc;
    if (o->normals != BF_NORMALS_FIT && o->normals != BF_NORMALS_FILE && o->normals != BF_NORMALS_FLAT)
        return bf_fail(err, BF_ERR_ARG, "%s: unknown kind %d (fit, flat or a file)", photo_option_name(o, "normals"),
                       (int)o->normals);
    if (o->normals == BF_NORMALS_FILE && !o->normals_file)
        return bf_fail(err, BF_ERR_ARG, "%s: no file", photo_option_name(o, "normals"));
    if (o->clusters < 0 || o->clusters > BF_PHOTO_MAX_CLUSTERS)
        return bad_int(o, "clusters", 1, BF_PHOTO_MAX_CLUSTERS, "", o->clusters, err);
    if (o->scale_given && o->scale != 0.0 && !(o->scale >= SCALE_MIN && o->scale <= SCALE_MAX)) {
        char text[32];
        snprintf(text, sizeof text, "%g", o->scale);
        return bad_scale(o, text, err);
    }
    if (o->tile_count < 0 || o->tile_count > BF_PHOTO_MAX_TILES ||
        (o->tile_count > 0 && (o->tile_index < 0 || o->tile_index >= o->tile_count))) {
        char text[32];
        snprintf(text, sizeof text, "%d/%d", o->tile_index + 1, o->tile_count);
        return bad_tile(o, text, err);
    }
    if (o->threads < 0 || o->threads > BF_PHOTO_MAX_THREADS)
        return bad_int(o, "threads", 1, BF_PHOTO_MAX_THREADS, " (0: every core)", o->threads, err);
    if (o->relit_images < 0 || o->relit_images > BF_PHOTO_MAX_RELIT)
        return bad_int(o, "relit", 0, BF_PHOTO_MAX_RELIT, "", o->relit_images, err);
    return BF_OK;
}

bf_status bf_photo_options_set_tile(bf_photo_options *o, const char *text, bf_error *err)
{
    if (!o || !text)
        return bf_fail(err, BF_ERR_ARG, "tile: no options or no text");
    const char *slash = strchr(text, '/');
    char head[32];
    size_t len = slash ? (size_t)(slash - text) : 0;
    long i, n;
    if (!slash || len >= sizeof head)
        return bad_tile(o, text, err);
    memcpy(head, text, len);
    head[len] = '\0';
    if (!bf_parse_long(head, 1, BF_PHOTO_MAX_TILES, &i) || !bf_parse_long(slash + 1, 1, BF_PHOTO_MAX_TILES, &n) ||
        i > n)
        return bad_tile(o, text, err);
    o->tile_index = (int)i - 1;
    o->tile_count = (int)n;
    return BF_OK;
}

bf_status bf_photo_options_set_normals(bf_photo_options *o, const char *text, bf_error *err)
{
    if (!o || !text)
        return bf_fail(err, BF_ERR_ARG, "normals: no options or no text");
    if (!strcmp(text, "fit") || !strcmp(text, "flat")) {
        o->normals = !strcmp(text, "fit") ? BF_NORMALS_FIT : BF_NORMALS_FLAT;
        o->normals_file = NULL;
    } else {
        o->normals = BF_NORMALS_FILE;
        o->normals_file = text;
    }
    return BF_OK;
}

bf_status bf_photo_options_set_scale(bf_photo_options *o, const char *text, bf_error *err)
{
    if (!o || !text)
        return bf_fail(err, BF_ERR_ARG, "scale: no options or no text");
    double v = 0.0; /* auto: the stack's rule */
    if (strcmp(text, "auto") && !(bf_parse_number(text, SCALE_MIN, SCALE_MAX, &v) && v > 0.0))
        return bad_scale(o, text, err);
    o->scale_given = 1;
    o->scale = v;
    return BF_OK;
}
