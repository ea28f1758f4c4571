/* Limits on sizes that files declare, checked before any arithmetic or allocation:
 * hostile or broken files must get a one-line error, not an overflow or an attempt to
 * allocate terabytes.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_LIMITS_H
#define BRDFIT_LIMITS_H

#include <stddef.h>

#include "brdfit/api.h"
#include "brdfit/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Channels of a sample set or a model (wavelengths of a spectral measurement, values of
 * an ALTA row, "channels" of a parameter file). Spectral data at 1 nm from 300 to
 * 2500 nm has 2,201; this leaves room and keeps a model's parameter vector (at most 64
 * parameters x channels) and every count derived from it far inside int. */
#define BF_MAX_CHANNELS 10000

/* Columns of a CSV table (channels plus angles, weights and ignored columns). */
#define BF_CSV_MAX_COLUMNS 65536

/* Memory: bytes this process may still allocate: the least of what the machine has
 * available, what its control group (container, batch job) still allows, its
 * address-space limit (ulimit -v) and the environment variable BRDFIT_MEMORY (bytes, or
 * with a K, M, G or T suffix: powers of 1024). SIZE_MAX when nothing is known. Arrays of
 * 1 MiB or more that grow with the input (samples, tables, images) are refused beyond it,
 * with a message saying so, rather than taken from memory the kernel would then kill the
 * process for touching. */
BF_API size_t bf_memory_available(void);

/* "123", "512M", "4G": a byte count as BRDFIT_MEMORY takes it (K, M, G, T: powers of
 * 1024, either case), into *out. BF_ERR_ARG when s is not one (NULL, empty, signs,
 * spaces, other suffixes, overflow). */
BF_API bf_status bf_bytes_parse(const char *s, size_t *out, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
