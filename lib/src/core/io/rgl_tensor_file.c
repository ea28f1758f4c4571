/* Mitsuba tensor files (rgl_tensor_file.h). Every size read from the file is checked
 * before it is used: a hostile header gets a one-line error, not an overflow. */
#include "rgl_tensor_file.h"

#include "read_binary.h"

#include "base/big_alloc.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAGIC "tensor_file" /* 12 bytes with its NUL */
#define HEADER_BYTES (12 + 2 + 4)
#define MAX_FIELDS 4096 /* RGL files have 11 */

static size_t type_size(int dtype)
{
    /* Mitsuba's Struct::Type: 1, 2 (u)int8; 3, 4 (u)int16; 5, 6 (u)int32; 7, 8 (u)int64;
     * 9 float16, 10 float32, 11 float64. */
    static const size_t sizes[12] = {0, 1, 1, 2, 2, 4, 4, 8, 8, 2, 4, 8};
    return dtype >= 1 && dtype <= 11 ? sizes[dtype] : 0;
}

/* Reads one field's header at *pos; 0 or an error. */
static bf_status parse_field(const bf_tensor_file *t, size_t *pos, bf_tensor_field *f, bf_error *err)
{
    const unsigned char *b = t->bytes;
    const size_t at = *pos;
    if (t->size - *pos < 2)
        return bf_fail(err, BF_ERR_PARSE, "%s: byte offset %zu: file ends inside a field header", t->path, *pos);
    const size_t name_len = bf_le_u16(b + *pos);
    *pos += 2;
    if (t->size - *pos < name_len + 2 + 1 + 8)
        return bf_fail(err, BF_ERR_PARSE, "%s: byte offset %zu: file ends inside a field header", t->path, at);
    const size_t keep = name_len < sizeof f->name ? name_len : sizeof f->name - 1;
    memcpy(f->name, b + *pos, keep);
    f->name[keep] = '\0';
    *pos += name_len;
    f->ndim = bf_le_u16(b + *pos);
    f->dtype = b[*pos + 2];
    const uint64_t offset = bf_le_u64(b + *pos + 3);
    *pos += 11;
    if (f->ndim > BF_TENSOR_MAX_DIMS)
        return bf_fail(err, BF_ERR_PARSE, "%s: byte offset %zu: field '%s' has %d dimensions (at most %d)", t->path, at,
                       f->name, f->ndim, BF_TENSOR_MAX_DIMS);
    const size_t width = type_size(f->dtype);
    if (!width)
        return bf_fail(err, BF_ERR_PARSE, "%s: byte offset %zu: field '%s' has unknown data type %d", t->path, at,
                       f->name, f->dtype);
    if (t->size - *pos < (size_t)f->ndim * 8)
        return bf_fail(err, BF_ERR_PARSE, "%s: byte offset %zu: file ends inside a field header", t->path, at);
    size_t count = 1;
    for (int d = 0; d < f->ndim; d++, *pos += 8) {
        const uint64_t e = bf_le_u64(b + *pos);
        if (e > t->size || (e && count > t->size / e))
            return bf_fail(err, BF_ERR_PARSE, "%s: byte offset %zu: field '%s' is larger than the file", t->path, *pos,
                           f->name);
        f->shape[d] = (size_t)e;
        count *= (size_t)e;
    }
    f->count = count;
    if (offset > t->size || count > (t->size - offset) / width)
        return bf_fail(err, BF_ERR_PARSE,
                       "%s: byte offset %zu: field '%s' (%zu values at byte %llu) does not fit in the %zu-byte file",
                       t->path, at, f->name, count, (unsigned long long)offset, t->size);
    f->offset = (size_t)offset;
    return BF_OK;
}

bf_status bf_tensor_file_parse(const char *path, const unsigned char *bytes, size_t size, bf_tensor_file *t,
                               bf_error *err)
{
    memset(t, 0, sizeof *t);
    t->path = path;
    t->bytes = bytes;
    t->size = size;
    if (size < HEADER_BYTES || memcmp(bytes, MAGIC, 12) != 0)
        return bf_fail(err, BF_ERR_PARSE, "%s: byte offset 0: not a tensor file (it starts with \"tensor_file\")",
                       path);
    if (bytes[12] != 1 || bytes[13] != 0)
        return bf_fail(err, BF_ERR_PARSE, "%s: byte offset 12: tensor file version %u.%u, only 1.0 is read", path,
                       bytes[12], bytes[13]);
    const uint32_t n = bf_le_u32(bytes + 14);
    if (n > MAX_FIELDS)
        return bf_fail(err, BF_ERR_PARSE, "%s: byte offset 14: %lu fields (at most %d)", path, (unsigned long)n,
                       MAX_FIELDS);
    t->fields = calloc(n ? n : 1, sizeof *t->fields);
    if (!t->fields)
        return bf_fail_memory(err, path, 0, n * sizeof *t->fields);
    size_t pos = HEADER_BYTES;
    for (t->nfields = 0; t->nfields < n; t->nfields++) {
        bf_status rc = parse_field(t, &pos, &t->fields[t->nfields], err);
        if (rc != BF_OK) {
            bf_tensor_file_clear(t);
            return rc;
        }
    }
    return BF_OK;
}

void bf_tensor_file_clear(bf_tensor_file *t)
{
    free(t->fields);
    t->fields = NULL;
    t->nfields = 0;
}

const bf_tensor_field *bf_tensor_file_field(const bf_tensor_file *t, const char *name)
{
    for (size_t i = 0; i < t->nfields; i++)
        if (!strcmp(t->fields[i].name, name))
            return &t->fields[i];
    return NULL;
}

bf_status bf_tensor_field_doubles(const bf_tensor_file *t, const bf_tensor_field *f, double **out, bf_error *err)
{
    *out = NULL;
    double *v = bf_big_malloc((f->count ? f->count : 1) * sizeof *v);
    if (!v)
        return bf_fail_memory(err, t->path, 0, f->count * sizeof *v);
    const unsigned char *p = t->bytes + f->offset;
    for (size_t i = 0; i < f->count; i++, p += 4) {
        v[i] = bf_le_f32(p);
        if (!isfinite(v[i])) {
            bf_status rc = bf_fail(err, BF_ERR_PARSE, "%s: byte offset %zu: field '%s' value %zu is %s", t->path,
                                   f->offset + 4 * i, f->name, i, isnan(v[i]) ? "NaN" : "Inf");
            free(v);
            return rc;
        }
    }
    *out = v;
    return BF_OK;
}
