/* What every back end takes of a solve's options and reports (brdfit/solve.h): the
 * sized structs' defaults, the stop reasons' names, and the cancel and progress check
 * each back end makes at every iteration. */
#include "brdfit/solve.h"
#include "base/sized.h"

const char *bf_stop_name(bf_stop stop)
{
    switch (stop) {
    case BF_STOP_CONVERGED: return "converged";
    case BF_STOP_ITERATIONS: return "iteration_limit";
    case BF_STOP_TIME: return "time_limit";
    case BF_STOP_CANCELLED: return "cancelled";
    case BF_STOP_FAILED: return "failed";
    }
    return "?";
}

int bf_solver_cancelled(const bf_solver_options *o, int iteration, double cost)
{
    if (o->cancel && *o->cancel)
        return 1;
    return o->progress && o->progress(o->progress_user, iteration, cost) != 0;
}

BF_SIZED_INIT_ZERO(bf_problem)

BF_SIZED_INIT_ZERO(bf_solver_options)
