/* Export in memory (bf_export_text) is the text bf_export_write writes, for every target,
 * and the sized material is refused when its size was never set. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/export.h"
#include "support.h"

static char *slurp(const char *path)
{
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    fseek(fp, 0, SEEK_END);
    long n = ftell(fp);
    rewind(fp);
    char *s = malloc((size_t)n + 1);
    assert_non_null(s);
    assert_int_equal(fread(s, 1, (size_t)n, fp), (size_t)n);
    s[n] = '\0';
    fclose(fp);
    return s;
}

static void test_text_is_the_file(void **state)
{
    (void)state;
    for (int t = 0; t < bf_export_target_count(); t++) {
        const bf_export_target *to = bf_export_target_get(t);
        bf_model *m = ts_model(to->model, 3); /* the target's own model: no conversion */
        double x[64];
        bf_model_defaults(m, x);
        bf_error err;
        bf_export_material e;
        bf_export_material_init(&e);
        bf_fit_result conversion;
        bf_fit_result_init(&conversion);
        assert_int_equal(bf_export_check(to, m, 0, &err), BF_OK);
        assert_int_equal(bf_export_prepare(to, m, x, &e, &conversion, &err), BF_OK);
        assert_int_equal(e.converted, 0);
        const char *path = ts_tmp_path("export.out");
        assert_int_equal(bf_export_write(to, &e, path, &err), BF_OK);
        char *text = NULL, *file = slurp(path);
        assert_int_equal(bf_export_text(to, &e, &text, &err), BF_OK);
        assert_true(strlen(text) > 100);
        assert_string_equal(text, file);
        bf_free(text);
        free(file);
        remove(path);
        /* A material whose size was never set is refused, naming it. */
        bf_export_material zero;
        memset(&zero, 0, sizeof zero);
        text = (char *)"untouched";
        assert_int_equal(bf_export_text(to, &zero, &text, &err), BF_ERR_ARG);
        assert_null(text);
        assert_non_null(strstr(err.msg, "bf_export_material"));
        bf_fit_result_clear(&conversion);
        bf_model_free(m);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_text_is_the_file),
    };
    return cmocka_run_group_tests_name("export_text", tests, NULL, NULL);
}
