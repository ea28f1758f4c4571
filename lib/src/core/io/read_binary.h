/* Internal: a whole binary file in memory, for the readers of formats addressed by byte
 * offsets (RGL-EPFL tensor files, NVIDIA mbsdf tables), and the little-endian scalars
 * they hold. */
#ifndef BF_READ_BINARY_H
#define BF_READ_BINARY_H

#include <stddef.h>
#include <stdint.h>

#include "brdfit/error.h"

/* The file's bytes (path "-": standard input) into *out, malloc'd (large ones through
 * bf_big_malloc, so they count against the memory limit); *len = bytes read. Errors
 * "PATH: cannot open: reason", "PATH: read error", "PATH: empty file", or not enough
 * memory. */
bf_status bf_read_binary(const char *path, unsigned char **out, size_t *len, bf_error *err);

/* Little-endian scalars at p (any alignment), whatever the host's byte order. */
uint16_t bf_le_u16(const unsigned char *p);
uint32_t bf_le_u32(const unsigned char *p);
uint64_t bf_le_u64(const unsigned char *p);
float bf_le_f32(const unsigned char *p);

#endif
