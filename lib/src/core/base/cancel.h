/* Internal: reading a caller's cancel flag (bf_cancel_flag, brdfit/error.h), which a
 * signal handler or another thread may set while the library works. */
#ifndef BRDFIT_CANCEL_H
#define BRDFIT_CANCEL_H

#include "brdfit/error.h"

/* 1 when flag (NULL: none) is set: an atomic load where the compiler has one, else the
 * volatile read. */
static inline int bf_cancel_is_set(const bf_cancel_flag *flag)
{
#if defined(__GNUC__)
    return flag && __atomic_load_n(flag, __ATOMIC_RELAXED);
#else
    return flag && *flag;
#endif
}

#endif
