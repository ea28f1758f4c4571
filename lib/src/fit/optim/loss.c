/* The robust losses, shared by every back end and the objective's normal equations
 * (brdfit/solve.h): their values and slopes, and their names. */
#include "brdfit/solve.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* Ceres floors rho' at the smallest normal double so that it never reaches zero; we do
 * the same so both back ends weight residuals identically. */
static double floor_d1(double v)
{
    return v > DBL_MIN ? v : DBL_MIN;
}

double bf_loss_eval(const bf_loss *l, double s, double *d1)
{
    const double a = l ? l->scale : 1.0;
    const bf_loss_kind kind = l ? l->kind : BF_LOSS_NONE;
    double rho, drho;
    switch (kind) {
    case BF_LOSS_HUBER: {
        const double b = a * a;
        if (s > b) {
            const double r = sqrt(s);
            rho = 2.0 * a * r - b;
            drho = floor_d1(a / r);
        } else {
            rho = s;
            drho = 1.0;
        }
        break;
    }
    case BF_LOSS_CAUCHY: {
        const double b = a * a, sum = 1.0 + s / b;
        rho = b * log1p(s / b); /* = b log(sum), exact for small s */
        drho = floor_d1(1.0 / sum);
        break;
    }
    case BF_LOSS_SOFT_L1: {
        const double b = a * a, t = sqrt(1.0 + s / b);
        rho = 2.0 * s / (t + 1.0); /* = 2 b (t - 1) without the cancellation at small s */
        drho = floor_d1(1.0 / t);
        break;
    }
    case BF_LOSS_ARCTAN: {
        const double b = 1.0 / (a * a);
        rho = a * atan2(s, a);
        drho = floor_d1(1.0 / (1.0 + s * s * b));
        break;
    }
    case BF_LOSS_NONE:
    default:
        rho = s;
        drho = 1.0;
        break;
    }
    if (d1)
        *d1 = drho;
    return rho;
}

bf_status bf_loss_parse(const char *text, bf_loss *out, bf_error *err)
{
    static const struct {
        const char *name;
        bf_loss_kind kind;
    } names[] = {
        {"none", BF_LOSS_NONE},       {"huber", BF_LOSS_HUBER},   {"cauchy", BF_LOSS_CAUCHY},
        {"soft_l1", BF_LOSS_SOFT_L1}, {"arctan", BF_LOSS_ARCTAN},
    };
    if (!out)
        return bf_fail(err, BF_ERR_ARG, "bf_loss_parse: no output");
    out->kind = BF_LOSS_NONE;
    out->scale = 1.0;
    if (!text) /* no loss asked for: plain least squares */
        return BF_OK;
    const char *colon = strchr(text, ':');
    size_t len = colon ? (size_t)(colon - text) : strlen(text);
    int found = -1;
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++)
        if (strlen(names[i].name) == len && strncasecmp(text, names[i].name, len) == 0)
            found = (int)i;
    if (found < 0)
        return bf_fail(err, BF_ERR_ARG,
                       "unknown loss \"%s\" (known: none, huber, cauchy, soft_l1, arctan, "
                       "optionally with :SCALE)",
                       text);
    double scale = 1.0;
    if (colon) {
        if (names[found].kind == BF_LOSS_NONE)
            return bf_fail(err, BF_ERR_ARG, "loss \"%s\": \"none\" takes no scale", text);
        char *end = NULL;
        scale = strtod(colon + 1, &end);
        if (end == colon + 1 || *end != '\0')
            return bf_fail(err, BF_ERR_ARG, "loss \"%s\": scale is not a number", text);
        if (!(scale > 0.0) || !isfinite(scale))
            return bf_fail(err, BF_ERR_ARG, "loss \"%s\": scale must be finite and > 0", text);
    }
    out->kind = names[found].kind;
    out->scale = scale;
    return BF_OK;
}
