/* brdfit export --to gltf: a glTF 2.0 document with one UV sphere carrying the material,
 * its buffer embedded as a base64 data URI so that the .gltf stands alone. The gltf
 * model's parameters are glTF's own (docs/export.md): baseColorFactor, metallicFactor,
 * roughnessFactor, KHR_materials_specular's specularFactor and specularColorFactor and
 * KHR_materials_ior's ior, so the mapping is a copy. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "export_impl.h"
#include "io/gltf_doc.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

enum { SEGMENTS = 48, RINGS = 24 }; /* longitude and latitude divisions */
enum { NVERT = (RINGS + 1) * (SEGMENTS + 1) };
/* Two triangles per quad except at the poles, where one of them is degenerate. */
enum { NTRI = 2 * SEGMENTS * (RINGS - 1) };
enum { IDX_BYTES = NTRI * 3 * 2, POS_BYTES = NVERT * 12 };
_Static_assert(IDX_BYTES % 4 == 0, "float data must stay 4-byte aligned");
_Static_assert(NVERT <= 65535, "indices are unsigned short");

/* Unit sphere, Y up: indices, then positions, then normals (equal to the positions).
 * Triangles wind counter-clockwise seen from outside. min/max: the positions' bounds,
 * which glTF requires on the POSITION accessor. */
static void build_sphere(unsigned char *buf, float mn[3], float mx[3])
{
    unsigned char *idx = buf, *pos = buf + IDX_BYTES, *nrm = pos + POS_BYTES;
    for (int k = 0; k < 3; k++)
        mn[k] = 1.0f, mx[k] = -1.0f;
    for (int r = 0; r <= RINGS; r++) {
        double th = M_PI * r / RINGS;
        for (int s = 0; s <= SEGMENTS; s++) {
            double ph = 2.0 * M_PI * s / SEGMENTS;
            /* Exact poles and seam: sin(pi) is not 0 in floating point. */
            double st = (r == 0 || r == RINGS) ? 0.0 : sin(th);
            double ct = r == 0 ? 1.0 : r == RINGS ? -1.0 : cos(th);
            double sp = (s == 0 || s == SEGMENTS) ? 0.0 : sin(ph);
            double cp = (s == 0 || s == SEGMENTS) ? 1.0 : cos(ph);
            float p[3] = {(float)(st * sp), (float)ct, (float)(st * cp)};
            int v = r * (SEGMENTS + 1) + s;
            for (int k = 0; k < 3; k++) {
                bf_gltf_put_f32(pos + 12 * v + 4 * k, p[k]);
                bf_gltf_put_f32(nrm + 12 * v + 4 * k, p[k]);
                mn[k] = p[k] < mn[k] ? p[k] : mn[k];
                mx[k] = p[k] > mx[k] ? p[k] : mx[k];
            }
        }
    }
    int t = 0;
    for (int r = 0; r < RINGS; r++)
        for (int s = 0; s < SEGMENTS; s++) {
            unsigned a = (unsigned)(r * (SEGMENTS + 1) + s), b = a + SEGMENTS + 1, c = b + 1, d = a + 1;
            const unsigned tri[2][3] = {{a, b, c}, {a, c, d}};
            for (int h = 0; h < 2; h++) {
                if ((h == 0 && r == RINGS - 1) || (h == 1 && r == 0))
                    continue; /* collapses onto a pole */
                for (int k = 0; k < 3; k++)
                    bf_gltf_put_u16(idx + 2 * (3 * t + k), tri[h][k]);
                t++;
            }
        }
}

static cJSON *material(const bf_export_material *e)
{
    double base[4] = {bf_export_param(e, "base_color", 0), bf_export_param(e, "base_color", 1),
                      bf_export_param(e, "base_color", 2), 1.0};
    double scol[3] = {bf_export_param(e, "specular_color", 0), bf_export_param(e, "specular_color", 1),
                      bf_export_param(e, "specular_color", 2)};
    cJSON *mat = cJSON_CreateObject(), *pbr = cJSON_CreateObject(), *ext = cJSON_CreateObject();
    cJSON *spec = cJSON_CreateObject(), *ior = cJSON_CreateObject();
    cJSON_AddStringToObject(mat, "name", "brdfit");
    cJSON_AddItemToObject(pbr, "baseColorFactor", bf_gltf_num_array(base, 4));
    cJSON_AddNumberToObject(pbr, "metallicFactor", bf_export_param(e, "metallic", 0));
    cJSON_AddNumberToObject(pbr, "roughnessFactor", bf_export_param(e, "roughness", 0));
    cJSON_AddItemToObject(mat, "pbrMetallicRoughness", pbr);
    cJSON_AddNumberToObject(spec, "specularFactor", bf_export_param(e, "specular", 0));
    cJSON_AddItemToObject(spec, "specularColorFactor", bf_gltf_num_array(scol, 3));
    cJSON_AddNumberToObject(ior, "ior", bf_export_param(e, "ior", 0));
    cJSON_AddItemToObject(ext, "KHR_materials_specular", spec);
    cJSON_AddItemToObject(ext, "KHR_materials_ior", ior);
    cJSON_AddItemToObject(mat, "extensions", ext);
    return mat;
}

/* asset.extras.brdfit: where the material came from and, for a conversion, its error. */
static cJSON *provenance(const bf_export_material *e)
{
    cJSON *b = cJSON_CreateObject();
    cJSON_AddStringToObject(b, "source_model", e->source);
    cJSON_AddBoolToObject(b, "converted", e->converted);
    if (e->converted) {
        cJSON *c = cJSON_CreateObject();
        cJSON_AddNumberToObject(c, "directions", (double)e->directions);
        cJSON_AddNumberToObject(c, "rmse", e->metrics.rmse);
        cJSON_AddNumberToObject(c, "rmse_cos", e->metrics.rmse_cos);
        cJSON_AddNumberToObject(c, "rmse_log", e->metrics.rmse_log);
        cJSON_AddNumberToObject(c, "rmse_rel", e->metrics.rmse_rel);
        cJSON_AddNumberToObject(c, "max_err", e->metrics.max_err);
        cJSON_AddItemToObject(b, "conversion", c);
    }
    cJSON *extras = cJSON_CreateObject();
    cJSON_AddItemToObject(extras, "brdfit", b);
    return extras;
}

static cJSON *document(const bf_export_material *e, const unsigned char *buf, const float mn[3], const float mx[3])
{
    const int total = IDX_BYTES + 2 * POS_BYTES;
    cJSON *doc = cJSON_CreateObject();
    cJSON *asset = cJSON_CreateObject();
    cJSON_AddStringToObject(asset, "version", "2.0");
    cJSON_AddStringToObject(asset, "generator", "brdfit export");
    cJSON_AddItemToObject(asset, "extras", provenance(e));
    cJSON_AddItemToObject(doc, "asset", asset);
    const char *used[2] = {"KHR_materials_specular", "KHR_materials_ior"};
    cJSON_AddItemToObject(doc, "extensionsUsed", cJSON_CreateStringArray(used, 2));
    cJSON_AddNumberToObject(doc, "scene", 0);

    cJSON *scene = cJSON_CreateObject(), *node = cJSON_CreateObject();
    const double zero = 0.0;
    cJSON_AddItemToObject(scene, "nodes", bf_gltf_num_array(&zero, 1));
    cJSON_AddItemToObject(doc, "scenes", cJSON_CreateArray());
    cJSON_AddItemToArray(cJSON_GetObjectItem(doc, "scenes"), scene);
    cJSON_AddStringToObject(node, "name", "sphere");
    cJSON_AddNumberToObject(node, "mesh", 0);
    cJSON_AddItemToObject(doc, "nodes", cJSON_CreateArray());
    cJSON_AddItemToArray(cJSON_GetObjectItem(doc, "nodes"), node);

    cJSON *prim = cJSON_CreateObject(), *attr = cJSON_CreateObject(), *mesh = cJSON_CreateObject();
    cJSON_AddNumberToObject(attr, "POSITION", 1);
    cJSON_AddNumberToObject(attr, "NORMAL", 2);
    cJSON_AddItemToObject(prim, "attributes", attr);
    cJSON_AddNumberToObject(prim, "indices", 0);
    cJSON_AddNumberToObject(prim, "material", 0);
    cJSON_AddItemToObject(mesh, "primitives", cJSON_CreateArray());
    cJSON_AddItemToArray(cJSON_GetObjectItem(mesh, "primitives"), prim);
    cJSON_AddItemToObject(doc, "meshes", cJSON_CreateArray());
    cJSON_AddItemToArray(cJSON_GetObjectItem(doc, "meshes"), mesh);

    cJSON_AddItemToObject(doc, "materials", cJSON_CreateArray());
    cJSON_AddItemToArray(cJSON_GetObjectItem(doc, "materials"), material(e));

    /* 34963: ELEMENT_ARRAY_BUFFER, 34962: ARRAY_BUFFER; 5123 unsigned short, 5126 float. */
    cJSON *views = cJSON_CreateArray(), *accs = cJSON_CreateArray();
    cJSON_AddItemToArray(views, bf_gltf_view(0, IDX_BYTES, 34963));
    cJSON_AddItemToArray(views, bf_gltf_view(IDX_BYTES, POS_BYTES, 34962));
    cJSON_AddItemToArray(views, bf_gltf_view(IDX_BYTES + POS_BYTES, POS_BYTES, 34962));
    cJSON_AddItemToObject(doc, "bufferViews", views);
    cJSON_AddItemToArray(accs, bf_gltf_accessor(0, 5123, NTRI * 3, "SCALAR"));
    cJSON *posacc = bf_gltf_accessor(1, 5126, NVERT, "VEC3");
    const double dmn[3] = {mn[0], mn[1], mn[2]}, dmx[3] = {mx[0], mx[1], mx[2]};
    cJSON_AddItemToObject(posacc, "min", bf_gltf_num_array(dmn, 3));
    cJSON_AddItemToObject(posacc, "max", bf_gltf_num_array(dmx, 3));
    cJSON_AddItemToArray(accs, posacc);
    cJSON_AddItemToArray(accs, bf_gltf_accessor(2, 5126, NVERT, "VEC3"));
    cJSON_AddItemToObject(doc, "accessors", accs);

    cJSON *buffer = cJSON_CreateObject();
    cJSON_AddNumberToObject(buffer, "byteLength", total);
    char *uri = bf_gltf_base64_uri(buf, (size_t)total);
    if (uri) {
        cJSON_AddStringToObject(buffer, "uri", uri);
        free(uri);
    }
    cJSON_AddItemToObject(doc, "buffers", cJSON_CreateArray());
    cJSON_AddItemToArray(cJSON_GetObjectItem(doc, "buffers"), buffer);
    return uri ? doc : (cJSON_Delete(doc), NULL);
}

bf_status bf_export_write_gltf(const bf_export_material *e, FILE *fp, bf_error *err)
{
    unsigned char *buf = malloc(IDX_BYTES + 2 * POS_BYTES);
    if (!buf)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for the glTF document");
    float mn[3], mx[3];
    build_sphere(buf, mn, mx);
    cJSON *doc = document(e, buf, mn, mx);
    free(buf);
    char *text = doc ? cJSON_Print(doc) : NULL;
    cJSON_Delete(doc);
    if (!text)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for the glTF document");
    fputs(text, fp);
    fputc('\n', fp);
    free(text);
    return BF_OK;
}
