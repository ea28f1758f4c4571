/* Reading is cancellable (brdfit/load.h): a cancel flag set before bf_samples_load stops
 * it at once; one set while a CSV, Cornell or MERL file is being read stops the reader
 * inside its loop. The files come through a FIFO whose writer sets the flag half way and
 * then keeps the pipe open: a reader that looked at the flag only at the end of the file
 * would wait for the writer's close, which comes only after the load returned (or
 * after a timeout, which fails the test). */
#include <errno.h>
#include <pthread.h>
#include <setjmp.h>
#include <signal.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <cmocka.h>

#include "brdfit/load.h"
#include "support.h"

static void test_status_name(void **state)
{
    (void)state;
    assert_string_equal(bf_status_name(BF_ERR_CANCELLED), "cancelled");
    /* Appended: no value before it moved. */
    assert_int_equal(BF_ERR_CANCELLED, BF_ERR_NOMEM + 1);
}

static const char *csv_text(size_t rows, size_t *len)
{
    size_t cap = 64 + rows * 64;
    char *t = malloc(cap);
    assert_non_null(t);
    size_t n = (size_t)snprintf(t, cap, "theta_i,phi_i,theta_o,phi_o,value\n");
    for (size_t i = 0; i < rows; i++)
        n += (size_t)snprintf(t + n, cap - n, "%zu,0,%zu,180,0.%zu\n", i % 80, (i * 7) % 80, 1 + i % 9);
    *len = n;
    return t;
}

/* A set flag: nothing read, BF_ERR_CANCELLED naming the file; the same load without it
 * works; bf_samples_read honours it too. */
static void test_flag_set_before(void **state)
{
    (void)state;
    size_t len;
    const char *text = csv_text(1000, &len);
    const char *path = ts_tmp_path("cancel_before.csv");
    ts_write_file(path, text, len);
    free((void *)text);
    bf_options *o = ts_options(BF_TASK_READ, NULL);
    bf_cancel_flag flag = 1;
    bf_options_set_cancel(o, &flag, NULL);
    bf_samples *s = (bf_samples *)1;
    bf_error err;
    assert_int_equal(bf_samples_load(path, o, &s, NULL, &err), BF_ERR_CANCELLED);
    assert_null(s);
    assert_int_equal(err.code, BF_ERR_CANCELLED);
    assert_non_null(strstr(err.msg, "cancelled"));
    assert_non_null(strstr(err.msg, "cancel_before.csv"));
    s = (bf_samples *)1;
    assert_int_equal(bf_samples_read(path, o, &s, &err), BF_ERR_CANCELLED);
    assert_null(s);
    flag = 0;
    assert_int_equal(bf_samples_load(path, o, &s, NULL, &err), BF_OK);
    assert_int_equal(s->n, 1000);
    bf_samples_free(s);
    bf_options_free(o);
}

/* The FIFO's writer: `before` bytes, the flag, `after` bytes, then the pipe held open
 * until the load has returned (at most 20 s). */
typedef struct feeder {
    const char *path;
    const unsigned char *data;
    size_t before, after;
    volatile bf_cancel_flag *flag;
    pthread_mutex_t lock;
    pthread_cond_t cond;
    int loaded;     /* set by the test when the load returned */
    int timed_out;  /* the load did not return while the pipe was open */
    int write_fail; /* a write failed */
} feeder;

static int write_all(int fd, const unsigned char *p, size_t n)
{
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return -1;
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

static void *feed(void *arg)
{
    feeder *f = arg;
    FILE *fp = fopen(f->path, "wb"); /* blocks until the reader opens */
    if (!fp) {
        f->write_fail = 1;
        return NULL;
    }
    int fd = fileno(fp);
    if (write_all(fd, f->data, f->before) != 0)
        f->write_fail = 1;
    *f->flag = 1;
    /* The reader may stop before it takes these (EPIPE): it saw the flag sooner. */
    if (write_all(fd, f->data + f->before, f->after) != 0 && errno != EPIPE)
        f->write_fail = 1;
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += 20;
    pthread_mutex_lock(&f->lock);
    while (!f->loaded && !f->timed_out)
        if (pthread_cond_timedwait(&f->cond, &f->lock, &until) == ETIMEDOUT)
            f->timed_out = 1;
    pthread_mutex_unlock(&f->lock);
    fclose(fp);
    return NULL;
}

/* Loads name (a FIFO) while data goes in as feeder says: the load must stop with
 * BF_ERR_CANCELLED from the reader ("reading cancelled") while the pipe is still open. */
static void load_through_fifo(const char *name, const char *words, const unsigned char *data, size_t before,
                              size_t after)
{
    const char *path = ts_tmp_path(name);
    unlink(path);
    assert_int_equal(mkfifo(path, 0600), 0);
    bf_cancel_flag flag = 0;
    feeder f = {.path = path, .data = data, .before = before, .after = after, .flag = &flag};
    pthread_mutex_init(&f.lock, NULL);
    pthread_cond_init(&f.cond, NULL);
    bf_options *o = ts_options(BF_TASK_READ, words);
    bf_options_set_cancel(o, &flag, NULL);
    pthread_t t;
    assert_int_equal(pthread_create(&t, NULL, feed, &f), 0);
    bf_samples *s = NULL;
    bf_error err;
    bf_status rc = bf_samples_load(path, o, &s, NULL, &err);
    pthread_mutex_lock(&f.lock);
    const int timed_out = f.timed_out;
    f.loaded = 1;
    pthread_cond_signal(&f.cond);
    pthread_mutex_unlock(&f.lock);
    pthread_join(t, NULL);
    assert_false(f.write_fail);
    assert_false(timed_out);
    if (rc != BF_ERR_CANCELLED)
        fail_msg("%s: status %s: %s", name, bf_status_name(rc), rc == BF_OK ? "read whole" : err.msg);
    assert_null(s);
    assert_non_null(strstr(err.msg, "reading cancelled"));
    assert_non_null(strstr(err.msg, name));
    bf_options_free(o);
    pthread_mutex_destroy(&f.lock);
    pthread_cond_destroy(&f.cond);
    unlink(path);
}

static void test_csv_reader_stops(void **state)
{
    (void)state;
    size_t len;
    const char *text = csv_text(20000, &len);
    /* The flag after about half the lines; one more line after it. */
    size_t half = len / 2;
    while (text[half - 1] != '\n')
        half++;
    size_t next = half;
    while (text[next - 1] != '\n' || next == half)
        next++;
    load_through_fifo("fifo.csv", NULL, (const unsigned char *)text, half, next - half);
    free((void *)text);
}

static void test_cornell_reader_stops(void **state)
{
    (void)state;
    size_t cap = 64 + 20000 * 64, n = 0;
    char *t = malloc(cap);
    assert_non_null(t);
    n += (size_t)snprintf(t + n, cap - n, "3 400 500 600\n");
    size_t half = 0, next = 0;
    for (size_t i = 0; i < 20000; i++) {
        n += (size_t)snprintf(t + n, cap - n, "0.%zu 0 0.%zu 3.14 0.1 0.2 0.3\n", 1 + i % 9, 1 + (i * 3) % 9);
        if (i == 10000)
            half = n;
        if (i == 10001)
            next = n;
    }
    load_through_fifo("fifo.brdf", NULL, (const unsigned char *)t, half, next - half);
    free(t);
}

/* A MERL table: the header and a first chunk of the reader's, the flag, a second chunk;
 * the third never comes while the load runs. */
static void test_merl_reader_stops(void **state)
{
    (void)state;
    const size_t cells = 90 * 90 * 180, chunk = 65536 * sizeof(double);
    const size_t len = 12 + 3 * cells * sizeof(double);
    unsigned char *data = malloc(len);
    assert_non_null(data);
    const int32_t dims[3] = {90, 90, 180}; /* little-endian hosts: as MERL wrote them */
    memcpy(data, dims, sizeof dims);
    for (size_t i = 0; i < 3 * cells; i++) {
        const double v = 0.5;
        memcpy(data + 12 + i * sizeof v, &v, sizeof v);
    }
    load_through_fifo("fifo.binary", "--format merl", data, 12 + chunk, chunk);
    free(data);
}

int main(void)
{
    signal(SIGPIPE, SIG_IGN); /* a write after the reader stopped: EPIPE, not a signal */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_status_name),       cmocka_unit_test(test_flag_set_before),
        cmocka_unit_test(test_csv_reader_stops),  cmocka_unit_test(test_cornell_reader_stops),
        cmocka_unit_test(test_merl_reader_stops),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
