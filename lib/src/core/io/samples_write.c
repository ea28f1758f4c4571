/* Writing a sample set in the format its path names (.csv, .binary). Kept apart from
 * the reader dispatch so that writing pulls in no reader. */
#include "brdfit/formats.h"
#include "brdfit/samples.h"

bf_status bf_samples_write(const bf_samples *s, const char *path, bf_format f, bf_error *err)
{
    if (f == BF_FORMAT_AUTO)
        f = bf_format_for_writing(path);
    if (f == BF_FORMAT_MERL)
        return bf_samples_write_merl(s, path, err);
    if (f == BF_FORMAT_CSV)
        return bf_samples_write_csv(s, path, err);
    return bf_fail(err, BF_ERR_ARG, "%s: cannot write %s (writable: .csv, .binary)", path,
                   f == BF_FORMAT_AUTO ? "this file type" : bf_format_name(f));
}
