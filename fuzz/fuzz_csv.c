/* CSV sample files with the default mapping (theta_i, phi_i, theta_o, phi_o, weight,
 * every other column a channel) and the round trip through the CSV writer; the bare
 * table reader under them; and the reader chosen by content for a file without a
 * known extension. */
#include "io/read_options.h"
#include "fuzz_common.h"

#include "brdfit/formats.h"
#include "brdfit/io.h"

static bf_status read_csv(const char *path, bf_samples **out, bf_error *err)
{
    return bf_samples_read_csv(path, NULL, out, err);
}

static bf_status read_any(const char *path, bf_samples **out, bf_error *err)
{
    return bf_samples_read(path, NULL, out, err);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_read_samples(read_csv, "in.csv", data, size);
    bf_error err;
    bf_csv *t = NULL;
    int rc = bf_csv_read(fuzz_path("in.csv"), &t, &err);
    fuzz_check_result(rc, &err, t);
    bf_csv_free(t);
    fuzz_read_samples(read_any, "in.data", data, size);
    return 0;
}
