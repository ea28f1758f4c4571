/* Fit options: the defaults every fitting command starts from, and the --accuracy
 * presets (bundles of them), so that fit, select, regress, tradeoff, compare and any
 * later command share one definition. */
#include <string.h>
#include <unistd.h>

#include "brdfit/fit.h"
#include "fit_impl.h"

void bf_fit_options_init(bf_fit_options *o)
{
    memset(o, 0, sizeof *o);
    /* The embedded caller structs carry their sizes (docs/api.md): bf_solve and
     * bf_objective_new refuse them unset. */
    bf_objective_options_init(&o->objective);
    bf_solver_options_init(&o->solver);
    /* Measured BRDFs span decades between the diffuse floor and the highlight: the log
     * form weighs both, where a linear fit serves the peak alone. */
    o->objective.residual = BF_RESIDUAL_LOG;
    o->objective.use_weights = 1;
    o->solver.backend = BF_BACKEND_CERES;
    o->starts = 0; /* automatic (search.c) */
    o->screen = BF_FIT_SCREEN;
    o->material = o->model = -1; /* a fit alone */
    /* Results do not depend on the thread count (fixed chunks summed in a fixed order),
     * so every core costs nothing in reproducibility. */
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    o->solver.threads = cores > 0 ? (int)cores : 1;
}

/* The presets (docs/tradeoff.md, "Accuracy presets"; docs/fitting.md for the search):
 *  - fast: a stratified subsample of BF_ACCURACY_FAST_SUBSAMPLE samples, Ceres, the
 *    data-driven start alone (brdfit's default before the screened search). On the MERL
 *    table it stayed within 0.2% of the full fit's held-out log RMSE at 14-32x less time;
 *    on the car paint a 500-sample subsample lost the highlight (3x the error), so the
 *    count keeps a wide margin (about 125 samples per stratum). Data sets at or below it
 *    are fitted whole. About one fit in ten of the bundled measurements ends in a worse
 *    optimum than the search finds (docs/fitting.md).
 *  - balanced: brdfit fit's defaults (all samples, Ceres, the screened search with
 *    automatic starts).
 *  - best: all samples, Ceres, the screened search with BF_ACCURACY_BEST_STARTS starts from
 *    BF_ACCURACY_BEST_SCREEN candidates and up to BF_ACCURACY_BEST_ITERATIONS Ceres
 *    iterations (two-lobe fits stopped at the default 100 before converging): as
 *    exhaustive as a fit gets, at 5-40x the time of balanced. */
typedef struct preset {
    const char *name;
    size_t subsample; /* 0: every sample */
    bf_backend backend;
    const char *algorithm;
    int starts; /* 0: automatic */
    int screen;
    int ceres_iterations; /* 0: the default; NLopt counts evaluations, so left alone */
} preset;

static const preset presets[] = {
    [BF_ACCURACY_NONE] = {"", 0, BF_BACKEND_CERES, NULL, 0, BF_FIT_SCREEN, 0},
    [BF_ACCURACY_FAST] = {"fast", BF_ACCURACY_FAST_SUBSAMPLE, BF_BACKEND_CERES, NULL, 1, 0, 0},
    [BF_ACCURACY_BALANCED] = {"balanced", 0, BF_BACKEND_CERES, NULL, 0, BF_FIT_SCREEN, 0},
    [BF_ACCURACY_BEST] = {"best", 0, BF_BACKEND_CERES, NULL, BF_ACCURACY_BEST_STARTS, BF_ACCURACY_BEST_SCREEN,
                          BF_ACCURACY_BEST_ITERATIONS},
};
#define NPRESETS ((int)(sizeof presets / sizeof presets[0]))

bf_status bf_fit_accuracy_parse(const char *name, bf_fit_accuracy *out, bf_error *err)
{
    for (int k = BF_ACCURACY_NONE + 1; name && k < NPRESETS; k++)
        if (!strcmp(name, presets[k].name)) {
            *out = (bf_fit_accuracy)k;
            return BF_OK;
        }
    return bf_fail(err, BF_ERR_ARG, "unknown accuracy '%s' (fast, balanced, best)", name ? name : "");
}

const char *bf_fit_accuracy_name(bf_fit_accuracy acc)
{
    return (int)acc >= 0 && (int)acc < NPRESETS ? presets[acc].name : "unknown";
}

void bf_fit_options_apply_accuracy(bf_fit_options *o, bf_fit_accuracy acc, unsigned given, size_t *subsample)
{
    if ((int)acc <= BF_ACCURACY_NONE || (int)acc >= NPRESETS)
        return;
    const preset *p = &presets[acc];
    if (subsample && !(given & BF_FIT_GIVEN_SUBSAMPLE) && p->subsample > 0)
        *subsample = p->subsample;
    if (!(given & (BF_FIT_GIVEN_BACKEND | BF_FIT_GIVEN_ALGORITHM))) {
        o->solver.backend = p->backend;
        o->solver.algorithm = p->algorithm;
    }
    if (!(given & BF_FIT_GIVEN_STARTS))
        o->starts = p->starts;
    if (!(given & BF_FIT_GIVEN_SCREEN))
        o->screen = p->screen;
    if (!(given & BF_FIT_GIVEN_MAX_ITERATIONS) && o->solver.backend == BF_BACKEND_CERES)
        o->solver.max_iterations = p->ceres_iterations;
}
