/* Reading a stack (photo.h): a DiLiGenT folder as it is, or a JSON stack file
 * (docs/images.md), then the header of every image and of the mask, so that a stack
 * whose files disagree fails before any pixel is read. */
#include "brdfit/photo.h"

#include <cjson/cJSON.h>
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "brdfit/image.h"
#include "io/json_keys.h"
#include "io/json_pos.h"
#include "io/read_text.h"

#define UNIT_TOLERANCE 1e-3 /* |length - 1| allowed of a light direction */

void bf_stack_free(bf_stack *s)
{
    if (!s)
        return;
    for (int k = 0; k < s->nimages; k++)
        free(s->images[k].file);
    free(s->images);
    free(s->mask);
    free(s->path);
    free(s);
}

/* folder/name, or name itself when it is absolute. */
static char *join(const char *folder, const char *name)
{
    if (name[0] == '/' || !folder[0])
        return strdup(name);
    size_t n = strlen(folder) + strlen(name) + 2;
    char *p = malloc(n);
    if (p)
        snprintf(p, n, "%s/%s", folder, name);
    return p;
}

static char *folder_of(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? strndup(path, (size_t)(slash - path) + (slash == path)) : strdup("");
}

static bf_stack *stack_new(const char *path, bf_stack_layout layout, int n)
{
    bf_stack *s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->path = strdup(path);
    s->layout = layout;
    s->images = calloc((size_t)(n > 0 ? n : 1), sizeof *s->images);
    s->nimages = n;
    s->camera.type = BF_CAMERA_ORTHOGRAPHIC;
    s->camera.pixel_size = 1.0;
    s->camera.rotation[0] = s->camera.rotation[4] = s->camera.rotation[8] = 1.0;
    s->camera.position[2] = 1.0;
    s->saturation = NAN; /* the format's default, set once the images are known */
    s->scale = 1.0;
    if (!s->path || !s->images) {
        bf_stack_free(s);
        return NULL;
    }
    for (int k = 0; k < n; k++) {
        s->images[k].exposure = 1.0;
        for (int c = 0; c < 3; c++)
            s->images[k].intensity[c] = 1.0;
    }
    return s;
}

/* ---- the DiLiGenT folder ---- */

/* The non-blank lines of a text file, each cut at its end (text modified in place). */
typedef struct lines {
    char *text;
    char **line;
    int *number; /* 1-based line numbers */
    int n;
} lines;

static void lines_free(lines *l)
{
    free(l->text);
    free(l->line);
    free(l->number);
    memset(l, 0, sizeof *l);
}

static bf_status lines_read(const char *path, lines *l, bf_error *err)
{
    memset(l, 0, sizeof *l);
    size_t len;
    bf_status rc = bf_read_text(path, &l->text, &len, err);
    if (rc != BF_OK)
        return rc;
    size_t cap = 16;
    l->line = malloc(cap * sizeof *l->line);
    l->number = malloc(cap * sizeof *l->number);
    int no = 0;
    for (char *p = l->text; l->line && l->number && *p;) {
        char *e = p + strcspn(p, "\n");
        int last = *e == '\0';
        *e = '\0';
        no++;
        char *t = e;
        while (t > p && isspace((unsigned char)t[-1]))
            *--t = '\0';
        while (isspace((unsigned char)*p))
            p++;
        if (*p) {
            if ((size_t)l->n == cap) {
                cap *= 2;
                char **nl = realloc(l->line, cap * sizeof *nl);
                int *nn = nl ? realloc(l->number, cap * sizeof *nn) : NULL;
                if (nl)
                    l->line = nl;
                if (!nn)
                    break;
                l->number = nn;
            }
            l->line[l->n] = p;
            l->number[l->n++] = no;
        }
        p = last ? e : e + 1;
    }
    if (!l->line || !l->number || (size_t)l->n > cap) {
        lines_free(l);
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
    }
    return BF_OK;
}

/* Three finite numbers and nothing else on a line. */
static bf_status three_numbers(const char *path, const lines *l, int i, double v[3], bf_error *err)
{
    const char *p = l->line[i];
    for (int c = 0; c < 3; c++) {
        char *end;
        errno = 0;
        v[c] = strtod(p, &end);
        if (end == p)
            return bf_fail(err, BF_ERR_PARSE, "%s:%d: expected 3 numbers, found %d", path, l->number[i], c);
        if (!isfinite(v[c]))
            return bf_fail(err, BF_ERR_RANGE, "%s:%d: not a finite number", path, l->number[i]);
        p = end;
        while (*p == ',' || isspace((unsigned char)*p))
            p++;
    }
    if (*p)
        return bf_fail(err, BF_ERR_PARSE, "%s:%d: more than 3 numbers", path, l->number[i]);
    return BF_OK;
}

static bf_status check_unit(const char *where, int line, const double d[3], bf_error *err)
{
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(fabs(len - 1.0) <= UNIT_TOLERANCE))
        return line > 0
                   ? bf_fail(err, BF_ERR_RANGE, "%s:%d: light direction is not a unit vector (length %.6g)", where,
                             line, len)
                   : bf_fail(err, BF_ERR_RANGE, "%s: light direction is not a unit vector (length %.6g)", where, len);
    return BF_OK;
}

static bf_status read_diligent(const char *dir, bf_stack **out, bf_error *err)
{
    char *names = join(dir, "filenames.txt"), *dirs = join(dir, "light_directions.txt"),
         *ints = join(dir, "light_intensities.txt"), *mask = join(dir, "mask.png");
    lines ln = {0}, ld = {0}, li = {0};
    bf_stack *s = NULL;
    bf_status rc = BF_OK;
    if (!names || !dirs || !ints || !mask)
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", dir);
    if (rc == BF_OK)
        rc = lines_read(names, &ln, err);
    if (rc == BF_OK)
        rc = lines_read(dirs, &ld, err);
    if (rc == BF_OK)
        rc = lines_read(ints, &li, err);
    if (rc == BF_OK && ld.n != ln.n)
        rc = bf_fail(err, BF_ERR_PARSE, "%s: %d light directions for %d images (%s)", dirs, ld.n, ln.n, names);
    if (rc == BF_OK && li.n != ln.n)
        rc = bf_fail(err, BF_ERR_PARSE, "%s: %d light intensities for %d images (%s)", ints, li.n, ln.n, names);
    if (rc == BF_OK && !(s = stack_new(dir, BF_STACK_DILIGENT, ln.n)))
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", dir);
    for (int k = 0; rc == BF_OK && k < ln.n; k++) {
        bf_stack_image *im = &s->images[k];
        if (!(im->file = join(dir, ln.line[k])))
            rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", dir);
        if (rc == BF_OK && (rc = three_numbers(dirs, &ld, k, im->dir, err)) == BF_OK)
            rc = check_unit(dirs, ld.number[k], im->dir, err);
        if (rc == BF_OK && (rc = three_numbers(ints, &li, k, im->intensity, err)) == BF_OK)
            for (int c = 0; c < 3 && rc == BF_OK; c++)
                if (!(im->intensity[c] > 0.0))
                    rc = bf_fail(err, BF_ERR_RANGE, "%s:%d: light intensity %g is not positive", ints, li.number[k],
                                 im->intensity[c]);
    }
    struct stat st;
    if (rc == BF_OK && stat(mask, &st) == 0) {
        s->mask = mask;
        mask = NULL;
    }
    if (rc == BF_OK)
        s->scale = 0.0; /* relative intensities: automatic */
    lines_free(&ln);
    lines_free(&ld);
    lines_free(&li);
    free(names);
    free(dirs);
    free(ints);
    free(mask);
    if (rc != BF_OK) {
        bf_stack_free(s);
        return rc;
    }
    *out = s;
    return BF_OK;
}

/* ---- the JSON stack file ---- */

typedef struct jctx {
    const char *text, *path;
    bf_error *err;
} jctx;

__attribute__((format(printf, 4, 5))) static bf_status jfail(const jctx *c, bf_status code, const char *at,
                                                             const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return bf_fail(c->err, code, "%s:%d: %s: %s", c->path, bf_json_line_of_path(c->text, at), at, msg);
}

static bf_status jnumber(const jctx *c, const cJSON *v, const char *at, double *out)
{
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble))
        return jfail(c, BF_ERR_PARSE, at, "expected a finite number");
    *out = v->valuedouble;
    return BF_OK;
}

static bf_status jvector(const jctx *c, const cJSON *v, const char *at, int n, double *out)
{
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != n)
        return jfail(c, BF_ERR_PARSE, at, "expected an array of %d numbers", n);
    for (int i = 0; i < n; i++) {
        const cJSON *e = cJSON_GetArrayItem(v, i);
        if (!cJSON_IsNumber(e) || !isfinite(e->valuedouble))
            return jfail(c, BF_ERR_PARSE, at, "element %d is not a finite number", i);
        out[i] = e->valuedouble;
    }
    return BF_OK;
}

/* Checks that obj has only the named members, none twice. */
static bf_status jmembers(const jctx *c, const cJSON *obj, const char *at, const char *const *known)
{
    if (!cJSON_IsObject(obj))
        return jfail(c, BF_ERR_PARSE, at, "expected an object");
    const char *dup;
    if (bf_json_repeated_key(obj, &dup) == 1)
        return jfail(c, BF_ERR_PARSE, at, "'%s' given twice", dup);
    for (const cJSON *m = obj->child; m; m = m->next) {
        int ok = 0;
        for (int i = 0; known[i] && !ok; i++)
            ok = !strcmp(m->string, known[i]);
        if (!ok)
            return jfail(c, BF_ERR_PARSE, at, "unknown member '%s'", m->string);
    }
    return BF_OK;
}

static bf_status parse_light(const jctx *c, const cJSON *l, const char *at, bf_stack_image *im)
{
    static const char *const known[] = {"direction", "position", "intensity", NULL};
    bf_status rc = jmembers(c, l, at, known);
    if (rc != BF_OK)
        return rc;
    char sub[96];
    const cJSON *d = cJSON_GetObjectItemCaseSensitive(l, "direction"),
                *p = cJSON_GetObjectItemCaseSensitive(l, "position"),
                *i = cJSON_GetObjectItemCaseSensitive(l, "intensity");
    if (!d == !p)
        return jfail(c, BF_ERR_PARSE, at, "give either a direction or a position");
    if (d) {
        snprintf(sub, sizeof sub, "%s/direction", at);
        if ((rc = jvector(c, d, sub, 3, im->dir)) != BF_OK)
            return rc;
        double len = sqrt(im->dir[0] * im->dir[0] + im->dir[1] * im->dir[1] + im->dir[2] * im->dir[2]);
        if (!(fabs(len - 1.0) <= UNIT_TOLERANCE))
            return jfail(c, BF_ERR_RANGE, sub, "not a unit vector (length %.6g)", len);
    } else {
        im->point = 1;
        snprintf(sub, sizeof sub, "%s/position", at);
        if ((rc = jvector(c, p, sub, 3, im->pos)) != BF_OK)
            return rc;
    }
    if (i) {
        snprintf(sub, sizeof sub, "%s/intensity", at);
        if (cJSON_IsNumber(i)) {
            if ((rc = jnumber(c, i, sub, &im->intensity[0])) != BF_OK)
                return rc;
            im->intensity[1] = im->intensity[2] = im->intensity[0];
        } else if ((rc = jvector(c, i, sub, 3, im->intensity)) != BF_OK)
            return rc;
        for (int k = 0; k < 3; k++)
            if (!(im->intensity[k] > 0.0))
                return jfail(c, BF_ERR_RANGE, sub, "intensity %g is not positive", im->intensity[k]);
    }
    return BF_OK;
}

static bf_status parse_camera(const jctx *c, const cJSON *cam, bf_stack_camera *out)
{
    static const char *const known[] = {"type", "pixel_size", "center",   "fx",       "fy",
                                        "cx",   "cy",         "rotation", "position", NULL};
    bf_status rc = jmembers(c, cam, "camera", known);
    if (rc != BF_OK)
        return rc;
    const cJSON *type = cJSON_GetObjectItemCaseSensitive(cam, "type");
    if (type &&
        (!cJSON_IsString(type) || (strcmp(type->valuestring, "orthographic") && strcmp(type->valuestring, "pinhole"))))
        return jfail(c, BF_ERR_PARSE, "camera/type", "expected \"orthographic\" or \"pinhole\"");
    out->type = type && !strcmp(type->valuestring, "pinhole") ? BF_CAMERA_PINHOLE : BF_CAMERA_ORTHOGRAPHIC;
    const cJSON *v;
    if ((v = cJSON_GetObjectItemCaseSensitive(cam, "pixel_size"))) {
        if ((rc = jnumber(c, v, "camera/pixel_size", &out->pixel_size)) != BF_OK)
            return rc;
        if (!(out->pixel_size > 0.0))
            return jfail(c, BF_ERR_RANGE, "camera/pixel_size", "must be positive");
    }
    if ((v = cJSON_GetObjectItemCaseSensitive(cam, "center")) &&
        (rc = jvector(c, v, "camera/center", 3, out->center)) != BF_OK)
        return rc;
    if ((v = cJSON_GetObjectItemCaseSensitive(cam, "position")) &&
        (rc = jvector(c, v, "camera/position", 3, out->position)) != BF_OK)
        return rc;
    if ((v = cJSON_GetObjectItemCaseSensitive(cam, "rotation"))) {
        if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 3)
            return jfail(c, BF_ERR_PARSE, "camera/rotation", "expected 3 rows of 3 numbers");
        for (int r = 0; r < 3; r++) {
            char at[32];
            snprintf(at, sizeof at, "camera/rotation/%d", r);
            if ((rc = jvector(c, cJSON_GetArrayItem(v, r), at, 3, out->rotation + 3 * r)) != BF_OK)
                return rc;
        }
        /* A rotation: R R' = I within a tolerance. */
        const double *R = out->rotation;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double d = R[3 * i] * R[3 * j] + R[3 * i + 1] * R[3 * j + 1] + R[3 * i + 2] * R[3 * j + 2];
                if (fabs(d - (i == j)) > 1e-3)
                    return jfail(c, BF_ERR_RANGE, "camera/rotation", "not a rotation matrix");
            }
    }
    static const char *const intr[] = {"fx", "fy", "cx", "cy"};
    double *dst[] = {&out->fx, &out->fy, &out->cx, &out->cy};
    for (int k = 0; k < 4; k++) {
        char at[32];
        snprintf(at, sizeof at, "camera/%s", intr[k]);
        v = cJSON_GetObjectItemCaseSensitive(cam, intr[k]);
        if (out->type == BF_CAMERA_PINHOLE && !v)
            return jfail(c, BF_ERR_PARSE, "camera", "a pinhole camera needs %s", intr[k]);
        if (v && (rc = jnumber(c, v, at, dst[k])) != BF_OK)
            return rc;
    }
    if (out->type == BF_CAMERA_PINHOLE && !(out->fx > 0.0 && out->fy > 0.0))
        return jfail(c, BF_ERR_RANGE, "camera", "fx and fy must be positive");
    return BF_OK;
}

static bf_status parse_transfer(const jctx *c, const cJSON *t, bf_stack *s)
{
    if (!cJSON_IsString(t))
        return jfail(c, BF_ERR_PARSE, "transfer", "expected \"linear\", \"srgb\" or \"gamma G\"");
    const char *v = t->valuestring;
    if (!strcmp(v, "linear"))
        s->transfer = BF_TRANSFER_LINEAR;
    else if (!strcmp(v, "srgb"))
        s->transfer = BF_TRANSFER_SRGB;
    else if (!strncmp(v, "gamma ", 6)) {
        char *end;
        s->gamma = strtod(v + 6, &end);
        if (end == v + 6 || *end || !(s->gamma > 0.0 && s->gamma < 10.0))
            return jfail(c, BF_ERR_RANGE, "transfer", "bad gamma in '%s'", v);
        s->transfer = BF_TRANSFER_GAMMA;
    } else
        return jfail(c, BF_ERR_PARSE, "transfer", "'%s' is not \"linear\", \"srgb\" or \"gamma G\"", v);
    return BF_OK;
}

static bf_status parse_root(const jctx *c, const cJSON *root, const char *folder, bf_stack *s, int *transfer_given)
{
    static const char *const known[] = {"images",      "camera",     "mask",  "transfer",
                                        "black_level", "saturation", "scale", NULL};
    static const char *const image_known[] = {"file", "light", "exposure", NULL};
    bf_status rc = jmembers(c, root, "", known);
    if (rc != BF_OK)
        return rc;
    const cJSON *images = cJSON_GetObjectItemCaseSensitive(root, "images");
    for (int k = 0; k < s->nimages && rc == BF_OK; k++) {
        char at[64];
        snprintf(at, sizeof at, "images/%d", k);
        const cJSON *im = cJSON_GetArrayItem(images, k);
        if ((rc = jmembers(c, im, at, image_known)) != BF_OK)
            break;
        const cJSON *f = cJSON_GetObjectItemCaseSensitive(im, "file"),
                    *l = cJSON_GetObjectItemCaseSensitive(im, "light"),
                    *e = cJSON_GetObjectItemCaseSensitive(im, "exposure");
        if (!cJSON_IsString(f) || !f->valuestring[0])
            rc = jfail(c, BF_ERR_PARSE, at, "needs a \"file\" name");
        else if (!(s->images[k].file = join(folder, f->valuestring)))
            rc = bf_fail(c->err, BF_ERR_NOMEM, "%s: out of memory", c->path);
        else if (!l)
            rc = jfail(c, BF_ERR_PARSE, at, "needs a \"light\"");
        else {
            char sub[80];
            snprintf(sub, sizeof sub, "%s/light", at);
            rc = parse_light(c, l, sub, &s->images[k]);
        }
        if (rc == BF_OK && e) {
            snprintf(at + strlen(at), sizeof at - strlen(at), "/exposure");
            if ((rc = jnumber(c, e, at, &s->images[k].exposure)) == BF_OK && !(s->images[k].exposure > 0.0))
                rc = jfail(c, BF_ERR_RANGE, at, "must be positive");
        }
    }
    const cJSON *v;
    if (rc == BF_OK && (v = cJSON_GetObjectItemCaseSensitive(root, "camera")))
        rc = parse_camera(c, v, &s->camera);
    if (rc == BF_OK && (v = cJSON_GetObjectItemCaseSensitive(root, "mask"))) {
        if (!cJSON_IsString(v) || !v->valuestring[0])
            rc = jfail(c, BF_ERR_PARSE, "mask", "expected a file name");
        else if (!(s->mask = join(folder, v->valuestring)))
            rc = bf_fail(c->err, BF_ERR_NOMEM, "%s: out of memory", c->path);
    }
    if (rc == BF_OK && (v = cJSON_GetObjectItemCaseSensitive(root, "transfer"))) {
        rc = parse_transfer(c, v, s);
        *transfer_given = 1;
    }
    if (rc == BF_OK && (v = cJSON_GetObjectItemCaseSensitive(root, "black_level")))
        rc = jnumber(c, v, "black_level", &s->black_level);
    if (rc == BF_OK && (v = cJSON_GetObjectItemCaseSensitive(root, "saturation")))
        rc = jnumber(c, v, "saturation", &s->saturation);
    if (rc == BF_OK && (v = cJSON_GetObjectItemCaseSensitive(root, "scale"))) {
        if (cJSON_IsString(v) && !strcmp(v->valuestring, "auto"))
            s->scale = 0.0;
        else if ((rc = jnumber(c, v, "scale", &s->scale)) == BF_OK && !(s->scale > 0.0))
            rc = jfail(c, BF_ERR_RANGE, "scale", "must be positive or \"auto\"");
    }
    return rc;
}

static bf_status read_json(const char *path, bf_stack **out, int *transfer_given, bf_error *err)
{
    char *text = NULL;
    size_t len;
    bf_status rc = bf_read_text(path, &text, &len, err);
    if (rc != BF_OK)
        return rc;
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithOpts(text, &end, 1);
    if (!root) {
        rc = bf_json_parse_failure(text, end, path, err);
        free(text);
        return rc;
    }
    jctx c = {text, path, err};
    const cJSON *images = cJSON_GetObjectItemCaseSensitive(root, "images");
    int n = cJSON_IsArray(images) ? cJSON_GetArraySize(images) : -1;
    bf_stack *s = NULL;
    char *folder = folder_of(path);
    if (!cJSON_IsObject(root))
        rc = bf_fail(err, BF_ERR_PARSE, "%s:1: a stack file is a JSON object", path);
    else if (n < 0)
        rc = jfail(&c, BF_ERR_PARSE, "images", "expected an array of images");
    else if (!folder || !(s = stack_new(path, BF_STACK_JSON, n)))
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
    else
        rc = parse_root(&c, root, folder, s, transfer_given);
    cJSON_Delete(root);
    free(text);
    free(folder);
    if (rc != BF_OK) {
        bf_stack_free(s);
        return rc;
    }
    *out = s;
    return BF_OK;
}

/* Every image's header (and the mask's) against the first image's. */
static bf_status check_images(bf_stack *s, int transfer_given, bf_error *err)
{
    if (s->nimages < 3)
        return bf_fail(err, BF_ERR_PARSE, "%s: %d images: a stack needs at least 3", s->path, s->nimages);
    for (int k = 0; k < s->nimages; k++) {
        bf_image_spec sp;
        bf_image_spec_init(&sp);
        bf_status rc = bf_image_info(s->images[k].file, &sp, err);
        if (rc != BF_OK)
            return rc;
        if (sp.channels != 1 && sp.channels != 3 && sp.channels != 4)
            return bf_fail(err, BF_ERR_PARSE, "%s: %d channels (a stack's images have 1 or 3, or RGBA)",
                           s->images[k].file, sp.channels);
        int ch = sp.channels == 1 ? 1 : 3;
        if (k == 0) {
            s->width = sp.width;
            s->height = sp.height;
            s->channels = ch;
            s->bits = sp.bits;
            s->is_float = sp.is_float;
        } else if (sp.width != s->width || sp.height != s->height)
            return bf_fail(err, BF_ERR_PARSE, "%s: %dx%d pixels, but %s has %dx%d", s->images[k].file, sp.width,
                           sp.height, s->images[0].file, s->width, s->height);
        else if (ch != s->channels)
            return bf_fail(err, BF_ERR_PARSE, "%s: %d channels, but %s has %d", s->images[k].file, sp.channels,
                           s->images[0].file, s->channels);
        else if (sp.is_float != s->is_float || sp.bits != s->bits)
            return bf_fail(err, BF_ERR_PARSE, "%s: %d-bit %s, but %s is %d-bit %s", s->images[k].file, sp.bits,
                           sp.is_float ? "float" : "integer", s->images[0].file, s->bits,
                           s->is_float ? "float" : "integer");
    }
    if (s->mask) {
        bf_image_spec sp;
        bf_image_spec_init(&sp);
        bf_status rc = bf_image_info(s->mask, &sp, err);
        if (rc != BF_OK)
            return rc;
        if (sp.width != s->width || sp.height != s->height)
            return bf_fail(err, BF_ERR_PARSE, "%s: the mask has %dx%d pixels, the images %dx%d", s->mask, sp.width,
                           sp.height, s->width, s->height);
    }
    if (!transfer_given)
        s->transfer = !s->is_float && s->bits <= 8 ? BF_TRANSFER_SRGB : BF_TRANSFER_LINEAR;
    if (isnan(s->saturation))
        s->saturation = s->is_float ? INFINITY : 1.0;
    if (!(s->saturation > s->black_level))
        return bf_fail(err, BF_ERR_RANGE, "%s: saturation %g is not above the black level %g", s->path, s->saturation,
                       s->black_level);
    return BF_OK;
}

bf_status bf_stack_read(const char *path, bf_stack **out, bf_error *err)
{
    *out = NULL;
    if (!path || !*path)
        return bf_fail(err, BF_ERR_ARG, "stack: empty name");
    struct stat st;
    if (stat(path, &st) != 0)
        return bf_fail(err, BF_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    bf_stack *s = NULL;
    int transfer_given = 0;
    bf_status rc = S_ISDIR(st.st_mode) ? read_diligent(path, &s, err) : read_json(path, &s, &transfer_given, err);
    if (rc == BF_OK && s->layout == BF_STACK_DILIGENT)
        transfer_given = 1; /* DiLiGenT codes are linear */
    if (rc == BF_OK && (rc = check_images(s, transfer_given, err)) != BF_OK) {
        bf_stack_free(s);
        return rc;
    }
    *out = s;
    return rc;
}
