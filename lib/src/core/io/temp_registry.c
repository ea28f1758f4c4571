/* The registry of live temporaries (temp_registry.h) and the fatal-signal handler that
 * removes them (bf_remove_temporaries_on_signals, io.h).
 *
 * The handler may run on any thread at any moment, so the registry is guarded by a spin
 * lock that its holders take with every signal blocked on their thread: a handler never
 * interrupts the holder it would wait for. The handler takes the lock and keeps it (the
 * process ends with the signal), so no other thread changes the list under it; it uses
 * only async-signal-safe calls (unlink, rmdir, open, getdents64, unlinkat, raise). */
#define _GNU_SOURCE /* getdents64 */
#include "io/temp_registry.h"

#include "brdfit/io.h"
#include "brdfit/tool.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

typedef struct entry {
    char *path; /* NULL: a free slot */
    int is_dir;
} entry;

static atomic_flag lock = ATOMIC_FLAG_INIT;
static entry *entries;
static size_t nentries, capacity;

static void acquire(sigset_t *old)
{
    sigset_t all;
    sigfillset(&all);
    pthread_sigmask(SIG_BLOCK, &all, old);
    while (atomic_flag_test_and_set_explicit(&lock, memory_order_acquire))
        ;
}

static void release(const sigset_t *old)
{
    atomic_flag_clear_explicit(&lock, memory_order_release);
    pthread_sigmask(SIG_SETMASK, old, NULL);
}

/* Registers path (copied); the handle, or -1 when memory runs out. */
static int add(const char *path, int is_dir)
{
    char *copy = strdup(path);
    if (!copy)
        return -1;
    sigset_t old;
    acquire(&old);
    size_t slot = 0;
    while (slot < nentries && entries[slot].path)
        slot++;
    if (slot == nentries && nentries == capacity) {
        size_t cap = capacity ? 2 * capacity : 16;
        entry *grown = realloc(entries, cap * sizeof *grown);
        if (!grown) {
            release(&old);
            free(copy);
            return -1;
        }
        entries = grown;
        capacity = cap;
    }
    if (slot == nentries)
        nentries++;
    entries[slot] = (entry){copy, is_dir};
    release(&old);
    return (int)slot;
}

void bf_temp_forget(int handle)
{
    if (handle < 0)
        return;
    sigset_t old;
    acquire(&old);
    char *path = NULL;
    if ((size_t)handle < nentries) {
        path = entries[handle].path;
        entries[handle].path = NULL;
    }
    release(&old);
    free(path);
}

/* Six random letters and digits into out (7 bytes); a clock-and-counter mix where the
 * kernel's random source is unavailable (O_EXCL still guarantees a new name). */
static void random_suffix(char *out)
{
    static const char set[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
    static atomic_uint counter;
    unsigned char r[6];
    if (getrandom(r, sizeof r, GRND_NONBLOCK) != (ssize_t)sizeof r) {
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        unsigned long long x = (unsigned long long)ts.tv_nsec * 2654435761u ^ (unsigned long long)getpid() << 20 ^
                               atomic_fetch_add(&counter, 1u);
        for (int k = 0; k < 6; k++, x >>= 8)
            r[k] = (unsigned char)x;
    }
    for (int k = 0; k < 6; k++)
        out[k] = set[r[k] % (sizeof set - 1)];
    out[6] = '\0';
}

int bf_temp_create(const char *base, int is_dir, mode_t mode, char **path, int *handle)
{
    size_t n = strlen(base);
    char *name = malloc(n + 12);
    if (!name) {
        errno = ENOMEM;
        return -1;
    }
    memcpy(name, base, n);
    memcpy(name + n, ".tmp.", 5);
    for (int attempt = 0; attempt < 100; attempt++) {
        random_suffix(name + n + 5);
        /* Registered first: there is no moment when it exists unregistered. */
        int h = add(name, is_dir);
        if (h < 0) {
            free(name);
            errno = ENOMEM;
            return -1;
        }
        int fd = is_dir ? mkdir(name, mode) : open(name, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, mode);
        if (fd >= 0) {
            *path = name;
            *handle = h;
            return fd;
        }
        int e = errno;
        bf_temp_forget(h);
        if (e != EEXIST) {
            free(name);
            errno = e;
            return -1;
        }
    }
    free(name);
    errno = EEXIST;
    return -1;
}

/* Removes the files in folder path (a report being built holds no subfolders). Runs in
 * the signal handler: no allocation, no stdio. Entries removed while the folder is read
 * may hide others from the same pass, so passes repeat until one removes nothing. */
static void empty_folder(const char *path)
{
    int fd = open(path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (fd < 0)
        return;
    for (int pass = 0, removed = 1; removed && pass < 16; pass++) {
        removed = 0;
        lseek(fd, 0, SEEK_SET);
        char buf[4096] __attribute__((aligned(8)));
        ssize_t got;
        while ((got = getdents64(fd, buf, sizeof buf)) > 0)
            for (ssize_t off = 0; off < got;) {
                const struct dirent64 *d = (const struct dirent64 *)(buf + off);
                off += d->d_reclen;
                if (strcmp(d->d_name, ".") && strcmp(d->d_name, "..") && unlinkat(fd, d->d_name, 0) == 0)
                    removed = 1;
            }
    }
    close(fd);
}

static void on_fatal_signal(int sig)
{
    /* Kept: the process ends below, and no other thread may change the list meanwhile. */
    while (atomic_flag_test_and_set_explicit(&lock, memory_order_acquire))
        ;
    for (size_t i = nentries; i-- > 0;) {
        const entry *e = &entries[i];
        if (!e->path)
            continue;
        if (e->is_dir) {
            empty_folder(e->path);
            rmdir(e->path);
        } else {
            unlink(e->path);
        }
    }
    /* The default action, as if no handler had run: pending until this returns. */
    signal(sig, SIG_DFL);
    raise(sig);
}

void bf_remove_temporaries_on_signals(void)
{
    /* The signals whose default action ends the process and that a user, the shell or a
     * resource limit sends (not the crash signals: a sanitizer handles those). */
    static const int sigs[] = {SIGHUP,  SIGINT,  SIGQUIT, SIGTERM, SIGPIPE,   SIGALRM,
                               SIGUSR1, SIGUSR2, SIGXCPU, SIGXFSZ, SIGVTALRM, SIGPROF};
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_fatal_signal;
    sigfillset(&sa.sa_mask); /* nothing interrupts the clean-up */
    for (size_t k = 0; k < sizeof sigs / sizeof sigs[0]; k++) {
        struct sigaction old;
        /* Only where the default action holds: a signal ignored at start (nohup) stays
         * ignored, and a handler someone installed stays theirs. */
        if (sigaction(sigs[k], NULL, &old) == 0 && !(old.sa_flags & SA_SIGINFO) && old.sa_handler == SIG_DFL)
            sigaction(sigs[k], &sa, NULL);
    }
}
