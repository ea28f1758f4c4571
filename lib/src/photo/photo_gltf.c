/* photo_write_gltf (photo_outputs.h): the gltf model's per-pixel fit as a textured glTF
 * 2.0 material on a quad the shape of the image, so that a viewer shows the photographed
 * sample as it was fitted:
 *  - base_color.png: baseColorTexture, the per-pixel base_color (sRGB-encoded, as glTF
 *    reads it; grey replicated for one channel), 0 outside the mask;
 *  - metallic_roughness.png: metallicRoughnessTexture, linear codes: R 1 (occlusion is
 *    not used), G roughness (perceptual, glTF's own), B metallic; outside the mask a rough
 *    (1) dielectric (0);
 *  - normal.png: normalTexture, tangent space as linear codes (n + 1) / 2, +Y up (OpenGL).
 *    The quad's tangent frame is the camera frame of the flat sample (T +x, B +y, N +z),
 *    so the camera-frame normal is the tangent-space one; (0, 0, 1) outside the mask;
 *  - material.gltf: one node, one mesh (the quad in the XY plane facing +Z, width
 *    W / max(W, H), height H / max(W, H), centred on the origin; UV origin top-left, so
 *    the image's top row is at v = 0), its buffer embedded as a base64 data URI, the
 *    images by relative URI, and one material "brdfit" whose factors are 1 (the textures
 *    hold the values) and whose KHR_materials_specular and KHR_materials_ior factors,
 *    which glTF does not texture here, are the medians of the masked pixels. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "brdfit/image.h"
#include "brdfit/version.h"
#include "io/json_out.h"
#include "io/out_folder.h"
#include "photo_outputs.h"
#include "io/gltf_doc.h"

/* The quad: 6 unsigned short indices, then 4 vertices' positions, normals, tangents and
 * texture coordinates, each in its own buffer view (every offset a multiple of 4). */
enum { NVERT = 4, NIDX = 6 };
enum {
    IDX_OFF = 0,
    IDX_BYTES = NIDX * 2,
    POS_OFF = IDX_OFF + IDX_BYTES,
    POS_BYTES = NVERT * 12,
    NRM_OFF = POS_OFF + POS_BYTES,
    NRM_BYTES = NVERT * 12,
    TAN_OFF = NRM_OFF + NRM_BYTES,
    TAN_BYTES = NVERT * 16,
    UV_OFF = TAN_OFF + TAN_BYTES,
    UV_BYTES = NVERT * 8,
    BUF_BYTES = UV_OFF + UV_BYTES
};
_Static_assert(IDX_BYTES % 4 == 0, "float data must stay 4-byte aligned");

/* glTF's codes: component types, buffer view targets, sampler filters and wrapping. */
enum {
    GL_UNSIGNED_SHORT = 5123,
    GL_FLOAT = 5126,
    GL_ARRAY_BUFFER = 34962,
    GL_ELEMENT_ARRAY_BUFFER = 34963,
    GL_LINEAR = 9729,
    GL_LINEAR_MIPMAP_LINEAR = 9987,
    GL_CLAMP_TO_EDGE = 33071
};

/* Vertices 0 bottom-left, 1 bottom-right, 2 top-right, 3 top-left (seen from +Z);
 * triangles (0 1 2) and (0 2 3), counter-clockwise from +Z (glTF's front faces).
 * mn, mx: the positions' bounds, which glTF requires on the POSITION accessor. */
static void build_quad(unsigned char *buf, float hw, float hh, float mn[3], float mx[3])
{
    static const unsigned idx[NIDX] = {0, 1, 2, 0, 2, 3};
    const float pos[NVERT][3] = {{-hw, -hh, 0.0f}, {hw, -hh, 0.0f}, {hw, hh, 0.0f}, {-hw, hh, 0.0f}};
    static const float uv[NVERT][2] = {{0.0f, 1.0f}, {1.0f, 1.0f}, {1.0f, 0.0f}, {0.0f, 0.0f}};
    static const float nrm[3] = {0.0f, 0.0f, 1.0f}, tan[4] = {1.0f, 0.0f, 0.0f, 1.0f};
    for (int i = 0; i < NIDX; i++)
        bf_gltf_put_u16(buf + IDX_OFF + 2 * i, idx[i]);
    for (int k = 0; k < 3; k++)
        mn[k] = pos[0][k], mx[k] = pos[0][k];
    for (int v = 0; v < NVERT; v++) {
        for (int k = 0; k < 3; k++) {
            bf_gltf_put_f32(buf + POS_OFF + 12 * v + 4 * k, pos[v][k]);
            bf_gltf_put_f32(buf + NRM_OFF + 12 * v + 4 * k, nrm[k]);
            mn[k] = pos[v][k] < mn[k] ? pos[v][k] : mn[k];
            mx[k] = pos[v][k] > mx[k] ? pos[v][k] : mx[k];
        }
        for (int k = 0; k < 4; k++)
            bf_gltf_put_f32(buf + TAN_OFF + 16 * v + 4 * k, tan[k]);
        for (int k = 0; k < 2; k++)
            bf_gltf_put_f32(buf + UV_OFF + 8 * v + 4 * k, uv[v][k]);
    }
}

/* The k-th smallest of a[0..n) (0 <= k < n), a reordered so that a[0..k) <= a[k] <=
 * a[k+1..n): Wirth's selection, whose partition splits runs of equal values evenly (a
 * shared parameter is one value over a whole cluster). */
static float select_kth(float *a, size_t n, size_t k)
{
    ptrdiff_t l = 0, m = (ptrdiff_t)n - 1, kk = (ptrdiff_t)k;
    while (l < m) {
        float x = a[kk];
        ptrdiff_t i = l, j = m;
        do {
            while (a[i] < x)
                i++;
            while (x < a[j])
                j--;
            if (i <= j) {
                float t = a[i];
                a[i] = a[j];
                a[j] = t;
                i++;
                j--;
            }
        } while (i <= j);
        if (j < kk)
            l = i;
        if (kk < i)
            m = j;
    }
    return a[kk];
}

/* v as the shortest decimal that reads back as the same float (0.6, not the float's
 * exact 0.600000023841858): the parameters are floats. */
static double float_decimal(double v)
{
    float f = (float)v;
    char buf[40];
    for (int digits = 1; digits <= 9; digits++) {
        snprintf(buf, sizeof buf, "%.*g", digits, (double)f);
        if ((float)strtod(buf, NULL) == f)
            break;
    }
    return strtod(buf, NULL);
}

/* The median of the finite values of model-vector entry e over the masked pixels
 * (tmp: width * height floats), as float_decimal; def when there are none. */
static double median_entry(const bf_photo_result *r, int e, float *tmp, double def)
{
    size_t n = (size_t)r->width * (size_t)r->height, m = 0;
    for (size_t p = 0; p < n; p++) {
        float v = r->params[p * (size_t)r->nvalues + (size_t)e];
        if (r->mask[p] && isfinite(v))
            tmp[m++] = v;
    }
    if (!m)
        return def;
    double hi = select_kth(tmp, m, m / 2);
    if (m % 2)
        return float_decimal(hi);
    float lo = tmp[0]; /* the largest of the lower half */
    for (size_t i = 1; i < m / 2; i++)
        lo = tmp[i] > lo ? tmp[i] : lo;
    return float_decimal(0.5 * ((double)lo + hi));
}

/* Where the model vector holds parameter `name`: its entry for channel c (0..2) of an RGB
 * texture or factor, the one value replicated for grey data or a mono parameter. */
typedef struct param_at {
    int off, ncol; /* first entry, entries (1 or channels) */
    double def;
} param_at;

static bf_status find_param(const bf_photo_result *r, const char *name, param_at *at, bf_error *err)
{
    int i = bf_model_find_param(r->model, name);
    if (i < 0)
        return bf_fail(err, BF_ERR_ARG, "glTF material: the model %s has no parameter %s", bf_model_name(r->model),
                       name);
    const bf_param_info *pi = bf_model_param(r->model, i);
    at->off = bf_model_param_offset(r->model, i);
    at->ncol = pi->color ? r->channels : 1;
    at->def = pi->def;
    return BF_OK;
}

static int entry_of(const param_at *at, int c)
{
    return at->off + (at->ncol == 3 ? c : 0);
}

/* The three PNG textures, through buf (width * height * 3 floats). */
static bf_status write_textures(const bf_out_folder *f, const bf_photo_result *r, const param_at *base,
                                const param_at *metal, const param_at *rough, float *buf, bf_error *err)
{
    int W = r->width, H = r->height;
    size_t n = (size_t)W * (size_t)H, P = (size_t)r->nvalues;
    for (size_t p = 0; p < n; p++) {
        const float *x = r->params + p * P;
        for (int c = 0; c < 3; c++) /* non-finite values are written as 0 (bf_image_write) */
            buf[3 * p + (size_t)c] = r->mask[p] ? x[entry_of(base, c)] : 0.0f;
    }
    bf_status rc = photo_write_image(f, "base_color.png", W, H, 3, buf, 0, err);
    if (rc != BF_OK)
        return rc;
    for (size_t p = 0; p < n; p++) {
        const float *x = r->params + p * P;
        buf[3 * p] = 1.0f;
        buf[3 * p + 1] = r->mask[p] ? x[rough->off] : 1.0f;
        buf[3 * p + 2] = r->mask[p] ? x[metal->off] : 0.0f;
    }
    if ((rc = photo_write_image(f, "metallic_roughness.png", W, H, 3, buf, BF_IMAGE_CODES, err)) != BF_OK)
        return rc;
    for (size_t p = 0; p < n; p++) {
        const float *nv = r->normals + 3 * p;
        int flat = !r->mask[p] || !isfinite(nv[0]) || !isfinite(nv[1]) || !isfinite(nv[2]);
        for (int c = 0; c < 3; c++)
            buf[3 * p + (size_t)c] = flat ? (c == 2 ? 1.0f : 0.5f) : 0.5f * (nv[c] + 1.0f);
    }
    return photo_write_image(f, "normal.png", W, H, 3, buf, BF_IMAGE_CODES, err);
}

/* A textureInfo: {"index": i}. */
static cJSON *texture_ref(int i)
{
    cJSON *t = cJSON_CreateObject();
    cJSON_AddNumberToObject(t, "index", i);
    return t;
}

/* Appends item to doc's array `key`, made when absent. */
static void add_to(cJSON *doc, const char *key, cJSON *item)
{
    cJSON *a = cJSON_GetObjectItem(doc, key);
    if (!a)
        a = cJSON_AddArrayToObject(doc, key);
    cJSON_AddItemToArray(a, item);
}

static cJSON *material(double spec, const double scol[3], double ior)
{
    static const double white[4] = {1.0, 1.0, 1.0, 1.0};
    cJSON *mat = cJSON_CreateObject(), *pbr = cJSON_CreateObject(), *ext = cJSON_CreateObject();
    cJSON *sp = cJSON_CreateObject(), *io = cJSON_CreateObject();
    cJSON_AddStringToObject(mat, "name", "brdfit");
    cJSON_AddItemToObject(pbr, "baseColorFactor", bf_gltf_num_array(white, 4));
    cJSON_AddItemToObject(pbr, "baseColorTexture", texture_ref(0));
    cJSON_AddNumberToObject(pbr, "metallicFactor", 1.0);
    cJSON_AddNumberToObject(pbr, "roughnessFactor", 1.0);
    cJSON_AddItemToObject(pbr, "metallicRoughnessTexture", texture_ref(1));
    cJSON_AddItemToObject(mat, "pbrMetallicRoughness", pbr);
    cJSON_AddItemToObject(mat, "normalTexture", texture_ref(2));
    cJSON_AddNumberToObject(sp, "specularFactor", spec);
    cJSON_AddItemToObject(sp, "specularColorFactor", bf_gltf_num_array(scol, 3));
    cJSON_AddNumberToObject(io, "ior", ior);
    cJSON_AddItemToObject(ext, "KHR_materials_specular", sp);
    cJSON_AddItemToObject(ext, "KHR_materials_ior", io);
    cJSON_AddItemToObject(mat, "extensions", ext);
    return mat;
}

static cJSON *document(const bf_photo_result *r, const unsigned char *buf, const float mn[3], const float mx[3],
                       double spec, const double scol[3], double ior)
{
    cJSON *doc = cJSON_CreateObject();
    if (!doc)
        return NULL;
    cJSON *asset = cJSON_AddObjectToObject(doc, "asset");
    char gen[128];
    snprintf(gen, sizeof gen, "brdfit %s", bf_version());
    cJSON_AddStringToObject(asset, "version", "2.0");
    cJSON_AddStringToObject(asset, "generator", gen);
    cJSON *extras = cJSON_AddObjectToObject(asset, "extras"), *b = cJSON_AddObjectToObject(extras, "brdfit");
    cJSON_AddStringToObject(b, "source", "fit-images");
    cJSON_AddStringToObject(b, "model", bf_model_spec(r->model));
    cJSON_AddNumberToObject(b, "width", r->width);
    cJSON_AddNumberToObject(b, "height", r->height);
    const char *used[2] = {"KHR_materials_specular", "KHR_materials_ior"};
    cJSON_AddItemToObject(doc, "extensionsUsed", cJSON_CreateStringArray(used, 2));
    cJSON_AddNumberToObject(doc, "scene", 0);

    const double zero = 0.0;
    cJSON *scene = cJSON_CreateObject(), *node = cJSON_CreateObject();
    cJSON_AddItemToObject(scene, "nodes", bf_gltf_num_array(&zero, 1));
    add_to(doc, "scenes", scene);
    cJSON_AddStringToObject(node, "name", "sample");
    cJSON_AddNumberToObject(node, "mesh", 0);
    add_to(doc, "nodes", node);

    cJSON *prim = cJSON_CreateObject(), *attr = cJSON_CreateObject(), *mesh = cJSON_CreateObject();
    cJSON_AddNumberToObject(attr, "POSITION", 1);
    cJSON_AddNumberToObject(attr, "NORMAL", 2);
    cJSON_AddNumberToObject(attr, "TANGENT", 3);
    cJSON_AddNumberToObject(attr, "TEXCOORD_0", 4);
    cJSON_AddItemToObject(prim, "attributes", attr);
    cJSON_AddNumberToObject(prim, "indices", 0);
    cJSON_AddNumberToObject(prim, "material", 0);
    cJSON_AddStringToObject(mesh, "name", "quad");
    add_to(mesh, "primitives", prim);
    add_to(doc, "meshes", mesh);

    add_to(doc, "materials", material(spec, scol, ior));

    static const char *const image_uri[3] = {"base_color.png", "metallic_roughness.png", "normal.png"};
    for (int i = 0; i < 3; i++) {
        cJSON *t = cJSON_CreateObject(), *im = cJSON_CreateObject();
        cJSON_AddNumberToObject(t, "sampler", 0);
        cJSON_AddNumberToObject(t, "source", i);
        add_to(doc, "textures", t);
        cJSON_AddStringToObject(im, "uri", image_uri[i]);
        add_to(doc, "images", im);
    }
    cJSON *smp = cJSON_CreateObject();
    cJSON_AddNumberToObject(smp, "magFilter", GL_LINEAR);
    cJSON_AddNumberToObject(smp, "minFilter", GL_LINEAR_MIPMAP_LINEAR);
    cJSON_AddNumberToObject(smp, "wrapS", GL_CLAMP_TO_EDGE);
    cJSON_AddNumberToObject(smp, "wrapT", GL_CLAMP_TO_EDGE);
    add_to(doc, "samplers", smp);

    add_to(doc, "bufferViews", bf_gltf_view(IDX_OFF, IDX_BYTES, GL_ELEMENT_ARRAY_BUFFER));
    add_to(doc, "bufferViews", bf_gltf_view(POS_OFF, POS_BYTES, GL_ARRAY_BUFFER));
    add_to(doc, "bufferViews", bf_gltf_view(NRM_OFF, NRM_BYTES, GL_ARRAY_BUFFER));
    add_to(doc, "bufferViews", bf_gltf_view(TAN_OFF, TAN_BYTES, GL_ARRAY_BUFFER));
    add_to(doc, "bufferViews", bf_gltf_view(UV_OFF, UV_BYTES, GL_ARRAY_BUFFER));
    add_to(doc, "accessors", bf_gltf_accessor(0, GL_UNSIGNED_SHORT, NIDX, "SCALAR"));
    cJSON *posacc = bf_gltf_accessor(1, GL_FLOAT, NVERT, "VEC3");
    const double dmn[3] = {mn[0], mn[1], mn[2]}, dmx[3] = {mx[0], mx[1], mx[2]};
    cJSON_AddItemToObject(posacc, "min", bf_gltf_num_array(dmn, 3));
    cJSON_AddItemToObject(posacc, "max", bf_gltf_num_array(dmx, 3));
    add_to(doc, "accessors", posacc);
    add_to(doc, "accessors", bf_gltf_accessor(2, GL_FLOAT, NVERT, "VEC3"));
    add_to(doc, "accessors", bf_gltf_accessor(3, GL_FLOAT, NVERT, "VEC4"));
    add_to(doc, "accessors", bf_gltf_accessor(4, GL_FLOAT, NVERT, "VEC2"));

    cJSON *buffer = cJSON_CreateObject();
    cJSON_AddNumberToObject(buffer, "byteLength", BUF_BYTES);
    char *uri = bf_gltf_base64_uri(buf, BUF_BYTES);
    if (!uri) {
        cJSON_Delete(buffer);
        cJSON_Delete(doc);
        return NULL;
    }
    cJSON_AddStringToObject(buffer, "uri", uri);
    free(uri);
    add_to(doc, "buffers", buffer);
    return doc;
}

bf_status photo_write_gltf(const bf_out_folder *f, const bf_photo_result *r, bf_error *err)
{
    if (!f || !r || !r->model || !r->mask || !r->params || !r->normals || r->width <= 0 || r->height <= 0)
        return bf_fail(err, BF_ERR_ARG, "glTF material: nothing to write");
    static const char *const names[6] = {"base_color", "metallic", "roughness", "specular", "specular_color", "ior"};
    param_at at[6] = {{0, 0, 0.0}};
    bf_status rc = BF_OK;
    for (int i = 0; rc == BF_OK && i < 6; i++)
        rc = find_param(r, names[i], &at[i], err);
    if (rc != BF_OK)
        return rc;
    const param_at *base = &at[0], *metal = &at[1], *rough = &at[2], *spec = &at[3], *scol = &at[4], *ior = &at[5];
    size_t n = (size_t)r->width * (size_t)r->height;
    float *buf = malloc(n * 3 * sizeof *buf);
    if (!buf)
        return bf_fail(err, BF_ERR_NOMEM, "glTF material: out of memory");

    /* The factors glTF takes for the whole material (before buf is reused for images). */
    double fspec = median_entry(r, spec->off, buf, spec->def), fior = median_entry(r, ior->off, buf, ior->def);
    double fscol[3];
    for (int c = 0; c < 3; c++)
        fscol[c] = c > 0 && scol->ncol == 1 ? fscol[0] : median_entry(r, entry_of(scol, c), buf, scol->def);

    rc = write_textures(f, r, base, metal, rough, buf, err);
    free(buf);
    if (rc != BF_OK)
        return rc;

    /* The quad: the image's aspect, its longer side 1. */
    int big = r->width > r->height ? r->width : r->height;
    float hw = (float)(0.5 * r->width / big), hh = (float)(0.5 * r->height / big);
    unsigned char geo[BUF_BYTES];
    float mn[3], mx[3];
    build_quad(geo, hw, hh, mn, mx);
    cJSON *doc = document(r, geo, mn, mx, fspec, fscol, fior);
    if (!doc)
        return bf_fail(err, BF_ERR_NOMEM, "glTF material: out of memory");
    char path[4200];
    if ((rc = bf_out_folder_path(f, "material.gltf", path, sizeof path, err)) != BF_OK) {
        cJSON_Delete(doc);
        return rc;
    }
    return bf_json_write(doc, path, "glTF material", err);
}
