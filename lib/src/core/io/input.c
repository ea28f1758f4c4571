/* Inputs by name, "-" being standard input (io.h, bf_input_open). Standard input is read
 * whole on first use and kept, because readers open a file more than once (the format
 * is sniffed from the first lines, then the reader starts over) and a pipe cannot be
 * rewound; every later open reads the kept bytes again. */
#include "brdfit/io.h"

#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "base/big_alloc.h"

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static char *kept;
static size_t kept_len;
static int kept_state; /* 0 not read, 1 read, -1 failed (errno in kept_errno) */
static int kept_errno;

/* Reads standard input to its end; called with the lock held. */
static void keep_stdin(void)
{
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap);
    while (buf) {
        n += fread(buf + n, 1, cap - n, stdin);
        if (n < cap)
            break;
        char *more = bf_memory_allows(cap) ? realloc(buf, cap * 2) : NULL;
        if (!more) {
            free(buf);
            buf = NULL;
            errno = ENOMEM;
            break;
        }
        buf = more;
        cap *= 2;
    }
    if (!buf || ferror(stdin)) {
        kept_errno = buf ? EIO : errno;
        free(buf);
        kept_state = -1;
        return;
    }
    kept = buf;
    kept_len = n;
    kept_state = 1;
}

FILE *bf_input_open(const char *path)
{
    if (strcmp(path, "-")) {
        /* A device is no data file, and some never end (/dev/zero, a terminal): refused
         * before any byte is read. Pipes (FIFOs) stay allowed. */
        struct stat st;
        if (stat(path, &st) == 0 && (S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode))) {
            errno = ENODEV;
            return NULL;
        }
        return fopen(path, "rb");
    }
    pthread_mutex_lock(&lock);
    if (kept_state == 0)
        keep_stdin();
    const int state = kept_state, e = kept_errno;
    pthread_mutex_unlock(&lock);
    if (state < 0) {
        errno = e;
        return NULL;
    }
    /* fmemopen of an empty buffer fails; an empty input reads as an empty file. */
    static char empty[1];
    FILE *fp = fmemopen(kept_len ? kept : empty, kept_len ? kept_len : 1, "rb");
    if (fp && !kept_len)
        fseek(fp, 0, SEEK_END);
    return fp;
}

const char *bf_input_error(int e)
{
    return e == ENODEV ? "a device, not a data file" : strerror(e);
}
