/* Fitting options shared by brdfit fit and brdfit compare (same spelling, same defaults
 * and the same messages as brdfit fit). */
#include "fit_options.h"

#include "args.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define STR_(x) #x
#define STR(x) STR_(x)

static int take_residual(void *target, const cli_option *o, const char *v, const char *cmd)
{
    bf_error err;
    (void)o;
    if (bf_residual_parse(v, &((fit_options *)target)->fit.objective.residual, &err) != BF_OK) {
        fprintf(stderr, "%s: --residual: %s\n", cmd, err.msg);
        return -1;
    }
    return 0;
}

static int take_loss(void *target, const cli_option *o, const char *v, const char *cmd)
{
    bf_error err;
    (void)o;
    if (bf_loss_parse(v, &((fit_options *)target)->fit.solver.loss, &err) != BF_OK) {
        fprintf(stderr, "%s: --loss: %s\n", cmd, err.msg);
        return -1;
    }
    return 0;
}

/* --fix NAME=VALUE or --bound NAME=LO:HI: one more override. */
static int take_override(void *target, int fix, const char *v, const char *cmd)
{
    fit_options *o = target;
    bf_error err;
    if (o->noverrides >= FIT_OPTIONS_MAX_OVERRIDES) {
        fprintf(stderr, "%s: more than %d --fix/--bound options\n", cmd, FIT_OPTIONS_MAX_OVERRIDES);
        return -1;
    }
    bf_override *ov = &o->overrides[o->noverrides];
    int rc = fix ? bf_override_parse_fix(v, ov, &err) : bf_override_parse_bound(v, ov, &err);
    if (rc != BF_OK) {
        fprintf(stderr, "%s: %s: %s\n", cmd, fix ? "--fix" : "--bound", err.msg);
        return -1;
    }
    o->noverrides++;
    return 0;
}

static int take_fix(void *target, const cli_option *o, const char *v, const char *cmd)
{
    (void)o;
    return take_override(target, 1, v, cmd);
}

static int take_bound(void *target, const cli_option *o, const char *v, const char *cmd)
{
    (void)o;
    return take_override(target, 0, v, cmd);
}

static int take_backend(void *target, const cli_option *o, const char *v, const char *cmd)
{
    (void)o;
    if (bf_backend_parse(v, &((fit_options *)target)->fit.solver.backend, NULL) != BF_OK) {
        fprintf(stderr, "%s: --backend takes ceres or nlopt, got '%s'\n", cmd, v);
        return -1;
    }
    return 0;
}

/* --presolve N|off. */
static int take_presolve(void *target, const cli_option *o, const char *v, const char *cmd)
{
    long n = -1; /* off */
    (void)o;
    if (strcmp(v, "off") && !args_int(v, 64, 1000000000, &n)) {
        fprintf(stderr, "%s: --presolve needs a sample count of at least 64 or 'off', got '%s'\n", cmd, v);
        return -1;
    }
    ((fit_options *)target)->fit.presolve = n;
    return 0;
}

/* The counts' limits: beyond these a run would take days or a thread per core many
 * times over, which is never what was meant. Options an --accuracy preset gives way to
 * carry their BF_FIT_GIVEN_* bit (bf_fit_options_apply_accuracy). */
static const cli_option fitting[] = {
    {"--residual", 0, "linear|cosine|log|cbrt|relative", "residual form (default log)", NULL, CLI_CALLS(take_residual),
     .given = BF_FIT_GIVEN_RESIDUAL},
    {"--loss", 0, "none|huber|cauchy|soft_l1|arctan[:SCALE]", "robust loss (default none)",
     "none|huber|cauchy|soft_l1|arctan", CLI_CALLS(take_loss)},
    {"--fix", 0, "NAME=VALUE", "hold a parameter (NAME or NAME[c]) at VALUE (repeatable)", NULL,
     CLI_CALLS(take_fix)},
    {"--bound", 0, "NAME=LO:HI", "narrow a parameter's bounds (repeatable)", NULL, CLI_CALLS(take_bound)},
    {"--solid-angle", 0, NULL, "weight MERL cells by their solid angle", NULL,
     CLI_SETS(fit_options, fit.objective.solid_angle, 1)},
    {"--no-weights", 0, NULL, "ignore the samples' own weights", NULL,
     CLI_SETS(fit_options, fit.objective.use_weights, 0)},
    {"--constrain-energy", 0, NULL, "energy conservation as a constraint (the methods that take one:\nbrdfit methods)",
     NULL, CLI_SETS(fit_options, fit.solver.use_constraint, 1)},
};
static const cli_option optimizer[] = {
    {"--backend", 0, "ceres|nlopt", "(default ceres)", NULL, CLI_CALLS(take_backend), .given = BF_FIT_GIVEN_BACKEND},
    {"--algorithm", 0, "NAME", "a method of the back end (default: the back end's own);\n"
                               "brdfit methods lists them with what each can do", "method",
     CLI_STRING_AT(fit_options, fit.solver.algorithm), .given = BF_FIT_GIVEN_ALGORITHM},
    {"--local", 0, "NAME", "local method of G_MLSL_LDS (default LD_LBFGS)", "local_method",
     CLI_STRING_AT(fit_options, fit.solver.local_algorithm)},
    {"--max-iterations", 0, "N", "(default: ceres 100 iterations, nlopt 2000 evaluations)", NULL,
     CLI_INT_AT(fit_options, fit.solver.max_iterations, 1, 10000000), .given = BF_FIT_GIVEN_MAX_ITERATIONS},
    {"--starts", 0, "N", "starts solved to convergence, the data-driven one first (default:\n"
                         "automatic, " STR(BF_FIT_STARTS) " to " STR(BF_FIT_STARTS_MAX) " by the data's size; 1: it alone)", NULL,
     CLI_INT_AT(fit_options, fit.starts, 1, FIT_OPTIONS_MAX_STARTS), .given = BF_FIT_GIVEN_STARTS},
    {"--screen", 0, "M", "random candidates whose cost on a small subsample chooses the\n"
                         "other starts, solved there first (default " STR(BF_FIT_SCREEN) "; 0: the other starts\n"
                         "are drawn at random and solved on all samples)", NULL,
     CLI_INT_AT(fit_options, fit.screen, 0, FIT_OPTIONS_MAX_STARTS), .given = BF_FIT_GIVEN_SCREEN},
    {"--presolve", 0, "N|off",
     "solve the starts on a seeded stratified subsample of N samples\nfirst (default: " STR(
         BF_FIT_PRESOLVE_SAMPLES) " for data of " STR(BF_FIT_PRESOLVE_MIN) " samples and more)",
     "off", CLI_CALLS(take_presolve)},
    {"--threads", 0, "N", "(default: every core; results do not depend on it)", NULL,
     CLI_INT_AT(fit_options, fit.solver.threads, 1, FIT_OPTIONS_MAX_THREADS)},
};
const cli_group fit_options_fitting = CLI_GROUP_GIVEN("fitting", fitting, fit_options, given);
const cli_group fit_options_optimizer = CLI_GROUP_GIVEN("optimizer", optimizer, fit_options, given);

static int take_accuracy(void *target, const cli_option *o, const char *v, const char *cmd)
{
    (void)o;
    if (bf_fit_accuracy_parse(v, &((fit_options *)target)->accuracy, NULL) != BF_OK) {
        fprintf(stderr, "%s: --accuracy takes fast, balanced or best, got '%s'\n", cmd, v);
        return -1;
    }
    return 0;
}

/* The numbers are the library's (brdfit/fit.h), which says why they were chosen. */
static const cli_option accuracy[] = {
    {"--accuracy", 0, "fast|balanced|best",
     "option bundles (explicit options win, in any order):\n"
     "fast: --subsample " STR(BF_ACCURACY_FAST_SUBSAMPLE) " --backend ceres --starts 1\n"
     "balanced: the defaults (all samples, --backend ceres, automatic starts,\n"
     "--screen " STR(BF_FIT_SCREEN) ")\n"
     "best: all samples, --backend ceres --starts " STR(BF_ACCURACY_BEST_STARTS) " --screen " STR(
         BF_ACCURACY_BEST_SCREEN) "\n--max-iterations " STR(BF_ACCURACY_BEST_ITERATIONS),
     NULL, CLI_CALLS(take_accuracy)},
};
const cli_group fit_options_accuracy = CLI_GROUP("accuracy", accuracy);

void fit_options_init(fit_options *o)
{
    memset(o, 0, sizeof *o);
    bf_fit_options_init(&o->fit);
}

void fit_options_finish(fit_options *o, data_options *d)
{
    o->fit.seed = d->prep.seed;
    o->fit.weighted_metrics = data_options_has_scene(d);
    unsigned given = o->given | (d->subsample_given ? BF_FIT_GIVEN_SUBSAMPLE : 0u);
    bf_fit_options_apply_accuracy(&o->fit, o->accuracy, given, &d->prep.subsample);
    o->fit.objective.overrides = o->overrides;
    o->fit.objective.noverrides = o->noverrides;
}

static int starts_model(const char *tok, size_t len)
{
    const char *eq = memchr(tok, '=', len), *colon = memchr(tok, ':', len);
    return !eq || colon;
}

int fit_options_split_models(const char *list, char **specs, int n, int max, const char *cmd)
{
    const char *p = list;
    if (!*p) {
        fprintf(stderr, "%s: empty model list in -m\n", cmd);
        return -1;
    }
    while (*p) {
        const char *comma = strchr(p, ',');
        size_t len = comma ? (size_t)(comma - p) : strlen(p);
        if (len == 0) {
            fprintf(stderr, "%s: empty model name in -m '%s'\n", cmd, list);
            return -1;
        }
        if (starts_model(p, len) || n == 0) {
            if (n >= max) {
                fprintf(stderr, "%s: more than %d models\n", cmd, max);
                return -1;
            }
            if (!(specs[n] = strndup(p, len))) {
                fprintf(stderr, "%s: out of memory\n", cmd);
                return -1;
            }
            n++;
        } else { /* an option of the previous model */
            size_t old = strlen(specs[n - 1]);
            char *s = realloc(specs[n - 1], old + len + 2);
            if (!s) {
                fprintf(stderr, "%s: out of memory\n", cmd);
                return -1;
            }
            s[old] = ',';
            memcpy(s + old + 1, p, len);
            s[old + len + 1] = '\0';
            specs[n - 1] = s;
        }
        p = comma ? comma + 1 : p + len;
    }
    return n;
}

int fit_options_check_models(const fit_options *o, char *const *specs, int n, const char *cmd)
{
    for (int k = 0; k < n; k++) {
        bf_error err;
        bf_model *m = NULL;
        if (bf_model_new(specs[k], 1, &m, &err) != BF_OK) {
            fprintf(stderr, "%s: %s\n", cmd, err.msg);
            return -1;
        }
        /* --fix and --bound against each model: bad usage before any data is read. */
        int rc = bf_overrides_check(m, 0, o->overrides, o->noverrides, &err);
        bf_model_free(m);
        if (rc != BF_OK) {
            fprintf(stderr, "%s: %s\n", cmd, err.msg);
            return -1;
        }
    }
    /* The method, its local method and the constraint against the method registry. */
    bf_error err;
    if (bf_solver_options_check(&o->fit.solver, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return -1;
    }
    return 0;
}
