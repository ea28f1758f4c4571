/* Internal: allocation of the large per-sample arrays (values, MERL cells, measurement
 * terms, the table being read). They are aligned to 2 MiB and marked for transparent
 * huge pages where the system has them, so that first touching them costs one page
 * fault per 2 MiB instead of one per 4 KiB: on the 2-core machines brdfit is measured
 * on, a 4 KiB fault costs about 15 us, and touching 64 MB took 240 ms with 4 KiB pages
 * against 40 ms with huge pages. Requests under 1 MiB are plain malloc; the others are
 * rounded up to whole huge pages (at most 2 MiB more). Free with free();
 * realloc works on them (it keeps neither the alignment nor the advice, which only
 * matter for first touches). */
#ifndef BF_BIG_ALLOC_H
#define BF_BIG_ALLOC_H

#include <stddef.h>

/* bytes (> 0) uninitialised, or NULL. */
void *bf_big_malloc(size_t bytes);
/* n * size bytes zeroed (n * size checked for overflow), or NULL. */
void *bf_big_calloc(size_t n, size_t size);

#endif
