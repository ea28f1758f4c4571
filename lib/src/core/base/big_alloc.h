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

#include "brdfit/error.h"

#include <stddef.h>

/* Requests below this are not checked against the memory available (memory.c). */
#define BF_MEMORY_UNCHECKED ((size_t)1 << 20)

/* 1 when `bytes` more may be allocated: under BF_MEMORY_UNCHECKED, or at most
 * bf_memory_available(). */
int bf_memory_allows(size_t bytes);

/* The error for an array of `bytes` refused or not obtained while reading path (at line,
 * when not 0): "PATH:LINE: not enough memory: 9.6 GB needed, 4.2 GB available". */
bf_status bf_fail_memory(bf_error *err, const char *path, size_t line, size_t bytes);

/* bytes (> 0) uninitialised, or NULL (also when bf_memory_allows refuses them). */
void *bf_big_malloc(size_t bytes);
/* n * size bytes zeroed (n * size checked for overflow), or NULL. */
void *bf_big_calloc(size_t n, size_t size);

#endif
