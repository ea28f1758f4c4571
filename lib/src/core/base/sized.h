/* Structs that carry their size (docs/api.md): the caller sets the first member, size,
 * to the sizeof it was compiled with (bf_x_init); fields are only ever added at the
 * end, so the library reads or writes the members that lie within that size and no
 * further, and an older program keeps working with a newer library. */
#ifndef BRDFIT_SIZED_H
#define BRDFIT_SIZED_H

#include <stddef.h>
#include <string.h>

#include "brdfit/error.h"

/* BF_OK when *dst (a struct whose first member is its size) has a size the library can
 * take: at least the first version's (min: its size then), else BF_ERR_ARG naming what. */
static inline bf_status bf_sized_check(const void *dst, size_t min, const char *what, bf_error *err)
{
    size_t n = *(const size_t *)dst;
    if (n < min)
        return bf_fail(err, BF_ERR_ARG, "%s: size %zu is not that of a %s (set it with its init function)", what, n,
                       what);
    return BF_OK;
}

/* Copies the library's whole struct src (lib_size bytes, size first) into dst as far as
 * dst's own size reaches, dst's size kept. */
static inline void bf_sized_copy(void *dst, const void *src, size_t lib_size)
{
    size_t n = *(const size_t *)dst;
    if (n > lib_size)
        n = lib_size;
    if (n > sizeof(size_t))
        memcpy((char *)dst + sizeof(size_t), (const char *)src + sizeof(size_t), n - sizeof(size_t));
}

/* The body of every bf_x_init_size: x, as the program has it (size bytes), from full, the
 * library's own struct with its defaults (lib_size bytes): the members within size, size
 * itself, and zeros for any tail this library does not know. */
static inline void bf_sized_init(void *x, size_t size, void *full, size_t lib_size)
{
    *(size_t *)full = size;
    memcpy(x, full, size < lib_size ? size : lib_size);
    if (size > lib_size)
        memset((char *)x + lib_size, 0, size - lib_size);
}

/* The library's bf_x_init_size for struct T (docs/api.md): a whole T zeroed, then given
 * its defaults by defaults(T *) (BF_SIZED_INIT_ZERO: none but zeros), copied into the
 * program's as far as its size reaches. */
#define BF_SIZED_INIT(T, defaults)                                                                                     \
    void T##_init_size(T *x, size_t size)                                                                              \
    {                                                                                                                  \
        T full;                                                                                                        \
        memset(&full, 0, sizeof full);                                                                                 \
        defaults(&full);                                                                                               \
        bf_sized_init(x, size, &full, sizeof full);                                                                    \
    }
#define BF_SIZED_INIT_ZERO(T)                                                                                          \
    void T##_init_size(T *x, size_t size)                                                                              \
    {                                                                                                                  \
        T full;                                                                                                        \
        memset(&full, 0, sizeof full);                                                                                 \
        bf_sized_init(x, size, &full, sizeof full);                                                                    \
    }

#endif
