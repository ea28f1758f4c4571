/* A fit's progress reports (progress.h). */
#include "progress.h"

#include <math.h>
#include <string.h>

const char *bf_fit_phase_name(bf_fit_phase phase)
{
    switch (phase) {
    case BF_PHASE_CANDIDATES: return "candidates";
    case BF_PHASE_SCREEN: return "screen";
    case BF_PHASE_PRESOLVE: return "presolve";
    case BF_PHASE_DATA: return "data";
    case BF_PHASE_DONE: return "done";
    }
    return "?";
}

void bf_fit_watch_init(bf_fit_watch *w, const bf_fit_options *o, const char *spec)
{
    memset(w, 0, sizeof *w);
    w->o = o;
    w->r.size = sizeof w->r;
    w->r.spec = spec;
    w->r.material = o->material;
    w->r.material_name = o->material_name;
    w->r.model = o->model;
    w->r.fold = o->fold;
}

void bf_fit_watch_phase(bf_fit_watch *w, bf_fit_phase phase, int starts, size_t samples)
{
    if (!w)
        return;
    w->r.phase = phase;
    w->r.starts = starts;
    w->r.samples = samples;
    w->next = 0;
}

/* The solver's progress callback while a report callback is set: the fit's own progress
 * first (as without reports), then the report. */
static int relay(void *user, int iteration, double cost)
{
    bf_fit_watch *w = user;
    const bf_solver_options *so = &w->o->solver;
    if (so->progress && so->progress(so->progress_user, iteration, cost) != 0)
        return 1;
    w->r.iteration = iteration;
    w->r.cost = cost;
    return w->o->report(w->o->report_user, &w->r) != 0;
}

void bf_fit_watch_solve(bf_fit_watch *w, bf_solver_options *so)
{
    if (!w || !w->o->report)
        return;
    w->r.start = w->next++;
    w->r.iteration = 0;
    w->r.cost = NAN;
    so->progress = relay;
    so->progress_user = w;
}

int bf_fit_watch_candidate(bf_fit_watch *w, int j, double cost)
{
    if (!w || !w->o->report)
        return 0;
    w->r.start = j;
    w->next = j + 1;
    w->r.iteration = 0;
    w->r.cost = isfinite(cost) ? cost : NAN;
    return w->o->report(w->o->report_user, &w->r) != 0;
}

void bf_fit_watch_done(bf_fit_watch *w, const bf_solution *sol, size_t samples)
{
    if (!w->o->report)
        return;
    bf_fit_watch_phase(w, BF_PHASE_DONE, 1, samples);
    w->r.start = 0;
    w->r.iteration = sol->iterations;
    w->r.cost = isfinite(sol->final_cost) ? sol->final_cost : NAN;
    (void)w->o->report(w->o->report_user, &w->r); /* the fit is over: nothing left to stop */
}
