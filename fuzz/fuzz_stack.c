/* Image stacks (photo.h): JSON stack files as bf_stack_read reads them. The input is the
 * stack file's text (stack.json in the scratch folder); the file names it lists are
 * relative to that folder, which holds the small images below, made on the first call:
 *
 *   a.png b.png c.png  4x3 RGB, 16-bit        d.png  4x3 RGBA, 16-bit
 *   e.png              4x3 RGB, 8-bit         f.exr  4x3 RGB, float
 *   g.png              4x3 grey, 16-bit       m.png  4x3 grey, 8-bit (a mask)
 *   big.png            5x2 RGB, 16-bit (a size no other image has)
 *
 * A stack read is checked against the images (every header read again: the stack's size,
 * channels and storage are theirs) and against the JSON itself (parsed here with cJSON):
 * the image count, each light, intensity and exposure, the camera, transfer, black level,
 * saturation and scale given, else the documented defaults (docs/images.md), and what
 * holds of every stack: at least 3 images, directional lights unit within 1e-3,
 * intensities and exposures finite and > 0, saturation above the black level or +inf.
 *
 * fuzz_diligent.c includes this file with FUZZ_STACK_COMMON_ONLY for the images and the
 * checks common to both layouts. */
#include "fuzz_common.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/image.h"
#include "brdfit/photo.h"

enum { W = 4, H = 3 };

/* The scratch images: name, size, channels, flags (BF_IMAGE_16BIT) or EXR. */
static const struct scratch_image {
    const char *name;
    int width, height, channels, exr;
    unsigned flags;
} scratch_images[] = {
    {"a.png", W, H, 3, 0, BF_IMAGE_16BIT},
    {"b.png", W, H, 3, 0, BF_IMAGE_16BIT},
    {"c.png", W, H, 3, 0, BF_IMAGE_16BIT},
    {"d.png", W, H, 4, 0, BF_IMAGE_16BIT},
    {"e.png", W, H, 3, 0, 0},
    {"f.exr", W, H, 3, 1, 0},
    {"g.png", W, H, 1, 0, BF_IMAGE_16BIT},
    {"m.png", W, H, 1, 0, 0},
    {"big.png", W + 1, H - 1, 3, 0, BF_IMAGE_16BIT},
};
enum { NSCRATCH = sizeof scratch_images / sizeof scratch_images[0] };

/* Writes the scratch images (once per process). */
static void make_images(void)
{
    static int made;
    if (made)
        return;
    made = 1;
    float px[(W + 1) * H * 4];
    for (int i = 0; i < NSCRATCH; i++) {
        const struct scratch_image *im = &scratch_images[i];
        const int n = im->width * im->height * im->channels;
        for (int k = 0; k < n; k++) /* a ramp, different in each image, some codes 0 and 1 */
            px[k] = (float)((k * 7 + i * 5) % 23) / 22.0f;
        bf_error err;
        if (bf_image_write(fuzz_path(im->name), im->exr ? BF_IMAGE_EXR : BF_IMAGE_PNG, im->width, im->height,
                           im->channels, px, im->flags, &err) != BF_OK)
            fuzz_fail("making the scratch image %s: %s", im->name, err.msg);
    }
}

/* What holds of every stack read, whichever the layout. */
static void check_stack(const bf_stack *s)
{
    if (s->nimages < 3 || !s->images)
        fuzz_fail("a stack of %d images", s->nimages);
    if (!s->path)
        fuzz_fail("a stack without its path");
    for (int k = 0; k < s->nimages; k++) {
        const bf_stack_image *im = &s->images[k];
        if (!im->file || !im->file[0])
            fuzz_fail("image %d: no file name", k);
        if (im->point != 0 && im->point != 1)
            fuzz_fail("image %d: point %d", k, im->point);
        if (!im->point) {
            const double len = sqrt(im->dir[0] * im->dir[0] + im->dir[1] * im->dir[1] + im->dir[2] * im->dir[2]);
            if (!(fabs(len - 1.0) <= 1e-3))
                fuzz_fail("image %d: light direction (%g, %g, %g) of length %.17g", k, im->dir[0], im->dir[1],
                          im->dir[2], len);
        } else
            for (int c = 0; c < 3; c++)
                if (!isfinite(im->pos[c]))
                    fuzz_fail("image %d: light position %d is %g", k, c, im->pos[c]);
        for (int c = 0; c < 3; c++)
            if (!(isfinite(im->intensity[c]) && im->intensity[c] > 0.0))
                fuzz_fail("image %d: intensity %d is %g", k, c, im->intensity[c]);
        if (!(isfinite(im->exposure) && im->exposure > 0.0))
            fuzz_fail("image %d: exposure %g", k, im->exposure);
    }
    if (!(s->width > 0 && s->height > 0 && (s->channels == 1 || s->channels == 3)))
        fuzz_fail("a stack of %dx%d pixels x %d channels", s->width, s->height, s->channels);
    if (s->is_float ? s->bits != 16 && s->bits != 32 : s->bits != 8 && s->bits != 16)
        fuzz_fail("a stack of %d-bit %s values", s->bits, s->is_float ? "float" : "integer");
    /* Every image (and the mask) as the stack says: the headers read again. */
    for (int k = 0; k <= s->nimages; k++) {
        const char *file = k < s->nimages ? s->images[k].file : s->mask;
        if (!file)
            continue;
        bf_image_spec sp;
        bf_image_spec_init(&sp);
        bf_error err;
        if (bf_image_info(file, &sp, &err) != BF_OK)
            fuzz_fail("%s, in the stack read, does not read: %s", file, err.msg);
        if (sp.width != s->width || sp.height != s->height)
            fuzz_fail("%s: %dx%d pixels in a stack of %dx%d", file, sp.width, sp.height, s->width, s->height);
        if (k < s->nimages && ((sp.channels == 1 ? 1 : 3) != s->channels || sp.channels > 4 || sp.bits != s->bits ||
                               sp.is_float != s->is_float))
            fuzz_fail("%s: %d channels, %d-bit %s, in a stack of %d channels, %d-bit %s", file, sp.channels, sp.bits,
                      sp.is_float ? "float" : "integer", s->channels, s->bits, s->is_float ? "float" : "integer");
    }
    if (s->transfer != BF_TRANSFER_LINEAR && s->transfer != BF_TRANSFER_SRGB && s->transfer != BF_TRANSFER_GAMMA)
        fuzz_fail("transfer %d", (int)s->transfer);
    if (s->transfer == BF_TRANSFER_GAMMA && !(s->gamma > 0.0 && isfinite(s->gamma)))
        fuzz_fail("gamma %g", s->gamma);
    if (!isfinite(s->black_level))
        fuzz_fail("black level %g", s->black_level);
    if (!(s->saturation > s->black_level) || isnan(s->saturation) || s->saturation == -INFINITY)
        fuzz_fail("saturation %.17g, black level %.17g", s->saturation, s->black_level);
    if (!(isfinite(s->scale) && s->scale >= 0.0))
        fuzz_fail("scale %g", s->scale);
    const bf_stack_camera *cam = &s->camera;
    if (cam->type == BF_CAMERA_ORTHOGRAPHIC ? !(cam->pixel_size > 0.0 && isfinite(cam->pixel_size))
                                            : !(cam->fx > 0.0 && cam->fy > 0.0 && isfinite(cam->fx) &&
                                                isfinite(cam->fy) && isfinite(cam->cx) && isfinite(cam->cy)))
        fuzz_fail("camera type %d: pixel size %g, fx %g, fy %g, cx %g, cy %g", (int)cam->type, cam->pixel_size, cam->fx,
                  cam->fy, cam->cx, cam->cy);
}

#ifndef FUZZ_STACK_COMMON_ONLY

/* The default transfer of a stack that gives none. */
static bf_transfer default_transfer(const bf_stack *s)
{
    return !s->is_float && s->bits <= 8 ? BF_TRANSFER_SRGB : BF_TRANSFER_LINEAR;
}

/* A number the reader took as it is. */
static void same_number(const cJSON *v, double got, const char *what, int k)
{
    if (!cJSON_IsNumber(v))
        fuzz_fail("%s (image %d): read as %g from a value that is not a number", what, k, got);
    if (got != v->valuedouble)
        fuzz_fail("%s (image %d): %.17g read as %.17g", what, k, v->valuedouble, got);
}

static void same_vector(const cJSON *v, const double *got, int n, const char *what, int k)
{
    if (cJSON_GetArraySize(v) != n)
        fuzz_fail("%s (image %d): %d values read from an array of %d", what, k, n, cJSON_GetArraySize(v));
    for (int i = 0; i < n; i++)
        same_number(cJSON_GetArrayItem(v, i), got[i], what, k);
}

/* The stack read against the JSON it was read from. */
static void check_json(const bf_stack *s, const char *text)
{
    cJSON *root = cJSON_ParseWithOpts(text, NULL, 1);
    if (!root)
        fuzz_fail("a stack read from text cJSON does not parse");
    if (s->layout != BF_STACK_JSON)
        fuzz_fail("a JSON stack of layout %d", (int)s->layout);
    const cJSON *images = cJSON_GetObjectItemCaseSensitive(root, "images"), *v;
    if (cJSON_GetArraySize(images) != s->nimages)
        fuzz_fail("%d images read from an array of %d", s->nimages, cJSON_GetArraySize(images));
    for (int k = 0; k < s->nimages; k++) {
        const bf_stack_image *im = &s->images[k];
        const cJSON *e = cJSON_GetArrayItem(images, k), *l = cJSON_GetObjectItemCaseSensitive(e, "light");
        const cJSON *f = cJSON_GetObjectItemCaseSensitive(e, "file");
        if (!cJSON_IsString(f))
            fuzz_fail("image %d: a file read from no name", k);
        const size_t n = strlen(im->file), m = strlen(f->valuestring);
        if (n < m || strcmp(im->file + n - m, f->valuestring) != 0)
            fuzz_fail("image %d: file '%s' read as '%s'", k, f->valuestring, im->file);
        if ((v = cJSON_GetObjectItemCaseSensitive(l, "direction"))) {
            if (im->point)
                fuzz_fail("image %d: a direction read as a point light", k);
            same_vector(v, im->dir, 3, "light direction", k);
        } else {
            if (!im->point)
                fuzz_fail("image %d: a position read as a directional light", k);
            same_vector(cJSON_GetObjectItemCaseSensitive(l, "position"), im->pos, 3, "light position", k);
        }
        if ((v = cJSON_GetObjectItemCaseSensitive(l, "intensity"))) {
            if (cJSON_IsNumber(v))
                for (int c = 0; c < 3; c++)
                    same_number(v, im->intensity[c], "intensity", k);
            else
                same_vector(v, im->intensity, 3, "intensity", k);
        } else if (im->intensity[0] != 1.0 || im->intensity[1] != 1.0 || im->intensity[2] != 1.0)
            fuzz_fail("image %d: intensity (%g, %g, %g), none given", k, im->intensity[0], im->intensity[1],
                      im->intensity[2]);
        if ((v = cJSON_GetObjectItemCaseSensitive(e, "exposure")))
            same_number(v, im->exposure, "exposure", k);
        else if (im->exposure != 1.0)
            fuzz_fail("image %d: exposure %g, none given", k, im->exposure);
    }
    const bf_stack_camera *cam = &s->camera;
    const cJSON *camera = cJSON_GetObjectItemCaseSensitive(root, "camera");
    const int pinhole = camera && !strcmp(cJSON_GetObjectItemCaseSensitive(camera, "type")->valuestring, "pinhole");
    if (cam->type != (pinhole ? BF_CAMERA_PINHOLE : BF_CAMERA_ORTHOGRAPHIC))
        fuzz_fail("camera type %d", (int)cam->type);
    if ((v = cJSON_GetObjectItemCaseSensitive(camera, "pixel_size")))
        same_number(v, cam->pixel_size, "camera pixel size", -1);
    else if (cam->pixel_size != 1.0)
        fuzz_fail("camera pixel size %g, none given", cam->pixel_size);
    static const char *const intr[] = {"fx", "fy", "cx", "cy"};
    const double got[] = {cam->fx, cam->fy, cam->cx, cam->cy};
    for (int k = 0; k < 4; k++)
        if ((v = cJSON_GetObjectItemCaseSensitive(camera, intr[k])))
            same_number(v, got[k], intr[k], -1);
    if ((v = cJSON_GetObjectItemCaseSensitive(camera, "position")))
        same_vector(v, cam->position, 3, "camera position", -1);
    if ((v = cJSON_GetObjectItemCaseSensitive(camera, "center")))
        same_vector(v, cam->center, 3, "camera center", -1);
    if ((v = cJSON_GetObjectItemCaseSensitive(camera, "rotation")))
        for (int r = 0; r < 3; r++)
            same_vector(cJSON_GetArrayItem(v, r), cam->rotation + 3 * r, 3, "camera rotation", r);
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "mask"))) {
        const size_t n = s->mask ? strlen(s->mask) : 0, m = strlen(v->valuestring);
        if (n < m || strcmp(s->mask + n - m, v->valuestring) != 0)
            fuzz_fail("mask '%s' read as '%s'", v->valuestring, s->mask ? s->mask : "(none)");
    } else if (s->mask)
        fuzz_fail("mask '%s', none given", s->mask);
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "transfer"))) {
        const char *t = v->valuestring;
        const bf_transfer want = !strcmp(t, "linear") ? BF_TRANSFER_LINEAR
                                 : !strcmp(t, "srgb") ? BF_TRANSFER_SRGB
                                                      : BF_TRANSFER_GAMMA;
        if (s->transfer != want || (want == BF_TRANSFER_GAMMA && s->gamma != strtod(t + 6, NULL)))
            fuzz_fail("transfer '%s' read as %d (gamma %g)", t, (int)s->transfer, s->gamma);
    } else if (s->transfer != default_transfer(s))
        fuzz_fail("transfer %d, none given, for %d-bit %s images", (int)s->transfer, s->bits,
                  s->is_float ? "float" : "integer");
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "black_level")))
        same_number(v, s->black_level, "black level", -1);
    else if (s->black_level != 0.0)
        fuzz_fail("black level %g, none given", s->black_level);
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "saturation")))
        same_number(v, s->saturation, "saturation", -1);
    else if (s->saturation != (s->is_float ? INFINITY : 1.0))
        fuzz_fail("saturation %g, none given, for %s images", s->saturation, s->is_float ? "float" : "integer");
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "scale"))) {
        if (cJSON_IsString(v) ? s->scale != 0.0 : (same_number(v, s->scale, "scale", -1), 0))
            fuzz_fail("scale \"auto\" read as %g", s->scale);
    } else if (s->scale != 1.0)
        fuzz_fail("scale %g, none given", s->scale);
    cJSON_Delete(root);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    make_images();
    const char *path = fuzz_write("stack.json", data, size);
    bf_error err;
    bf_stack *s = NULL;
    int rc = bf_stack_read(path, &s, &err);
    fuzz_check_result(rc, &err, s);
    if (s) {
        if (strcmp(s->path, path) != 0)
            fuzz_fail("a stack read from %s says it is %s", path, s->path);
        check_stack(s);
        /* The reader refuses NUL bytes: what it read is the whole input. */
        char *text = malloc(size + 1);
        if (!text)
            fuzz_fail("out of memory");
        memcpy(text, data, size);
        text[size] = '\0';
        check_json(s, text);
        free(text);
    }
    bf_stack_free(s);
    return 0;
}

#endif
