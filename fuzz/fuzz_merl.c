/* MERL tables (.binary). A table is 35 MB and a fuzz input a few kB, so the first byte
 * chooses how the rest is used:
 *   even: as the file itself (header, size and value checks: every error path);
 *   odd:  12 header bytes, then the rest repeated to the full table size: a table that
 *         reads, with whatever values the input holds. Read keeping the raw table and
 *         written back, it must give the same bytes; read without it, the same samples;
 *         a few of its samples must survive the CSV round trip. */
#include "fuzz_common.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define HEADER 12
#define TABLE_BYTES ((size_t)3 * BF_MERL_CELLS * sizeof(double))

#ifndef MERL_FILE_ONLY
static unsigned char *slurp(const char *path, size_t *n)
{
    FILE *fp = fopen(path, "rb");
    unsigned char *buf = fp ? malloc(HEADER + TABLE_BYTES + 1) : NULL;
    if (!buf)
        fuzz_fail("cannot read %s", path);
    *n = fread(buf, 1, HEADER + TABLE_BYTES + 1, fp);
    fclose(fp);
    return buf;
}

static void full_table(const uint8_t *data, size_t size)
{
    if (size < HEADER + 1)
        return;
    unsigned char *file = malloc(HEADER + TABLE_BYTES);
    if (!file)
        fuzz_fail("out of memory");
    memcpy(file, data, HEADER);
    /* The pattern, then the filled part copied onto the rest, doubling. */
    size_t filled = size - HEADER < TABLE_BYTES ? size - HEADER : TABLE_BYTES;
    memcpy(file + HEADER, data + HEADER, filled);
    for (size_t n; filled < TABLE_BYTES; filled += n) {
        n = filled < TABLE_BYTES - filled ? filled : TABLE_BYTES - filled;
        memcpy(file + HEADER + filled, file + HEADER, n);
    }
    const char *in = fuzz_write("in.binary", file, HEADER + TABLE_BYTES);
    bf_error err;
    bf_samples *raw = NULL, *plain = NULL;
    int rc = bf_samples_read_merl(in, 1, &raw, &err);
    fuzz_check_result(rc, &err, raw);
    int rc2 = bf_samples_read_merl(in, 0, &plain, &err);
    fuzz_check_result(rc2, &err, plain);
    if ((rc == BF_OK) != (rc2 == BF_OK))
        fuzz_fail("the table reads %s the raw table but not %s", rc == BF_OK ? "with" : "without",
                  rc == BF_OK ? "without" : "with");
    if (raw) {
        fuzz_same_samples(raw, plain, "MERL with and without the raw table");
        const char *out = fuzz_path("out.binary");
        if (bf_samples_write_merl(raw, out, &err) != BF_OK)
            fuzz_fail("writing the table back: %s", err.msg);
        size_t n;
        unsigned char *back = slurp(out, &n);
        if (n != HEADER + TABLE_BYTES || memcmp(back, file, n) != 0)
            fuzz_fail("the table written back differs from the one read");
        free(back);
        /* Every 4099th sample (cell directions in degrees) through CSV. */
        unsigned char *keep = calloc(plain->n + 1, 1);
        if (!keep)
            fuzz_fail("out of memory");
        for (size_t i = 0; i < plain->n; i += 4099)
            keep[i] = 1;
        bf_samples *few = NULL;
        if (bf_samples_copy(plain, keep, &few, &err) != BF_OK)
            fuzz_fail("copy: %s", err.msg);
        fuzz_csv_round_trip(few);
        bf_samples_free(few);
        free(keep);
    }
    bf_samples_free(raw);
    bf_samples_free(plain);
    free(file);
}

#endif

#ifdef MERL_FILE_ONLY
/* The merl_file target: every input is the file itself, read with and without the raw
 * table. No input short of 35 MB reads, so this is the header, size and truncation checks
 * at thousands of executions a second, where the merl target makes about one a second. */
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_write("in.binary", data, size);
    for (int keep = 0; keep < 2; keep++) {
        bf_error err;
        bf_samples *s = NULL;
        int rc = bf_samples_read_merl(path, keep, &s, &err);
        fuzz_check_result(rc, &err, s);
        bf_samples_free(s);
    }
    return 0;
}
#else
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0)
        return 0;
    if (data[0] & 1) {
        full_table(data + 1, size - 1);
        return 0;
    }
    const char *path = fuzz_write("in.binary", data + 1, size - 1);
    bf_error err;
    bf_samples *s = NULL;
    int rc = bf_samples_read_merl(path, data[0] & 2, &s, &err);
    fuzz_check_result(rc, &err, s);
    bf_samples_free(s);
    return 0;
}
#endif
