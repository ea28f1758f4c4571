/* RGL-EPFL .bsdf tensor files: the header, the warps (a hostile VNDF) and the
 * evaluation at the measured points, and the round trip of what it reads through CSV. */
#include "fuzz_common.h"

static bf_status read_rgl(const char *path, bf_samples **out, bf_error *err)
{
    return bf_samples_read_rgl(path, NULL, out, err);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_read_samples(read_rgl, "in.bsdf", data, size);
    return 0;
}
