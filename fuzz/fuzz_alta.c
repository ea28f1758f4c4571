/* ALTA text data (#DIM, #PARAM_IN, #PARAM_OUT, #VS, rows), and the round trip of what
 * it reads through CSV. */
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_read_samples(bf_samples_read_alta, "in.alta", data, size);
    return 0;
}
