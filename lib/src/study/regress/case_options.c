/* A baseline case's run options (bf_regress_case_options): the rules of what a case may
 * hold, so that the command and any other runner of baselines read cases alike. */
#include "brdfit/regress.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "brdfit/options.h"
#include "brdfit/scene.h"
#include "run_options.h"

/* The option brdfit fit takes (the run options of BF_TASK_FIT: its data and fit options)
 * that the command line writes as the first len bytes of a ("--max-theta"); NULL when
 * there is none. */
static const bf_option *case_option(const bf_options *o, const char *a, size_t len)
{
    char spelled[96];
    for (int i = 0; i < bf_option_count(); i++) {
        const bf_option *opt = bf_option_get(i);
        if ((opt->tasks & BF_TASK_FIT) && strlen(option_spelled(o, opt->name, spelled, sizeof spelled)) == len &&
            !strncmp(spelled, a, len))
            return opt;
    }
    return NULL;
}

/* One option of case c at options[*i] (and its value, the next entry, unless written
 * --name=value), set into o; *i left on the last entry taken. */
static bf_status take(const bf_regress_baseline *b, const bf_regress_case *cs, int *i, bf_options *o, bf_error *err)
{
    const int line = cs->option_lines[*i];
    const char *a = cs->options[*i], *eq = strchr(a, '='), *v = NULL;
    const size_t len = eq ? (size_t)(eq - a) : strlen(a);
    const bf_option *opt = !strncmp(a, "--", 2) && len < 64 ? case_option(o, a, len) : NULL;
    char name[64];
    if (!opt) {
        if (!strcmp(a, "-m") || !strncmp(a, "--model", 7) || !strcmp(a, "-o") || !strncmp(a, "--output", 8))
            return bf_fail(err, BF_ERR_ARG,
                           "%s:%d: case '%s': option '%s' has no place in a baseline (the case's \"model\" names the "
                           "model)",
                           b->path, line, cs->name, a);
        return bf_fail(err, BF_ERR_ARG,
                       "%s:%d: case '%s': unknown option '%s' (brdfit fit's data and fit options only)", b->path, line,
                       cs->name, a);
    }
    memcpy(name, a, len);
    name[len] = '\0';
    if (!opt->arg && eq)
        return bf_fail(err, BF_ERR_ARG, "%s:%d: case '%s': %s takes no value", b->path, line, cs->name, name);
    if (opt->arg && !eq) {
        if (*i + 1 >= cs->noptions)
            return bf_fail(err, BF_ERR_ARG, "%s:%d: case '%s': %s needs a value", b->path, line, cs->name, name);
        v = cs->options[++*i];
    } else if (eq) {
        v = eq + 1;
    }
    /* A scene, like the data, is relative to the baseline's folder. */
    char *resolved = NULL;
    if (!strcmp(opt->name, "scene") && v && !(v = resolved = bf_regress_resolve(b, v)))
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    bf_error e;
    bf_status rc = bf_options_set(o, name, v, &e);
    free(resolved);
    if (rc != BF_OK)
        return bf_fail(err, rc, "%s:%d: case '%s': %s", b->path, line, cs->name, e.msg);
    return BF_OK;
}

/* The case's data file readable and its scene file valid: a bad baseline is found
 * before any fit runs. */
static bf_status check_files(const bf_regress_baseline *b, const bf_regress_case *cs, const bf_options *o,
                             bf_error *err)
{
    if (access(cs->data_path, R_OK) != 0)
        return bf_fail(err, BF_ERR_IO, "%s:%d: case '%s': data file '%s': %s", b->path, cs->data_line, cs->name,
                       cs->data_path, strerror(errno));
    char scene[4096];
    if (bf_options_get(o, "scene", scene, sizeof scene, NULL) != BF_OK || !*scene)
        return BF_OK;
    bf_scene *sc = NULL;
    bf_error e;
    bf_status rc = bf_scene_read(scene, &sc, &e);
    bf_scene_free(sc);
    if (rc != BF_OK)
        return bf_fail(err, rc, "%s:%d: case '%s': --scene: %s", b->path, cs->data_line, cs->name, e.msg);
    return BF_OK;
}

bf_status bf_regress_case_options(const bf_regress_baseline *b, int c, bf_options **out, bf_error *err)
{
    *out = NULL;
    if (!b || c < 0 || c >= b->ncases)
        return bf_fail(err, BF_ERR_ARG, "regress: no case %d in the baseline", c);
    const bf_regress_case *cs = &b->cases[c];
    bf_options *o = NULL;
    bf_status rc = bf_options_new(BF_TASK_FIT, &o, err);
    if (rc != BF_OK)
        return rc;
    bf_options_set_spelling(o, BF_SPELL_COMMAND_LINE);
    /* One thread unless the case says otherwise: results identical across machines. */
    rc = bf_options_set(o, "threads", "1", err);
    for (int i = 0; rc == BF_OK && i < cs->noptions; i++)
        rc = take(b, cs, &i, o, err);
    if (rc == BF_OK)
        rc = check_files(b, cs, o, err);
    if (rc != BF_OK) {
        bf_options_free(o);
        return rc;
    }
    *out = o;
    return BF_OK;
}
