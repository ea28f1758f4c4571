/* Reference files as brdfit compare --reference reads them (brdfit/reference.h): a
 * reference set (source, table, materials of parameter files) or a parameter file. What
 * reads has a source, a material and finite values of a model with the file's channel
 * count; the entries outside the bounds are exactly those it names; each is matched to
 * its own material and spec; a failure leaves the set as it was, and reading the same
 * text again gives the same references. */
#include "fuzz_common.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/reference.h"

/* The entries outside r's bounds, named as the reader names them. */
static void check_outside(const bf_reference *r)
{
    const bf_model *m = r->model;
    char want[BF_REFERENCE_OUTSIDE_LEN] = "";
    size_t used = 0;
    int cut = 0;
    for (int i = 0; i < bf_model_nparams(m) && !cut; i++) {
        const bf_param_info *p = bf_model_param(m, i);
        for (int c = 0; c < (p->color ? bf_model_channels(m) : 1) && !cut; c++) {
            const int k = bf_model_param_offset(m, i) + c;
            const double v = r->x[k];
            if (!isfinite(v))
                fuzz_fail("%s: entry %d is %g", r->material, k, v);
            if (!(v < p->lo || (p->lo_open && v == p->lo) || v > p->hi || (p->hi_open && v == p->hi)))
                continue;
            char name[64];
            bf_model_entry_name(m, k, name, sizeof name);
            int n = snprintf(want + used, sizeof want - used, "%s%s", used ? ", " : "", name);
            cut = n < 0 || (size_t)n >= sizeof want - used;
            used += cut ? 0 : (size_t)n;
        }
    }
    if (!cut && strcmp(want, r->outside))
        fuzz_fail("%s: outside the bounds '%s', named '%s'", r->material, want, r->outside);
    if (cut && strcmp(r->outside + strlen(r->outside) - 3, "..."))
        fuzz_fail("%s: a long list of entries outside the bounds not marked as cut", r->material);
}

static void check_reference(const bf_reference *r)
{
    if (!r->model || !r->x || !r->source || !*r->source || !r->material || !r->file || r->line < 1)
        fuzz_fail("a reference without a model, values, source, material, file or line");
    if (r->table && !*r->table)
        fuzz_fail("an empty table name");
    check_outside(r);
    if (!bf_reference_matches(r, r->material, bf_model_spec(r->model)))
        fuzz_fail("%s (%s) does not match its own material and spec", r->material, bf_model_spec(r->model));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_write("gold.json", data, size);
    bf_reference_set *s = NULL, *again = NULL;
    bf_error err;
    if (bf_reference_set_new(&s, &err) != BF_OK || bf_reference_set_new(&again, &err) != BF_OK)
        fuzz_fail("no set: %s", err.msg);
    int rc = bf_reference_read(s, path, &err);
    fuzz_check_result(rc, &err, rc == BF_OK ? s : NULL);
    if (rc != BF_OK && s->n != 0)
        fuzz_fail("a failed read left %d references", s->n);
    for (int k = 0; k < s->n; k++)
        check_reference(&s->refs[k]);
    /* The same text again, and a failure after it keeps it whole. */
    if (rc == BF_OK) {
        if (bf_reference_read(again, path, &err) != BF_OK || again->n != s->n)
            fuzz_fail("read again: %s", err.msg);
        for (int k = 0; k < s->n; k++)
            if (strcmp(bf_model_spec(s->refs[k].model), bf_model_spec(again->refs[k].model)) ||
                memcmp(s->refs[k].x, again->refs[k].x, (size_t)bf_model_nvalues(s->refs[k].model) * sizeof(double)))
                fuzz_fail("reference %d read differently the second time", k);
        if (bf_reference_parse(again, "{", "cut.json", &err) == BF_OK || again->n != s->n)
            fuzz_fail("a bad file changed the set");
    }
    bf_reference_set_free(s);
    bf_reference_set_free(again);
    return 0;
}
