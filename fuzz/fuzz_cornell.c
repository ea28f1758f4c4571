/* Cornell spectral text (.brdf), and the round trip of what it reads through CSV
 * (wavelength channels named "400", "410" ...). */
#include "fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_read_samples(bf_samples_read_cornell, "in.brdf", data, size);
    return 0;
}
