/* The pieces of a glTF document (gltf_doc.h). */
#include "gltf_doc.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

void bf_gltf_put_u16(unsigned char *p, unsigned v)
{
    p[0] = (unsigned char)(v & 0xff);
    p[1] = (unsigned char)(v >> 8);
}

void bf_gltf_put_f32(unsigned char *p, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    for (int k = 0; k < 4; k++)
        p[k] = (unsigned char)(u >> (8 * k));
}

char *bf_gltf_base64_uri(const unsigned char *p, size_t n)
{
    static const char tab[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    static const char head[] = "data:application/octet-stream;base64,";
    size_t hl = sizeof head - 1;
    char *out = malloc(hl + 4 * ((n + 2) / 3) + 1);
    if (!out)
        return NULL;
    memcpy(out, head, hl);
    char *o = out + hl;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)p[i] << 16 | (i + 1 < n ? (uint32_t)p[i + 1] << 8 : 0) | (i + 2 < n ? p[i + 2] : 0);
        *o++ = tab[v >> 18 & 63];
        *o++ = tab[v >> 12 & 63];
        *o++ = i + 1 < n ? tab[v >> 6 & 63] : '=';
        *o++ = i + 2 < n ? tab[v & 63] : '=';
    }
    *o = '\0';
    return out;
}

cJSON *bf_gltf_num_array(const double *v, int n)
{
    cJSON *a = cJSON_CreateArray();
    for (int k = 0; a && k < n; k++)
        cJSON_AddItemToArray(a, cJSON_CreateNumber(v[k]));
    return a;
}

cJSON *bf_gltf_view(int offset, int length, int target)
{
    cJSON *v = cJSON_CreateObject();
    cJSON_AddNumberToObject(v, "buffer", 0);
    cJSON_AddNumberToObject(v, "byteOffset", offset);
    cJSON_AddNumberToObject(v, "byteLength", length);
    cJSON_AddNumberToObject(v, "target", target);
    return v;
}

cJSON *bf_gltf_accessor(int view_index, int type_code, int count, const char *type)
{
    cJSON *a = cJSON_CreateObject();
    cJSON_AddNumberToObject(a, "bufferView", view_index);
    cJSON_AddNumberToObject(a, "componentType", type_code);
    cJSON_AddNumberToObject(a, "count", count);
    cJSON_AddStringToObject(a, "type", type);
    return a;
}
