/* bf_photo_write (photo.h): the outputs of a per-pixel fit, in a folder written whole or
 * not at all (io/out_folder.h): normals.exr, one EXR per parameter, error.exr, the
 * Lambertian baseline's normals and albedo, clusters.exr with clusters, fit.json, PNG
 * previews (normal map, albedo), relit comparisons (measured | relit) and, for the gltf
 * model, a textured glTF material (photo_gltf.c). docs/images.md describes them. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/sized.h"
#include "brdfit/image.h"
#include "brdfit/version.h"
#include "io/json_out.h"
#include "io/out_folder.h"
#include "photo_impl.h"
#include "photo_outputs.h"

#define MARKER ".brdfit-fit-images"
#define WHAT "fit-images output"
#define NAME_CHARS 96
#define MAX_FILES (2 * BF_PHOTO_MAX_RELIT + 96)

bf_status bf_photo_check_output(const char *dir, bf_error *err)
{
    return bf_out_folder_check(dir, MARKER, WHAT, err);
}

/* Entry e's map (a scalar parameter, or one channel of a colour one). */
static bf_status write_param(const bf_out_folder *f, const bf_photo_result *r, int i, float *buf, bf_error *err)
{
    const bf_param_info *pi = bf_model_param(r->model, i);
    int off = bf_model_param_offset(r->model, i), ch = pi->color ? r->channels : 1;
    size_t n = (size_t)r->width * (size_t)r->height;
    for (size_t p = 0; p < n; p++)
        for (int c = 0; c < ch; c++)
            buf[p * (size_t)ch + (size_t)c] = r->mask[p] ? r->params[p * (size_t)r->nvalues + (size_t)(off + c)] : 0.0f;
    char name[96];
    snprintf(name, sizeof name, "%s.exr", pi->name);
    return photo_write_image(f, name, r->width, r->height, ch, buf, 0, err);
}

/* The diffuse colour (the parameter whose role is diffuse), else the Lambertian albedo, as
 * an RGB (or grey) image into buf; 1 when taken from the model. */
static int albedo_image(const bf_photo_result *r, float *buf)
{
    size_t n = (size_t)r->width * (size_t)r->height;
    int C = r->channels, np = bf_model_nparams(r->model);
    for (int i = 0; i < np; i++) {
        const bf_param_info *pi = bf_model_param(r->model, i);
        if (pi->role != BF_ROLE_DIFFUSE)
            continue;
        int off = bf_model_param_offset(r->model, i);
        for (size_t p = 0; p < n; p++)
            for (int c = 0; c < 3; c++) {
                int cc = pi->color ? (C == 3 ? c : 0) : 0;
                buf[3 * p + (size_t)c] = r->mask[p] ? r->params[p * (size_t)r->nvalues + (size_t)(off + cc)] : 0.0f;
            }
        return 1;
    }
    for (size_t p = 0; p < n; p++)
        for (int c = 0; c < 3; c++)
            buf[3 * p + (size_t)c] =
                r->mask[p] ? r->lambert_albedo[p * (size_t)C + (size_t)(C == 3 ? c : 0)] / M_PI : 0.0f;
    return 0;
}

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

/* Measured | relit side by side, one exposure for both: the measured image's 99th
 * percentile inside the mask shown at 0.9. */
static bf_status write_relit(const bf_out_folder *f, const bf_photo_result *r, int i, bf_error *err)
{
    int W = r->width, H = r->height, C = r->channels;
    size_t n = (size_t)W * (size_t)H;
    float *vals = malloc((n ? n : 1) * (size_t)C * sizeof *vals), *img = malloc(n * 2 * 3 * sizeof *img);
    if (!vals || !img) {
        free(vals);
        free(img);
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    }
    size_t m = 0;
    for (size_t p = 0; p < n; p++)
        if (r->mask[p])
            for (int c = 0; c < C; c++)
                vals[m++] = r->relit_measured[i][p * (size_t)C + (size_t)c];
    float top = 1.0f;
    if (m) {
        qsort(vals, m, sizeof *vals, cmp_float);
        top = vals[(size_t)floor(0.99 * (double)(m - 1))];
    }
    float gain = top > 0.0f ? 0.9f / top : 1.0f;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            size_t p = (size_t)y * (size_t)W + (size_t)x;
            for (int c = 0; c < 3; c++) {
                int cc = C == 3 ? c : 0;
                float a = r->relit_measured[i][p * (size_t)C + (size_t)cc] * gain,
                      b = r->relit_model[i][p * (size_t)C + (size_t)cc] * gain;
                img[((size_t)y * 2 * (size_t)W + (size_t)x) * 3 + (size_t)c] = r->mask[p] ? a : 0.0f;
                img[((size_t)y * 2 * (size_t)W + (size_t)W + (size_t)x) * 3 + (size_t)c] = r->mask[p] ? b : 0.0f;
            }
        }
    char name[64];
    snprintf(name, sizeof name, "relit_%03d.png", r->relit_index[i]);
    bf_status rc = photo_write_image(f, name, 2 * W, H, 3, img, 0, err);
    if (rc == BF_OK) { /* the same in linear values, for measurements and merges */
        for (size_t k = 0; k < n * 6; k++)
            img[k] /= gain;
        snprintf(name, sizeof name, "relit_%03d.exr", r->relit_index[i]);
        rc = photo_write_image(f, name, 2 * W, H, 3, img, 0, err);
    }
    free(vals);
    free(img);
    return rc;
}

static cJSON *counts_json(const bf_photo_counts *c)
{
    cJSON *o = cJSON_CreateObject();
    bf_json_add_number(o, "pixels", (double)c->pixels);
    bf_json_add_number(o, "masked_pixels", (double)c->masked);
    bf_json_add_number(o, "failed_pixels", (double)c->failed);
    bf_json_add_number(o, "samples_used", (double)c->samples);
    bf_json_add_number(o, "shadowed", (double)c->shadowed);
    bf_json_add_number(o, "dark_outliers", (double)c->dark);
    bf_json_add_number(o, "saturated", (double)c->saturated);
    bf_json_add_number(o, "invalid", (double)c->invalid);
    return o;
}

static const char *normals_name(bf_photo_normals n)
{
    return n == BF_NORMALS_FILE ? "file" : n == BF_NORMALS_FLAT ? "flat" : "fit";
}

/* The files bf_photo_write writes, in its order, into names: their count. */
static int output_names(const bf_photo_result *r, char names[][NAME_CHARS], int max)
{
    int n = 0;
#define NAME(...) (n < max ? (void)snprintf(names[n++], NAME_CHARS, __VA_ARGS__) : (void)0)
    NAME("normals.exr");
    int np = bf_model_nparams(r->model);
    for (int i = 0; i < np; i++)
        NAME("%s.exr", bf_model_param(r->model, i)->name);
    NAME("error.exr");
    NAME("lambert_normals.exr");
    NAME("lambert_albedo.exr");
    if (r->cluster)
        NAME("clusters.exr");
    NAME("normals.png");
    NAME("albedo.png");
    for (int i = 0; i < r->nrelit; i++) {
        NAME("relit_%03d.png", r->relit_index[i]);
        NAME("relit_%03d.exr", r->relit_index[i]);
    }
    NAME("mask.png");
    if (!strcmp(bf_model_name(r->model), "gltf")) {
        NAME("material.gltf");
        NAME("base_color.png");
        NAME("metallic_roughness.png");
        NAME("normal.png");
    }
#undef NAME
    return n;
}

/* fit.json's document (docs/images.md). */
static cJSON *summary_json(const bf_photo_result *r, const bf_stack *s, const bf_photo_options *o,
                           const char *command_line)
{
    cJSON *root = cJSON_CreateObject();
    bf_json_add_version(root);
    bf_json_add_string(root, "command", command_line);
    bf_json_add_string(root, "model", bf_model_name(r->model));
    bf_json_add_string(root, "spec", bf_model_spec(r->model));
    bf_json_add_number(root, "channels", r->channels);
    cJSON *st = cJSON_AddObjectToObject(root, "stack");
    bf_json_add_string(st, "path", s->path);
    bf_json_add_string(st, "layout", s->layout == BF_STACK_DILIGENT ? "diligent" : "json");
    bf_json_add_number(st, "images", s->nimages);
    bf_json_add_number(st, "width", s->width);
    bf_json_add_number(st, "height", s->height);
    cJSON *opt = cJSON_AddObjectToObject(root, "options");
    bf_json_add_string(opt, "normals", normals_name(o->normals));
    bf_json_add_string(opt, "normals_file", o->normals == BF_NORMALS_FILE ? o->normals_file : NULL);
    bf_json_add_string(opt, "share", o->share && *o->share ? o->share : NULL);
    bf_json_add_number(opt, "clusters", r->nclusters);
    bf_json_add_number(opt, "scale", r->scale);
    bf_json_add_number(opt, "seed", (double)o->seed);
    if (o->tile_count > 0) {
        cJSON *t = cJSON_AddObjectToObject(opt, "tile");
        bf_json_add_number(t, "index", o->tile_index + 1);
        bf_json_add_number(t, "count", o->tile_count);
        bf_json_add_number(t, "rows_from", r->y0);
        bf_json_add_number(t, "rows_to", r->y1);
    }
    cJSON *counts = counts_json(&r->counts);
    bf_json_add_number(counts, "restarted_pixels", (double)r->restarted);
    cJSON_AddItemToObject(root, "counts", counts);
    cJSON *rel = cJSON_AddObjectToObject(root, "relit_error");
    bf_json_add_number(rel, "model", r->relit_rms);
    bf_json_add_number(rel, "lambert", r->lambert_rms);
    bf_json_add_number(rel, "ratio", r->lambert_rms > 0.0 ? r->relit_rms / r->lambert_rms : NAN);
    cJSON *per = cJSON_AddArrayToObject(rel, "per_image");
    for (int k = 0; k < r->nimages; k++) {
        cJSON *e = cJSON_CreateObject();
        bf_json_add_number(e, "image", k);
        bf_json_add_string(e, "file", s->images[k].file);
        bf_json_add_number(e, "model", r->image_rms[k]);
        bf_json_add_number(e, "lambert", r->image_lambert_rms[k]);
        bf_json_add_number(e, "samples", (double)r->image_samples[k]);
        cJSON_AddItemToArray(per, e);
    }
    if (r->nshared) {
        cJSON *sh = cJSON_AddArrayToObject(root, "shared");
        double *x = malloc((size_t)r->nvalues * sizeof *x);
        for (int cl = 0; x && cl < r->nclusters; cl++) {
            /* The shared entries of the cluster, as a parameter object of those entries. */
            cJSON *e = cJSON_CreateObject();
            bf_json_add_number(e, "cluster", cl);
            cJSON *vals = cJSON_AddObjectToObject(e, "values");
            for (int i = 0; i < r->nshared; i++) {
                char name[96];
                bf_model_entry_name(r->model, r->shared_entry[i], name, sizeof name);
                cJSON_AddItemToObject(vals, name, bf_json_number(r->shared[cl * r->nshared + i]));
            }
            cJSON_AddItemToArray(sh, e);
        }
        free(x);
    }
    char files[MAX_FILES][NAME_CHARS];
    int nfiles = output_names(r, files, MAX_FILES);
    cJSON *fl = cJSON_AddArrayToObject(root, "files");
    for (int i = 0; i < nfiles; i++)
        cJSON_AddItemToArray(fl, cJSON_CreateString(files[i]));
    cJSON *tm = cJSON_AddObjectToObject(root, "timing");
    bf_json_add_number(tm, "seconds", r->seconds);
    bf_json_add_number(tm, "threads", r->threads);
    bf_json_add_number(tm, "iterations_per_pixel",
                       r->counts.pixels ? (double)r->iterations / (double)r->counts.pixels : 0.0);
    return root;
}

/* What a result's summary needs: r, s and o (a fit that ran to its end: the callers). */
static bf_status summary_ready(const bf_photo_result *r, const bf_stack *s, const bf_photo_options *o, bf_error *err)
{
    if (!r || !s || !o)
        return bf_fail(err, BF_ERR_ARG, "fit-images: nothing to write");
    if (bf_sized_check(o, PHOTO_OPTIONS_MIN_SIZE, "bf_photo_options", err) != BF_OK)
        return BF_ERR_ARG;
    return BF_OK;
}

bf_status bf_photo_result_json(const bf_photo_result *r, const bf_stack *s, const bf_photo_options *o,
                               const char *command_line, char **out, bf_error *err)
{
    *out = NULL;
    bf_status rc = summary_ready(r, s, o, err);
    if (rc != BF_OK)
        return rc;
    if (r->cancelled)
        return bf_fail(err, BF_ERR_ARG, "fit-images: the fit was cancelled: it has no summary");
    return bf_json_text(summary_json(r, s, o, command_line), "fit-images summary", out, err);
}

static bf_status write_json(const bf_out_folder *f, const bf_photo_result *r, const bf_stack *s,
                            const bf_photo_options *o, const char *command_line, bf_error *err)
{
    char path[4200];
    bf_status rc = bf_out_folder_path(f, "fit.json", path, sizeof path, err);
    return rc != BF_OK ? rc : bf_json_write(summary_json(r, s, o, command_line), path, "fit-images summary", err);
}

bf_status bf_photo_write(const bf_photo_result *r, const bf_stack *s, const bf_photo_options *o, const char *dir,
                         const char *command_line, bf_error *err)
{
    bf_status rc = summary_ready(r, s, o, err);
    if (rc != BF_OK)
        return rc;
    if (r->cancelled)
        return bf_fail(err, BF_ERR_ARG, "%s: the fit was cancelled: nothing written", dir);
    bf_out_folder f;
    rc = bf_out_folder_begin(&f, dir, MARKER, WHAT,
                             "brdfit fit-images output: this folder is replaced by the next run written here", err);
    if (rc != BF_OK)
        return rc;
    int W = r->width, H = r->height, C = r->channels;
    size_t n = (size_t)W * (size_t)H;
    float *buf = malloc(n * 4 * sizeof *buf);
    if (!buf)
        rc = bf_fail(err, BF_ERR_NOMEM, "out of memory");
    if (rc == BF_OK)
        rc = photo_write_image(&f, "normals.exr", W, H, 3, r->normals, 0, err);
    int np = bf_model_nparams(r->model);
    for (int i = 0; rc == BF_OK && i < np; i++)
        rc = write_param(&f, r, i, buf, err);
    if (rc == BF_OK)
        rc = photo_write_image(&f, "error.exr", W, H, 1, r->error, 0, err);
    if (rc == BF_OK)
        rc = photo_write_image(&f, "lambert_normals.exr", W, H, 3, r->lambert_normals, 0, err);
    if (rc == BF_OK)
        rc = photo_write_image(&f, "lambert_albedo.exr", W, H, C, r->lambert_albedo, 0, err);
    if (rc == BF_OK && r->cluster) {
        for (size_t p = 0; p < n; p++)
            buf[p] = (float)r->cluster[p];
        rc = photo_write_image(&f, "clusters.exr", W, H, 1, buf, 0, err);
    }
    if (rc == BF_OK) { /* the normal map: (n + 1) / 2 as codes, the usual encoding */
        for (size_t p = 0; p < n; p++)
            for (int c = 0; c < 3; c++)
                buf[3 * p + (size_t)c] = r->mask[p] ? 0.5f * (r->normals[3 * p + (size_t)c] + 1.0f) : 0.0f;
        rc = photo_write_image(&f, "normals.png", W, H, 3, buf, BF_IMAGE_CODES, err);
    }
    if (rc == BF_OK) {
        albedo_image(r, buf);
        rc = photo_write_image(&f, "albedo.png", W, H, 3, buf, 0, err);
    }
    for (int i = 0; rc == BF_OK && i < r->nrelit; i++)
        rc = write_relit(&f, r, i, err);
    if (rc == BF_OK) { /* the fitted pixels */
        for (size_t p = 0; p < n; p++)
            buf[p] = r->mask[p] ? 1.0f : 0.0f;
        rc = photo_write_image(&f, "mask.png", W, H, 1, buf, BF_IMAGE_CODES, err);
    }
    if (rc == BF_OK && !strcmp(bf_model_name(r->model), "gltf"))
        rc = photo_write_gltf(&f, r, err);
    if (rc == BF_OK) /* fit.json lists the files just written (output_names) */
        rc = write_json(&f, r, s, o, command_line, err);
    free(buf);
    return bf_out_folder_end(&f, rc, err);
}
