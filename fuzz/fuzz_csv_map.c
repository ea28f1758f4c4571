/* CSV sample files read with a column mapping (--angles, --channels, --weight,
 * --radians). The input's first line is the mapping, the rest the file:
 *   ANGLES|CHANNELS|WEIGHT|RADIANS
 * four comma-separated angle column names (or empty: the defaults), the channel list
 * (empty: every other column), the weight column (empty: "weight" if present) and
 * anything non-empty for radians. Whatever is read must survive the CSV round trip:
 * value columns named like angle or weight columns are the case that needs care. */
#include "io/read_options.h"
#include "fuzz_common.h"

#include <stdlib.h>
#include <string.h>

#include "brdfit/formats.h"
#include "brdfit/io.h"

/* The next '|'-separated piece of *p, NUL-terminated in place. */
static char *piece(char **p)
{
    char *s = *p, *bar = strchr(s, '|');
    if (bar) {
        *bar = '\0';
        *p = bar + 1;
    } else {
        *p = s + strlen(s);
    }
    return s;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const uint8_t *nl = memchr(data, '\n', size);
    if (!nl)
        return 0;
    size_t mlen = (size_t)(nl - data);
    char *spec = malloc(mlen + 1);
    if (!spec)
        return 0;
    memcpy(spec, data, mlen);
    spec[mlen] = '\0';
    if (strlen(spec) != mlen) { /* a NUL in the mapping: no command line can give one */
        free(spec);
        return 0;
    }
    char *p = spec, *angles = piece(&p), *channels = piece(&p), *weight = piece(&p), *radians = piece(&p);
    bf_csv_map map = {{NULL, NULL, NULL, NULL}, *radians != '\0', *channels ? channels : NULL, *weight ? weight : NULL};
    /* Angle names: four comma-separated, as --angles takes them; otherwise the defaults. */
    char *a[4] = {angles, NULL, NULL, NULL};
    int k = 1;
    for (char *q = angles; k < 4 && (q = strchr(q, ',')); k++) {
        *q++ = '\0';
        a[k] = q;
    }
    if (k == 4 && !strchr(a[3], ','))
        for (int j = 0; j < 4; j++)
            map.angle_cols[j] = a[j];

    const char *path = fuzz_write("in.csv", nl + 1, size - mlen - 1);
    bf_error err;
    bf_samples *s = NULL;
    int rc = bf_samples_read_csv(path, &map, &s, &err);
    fuzz_check_result(rc, &err, s);
    if (s)
        fuzz_csv_round_trip(s);
    bf_samples_free(s);
    free(spec);
    return 0;
}
