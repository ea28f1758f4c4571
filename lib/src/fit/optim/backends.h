/* Internal: the back ends bf_solve (solve.h) dispatches to, one per optimizer library.
 * Callers outside the optimizer layer use bf_solve. */
#ifndef BF_BACKENDS_H
#define BF_BACKENDS_H

#include "brdfit/solve.h"

#ifdef __cplusplus
extern "C" {
#endif

bf_status bf_solve_ceres(const bf_problem *p, const bf_solver_options *o, double *x, bf_solution *s, bf_error *err);
bf_status bf_solve_nlopt(const bf_problem *p, const bf_solver_options *o, double *x, bf_solution *s, bf_error *err);

#ifdef __cplusplus
}
#endif

#endif
