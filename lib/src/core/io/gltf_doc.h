/* Internal: the pieces every glTF document brdfit writes is made of (export/gltf.c's
 * sphere, photo/photo_gltf.c's textured quad): little-endian buffer data, the embedded
 * base64 buffer, and the bufferView and accessor objects. */
#ifndef BF_GLTF_DOC_H
#define BF_GLTF_DOC_H

#include <cjson/cJSON.h>
#include <stddef.h>

/* Little-endian unsigned short and IEEE float, as glTF stores them, whatever the host's
 * byte order. */
void bf_gltf_put_u16(unsigned char *p, unsigned v);
void bf_gltf_put_f32(unsigned char *p, float f);
/* "data:application/octet-stream;base64,..." of n bytes (malloc'd; NULL when out of
 * memory). */
char *bf_gltf_base64_uri(const unsigned char *p, size_t n);
/* A JSON array of n numbers. */
cJSON *bf_gltf_num_array(const double *v, int n);
/* A bufferView of buffer 0, and an accessor of a view. */
cJSON *bf_gltf_view(int offset, int length, int target);
cJSON *bf_gltf_accessor(int view_index, int type_code, int count, const char *type);

#endif
