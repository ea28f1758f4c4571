/* Internal: Mitsuba's "tensor_file" container, which RGL-EPFL .bsdf materials use:
 * the magic "tensor_file\0", uint8 major and minor version (1, 0), uint32 field count,
 * then per field uint16 name length, the name, uint16 ndim, uint8 dtype, uint64 byte
 * offset of the data and ndim uint64 extents (outermost first); all little-endian. The
 * data of each field lies at its offset, contiguous, last extent fastest. */
#ifndef BF_RGL_TENSOR_FILE_H
#define BF_RGL_TENSOR_FILE_H

#include <stddef.h>
#include <stdint.h>

#include "brdfit/error.h"

/* Mitsuba's Struct::Type numbers; only these two are read. */
#define BF_TENSOR_UINT8 1
#define BF_TENSOR_FLOAT32 10

#define BF_TENSOR_MAX_DIMS 8

typedef struct bf_tensor_field {
    char name[64]; /* longer names are kept cut (no field we read has one) */
    int dtype, ndim;
    size_t shape[BF_TENSOR_MAX_DIMS];
    size_t count;  /* product of the extents */
    size_t offset; /* byte offset of the data in the file */
} bf_tensor_field;

typedef struct bf_tensor_file {
    const char *path;
    const unsigned char *bytes; /* the whole file (not owned) */
    size_t size;
    size_t nfields;
    bf_tensor_field *fields; /* malloc'd */
} bf_tensor_file;

/* Parses the header of a file in memory: every field's name, type and extents, its data
 * checked to lie inside the file (sizes without overflow). Errors "PATH: byte offset N:
 * problem". Free with bf_tensor_file_clear. */
bf_status bf_tensor_file_parse(const char *path, const unsigned char *bytes, size_t size, bf_tensor_file *t,
                               bf_error *err);
void bf_tensor_file_clear(bf_tensor_file *t);

/* The field of that name, or NULL. */
const bf_tensor_field *bf_tensor_file_field(const bf_tensor_file *t, const char *name);

/* *out: a float32 field's values as doubles (malloc'd, f->count), every one finite; NULL
 * with err set naming the field and the byte offset of a NaN or Inf. */
bf_status bf_tensor_field_doubles(const bf_tensor_file *t, const bf_tensor_field *f, double **out, bf_error *err);

#endif
