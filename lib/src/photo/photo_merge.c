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

bf_status bf_photo_merge(const char *const *dirs, int n, const char *out, const char *command_line, bf_error *err)
{
    if (n < 1)
        return bf_fail(err, BF_ERR_ARG, "merge-images: no tile folders");
    tile *t = calloc((size_t)n, sizeof *t);
    bf_stack s = {0};
    bf_photo_options o;
    bf_photo_result *r = calloc(1, sizeof *r);
    bf_status rc = t && r ? BF_OK : bf_fail(err, BF_ERR_NOMEM, "out of memory");
    for (int i = 0; rc == BF_OK && i < n; i++)
        rc = read_tile(dirs[i], &t[i], err);
    if (rc == BF_OK)
        qsort(t, (size_t)n, sizeof *t, cmp_tile);
    /* The same run's tiles, each once, all of them. */
    for (int i = 0; rc == BF_OK && i < n; i++) {
        const char *keys[] = {"spec", "stack/path", "options/normals", "options/share"};
        for (int k = 0; rc == BF_OK && k < 4; k++) {
            const char *a = str(t[0].json, keys[k]), *b = str(t[i].json, keys[k]);
            if ((a == NULL) != (b == NULL) || (a && strcmp(a, b)))
                rc = bf_fail(err, BF_ERR_ARG, "%s: %s differs from %s's: not tiles of one run", t[i].dir, keys[k],
                             t[0].dir);
        }
        if (rc == BF_OK && (t[i].count != n || t[i].index != i + 1))
            rc = bf_fail(err, BF_ERR_ARG, "%s: tile %d/%d, but %d tile folders were given (each of 1..%d once)",
                         t[i].dir, t[i].index, t[i].count, n, t[i].count);
        if (rc == BF_OK && num(t[i].json, "options/scale", NAN) != num(t[0].json, "options/scale", NAN))
            rc = bf_fail(err, BF_ERR_ARG, "%s: its scale differs from %s's: not tiles of one run", t[i].dir, t[0].dir);
    }
    if (rc == BF_OK)
        rc = describe(&t[0], &s, &o, err);
    if (rc == BF_OK)
        rc = bf_model_new(o.model, s.channels, &r->model, err);
    int W = s.width, H = s.height, C = s.channels, K = s.nimages;
    size_t WH = (size_t)W * (size_t)H;
    if (rc == BF_OK) {
        r->width = W;
        r->height = H;
        r->channels = C;
        r->y1 = H;
        r->nimages = K;
        r->nvalues = bf_model_nvalues(r->model);
        r->scale = num(t[0].json, "options/scale", 1.0);
        r->nclusters = (int)num(t[0].json, "options/clusters", 1);
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
            rc = bf_fail(err, BF_ERR_NOMEM, "out of memory for %dx%d maps", W, H);
    }
    /* Which optional maps the run wrote: clusters, relit images. */
    const cJSON *files = rc == BF_OK ? get(t[0].json, "files") : NULL;
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
    if (rc == BF_OK && has_clusters && !(r->cluster = malloc(WH * sizeof *r->cluster)))
        rc = bf_fail(err, BF_ERR_NOMEM, "out of memory");
    for (int i = 0; rc == BF_OK && i < r->nrelit; i++)
        if (!(r->relit_measured[i] = calloc(WH * (size_t)C, sizeof(float))) ||
            !(r->relit_model[i] = calloc(WH * (size_t)C, sizeof(float))))
            rc = bf_fail(err, BF_ERR_NOMEM, "out of memory");
    float *buf = rc == BF_OK ? malloc(WH * 6 * sizeof *buf) : NULL;
    if (rc == BF_OK && !buf)
        rc = bf_fail(err, BF_ERR_NOMEM, "out of memory");
    if (buf)
        memset(buf, 0, WH * 6 * sizeof *buf);
    for (int i = 0; rc == BF_OK && i < n; i++) {
        const tile *ti = &t[i];
        if ((rc = copy_rows(ti, "mask.png", W, H, 1, buf, err)) != BF_OK)
            break;
        for (size_t p = (size_t)ti->y0 * (size_t)W; p < (size_t)ti->y1 * (size_t)W; p++)
            r->mask[p] = buf[p] > 0.5f;
        if ((rc = copy_rows(ti, "normals.exr", W, H, 3, r->normals, err)) != BF_OK ||
            (rc = copy_rows(ti, "error.exr", W, H, 1, r->error, err)) != BF_OK ||
            (rc = copy_rows(ti, "lambert_normals.exr", W, H, 3, r->lambert_normals, err)) != BF_OK ||
            (rc = copy_rows(ti, "lambert_albedo.exr", W, H, C, r->lambert_albedo, err)) != BF_OK)
            break;
        int np = bf_model_nparams(r->model);
        for (int q = 0; rc == BF_OK && q < np; q++) {
            const bf_param_info *pi = bf_model_param(r->model, q);
            int off = bf_model_param_offset(r->model, q), ch = pi->colour ? C : 1;
            char name[96];
            snprintf(name, sizeof name, "%s.exr", pi->name);
            if ((rc = copy_rows(ti, name, W, H, ch, buf, err)) != BF_OK)
                break;
            for (size_t p = (size_t)ti->y0 * (size_t)W; p < (size_t)ti->y1 * (size_t)W; p++)
                for (int c = 0; c < ch; c++)
                    r->params[p * (size_t)r->nvalues + (size_t)(off + c)] = buf[p * (size_t)ch + (size_t)c];
        }
        if (rc == BF_OK && r->cluster && (rc = copy_rows(ti, "clusters.exr", W, H, 1, buf, err)) == BF_OK)
            for (size_t p = (size_t)ti->y0 * (size_t)W; p < (size_t)ti->y1 * (size_t)W; p++)
                r->cluster[p] = (int)buf[p];
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
        /* Counts and the relit errors' sums. */
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
        if (cJSON_GetArraySize(per) != K) {
            rc = bf_fail(err, BF_ERR_PARSE, "%s/fit.json: %d images, the first tile has %d", ti->dir,
                         cJSON_GetArraySize(per), K);
            break;
        }
        for (int k = 0; k < K; k++) {
            const cJSON *e = cJSON_GetArrayItem(per, k);
            double m = num(e, "samples", 0), a = num(e, "model", 0), l = num(e, "lambert", 0);
            r->image_rms[k] += a * a * m;
            r->image_lambert_rms[k] += l * l * m;
            r->image_samples[k] += (size_t)m;
        }
    }
    /* Shared values: the same in every tile (one start). */
    const cJSON *shared = rc == BF_OK ? get(t[0].json, "shared") : NULL;
    if (rc == BF_OK && cJSON_IsArray(shared)) {
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
            rc = bf_fail(err, BF_ERR_NOMEM, "out of memory");
        for (int cl = 0; rc == BF_OK && cl < nc; cl++) {
            const cJSON *cv = get(cJSON_GetArrayItem(shared, cl), "values");
            int i = 0;
            for (const cJSON *v = cv ? cv->child : NULL; v && i < r->nshared; v = v->next, i++)
                r->shared[cl * r->nshared + i] = cJSON_IsNumber(v) ? v->valuedouble : NAN;
        }
    }
    if (rc == BF_OK) {
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
        rc = bf_photo_write(r, &s, &o, out, command_line, err);
    }
    free(buf);
    for (int i = 0; t && i < n; i++) {
        free(t[i].dir);
        cJSON_Delete(t[i].json);
    }
    free(t);
    for (int k = 0; s.images && k < s.nimages; k++)
        free(s.images[k].file);
    free(s.images);
    free(s.path);
    bf_photo_result_free(r);
    return rc;
}
