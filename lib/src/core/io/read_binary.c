/* Whole binary files in memory (read_binary.h). */
#include "read_binary.h"

#include "brdfit/io.h"

#include "base/big_alloc.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* A regular file is read in one allocation of its size; anything else (standard input,
 * a pipe) grows its buffer by doubling, each step checked against the memory limit. */
bf_status bf_read_binary(const char *path, unsigned char **out, size_t *len, bf_error *err)
{
    *out = NULL;
    *len = 0;
    FILE *fp = bf_input_open(path);
    if (!fp) {
        return bf_fail(err, BF_ERR_IO, "%s: cannot open: %s", path, bf_input_error(errno));
    }
    struct stat st;
    size_t cap = 1 << 16;
    if (fileno(fp) >= 0 && fstat(fileno(fp), &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0)
        cap = (size_t)st.st_size + 1; /* + 1: reaching EOF inside the buffer proves the size */
    unsigned char *buf = bf_big_malloc(cap);
    size_t n = 0;
    while (buf) {
        n += fread(buf + n, 1, cap - n, fp);
        if (n < cap || ferror(fp))
            break;
        unsigned char *more = cap <= ((size_t)-1) / 2 && bf_memory_allows(cap * 2) ? realloc(buf, cap * 2) : NULL;
        if (!more) {
            free(buf);
            buf = NULL;
            break;
        }
        buf = more;
        cap *= 2;
    }
    const int read_failed = buf && ferror(fp);
    fclose(fp);
    if (!buf)
        return bf_fail_memory(err, path, 0, cap * 2);
    if (read_failed || n == 0) {
        free(buf);
        return read_failed ? bf_fail(err, BF_ERR_IO, "%s: read error", path)
                           : bf_fail(err, BF_ERR_PARSE, "%s: empty file", path);
    }
    *out = buf;
    *len = n;
    return BF_OK;
}

uint16_t bf_le_u16(const unsigned char *p)
{
    return (uint16_t)(p[0] | (unsigned)p[1] << 8);
}

uint32_t bf_le_u32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

uint64_t bf_le_u64(const unsigned char *p)
{
    return (uint64_t)bf_le_u32(p) | (uint64_t)bf_le_u32(p + 4) << 32;
}

float bf_le_f32(const unsigned char *p)
{
    const uint32_t u = bf_le_u32(p);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}
