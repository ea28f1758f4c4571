/* Large arrays on transparent huge pages (big_alloc.h). */
#include "big_alloc.h"

#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#define HUGE_PAGE ((size_t)2 << 20)
#define BIG_ENOUGH ((size_t)1 << 20) /* below this, a huge page would be mostly waste */

void *bf_big_malloc(size_t bytes)
{
    if (bytes < BIG_ENOUGH)
        return malloc(bytes ? bytes : 1);
    if (!bf_memory_allows(bytes)) {
        errno = ENOMEM;
        return NULL;
    }
    /* Whole huge pages, so that the last one is the allocation's too. */
    if (bytes > SIZE_MAX - HUGE_PAGE)
        return NULL;
    const size_t whole = (bytes + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
    void *p = NULL;
    if (posix_memalign(&p, HUGE_PAGE, whole) != 0)
        return NULL;
#ifdef MADV_HUGEPAGE
    /* Advice only: where it is refused the memory is still good, with 4 KiB pages. */
    (void)madvise(p, whole, MADV_HUGEPAGE);
#endif
    return p;
}

void *bf_big_calloc(size_t n, size_t size)
{
    if (size && n > SIZE_MAX / size)
        return NULL;
    size_t bytes = n * size;
    if (bytes < BIG_ENOUGH)
        return calloc(n ? n : 1, size ? size : 1);
    void *p = bf_big_malloc(bytes);
    if (p)
        memset(p, 0, bytes);
    return p;
}
