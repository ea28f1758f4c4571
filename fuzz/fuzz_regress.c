/* Regression baselines: load; each case checked against a fit result made up from its
 * model (defaults, fixed metrics, a warning that quotes the case name), updated with
 * it, written, reloaded and checked again, which must pass; and the JUnit report of
 * the checks, which must be XML that libxml2 reads. */
#include "fuzz_common.h"

#include <libxml/parser.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/fit.h"
#include "brdfit/regress.h"

enum { MAX_CASES = 4 };

/* A result for case c's model with C channels: the model's defaults, fixed metrics. */
static int make_result(const bf_regress_case *cs, int C, bf_fit_result *r)
{
    bf_fit_result_init(r);
    if (bf_model_new(cs->model, C, &r->model, NULL) != BF_OK)
        return 0;
    if (!(r->x = malloc((size_t)bf_model_nvalues(r->model) * sizeof *r->x + 1)))
        fuzz_fail("out of memory");
    bf_model_defaults(r->model, r->x);
    r->metrics = (bf_metrics){.n = 100,
                              .k = bf_model_nvalues(r->model),
                              .rmse = 0.125,
                              .rmse_cos = 0.25,
                              .rmse_log = 0.03125,
                              .rmse_rel = 1.5e-3,
                              .max_err = 2.0,
                              .crit_n = 100,
                              .loglik = -12.5,
                              .aic = 31.0,
                              .aicc = 32.25,
                              .bic = 40.0};
    r->ok = 1;
    r->seconds = 0.5;
    r->nwarnings = 1;
    snprintf(r->warnings[0], sizeof r->warnings[0], "case %s: fitted", cs->name);
    snprintf(r->solution.termination, sizeof r->solution.termination, "converged");
    return 1;
}

static void free_result(bf_fit_result *r)
{
    bf_model_free(r->model);
    free(r->x);
}

static void check_junit(const bf_regress_baseline *b, const bf_regress_outcome *outs)
{
    bf_error err;
    const char *path = fuzz_path("junit.xml");
    int rc = bf_regress_write_junit(b, outs, path, &err);
    fuzz_check_result(rc, &err, rc == BF_OK ? path : NULL);
    if (rc != BF_OK)
        return;
    xmlDocPtr doc = xmlReadFile(path, NULL, XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING);
    if (!doc)
        fuzz_fail("the JUnit report is not well-formed XML");
    xmlFreeDoc(doc);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text)
        return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    bf_error err;
    bf_regress_baseline *b = NULL;
    int rc = bf_regress_parse(text, "cases/baseline.json", &b, &err);
    fuzz_check_result(rc, &err, b);
    free(text);
    if (!b)
        return 0;
    const int n = b->ncases < MAX_CASES ? b->ncases : MAX_CASES;
    bf_fit_result r[MAX_CASES];
    bf_regress_outcome outs[MAX_CASES];
    int made[MAX_CASES] = {0};
    for (int c = 0; c < MAX_CASES; c++)
        bf_regress_outcome_init(&outs[c]);
    for (int c = 0; c < n; c++) {
        /* The case's options as a runner reads them: taken, or refused with one line
         * naming the baseline. Not with a scene: it would be read from wherever the
         * input points (a device, a pipe). */
        int scene = 0;
        for (int k = 0; k < b->cases[c].noptions; k++)
            scene |= strstr(b->cases[c].options[k], "scene") != NULL;
        if (!scene) {
            bf_options *o = NULL;
            fuzz_check_result(bf_regress_case_options(b, c, &o, &err), &err, o);
            bf_options_free(o);
        }
        /* One channel for even cases, three for odd ones. */
        if (!(made[c] = make_result(&b->cases[c], c % 2 ? 3 : 1, &r[c])))
            fuzz_fail("case %d: model '%s' passed the loader but does not build", c, b->cases[c].model);
        if (bf_regress_check(b, c, &r[c], &outs[c], &err) != BF_OK)
            fuzz_fail("check: %s", err.msg);
        char **changes = NULL;
        int nchanges = 0;
        if (bf_regress_update(b, c, &r[c], &changes, &nchanges, &err) != BF_OK)
            fuzz_fail("update: %s", err.msg);
        for (int k = 0; k < nchanges; k++)
            free(changes[k]);
        free(changes);
    }
    if (b->ncases <= MAX_CASES)
        check_junit(b, outs);
    const char *path = fuzz_path("baseline.json");
    if (bf_regress_write(b, path, &err) != BF_OK)
        fuzz_fail("write: %s", err.msg);
    bf_regress_baseline *b2 = NULL;
    if (bf_regress_load(path, &b2, &err) != BF_OK)
        fuzz_fail("reloading the updated baseline: %s", err.msg);
    if (b2->ncases != b->ncases)
        fuzz_fail("%d cases reloaded as %d", b->ncases, b2->ncases);
    for (int c = 0; c < n; c++) {
        bf_regress_outcome o;
        bf_regress_outcome_init(&o);
        if (bf_regress_check(b2, c, &r[c], &o, &err) != BF_OK)
            fuzz_fail("check after update: %s", err.msg);
        if (o.status != BF_REGRESS_PASS)
            fuzz_fail("case %d fails right after its update: %s", c, o.nlines ? o.lines[0] : "?");
        bf_regress_outcome_clear(&o);
    }
    for (int c = 0; c < n; c++) {
        bf_regress_outcome_clear(&outs[c]);
        if (made[c])
            free_result(&r[c]);
    }
    bf_regress_baseline_free(b2);
    bf_regress_baseline_free(b);
    return 0;
}
