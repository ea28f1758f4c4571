/* Outputs that survive failures (io.h's bf_outfile, bf_outputs_check and the signal
 * clean-up): new and replaced files, modes, symbolic links, devices, real write
 * failures (/dev/full, a file size limit), the same-file checks, and temporaries removed
 * by fatal signals (in a child process killed for real). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "brdfit/io.h"
#include "brdfit/tool.h"
#include "io/temp_registry.h"
#include "support.h"

/* A fresh folder per test, so "no temporary left" looks at this test's files only. */
static const char *folder(const char *name)
{
    const char *d = ts_tmp_path(name);
    assert_int_equal(mkdir(d, 0755), 0);
    return d;
}

static char *join(const char *dir, const char *name)
{
    static char buf[4][512];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", dir, name);
    return buf[k];
}

static void put(const char *path, const char *text)
{
    ts_write_file(path, text, strlen(text));
}

/* The file's text (static buffer), "" when unreadable. */
static const char *text_of(const char *path)
{
    static char buf[8192];
    buf[0] = '\0';
    FILE *fp = fopen(path, "rb");
    if (fp) {
        buf[fread(buf, 1, sizeof buf - 1, fp)] = '\0';
        fclose(fp);
    }
    return buf;
}

/* Entries of dir whose name holds ".tmp." (temporaries). */
static int temporaries(const char *dir)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        n += strstr(e->d_name, ".tmp.") != NULL;
    closedir(d);
    return n;
}

static bf_status write_text(const char *path, const char *text, bf_error *err)
{
    bf_outfile o;
    int rc = bf_outfile_open(&o, path, err);
    if (rc != BF_OK)
        return rc;
    fputs(text, o.fp);
    return bf_outfile_commit(&o, err);
}

static void test_new_file_gets_the_umask_mode(void **state)
{
    (void)state;
    const char *d = folder("new");
    bf_error err;
    mode_t old = umask(027);
    assert_int_equal(write_text(join(d, "a.json"), "{}\n", &err), BF_OK);
    umask(old);
    struct stat st;
    assert_int_equal(stat(join(d, "a.json"), &st), 0);
    assert_int_equal(st.st_mode & 07777, 0640);
    assert_string_equal(text_of(join(d, "a.json")), "{}\n");
    assert_int_equal(temporaries(d), 0);
}

static void test_replaced_file_keeps_its_mode(void **state)
{
    (void)state;
    const char *d = folder("mode");
    const char *p = join(d, "r.json");
    put(p, "old\n");
    assert_int_equal(chmod(p, 0600), 0);
    bf_error err;
    assert_int_equal(write_text(p, "new\n", &err), BF_OK);
    struct stat st;
    assert_int_equal(stat(p, &st), 0);
    assert_int_equal(st.st_mode & 07777, 0600);
    assert_string_equal(text_of(p), "new\n");
    /* And 0640 stays 0640 under a umask that would take more away. */
    assert_int_equal(chmod(p, 0640), 0);
    mode_t old = umask(077);
    assert_int_equal(write_text(p, "newer\n", &err), BF_OK);
    umask(old);
    assert_int_equal(stat(p, &st), 0);
    assert_int_equal(st.st_mode & 07777, 0640);
    assert_int_equal(temporaries(d), 0);
}

static void test_abort_keeps_the_old_file(void **state)
{
    (void)state;
    const char *d = folder("abort");
    const char *p = join(d, "r.csv");
    put(p, "old\n");
    bf_outfile o;
    bf_error err;
    assert_int_equal(bf_outfile_open(&o, p, &err), BF_OK);
    fputs("half a file", o.fp);
    fflush(o.fp);
    assert_int_equal(temporaries(d), 1); /* the temporary sits beside the target */
    bf_outfile_abort(&o);
    assert_string_equal(text_of(p), "old\n");
    assert_int_equal(temporaries(d), 0);
}

static void test_symlink_is_followed(void **state)
{
    (void)state;
    const char *d = folder("link");
    char real[512], link[512], dangling[512];
    snprintf(real, sizeof real, "%s", join(d, "real.json"));
    snprintf(link, sizeof link, "%s", join(d, "link.json"));
    snprintf(dangling, sizeof dangling, "%s", join(d, "dangling.json"));
    put(real, "old\n");
    assert_int_equal(symlink("real.json", link), 0); /* relative: resolved from the link's folder */
    bf_error err;
    assert_int_equal(write_text(link, "new\n", &err), BF_OK);
    struct stat st;
    assert_int_equal(lstat(link, &st), 0);
    assert_true(S_ISLNK(st.st_mode));
    assert_string_equal(text_of(real), "new\n");
    /* A link to nothing yet: the file it names is created, the link kept. */
    assert_int_equal(symlink("made.json", dangling), 0);
    assert_int_equal(write_text(dangling, "made\n", &err), BF_OK);
    assert_int_equal(lstat(dangling, &st), 0);
    assert_true(S_ISLNK(st.st_mode));
    assert_string_equal(text_of(join(d, "made.json")), "made\n");
    assert_int_equal(temporaries(d), 0);
}

static void test_device_is_written_through(void **state)
{
    (void)state;
    bf_error err;
    assert_int_equal(write_text("/dev/null", "nothing\n", &err), BF_OK);
    struct stat st;
    assert_int_equal(stat("/dev/null", &st), 0);
    assert_true(S_ISCHR(st.st_mode));
    /* A link to the device: still written through, the link kept. */
    const char *d = folder("dev");
    assert_int_equal(symlink("/dev/null", join(d, "null.json")), 0);
    assert_int_equal(write_text(join(d, "null.json"), "x\n", &err), BF_OK);
    assert_int_equal(lstat(join(d, "null.json"), &st), 0);
    assert_true(S_ISLNK(st.st_mode));
    assert_int_equal(temporaries(d), 0);
}

static void test_full_device_fails_with_the_cause(void **state)
{
    (void)state;
    bf_error err;
    assert_int_equal(write_text("/dev/full", "no room\n", &err), BF_ERR_IO);
    assert_non_null(strstr(err.msg, "/dev/full: write error: "));
    assert_non_null(strstr(err.msg, strerror(ENOSPC)));
}

/* One fwrite larger than the stream's buffer goes straight to the failing write: the
 * stream must stop at the error, not read past the caller's block. The block ends at a
 * page with no access, so reading past it (glibc does when a stdio cookie reports an
 * error as -1) crashes the test rather than going unseen. */
static void big_write_fails(const char *path, int code)
{
    size_t page = (size_t)sysconf(_SC_PAGESIZE), n = 1 << 20;
    unsigned char *block = mmap(NULL, n + page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    assert_true(block != MAP_FAILED);
    assert_int_equal(mprotect(block + n, page, PROT_NONE), 0);
    bf_outfile o;
    bf_error err;
    int rc = bf_outfile_open(&o, path, &err);
    if (rc == BF_OK) {
        assert_true(fwrite(block, 1, n, o.fp) < n);
        rc = bf_outfile_commit(&o, &err);
    }
    munmap(block, n + page);
    assert_int_equal(rc, BF_ERR_IO);
    assert_non_null(strstr(err.msg, strerror(code)));
}

static void test_big_write_to_full_device(void **state)
{
    (void)state;
    big_write_fails("/dev/full", ENOSPC);
}

/* A real failed write on a regular file: past RLIMIT_FSIZE with SIGXFSZ ignored, write()
 * fails with EFBIG, as on a full disk with ENOSPC. The old file must stay whole. */
static void test_failed_write_keeps_the_old_file(void **state)
{
    (void)state;
    const char *d = folder("efbig");
    const char *p = join(d, "big.csv");
    put(p, "the old, good file\n");
    struct rlimit old, low;
    assert_int_equal(getrlimit(RLIMIT_FSIZE, &old), 0);
    low = old;
    low.rlim_cur = 4096;
    void (*was)(int) = signal(SIGXFSZ, SIG_IGN);
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &low), 0);
    bf_outfile o;
    bf_error err;
    int rc = bf_outfile_open(&o, p, &err);
    if (rc == BF_OK) {
        for (int i = 0; i < 2000; i++)
            fprintf(o.fp, "%d,0.123456789\n", i);
        rc = bf_outfile_commit(&o, &err);
    }
    setrlimit(RLIMIT_FSIZE, &old);
    signal(SIGXFSZ, was);
    assert_int_equal(rc, BF_ERR_IO);
    assert_non_null(strstr(err.msg, "big.csv: write error: "));
    assert_non_null(strstr(err.msg, strerror(EFBIG)));
    assert_string_equal(text_of(p), "the old, good file\n");
    assert_int_equal(temporaries(d), 0);
    /* The same with one big block. */
    assert_int_equal(setrlimit(RLIMIT_FSIZE, &low), 0);
    signal(SIGXFSZ, SIG_IGN);
    big_write_fails(p, EFBIG);
    setrlimit(RLIMIT_FSIZE, &old);
    signal(SIGXFSZ, was);
    assert_string_equal(text_of(p), "the old, good file\n");
    assert_int_equal(temporaries(d), 0);
}

static void test_unusable_targets(void **state)
{
    (void)state;
    const char *d = folder("bad");
    bf_error err;
    bf_outfile o;
    assert_int_equal(bf_outfile_open(&o, "", &err), BF_ERR_ARG);
    assert_int_equal(bf_outfile_open(&o, d, &err), BF_ERR_IO);
    assert_non_null(strstr(err.msg, "is a folder"));
    assert_int_equal(bf_outfile_open(&o, join(d, "no/x.json"), &err), BF_ERR_IO);
    assert_non_null(strstr(err.msg, "cannot write in the folder"));
    assert_non_null(strstr(err.msg, strerror(ENOENT)));
    assert_int_equal(bf_outfile_check(join(d, "no/x.json"), &err), BF_ERR_IO);
    assert_int_equal(bf_outfile_check(join(d, "x.json"), &err), BF_OK);
    assert_int_equal(bf_outfile_check("-", &err), BF_OK);
    assert_int_equal(temporaries(d), 0);
    /* A loop of links. */
    assert_int_equal(symlink("b", join(d, "a")), 0);
    assert_int_equal(symlink("a", join(d, "b")), 0);
    assert_int_equal(bf_outfile_check(join(d, "a"), &err), BF_ERR_IO);
    assert_non_null(strstr(err.msg, strerror(ELOOP)));
}

/* bf_outputs_check on one input and one or two outputs. */
static bf_status check(const char *in, const char *out1, const char *out2, bf_error *err)
{
    const bf_path_use i[] = {{"data file", in}}, o[] = {{"-o", out1}, {"--json", out2}};
    return bf_outputs_check(i, 1, o, 2, err);
}

static void test_same_file_by_inode(void **state)
{
    (void)state;
    const char *d = folder("same");
    char data[512], dotted[512], hard[512], soft[512], new1[512], new2[512];
    snprintf(data, sizeof data, "%s", join(d, "s.csv"));
    snprintf(dotted, sizeof dotted, "%s/./s.csv", d);
    snprintf(hard, sizeof hard, "%s", join(d, "hard.csv"));
    snprintf(soft, sizeof soft, "%s", join(d, "soft.csv"));
    snprintf(new1, sizeof new1, "%s", join(d, "x.json"));
    snprintf(new2, sizeof new2, "%s/../same/x.json", d);
    put(data, "theta_i\n");
    assert_int_equal(link(data, hard), 0);
    assert_int_equal(symlink("s.csv", soft), 0);
    bf_error err;
    const char *same_as_data[] = {data, dotted, hard, soft};
    for (int k = 0; k < 4; k++) {
        assert_int_equal(check(data, same_as_data[k], NULL, &err), BF_ERR_ARG);
        assert_non_null(strstr(err.msg, same_as_data[k]));
        assert_non_null(strstr(err.msg, "data file"));
        assert_null(strchr(err.msg, '\n'));
    }
    /* Two outputs not there yet, under two spellings. */
    assert_int_equal(check(data, new1, new2, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "are the same file"));
    assert_int_equal(check(data, new1, NULL, &err), BF_OK);
    assert_int_equal(check(data, "-", "-", &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "standard output"));
    assert_int_equal(check(data, "", NULL, &err), BF_ERR_ARG);
    /* Devices destroy nothing: shared freely. */
    assert_int_equal(check("/dev/null", "/dev/null", "/dev/null", &err), BF_OK);
    assert_int_equal(check(data, join(d, "no/x.json"), NULL, &err), BF_ERR_IO);
    assert_int_equal(temporaries(d), 0);
}

/* A child with an output and a report-like folder in progress is killed by sig: it must
 * die by that signal (default action kept) and leave no temporary; the old output stays. */
static void killed_while_writing(int sig)
{
    char name[32];
    snprintf(name, sizeof name, "sig%d", sig);
    const char *d = folder(name);
    char target[512], report[512];
    snprintf(target, sizeof target, "%s", join(d, "r.json"));
    snprintf(report, sizeof report, "%s", join(d, "report"));
    put(target, "old\n");
    int ready[2];
    assert_int_equal(pipe(ready), 0);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        /* As at a program's start, whatever the test runner left. */
        signal(sig, SIG_DFL);
        sigset_t none;
        sigemptyset(&none);
        sigprocmask(SIG_SETMASK, &none, NULL);
        bf_remove_temporaries_on_signals();
        bf_outfile o;
        bf_error err;
        char *dir = NULL;
        int h;
        if (bf_outfile_open(&o, target, &err) != BF_OK || bf_temp_create(report, 1, 0755, &dir, &h) != 0)
            _exit(3);
        fputs("half", o.fp);
        fflush(o.fp);
        char inner[600];
        snprintf(inner, sizeof inner, "%s/index.html", dir);
        FILE *fp = fopen(inner, "w");
        if (!fp || fputs("<html>", fp) < 0 || fclose(fp) != 0)
            _exit(4);
        if (write(ready[1], "r", 1) != 1)
            _exit(5);
        for (;;)
            pause();
    }
    close(ready[1]);
    char c;
    assert_int_equal(read(ready[0], &c, 1), 1);
    close(ready[0]);
    assert_int_equal(temporaries(d), 2); /* the file and the folder exist now */
    assert_int_equal(kill(pid, sig), 0);
    int status;
    assert_int_equal(waitpid(pid, &status, 0), pid);
    assert_true(WIFSIGNALED(status));
    assert_int_equal(WTERMSIG(status), sig);
    assert_int_equal(temporaries(d), 0);
    assert_string_equal(text_of(target), "old\n");
}

static void test_fatal_signals_leave_no_temporary(void **state)
{
    (void)state;
    const int sigs[] = {SIGTERM, SIGINT, SIGHUP, SIGXFSZ, SIGPIPE};
    for (size_t k = 0; k < sizeof sigs / sizeof sigs[0]; k++)
        killed_while_writing(sigs[k]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_new_file_gets_the_umask_mode),
        cmocka_unit_test(test_replaced_file_keeps_its_mode),
        cmocka_unit_test(test_abort_keeps_the_old_file),
        cmocka_unit_test(test_symlink_is_followed),
        cmocka_unit_test(test_device_is_written_through),
        cmocka_unit_test(test_full_device_fails_with_the_cause),
        cmocka_unit_test(test_big_write_to_full_device),
        cmocka_unit_test(test_failed_write_keeps_the_old_file),
        cmocka_unit_test(test_unusable_targets),
        cmocka_unit_test(test_same_file_by_inode),
        cmocka_unit_test(test_fatal_signals_leave_no_temporary),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
