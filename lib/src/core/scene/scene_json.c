/* Scene files (JSON, via cJSON): ranges of incidence and view angles, explicit light and
 * view directions with weights, kernel radius, reciprocity (format in scene.h).
 *
 * cJSON keeps no positions, so every error is located by walking the (already valid)
 * text along the same path as the parsed tree: the line reported is the one holding the
 * offending value, even when the same key ("theta", "weight") appears many times. */
#include "brdfit/scene.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/json_keys.h"
#include "io/json_pos.h"
#include "io/read_text.h"

/* ---- Positions in the text (io/json_pos.h) ---------------------------------------- */

/* The value (or the key, with want_key) of member key of the object at p; p itself when
 * absent, so that an error still points somewhere sensible. */
static const char *member_at(const char *p, const char *key, int want_key)
{
    const char *v = bf_json_member(p, key, strlen(key), want_key);
    return v ? v : p;
}

static const char *element_at(const char *p, int k)
{
    const char *v = bf_json_element(p, k);
    return v ? v : p;
}

/* ---- Parsing -------------------------------------------------------------------- */

typedef struct ctx {
    const char *text, *path;
    bf_error *err;
} ctx;

#if defined(__GNUC__)
__attribute__((format(printf, 4, 5)))
#endif
static bf_status
fail_at(const ctx *c, const char *pos, bf_status code, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return bf_fail(c->err, code, "%s:%zu: %s", c->path, (size_t)bf_json_line(c->text, pos), msg);
}

/* Every member of obj must be one of names (a NULL-terminated list). */
static bf_status check_keys(const ctx *c, const cJSON *obj, const char *at, const char *where, const char *const *names,
                            const char *list)
{
    const cJSON *m;
    cJSON_ArrayForEach(m, obj)
    {
        int known = 0;
        for (int k = 0; names[k]; k++)
            known |= strcmp(m->string, names[k]) == 0;
        if (!known)
            return fail_at(c, member_at(at, m->string, 1), BF_ERR_PARSE, "%sunknown key \"%s\" (expected %s)", where,
                           m->string, list);
    }
    const char *key;
    int found = bf_json_repeated_key(obj, &key);
    if (found < 0)
        return bf_fail(c->err, BF_ERR_NOMEM, "%s: out of memory", c->path);
    if (found > 0)
        return fail_at(c, member_at(at, key, 1), BF_ERR_PARSE, "%s\"%s\" given twice", where, key);
    return BF_OK;
}

static bf_status number(const ctx *c, const cJSON *v, const char *pos, const char *name, double *out)
{
    if (!cJSON_IsNumber(v))
        return fail_at(c, pos, BF_ERR_PARSE, "%s must be a number", name);
    if (!isfinite(v->valuedouble))
        return fail_at(c, pos, BF_ERR_RANGE, "%s is not finite", name);
    *out = v->valuedouble;
    return BF_OK;
}

static bf_status polar(const ctx *c, const cJSON *v, const char *pos, const char *name, double *out)
{
    bf_status rc = number(c, v, pos, name, out);
    if (rc == BF_OK && !(*out >= 0.0 && *out <= 90.0))
        return fail_at(c, pos, BF_ERR_RANGE, "%s = %g degrees is outside [0, 90]", name, *out);
    return rc;
}

/* "light"/"view": {"theta": [lo, hi]}. */
static bf_status parse_range(const ctx *c, const cJSON *obj, const char *at, const char *name, bf_range *r)
{
    static const char *const keys[] = {"theta", NULL};
    char where[64];
    if (!cJSON_IsObject(obj))
        return fail_at(c, at, BF_ERR_PARSE, "\"%s\" must be an object like {\"theta\": [0, 60]}", name);
    snprintf(where, sizeof where, "\"%s\": ", name);
    bf_status rc = check_keys(c, obj, at, where, keys, "\"theta\"");
    if (rc != BF_OK)
        return rc;
    const cJSON *th = cJSON_GetObjectItemCaseSensitive(obj, "theta");
    if (!th)
        return BF_OK;
    const char *tat = member_at(at, "theta", 0);
    if (!cJSON_IsArray(th) || cJSON_GetArraySize(th) != 2)
        return fail_at(c, tat, BF_ERR_PARSE, "%s.theta must be [lo, hi] in degrees", name);
    char lo_name[64], hi_name[64];
    snprintf(lo_name, sizeof lo_name, "%s.theta lower bound", name);
    snprintf(hi_name, sizeof hi_name, "%s.theta upper bound", name);
    if ((rc = polar(c, cJSON_GetArrayItem(th, 0), element_at(tat, 0), lo_name, &r->lo)) != BF_OK ||
        (rc = polar(c, cJSON_GetArrayItem(th, 1), element_at(tat, 1), hi_name, &r->hi)) != BF_OK)
        return rc;
    if (r->lo > r->hi)
        return fail_at(c, tat, BF_ERR_RANGE, "%s.theta: lower bound %g > upper bound %g", name, r->lo, r->hi);
    return BF_OK;
}

/* "lights"/"views": [{"theta": T, "phi": P, "weight": W}, ...]; theta required. */
static bf_status parse_dirs(const ctx *c, const cJSON *arr, const char *at, const char *name, bf_scene_dir **out,
                            int *n)
{
    static const char *const keys[] = {"theta", "phi", "weight", NULL};
    if (!cJSON_IsArray(arr))
        return fail_at(c, at, BF_ERR_PARSE, "\"%s\" must be an array of {\"theta\", \"phi\", \"weight\"} objects",
                       name);
    int count = cJSON_GetArraySize(arr);
    if (count == 0)
        return fail_at(c, at, BF_ERR_PARSE, "\"%s\" is empty (leave it out to accept every direction)", name);
    if (!(*out = calloc((size_t)count, sizeof **out)))
        return bf_fail(c->err, BF_ERR_NOMEM, "%s: out of memory", c->path);
    *n = count;
    int k = 0;
    const cJSON *e;
    cJSON_ArrayForEach(e, arr)
    {
        const char *eat = element_at(at, k);
        char where[64], field[80];
        snprintf(where, sizeof where, "%s[%d]: ", name, k);
        if (!cJSON_IsObject(e))
            return fail_at(c, eat, BF_ERR_PARSE, "%s[%d] must be an object like {\"theta\": 30, \"phi\": 0}", name, k);
        bf_status rc = check_keys(c, e, eat, where, keys, "theta, phi, weight");
        if (rc != BF_OK)
            return rc;
        bf_scene_dir *d = &(*out)[k];
        d->weight = 1.0;
        const cJSON *th = cJSON_GetObjectItemCaseSensitive(e, "theta");
        if (!th)
            return fail_at(c, eat, BF_ERR_PARSE, "%s[%d] has no \"theta\"", name, k);
        snprintf(field, sizeof field, "%s[%d].theta", name, k);
        if ((rc = polar(c, th, member_at(eat, "theta", 0), field, &d->theta)) != BF_OK)
            return rc;
        const cJSON *ph = cJSON_GetObjectItemCaseSensitive(e, "phi");
        snprintf(field, sizeof field, "%s[%d].phi", name, k);
        if (ph && (rc = number(c, ph, member_at(eat, "phi", 0), field, &d->phi)) != BF_OK)
            return rc;
        const cJSON *w = cJSON_GetObjectItemCaseSensitive(e, "weight");
        snprintf(field, sizeof field, "%s[%d].weight", name, k);
        if (w) {
            const char *wat = member_at(eat, "weight", 0);
            if ((rc = number(c, w, wat, field, &d->weight)) != BF_OK)
                return rc;
            if (!(d->weight > 0.0))
                return fail_at(c, wat, BF_ERR_RANGE, "%s = %g must be > 0", field, d->weight);
        }
        k++;
    }
    return BF_OK;
}

static bf_status parse_root(const ctx *c, const cJSON *root, bf_scene *sc)
{
    static const char *const keys[] = {"description", "light", "view", "lights", "views", "radius", "reciprocal", NULL};
    const char *at = bf_json_skip_ws(c->text);
    if (!cJSON_IsObject(root))
        return fail_at(c, at, BF_ERR_PARSE, "a scene must be a JSON object");
    bf_status rc = check_keys(c, root, at, "", keys, "description, light, view, lights, views, radius, reciprocal");
    if (rc != BF_OK)
        return rc;
    const cJSON *v;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "description"))) {
        if (!cJSON_IsString(v))
            return fail_at(c, member_at(at, "description", 0), BF_ERR_PARSE, "\"description\" must be a string");
        if (!(sc->description = strdup(v->valuestring)))
            return bf_fail(c->err, BF_ERR_NOMEM, "%s: out of memory", c->path);
    }
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "light")) &&
        (rc = parse_range(c, v, member_at(at, "light", 0), "light", &sc->light_theta)) != BF_OK)
        return rc;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "view")) &&
        (rc = parse_range(c, v, member_at(at, "view", 0), "view", &sc->view_theta)) != BF_OK)
        return rc;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "lights")) &&
        (rc = parse_dirs(c, v, member_at(at, "lights", 0), "lights", &sc->lights, &sc->nlights)) != BF_OK)
        return rc;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "views")) &&
        (rc = parse_dirs(c, v, member_at(at, "views", 0), "views", &sc->views, &sc->nviews)) != BF_OK)
        return rc;
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "radius"))) {
        const char *rat = member_at(at, "radius", 0);
        if ((rc = number(c, v, rat, "\"radius\"", &sc->radius)) != BF_OK)
            return rc;
        if (!(sc->radius > 0.0 && sc->radius <= 180.0))
            return fail_at(c, rat, BF_ERR_RANGE, "\"radius\" = %g degrees must be in (0, 180]", sc->radius);
    }
    if ((v = cJSON_GetObjectItemCaseSensitive(root, "reciprocal"))) {
        if (!cJSON_IsBool(v))
            return fail_at(c, member_at(at, "reciprocal", 0), BF_ERR_PARSE, "\"reciprocal\" must be true or false");
        sc->reciprocal = cJSON_IsTrue(v);
    }
    return BF_OK;
}

bf_status bf_scene_parse(const char *text, const char *path, bf_scene **out, bf_error *err)
{
    *out = NULL;
    if (!path)
        path = "(scene)";
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithOpts(text, &end, 1);
    if (!root)
        return bf_json_parse_failure(text, end, path, err);
    bf_scene *sc = calloc(1, sizeof *sc);
    if (!sc) {
        cJSON_Delete(root);
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
    }
    sc->light_theta = (bf_range){0.0, 90.0};
    sc->view_theta = (bf_range){0.0, 90.0};
    sc->radius = 5.0;
    sc->reciprocal = 1;
    ctx c = {text, path, err};
    bf_status rc = parse_root(&c, root, sc);
    cJSON_Delete(root);
    if (rc != BF_OK) {
        bf_scene_free(sc);
        return rc;
    }
    *out = sc;
    return BF_OK;
}

bf_status bf_scene_read(const char *path, bf_scene **out, bf_error *err)
{
    *out = NULL;
    size_t n;
    char *buf;
    bf_status rc = bf_read_text(path, &buf, &n, err);
    if (rc != BF_OK)
        return rc;
    rc = bf_scene_parse(buf, path, out, err);
    free(buf);
    return rc;
}

void bf_scene_free(bf_scene *sc)
{
    if (!sc)
        return;
    free(sc->description);
    free(sc->lights);
    free(sc->views);
    free(sc);
}
