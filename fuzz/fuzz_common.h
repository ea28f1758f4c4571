/* Shared by the libFuzzer harnesses: scratch files (the readers take paths), the
 * checks every harness makes on what a reader returns, and the CSV round trip. A
 * failed check aborts, which libFuzzer reports as a crash with the input. */
#ifndef BRDFIT_FUZZ_COMMON_H
#define BRDFIT_FUZZ_COMMON_H

#include <stddef.h>
#include <stdint.h>

#include "brdfit/error.h"
#include "brdfit/formats.h"
#include "brdfit/samples.h"

/* Prints the message and aborts. */
void fuzz_fail(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2), noreturn))
#endif
    ;

/* A path in this process's scratch folder (made on first use, removed at exit). */
const char *fuzz_path(const char *name);
/* Writes the bytes to fuzz_path(name) and returns that path. */
const char *fuzz_write(const char *name, const uint8_t *data, size_t size);

/* What every reader owes its caller: BF_OK, or a known error code with a message that
 * is safe to print (one line, at most BF_ERROR_MAX_CHARS characters, no control bytes,
 * valid UTF-8 without C1 controls), checked here independently of the library. */
void fuzz_check_result(int rc, const bf_error *err, const void *out);

/* The same samples: count, channels, directions, values and weights bit for bit (NaN
 * nowhere), channel names the same or renamed NAME_k as the CSV writer does. */
void fuzz_same_samples(const bf_samples *a, const bf_samples *b, const char *what);

/* Writes s as CSV, reads it back with the default mapping and checks both are the same
 * samples: whatever brdfit reads and writes as CSV, it reads back. */
void fuzz_csv_round_trip(const bf_samples *s);

/* The input as file NAME through a sample reader, checked, and what it reads through
 * the CSV round trip. */
typedef bf_status (*fuzz_reader)(const char *path, bf_samples **out, bf_error *err);
void fuzz_read_samples(fuzz_reader read, const char *name, const uint8_t *data, size_t size);

#endif
