/* Shared by the regression baseline files (lib/src/study/regress/): growing lists of message
 * lines, metric values by name. */
#ifndef BRDFIT_REGRESS_IMPL_H
#define BRDFIT_REGRESS_IMPL_H

#include "brdfit/metrics.h"

/* Appends a formatted line to *lines (*n entries); returns 0, or -1 out of memory. */
int bf_regress_addf(char ***lines, int *n, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* The metric called name (one of bf_regress_metric_names); 0 if it is none. */
int bf_regress_metric(const bf_metrics *m, const char *name, double *out);

#endif
