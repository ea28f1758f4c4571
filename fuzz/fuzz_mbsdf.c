/* NVIDIA .mbsdf tables: text lines, part headers, sizes, values, and the round trip of
 * what it reads through CSV. */
#include "fuzz_common.h"

static bf_status read_mbsdf(const char *path, bf_samples **out, bf_error *err)
{
    return bf_samples_read_mbsdf(path, NULL, out, err);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_read_samples(read_mbsdf, "in.mbsdf", data, size);
    return 0;
}
