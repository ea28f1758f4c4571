/* Error messages are safe to print: one line, at most BF_ERROR_MAX_CHARS characters,
 * control bytes and invalid UTF-8 escaped, long runs without a blank shortened around
 * "...", and the rest of the message (file, line, problem) kept. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/error.h"

static size_t chars(const char *s) /* UTF-8 characters */
{
    size_t n = 0;
    for (; *s; s++)
        n += ((unsigned char)*s & 0xc0) != 0x80;
    return n;
}

static void test_controls_and_invalid_utf8_escaped(void **state)
{
    (void)state;
    bf_error err;
    /* The header of a binary file: ESC sequence, a tab, a newline, bytes that are no UTF-8. */
    bf_fail(&err, BF_ERR_PARSE, "%s:%d: column '%s' appears twice", "junk.csv", 1, "\x1b[31m\t\n\xff\xfe\x7f");
    assert_int_equal(err.code, BF_ERR_PARSE);
    assert_string_equal(err.msg, "junk.csv:1: column '\\x1b[31m\\x09\\x0a\\xff\\xfe\\x7f' appears twice");
    /* UTF-8 stays; C1 controls (U+009B is a CSI), bidirectional overrides, U+2028, overlong
     * forms, surrogates and a sequence cut short are escaped. */
    bf_fail(&err, BF_ERR_PARSE, "%s", "caf\xc3\xa9 \xc2\x9b \xe2\x80\xae \xe2\x80\xa8 \xc0\xaf \xed\xa0\x80 \xe2\x82");
    assert_string_equal(err.msg, "caf\xc3\xa9 \\u009b \\u202e \\u2028 \\xc0\\xaf \\xed\\xa0\\x80 \\xe2\\x82");
}

static void test_long_token_shortened(void **state)
{
    (void)state;
    /* A 9 kB number: the message keeps its start and end, and names file, line and problem. */
    char *token = malloc(9001);
    memset(token, '1', 9000);
    token[4] = '2';
    token[8990] = '3';
    token[9000] = '\0';
    bf_error err;
    bf_fail(&err, BF_ERR_PARSE, "%s:%d: column v: '%s' is not a number", "big.csv", 2, token);
    char want[256];
    /* 31 characters, "...", 30 characters, counting the quotes. */
    snprintf(want, sizeof want, "big.csv:2: column v: '%.30s...%s' is not a number", token, token + 9000 - 29);
    assert_string_equal(err.msg, want);
    /* The shortened run is exactly BF_ERROR_TOKEN_CHARS characters, quotes included. */
    const char *q = strchr(err.msg, '\'');
    assert_int_equal(strcspn(q, " "), BF_ERROR_TOKEN_CHARS);
    free(token);
}

static void test_whole_message_capped(void **state)
{
    (void)state;
    /* Many short words: cut to the limit, ending in "...". */
    char words[2000] = "";
    for (int i = 0; i < 300; i++)
        strcat(words, "word ");
    bf_error err;
    bf_fail(&err, BF_ERR_ARG, "x.csv:9: %s", words);
    assert_int_equal(chars(err.msg), BF_ERROR_MAX_CHARS);
    assert_int_equal(strncmp(err.msg, "x.csv:9: word word", 18), 0);
    assert_string_equal(err.msg + strlen(err.msg) - 3, "...");
    /* Escapes count as what they print, and are never cut in two. */
    char ctl[300];
    memset(ctl, '\x01', 299);
    ctl[299] = '\0';
    bf_printable(ctl, 0, 50, err.msg, sizeof err.msg);
    assert_string_equal(err.msg, "\\x01\\x01\\x01\\x01\\x01\\x01\\x01\\x01\\x01\\x01\\x01...");
    /* Wide characters: the byte size is the limit before the character count. */
    char wide[4 * 400 + 1] = "";
    for (int i = 0; i < 400; i++)
        strcat(wide, "\xe2\x82\xac "); /* a euro sign and a blank */
    char small[40];
    bf_printable(wide, 0, 0, small, sizeof small);
    assert_true(strlen(small) < sizeof small);
    assert_string_equal(small + strlen(small) - 3, "...");
}

static void test_message_built_from_itself(void **state)
{
    (void)state;
    /* Readers prefix a message they got back: err->msg may be an argument. */
    bf_error err;
    bf_fail(&err, BF_ERR_RANGE, "parameter alpha is %g", -1.0);
    bf_fail(&err, err.code, "%s:%d: %s", "p.json", 3, err.msg);
    assert_string_equal(err.msg, "p.json:3: parameter alpha is -1");
    assert_int_equal(err.code, BF_ERR_RANGE);
    /* A message already safe is kept as it is. */
    bf_fail(&err, BF_ERR_PARSE, "%s", "a\\x1b b...c");
    assert_string_equal(err.msg, "a\\x1b b...c");
    assert_int_equal(bf_fail(NULL, BF_ERR_IO, "no error to fill"), BF_ERR_IO);
}

static void test_printable_dup(void **state)
{
    (void)state;
    /* Nothing shortened, everything escaped (for XML and HTML reports). */
    char long_name[1000];
    memset(long_name, 'n', sizeof long_name - 2);
    long_name[sizeof long_name - 2] = '\x1b';
    long_name[sizeof long_name - 1] = '\0';
    char *s = bf_printable_dup(long_name);
    assert_non_null(s);
    assert_int_equal(strlen(s), sizeof long_name - 2 + 4);
    assert_string_equal(s + strlen(s) - 5, "n\\x1b");
    free(s);
    s = bf_printable_dup("\xef\xbf\xbe\xef\xbf\xbf ok"); /* U+FFFE, U+FFFF: not characters */
    assert_string_equal(s, "\\ufffe\\uffff ok");
    free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_controls_and_invalid_utf8_escaped),
        cmocka_unit_test(test_long_token_shortened),
        cmocka_unit_test(test_whole_message_capped),
        cmocka_unit_test(test_message_built_from_itself),
        cmocka_unit_test(test_printable_dup),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
