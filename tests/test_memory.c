/* The memory limit (brdfit/limits.h): byte counts as BRDFIT_MEMORY takes them, the limit
 * the environment variable and ulimit -v set, and large arrays refused beyond it while
 * small ones are not asked about. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "base/big_alloc.h"
#include "brdfit/limits.h"

static void test_parse_bytes(void **state)
{
    (void)state;
    size_t v = 0;
    assert_int_equal(bf_bytes_parse("1000000", &v, NULL), BF_OK);
    assert_int_equal(v, 1000000);
    assert_int_equal(bf_bytes_parse("512M", &v, NULL), BF_OK);
    assert_int_equal(v, (size_t)512 << 20);
    assert_int_equal(bf_bytes_parse("4g", &v, NULL), BF_OK);
    assert_int_equal(v, (size_t)4 << 30);
    assert_int_equal(bf_bytes_parse("3K", &v, NULL), BF_OK);
    assert_int_equal(v, 3072);
    assert_int_equal(bf_bytes_parse("2T", &v, NULL), BF_OK);
    assert_int_equal(v, (size_t)2 << 40);
    assert_int_equal(bf_bytes_parse("0", &v, NULL), BF_OK);
    assert_int_equal(v, 0);
    const char *bad[] = {NULL, "", "-3", "+3", " 3", "3 ", "4X", "4GB", "1.5G", "99999999999999999999", "17179869184G"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        v = 7;
        assert_int_equal(bf_bytes_parse(bad[i], &v, NULL), BF_ERR_ARG);
        assert_int_equal(v, 7); /* untouched */
    }
}

static void test_environment_limit(void **state)
{
    (void)state;
    const size_t machine = bf_memory_available();
    assert_true(machine > ((size_t)16 << 20)); /* the test machines have gigabytes */
    setenv("BRDFIT_MEMORY", "10M", 1);
    assert_int_equal(bf_memory_available(), (size_t)10 << 20);
    assert_true(bf_memory_allows((size_t)9 << 20));
    assert_false(bf_memory_allows((size_t)11 << 20));
    assert_true(bf_memory_allows(BF_MEMORY_UNCHECKED - 1)); /* small requests are not asked */
    void *p = bf_big_malloc((size_t)11 << 20);
    assert_null(p);
    p = bf_big_calloc((size_t)1 << 20, 9);
    assert_non_null(p);
    free(p);
    setenv("BRDFIT_MEMORY", "0", 1);
    assert_false(bf_memory_allows(BF_MEMORY_UNCHECKED));
    assert_true(bf_memory_allows(100));
    /* Not a byte count: ignored by the library (the command refuses it before). */
    setenv("BRDFIT_MEMORY", "lots", 1);
    assert_true(bf_memory_available() > ((size_t)16 << 20));
    unsetenv("BRDFIT_MEMORY");
}

static void test_memory_error(void **state)
{
    (void)state;
    setenv("BRDFIT_MEMORY", "8M", 1);
    bf_error err = {0};
    assert_int_equal(bf_fail_memory(&err, "big.csv", 12, 19200000), BF_ERR_NOMEM);
    assert_string_equal(err.msg, "big.csv:12: not enough memory: 18.3 MiB needed, 8 MiB available (BRDFIT_MEMORY)");
    assert_int_equal(bf_fail_memory(&err, "m.binary", 0, SIZE_MAX), BF_ERR_NOMEM);
    assert_string_equal(err.msg, "m.binary: out of memory");
    unsetenv("BRDFIT_MEMORY");
    assert_int_equal(bf_fail_memory(&err, "t.csv", 3, (size_t)5 << 40), BF_ERR_NOMEM);
    assert_non_null(strstr(err.msg, "t.csv:3: not enough memory: 5 TiB needed, "));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_parse_bytes),
        cmocka_unit_test(test_environment_limit),
        cmocka_unit_test(test_memory_error),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
