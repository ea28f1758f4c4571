/* Scratch files, result checks and the CSV round trip for the harnesses (fuzz_common.h). */
#include "io/read_options.h"
#include "fuzz_common.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "brdfit/formats.h"
#include "brdfit/io.h"

void fuzz_fail(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("fuzz check failed: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    abort();
}

static char scratch[256];
static char names[16][64];
static int nnames;

static void remove_scratch(void)
{
    char path[512];
    for (int i = 0; i < nnames; i++) {
        snprintf(path, sizeof path, "%s/%s", scratch, names[i]);
        unlink(path);
    }
    rmdir(scratch);
}

const char *fuzz_path(const char *name)
{
    static char path[16][512];
    if (!scratch[0]) {
        /* $TMPDIR, else memory (/dev/shm): every execution writes files, and on a disk
         * file system creating and renaming them costs ten times the parsing. */
        const char *tmp = getenv("TMPDIR");
        if (!tmp || !*tmp)
            tmp = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
        snprintf(scratch, sizeof scratch, "%s/brdfit_fuzz_XXXXXX", tmp);
        if (!mkdtemp(scratch))
            fuzz_fail("cannot make a scratch folder in %s", tmp);
        atexit(remove_scratch);
    }
    int i = 0;
    while (i < nnames && strcmp(names[i], name) != 0)
        i++;
    if (i == nnames) {
        if (nnames == 16 || strlen(name) >= sizeof names[0])
            fuzz_fail("too many scratch names (%s)", name);
        snprintf(names[nnames++], sizeof names[0], "%s", name);
        snprintf(path[i], sizeof path[i], "%s/%s", scratch, name);
    }
    return path[i];
}

const char *fuzz_write(const char *name, const uint8_t *data, size_t size)
{
    const char *path = fuzz_path(name);
    FILE *fp = fopen(path, "wb");
    if (!fp || fwrite(data, 1, size, fp) != size || fclose(fp) != 0)
        fuzz_fail("cannot write %s", path);
    return path;
}

/* Length of the UTF-8 sequence at s that is a printable character, or 0. */
static size_t printable_char(const unsigned char *s)
{
    if (s[0] >= 0x20 && s[0] < 0x7f)
        return 1;
    size_t n = s[0] >= 0xc2 && s[0] <= 0xdf   ? 2
               : s[0] >= 0xe0 && s[0] <= 0xef ? 3
               : s[0] >= 0xf0 && s[0] <= 0xf4 ? 4
                                              : 0;
    unsigned cp = s[0] & (0x7f >> n);
    for (size_t k = 1; k < n; k++) {
        if ((s[k] & 0xc0) != 0x80)
            return 0;
        cp = cp << 6 | (s[k] & 0x3f);
    }
    if (n == 0 || (n == 3 && cp < 0x800) || (n == 4 && (cp < 0x10000 || cp > 0x10ffff)) ||
        (cp >= 0xd800 && cp <= 0xdfff) || cp <= 0x9f || (cp >= 0x2028 && cp <= 0x202e) ||
        (cp >= 0x2066 && cp <= 0x2069))
        return 0;
    return n;
}

void fuzz_check_result(int rc, const bf_error *err, const void *out)
{
    if (rc == BF_OK) {
        if (!out)
            fuzz_fail("BF_OK without a result");
        return;
    }
    if (rc < BF_ERR_ARG || rc > BF_ERR_NOMEM || (int)err->code != rc)
        fuzz_fail("return code %d, error code %d", rc, (int)err->code);
    if (out)
        fuzz_fail("an error (%s) with a result", err->msg);
    const unsigned char *m = (const unsigned char *)err->msg;
    size_t chars = 0, bytes = strnlen(err->msg, sizeof err->msg);
    if (bytes == 0 || bytes == sizeof err->msg)
        fuzz_fail("error message empty or not terminated");
    for (size_t i = 0; i < bytes; chars++) {
        size_t n = printable_char(m + i);
        if (!n)
            fuzz_fail("error message byte %zu (0x%02x) is not printable: %s", i, m[i], err->msg);
        i += n;
    }
    if (chars > BF_ERROR_MAX_CHARS)
        fuzz_fail("error message of %zu characters: %s", chars, err->msg);
}

static int same_double(double a, double b)
{
    return a == b && !isnan(a) && signbit(a) == signbit(b);
}

/* b's name is a's, or a's with "_<digits>" appended (the writer's renaming). */
static int same_name(const char *a, const char *b)
{
    size_t n = strlen(a);
    if (strncmp(a, b, n) != 0)
        return 0;
    if (!b[n])
        return 1;
    if (b[n] != '_' || !b[n + 1])
        return 0;
    return strspn(b + n + 1, "0123456789") == strlen(b + n + 1);
}

void fuzz_same_samples(const bf_samples *a, const bf_samples *b, const char *what)
{
    if (a->n != b->n || a->channels != b->channels)
        fuzz_fail("%s: %zu samples x %d channels became %zu x %d", what, a->n, a->channels, b->n, b->channels);
    const size_t C = (size_t)a->channels;
    for (size_t c = 0; c < C; c++)
        if (!same_name(a->channel_names[c], b->channel_names[c]))
            fuzz_fail("%s: channel %zu '%s' became '%s'", what, c, a->channel_names[c], b->channel_names[c]);
    if ((a->weight != NULL) != (b->weight != NULL))
        fuzz_fail("%s: weights %s", what, a->weight ? "lost" : "appeared");
    /* MERL cells on both sides: the same cells are the same directions. */
    const int cells = a->merl && b->merl;
    if (cells && memcmp(a->merl->cell, b->merl->cell, a->n * sizeof *a->merl->cell) != 0)
        fuzz_fail("%s: MERL cells differ", what);
    for (size_t i = 0; i < a->n; i++) {
        double da[4], db[4];
        if (!cells) {
            bf_samples_direction(a, i, da);
            bf_samples_direction(b, i, db);
        }
        for (int k = 0; !cells && k < 4; k++)
            if (!same_double(da[k], db[k]))
                fuzz_fail("%s: sample %zu angle %d: %.17g became %.17g", what, i, k, da[k], db[k]);
        for (size_t c = 0; c < C; c++)
            if (!same_double(a->value[i * C + c], b->value[i * C + c]))
                fuzz_fail("%s: sample %zu channel %zu: %.17g became %.17g", what, i, c, a->value[i * C + c],
                          b->value[i * C + c]);
        if (a->weight && !same_double(a->weight[i], b->weight[i]))
            fuzz_fail("%s: sample %zu weight %.17g became %.17g", what, i, a->weight[i], b->weight[i]);
    }
}

void fuzz_read_samples(fuzz_reader read, const char *name, const uint8_t *data, size_t size)
{
    bf_error err;
    bf_samples *s = NULL;
    int rc = read(fuzz_write(name, data, size), &s, &err);
    fuzz_check_result(rc, &err, s);
    if (s)
        fuzz_csv_round_trip(s);
    bf_samples_free(s);
}

void fuzz_csv_round_trip(const bf_samples *s)
{
    const char *path = fuzz_path("round_trip.csv");
    bf_error err;
    if (bf_samples_write_csv(s, path, &err) != BF_OK)
        fuzz_fail("writing the CSV: %s", err.msg);
    bf_samples *back = NULL;
    if (bf_samples_read_csv(path, NULL, &back, &err) != BF_OK)
        fuzz_fail("reading back the CSV written: %s", err.msg);
    fuzz_same_samples(s, back, "CSV round trip");
    bf_samples_free(back);
}
