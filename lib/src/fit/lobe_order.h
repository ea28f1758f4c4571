/* Internal: the lobes of a multi-lobe fit in one order, narrowest first (lobe_order.c),
 * and the half width that orders them (also the diagnostics' measure of a lobe). */
#ifndef BF_FIT_LOBE_ORDER_H
#define BF_FIT_LOBE_ORDER_H

#include "objective_state.h"

/* Half width at half maximum in theta_h (radians) of lobe k (0-based) of m (a lobe model,
 * not mono-tied: bf_model_untied) at x, at theta_d = 10 degrees in the plane of
 * incidence; 0 when it does not fall to half within 80 degrees (a broad lobe) or has no
 * peak. */
double bf_fit_lobe_hwhm(const bf_model *m, const double *x, int k);

/* Puts the lobes of model vector x (o's model) in order of their half width, narrowest
 * first (a broad or dead lobe last), the way the data-driven start numbers them: a fit's
 * lobe 1 is then the same lobe whichever start found it. Only where the lobes are
 * interchangeable: the same parameters, bounds and fixed values per lobe (a --fix or
 * --bound on one lobe leaves the order as it is). The model's value is unchanged. */
void bf_fit_order_lobes(const bf_objective *o, double *x);

#endif
