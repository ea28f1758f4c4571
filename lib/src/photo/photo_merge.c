/* bf_photo_merge (photo.h): the outputs of `fit-images --tile I/N` runs put together.
 * Every tile starts from the same whole-image subsample (photo_fit.c), so its pixels are
 * fitted exactly as in a run of the whole image; the merge copies each tile's rows of
 * every map, adds the counts and the relit errors' sums (RMS x RMS x samples per image),
 * and writes the whole through bf_photo_write, previews included. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/image.h"
#include "io/read_text.h"
#include "photo_impl.h"

typedef struct tile {
    char *dir;
    cJSON *json;
    int index, count, y0, y1;
} tile;

static const cJSON *get(const cJSON *o, const char *path)
{
    char buf[128];
    snprintf(buf, sizeof buf, "%s", path);
    const cJSON *v = o;
    for (char *save = NULL, *t = strtok_r(buf, "/", &save); t && v; t = strtok_r(NULL, "/", &save))
        v = cJSON_GetObjectItemCaseSensitive(v, t);
    return v;
}

static double num(const cJSON *o, const char *path, double def)
{
    const cJSON *v = get(o, path);
    return cJSON_IsNumber(v) ? v->valuedouble : def;
}

static const char *str(const cJSON *o, const char *path)
{
    const cJSON *v = get(o, path);
    return cJSON_IsString(v) ? v->valuestring : NULL;
}

static bf_status read_tile(const char *dir, tile *t, bf_error *err)
{
    memset(t, 0, sizeof *t);
    char path[4200], *text = NULL;
    size_t len;
    snprintf(path, sizeof path, "%s/fit.json", dir);
    bf_status rc = bf_read_text(path, &text, &len, err);
    if (rc != BF_OK)
        return rc;
    t->json = cJSON_Parse(text);
    free(text);
    if (!t->json)
        return bf_fail(err, BF_ERR_PARSE, "%s: not a fit-images summary (malformed JSON)", path);
    t->dir = strdup(dir);
    t->index = (int)num(t->json, "options/tile/index", 0);
    t->count = (int)num(t->json, "options/tile/count", 0);
    t->y0 = (int)num(t->json, "options/tile/rows_from", -1);
    t->y1 = (int)num(t->json, "options/tile/rows_to", -1);
    if (!t->dir || !t->count || t->y0 < 0 || t->y1 <= t->y0 || !str(t->json, "spec") || !str(t->json, "stack/path"))
        return bf_fail(err, BF_ERR_PARSE, "%s: not the output of a fit-images --tile run", path);
    return BF_OK;
}

/* Rows [y0, y1) of the image dir/name into dst (width*height*ch, the whole image). */
static bf_status copy_rows(const tile *t, const char *name, int W, int H, int ch, float *dst, bf_error *err)
{
    char path[4200];
    snprintf(path, sizeof path, "%s/%s", t->dir, name);
    bf_image img;
    bf_image_init(&img);
    bf_status rc = bf_image_read(path, &img, err);
    if (rc != BF_OK)
        return rc;
    if (img.width != W || img.height != H || img.channels < ch) {
        bf_image_clear(&img);
        return bf_fail(err, BF_ERR_PARSE, "%s: %dx%d pixels of %d channels, expected %dx%d of %d", path, img.width,
                       img.height, img.channels, W, H, ch);
    }
    for (size_t y = (size_t)t->y0; y < (size_t)t->y1; y++)
        for (size_t x = 0; x < (size_t)W; x++)
            for (int c = 0; c < ch; c++)
                dst[(y * (size_t)W + x) * (size_t)ch + (size_t)c] =
                    img.pixels[(y * (size_t)W + x) * (size_t)img.channels + (size_t)c];
    bf_image_clear(&img);
    return BF_OK;
}

/* The minimal stack and options the writer needs, from the first tile's summary. */
static bf_status describe(const tile *t, bf_stack *s, bf_photo_options *o, bf_error *err)
{
    const cJSON *j = t->json, *per = get(j, "relit_error/per_image");
    memset(s, 0, sizeof *s);
    s->path = strdup(str(j, "stack/path"));
    s->layout =
        str(j, "stack/layout") && !strcmp(str(j, "stack/layout"), "diligent") ? BF_STACK_DILIGENT : BF_STACK_JSON;
    s->width = (int)num(j, "stack/width", 0);
    s->height = (int)num(j, "stack/height", 0);
    s->nimages = (int)num(j, "stack/images", 0);
    s->channels = (int)num(j, "channels", 0);
    if (!s->path || s->width <= 0 || s->height <= 0 || s->nimages <= 0 || (s->channels != 1 && s->channels != 3) ||
        cJSON_GetArraySize(per) != s->nimages)
        return bf_fail(err, BF_ERR_PARSE, "%s/fit.json: incomplete stack description", t->dir);
    if (!(s->images = calloc((size_t)s->nimages, sizeof *s->images)))
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    for (int k = 0; k < s->nimages; k++) {
        const char *f = str(cJSON_GetArrayItem(per, k), "file");
        s->images[k].file = strdup(f ? f : "");
    }
    bf_photo_options_init(o);
    const char *nm = str(j, "options/normals");
    o->normals = nm && !strcmp(nm, "flat")   ? BF_NORMALS_FLAT
                 : nm && !strcmp(nm, "file") ? BF_NORMALS_FILE
                                             : BF_NORMALS_FIT;
    o->normals_file = str(j, "options/normals_file");
    o->share = str(j, "options/share");
    o->clusters = (int)num(j, "options/clusters", 1);
    o->seed = (uint64_t)num(j, "options/seed", 0);
    o->model = str(j, "spec");
    return BF_OK;
}

static int cmp_tile(const void *a, const void *b)
{
    return ((const tile *)a)->index - ((const tile *)b)->index;
}

/* One merge: the tiles (in index order), the stack and options the writer needs, the
 * whole image's result and a buffer of up to 6 channels a pixel for a map's rows. */
typedef struct merge {
    tile *t;
    int n;
    bf_stack s;
    bf_photo_options o;
    bf_photo_result *r;
    float *buf;
} merge;

static bf_status read_tiles(merge *m, const char *const *dirs, bf_error *err)
{
    for (int i = 0; i < m->n; i++) {
        bf_status rc = read_tile(dirs[i], &m->t[i], err);
        if (rc != BF_OK)
            return rc;
    }
    qsort(m->t, (size_t)m->n, sizeof *m->t, cmp_tile);
    return BF_OK;
}

/* The same run's tiles, each once, all of them. */
static bf_status check_tiles(const merge *m, bf_error *err)
{
    const tile *t = m->t;
    int n = m->n;
    for (int i = 0; i < n; i++) {
        const char *keys[] = {"spec", "stack/path", "options/normals", "options/share"};
        for (int k = 0; k < 4; k++) {
            const char *a = str(t[0].json, keys[k]), *b = str(t[i].json, keys[k]);
            if ((a == NULL) != (b == NULL) || (a && strcmp(a, b)))
                return bf_fail(err, BF_ERR_ARG, "%s: %s differs from %s's: not tiles of one run", t[i].dir, keys[k],
                               t[0].dir);
        }
        if (t[i].count != n || t[i].index != i + 1)
            return bf_fail(err, BF_ERR_ARG, "%s: tile %d/%d, but %d tile folders were given (each of 1..%d once)",
                           t[i].dir, t[i].index, t[i].count, n, t[i].count);
        if (num(t[i].json, "options/scale", NAN) != num(t[0].json, "options/scale", NAN))
            return bf_fail(err, BF_ERR_ARG, "%s: its scale differs from %s's: not tiles of one run", t[i].dir,
                           t[0].dir);
    }
    return BF_OK;
}

/* The whole image's result: its model and maps, from the first tile's summary. */
static bf_status result_maps(merge *m, bf_error *err)
{
    bf_status rc = describe(&m->t[0], &m->s, &m->o, err);
    bf_photo_result *r = m->r;
    if (rc == BF_OK)
        rc = bf_model_new(m->o.model, m->s.channels, &r->model, err);
    if (rc != BF_OK)
        return rc;
    int W = m->s.width, H = m->s.height, C = m->s.channels, K = m->s.nimages;
    size_t WH = (size_t)W * (size_t)H;
    r->width = W;
    r->height = H;
    r->channels = C;
    r->y1 = H;
    r->nimages = K;
    r->nvalues = bf_model_nvalues(r->model);
    r->scale = num(m->t[0].json, "options/scale", 1.0);
    r->nclusters = (int)num(m->t[0].json, "options/clusters", 1);
    r->mask = calloc(WH, 1);
    r->normals = calloc(WH * 3, sizeof(float));
    r->params = calloc(WH * (size_t)r->nvalues, sizeof(float));
    r->error = calloc(WH, sizeof(float));
    r->lambert_normals = calloc(WH * 3, sizeof(float));
    r->lambert_albedo = calloc(WH * (size_t)C, sizeof(float));
    r->image_rms = calloc((size_t)K, sizeof(double));
    r->image_lambert_rms = calloc((size_t)K, sizeof(double));
    r->image_samples = calloc((size_t)K, sizeof(size_t));
    if (!r->mask || !r->normals || !r->params || !r->error || !r->lambert_normals || !r->lambert_albedo ||
        !r->image_rms || !r->image_lambert_rms || !r->image_samples)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for %dx%d maps", W, H);
    return BF_OK;
}

/* Which optional maps the run wrote (clusters, relit images), and room for them and for
 * one map's rows. */
static bf_status optional_maps(merge *m, bf_error *err)
{
    bf_photo_result *r = m->r;
    int K = m->s.nimages, C = m->s.channels;
    size_t WH = (size_t)m->s.width * (size_t)m->s.height;
    const cJSON *files = get(m->t[0].json, "files");
    int has_clusters = 0;
    for (const cJSON *f = files ? files->child : NULL; f; f = f->next) {
        int idx;
        char ext[8];
        if (!cJSON_IsString(f))
            continue;
        if (!strcmp(f->valuestring, "clusters.exr"))
            has_clusters = 1;
        if (sscanf(f->valuestring, "relit_%d.%4s", &idx, ext) == 2 && !strcmp(ext, "exr") && idx >= 0 && idx < K &&
            r->nrelit < BF_PHOTO_MAX_RELIT)
            r->relit_index[r->nrelit++] = idx;
    }
    if (has_clusters && !(r->cluster = malloc(WH * sizeof *r->cluster)))
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    for (int i = 0; i < r->nrelit; i++)
        if (!(r->relit_measured[i] = calloc(WH * (size_t)C, sizeof(float))) ||
            !(r->relit_model[i] = calloc(WH * (size_t)C, sizeof(float))))
            return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    if (!(m->buf = malloc(WH * 6 * sizeof *m->buf)))
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    memset(m->buf, 0, WH * 6 * sizeof *m->buf);
    return BF_OK;
}

/* The tile's rows of the mask, the normals, the error and the Lambertian maps. */
static bf_status copy_base_maps(merge *m, const tile *ti, bf_error *err)
{
    bf_photo_result *r = m->r;
    int W = m->s.width, H = m->s.height, C = m->s.channels;
    bf_status rc;
    if ((rc = copy_rows(ti, "mask.png", W, H, 1, m->buf, err)) != BF_OK)
        return rc;
    for (size_t p = (size_t)ti->y0 * (size_t)W; p < (size_t)ti->y1 * (size_t)W; p++)
        r->mask[p] = m->buf[p] > 0.5f;
    if ((rc = copy_rows(ti, "normals.exr", W, H, 3, r->normals, err)) != BF_OK ||
        (rc = copy_rows(ti, "error.exr", W, H, 1, r->error, err)) != BF_OK ||
        (rc = copy_rows(ti, "lambert_normals.exr", W, H, 3, r->lambert_normals, err)) != BF_OK ||
        (rc = copy_rows(ti, "lambert_albedo.exr", W, H, C, r->lambert_albedo, err)) != BF_OK)
        return rc;
    return BF_OK;
}

/* The tile's rows of each parameter's map and of the clusters. */
static bf_status copy_param_maps(merge *m, const tile *ti, bf_error *err)
{
    bf_photo_result *r = m->r;
    int W = m->s.width, H = m->s.height, C = m->s.channels;
    float *buf = m->buf;
    bf_status rc;
    int np = bf_model_nparams(r->model);
    for (int q = 0; q < np; q++) {
        const bf_param_info *pi = bf_model_param(r->model, q);
        int off = bf_model_param_offset(r->model, q), ch = pi->color ? C : 1;
        char name[96];
        snprintf(name, sizeof name, "%s.exr", pi->name);
        if ((rc = copy_rows(ti, name, W, H, ch, buf, err)) != BF_OK)
            return rc;
        for (size_t p = (size_t)ti->y0 * (size_t)W; p < (size_t)ti->y1 * (size_t)W; p++)
            for (int c = 0; c < ch; c++)
                r->params[p * (size_t)r->nvalues + (size_t)(off + c)] = buf[p * (size_t)ch + (size_t)c];
    }
    if (r->cluster && (rc = copy_rows(ti, "clusters.exr", W, H, 1, buf, err)) != BF_OK)
        return rc;
    if (r->cluster)
        for (size_t p = (size_t)ti->y0 * (size_t)W; p < (size_t)ti->y1 * (size_t)W; p++)
            r->cluster[p] = (int)buf[p];
    return BF_OK;
}

/* The tile's rows of each relit comparison: the measured half and the model's half. */
static bf_status copy_relit(merge *m, const tile *ti, bf_error *err)
{
    bf_photo_result *r = m->r;
    int W = m->s.width, H = m->s.height, C = m->s.channels;
    bf_status rc = BF_OK;
    for (int q = 0; rc == BF_OK && q < r->nrelit; q++) {
        char name[64], path[4200];
        snprintf(name, sizeof name, "relit_%03d.exr", r->relit_index[q]);
        snprintf(path, sizeof path, "%s/%s", ti->dir, name);
        bf_image img;
        bf_image_init(&img);
        if ((rc = bf_image_read(path, &img, err)) != BF_OK)
            break;
        if (img.width != 2 * W || img.height != H || img.channels < 3)
            rc = bf_fail(err, BF_ERR_PARSE, "%s: not a %dx%d relit comparison", path, 2 * W, H);
        for (size_t y = (size_t)ti->y0; rc == BF_OK && y < (size_t)ti->y1; y++)
            for (size_t x = 0; x < (size_t)W; x++)
                for (int c = 0; c < C; c++) {
                    const float *row = img.pixels + y * 2 * (size_t)W * (size_t)img.channels;
                    r->relit_measured[q][(y * (size_t)W + x) * (size_t)C + (size_t)c] =
                        row[x * (size_t)img.channels + (size_t)c];
                    r->relit_model[q][(y * (size_t)W + x) * (size_t)C + (size_t)c] =
                        row[((size_t)W + x) * (size_t)img.channels + (size_t)c];
                }
        bf_image_clear(&img);
    }
    return rc;
}

/* The tile's counts and its relit errors' sums (RMS x RMS x samples per image). */
static bf_status add_tile_sums(merge *m, const tile *ti, bf_error *err)
{
    bf_photo_result *r = m->r;
    int K = m->s.nimages;
    const cJSON *j = ti->json;
    r->counts.pixels += (size_t)num(j, "counts/pixels", 0);
    r->counts.masked += (size_t)num(j, "counts/masked_pixels", 0);
    r->counts.failed += (size_t)num(j, "counts/failed_pixels", 0);
    r->counts.samples += (size_t)num(j, "counts/samples_used", 0);
    r->counts.shadowed += (size_t)num(j, "counts/shadowed", 0);
    r->counts.dark += (size_t)num(j, "counts/dark_outliers", 0);
    r->counts.saturated += (size_t)num(j, "counts/saturated", 0);
    r->counts.invalid += (size_t)num(j, "counts/invalid", 0);
    r->seconds += num(j, "timing/seconds", 0);
    r->threads = (int)fmax(r->threads, num(j, "timing/threads", 1));
    r->iterations += (size_t)(num(j, "timing/iterations_per_pixel", 0) * num(j, "counts/pixels", 0) + 0.5);
    const cJSON *per = get(j, "relit_error/per_image");
    if (cJSON_GetArraySize(per) != K)
        return bf_fail(err, BF_ERR_PARSE, "%s/fit.json: %d images, the first tile has %d", ti->dir,
                       cJSON_GetArraySize(per), K);
    for (int k = 0; k < K; k++) {
        const cJSON *e = cJSON_GetArrayItem(per, k);
        double ns = num(e, "samples", 0), a = num(e, "model", 0), l = num(e, "lambert", 0);
        r->image_rms[k] += a * a * ns;
        r->image_lambert_rms[k] += l * l * ns;
        r->image_samples[k] += (size_t)ns;
    }
    return BF_OK;
}

/* One tile into the whole. Its summary is read after a failed copy of its parameters,
 * clusters or relit images too, and a wrong image count there is the error reported. */
static bf_status merge_tile(merge *m, const tile *ti, bf_error *err)
{
    bf_status rc = copy_base_maps(m, ti, err);
    if (rc != BF_OK)
        return rc;
    rc = copy_param_maps(m, ti, err);
    if (rc == BF_OK)
        rc = copy_relit(m, ti, err);
    bf_status sums = add_tile_sums(m, ti, err);
    return sums != BF_OK ? sums : rc;
}

/* Shared values: the same in every tile (one start). */
static bf_status read_shared(merge *m, bf_error *err)
{
    bf_photo_result *r = m->r;
    const cJSON *shared = get(m->t[0].json, "shared");
    if (!cJSON_IsArray(shared))
        return BF_OK;
    const cJSON *vals = get(cJSON_GetArrayItem(shared, 0), "values");
    r->nshared = 0;
    for (const cJSON *v = vals ? vals->child : NULL; v && r->nshared < BF_PHOTO_MAX_SHARED; v = v->next) {
        char name[96];
        for (int e = 0; e < r->nvalues; e++)
            if (!strcmp(bf_model_entry_name(r->model, e, name, sizeof name), v->string))
                r->shared_entry[r->nshared++] = e;
    }
    int nc = cJSON_GetArraySize(shared);
    r->nclusters = nc > 0 ? nc : 1;
    r->shared = calloc((size_t)r->nclusters * (size_t)(r->nshared ? r->nshared : 1), sizeof *r->shared);
    if (!r->shared)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    for (int cl = 0; cl < nc; cl++) {
        const cJSON *cv = get(cJSON_GetArrayItem(shared, cl), "values");
        int i = 0;
        for (const cJSON *v = cv ? cv->child : NULL; v && i < r->nshared; v = v->next, i++)
            r->shared[cl * r->nshared + i] = cJSON_IsNumber(v) ? v->valuedouble : NAN;
    }
    return BF_OK;
}

/* The relit errors' sums as RMS, per image and over all. */
static void relit_rms(bf_photo_result *r, int K)
{
    double sm = 0.0, sl = 0.0;
    size_t m = 0;
    for (int k = 0; k < K; k++) {
        sm += r->image_rms[k];
        sl += r->image_lambert_rms[k];
        m += r->image_samples[k];
        double nk = (double)r->image_samples[k];
        r->image_rms[k] = nk > 0 ? sqrt(r->image_rms[k] / nk) : 0.0;
        r->image_lambert_rms[k] = nk > 0 ? sqrt(r->image_lambert_rms[k] / nk) : 0.0;
    }
    r->relit_rms = m ? sqrt(sm / (double)m) : 0.0;
    r->lambert_rms = m ? sqrt(sl / (double)m) : 0.0;
}

static void merge_free(merge *m)
{
    free(m->buf);
    for (int i = 0; m->t && i < m->n; i++) {
        free(m->t[i].dir);
        cJSON_Delete(m->t[i].json);
    }
    free(m->t);
    for (int k = 0; m->s.images && k < m->s.nimages; k++)
        free(m->s.images[k].file);
    free(m->s.images);
    free(m->s.path);
    bf_photo_result_free(m->r);
}

bf_status bf_photo_merge(const char *const *dirs, int n, const char *out, const char *command_line, bf_error *err)
{
    if (n < 1)
        return bf_fail(err, BF_ERR_ARG, "merge-images: no tile folders");
    merge m = {.t = calloc((size_t)n, sizeof *m.t), .n = n, .r = calloc(1, sizeof *m.r)};
    bf_status rc = m.t && m.r ? BF_OK : bf_fail(err, BF_ERR_NOMEM, "out of memory");
    if (rc == BF_OK)
        rc = read_tiles(&m, dirs, err);
    if (rc == BF_OK)
        rc = check_tiles(&m, err);
    if (rc == BF_OK)
        rc = result_maps(&m, err);
    if (rc == BF_OK)
        rc = optional_maps(&m, err);
    for (int i = 0; rc == BF_OK && i < n; i++)
        rc = merge_tile(&m, &m.t[i], err);
    if (rc == BF_OK)
        rc = read_shared(&m, err);
    if (rc == BF_OK) {
        relit_rms(m.r, m.s.nimages);
        rc = bf_photo_write(m.r, &m.s, &m.o, out, command_line, err);
    }
    merge_free(&m);
    return rc;
}
