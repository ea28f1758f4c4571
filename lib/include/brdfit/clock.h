/* The clock of every wall-time field (bf_fit_result.seconds, bf_solution.seconds, the
 * compare and batch timings): for measuring and progress only, never for deciding, so
 * results stay the same bytes on any machine. */
#ifndef BRDFIT_CLOCK_H
#define BRDFIT_CLOCK_H

#include "brdfit/api.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Monotonic wall time in seconds from an arbitrary origin (CLOCK_MONOTONIC). */
BF_API double bf_now_seconds(void);

#ifdef __cplusplus
}
#endif
#endif
