/* The method registry (solve.h): every back end's methods with what they can do. The
 * back ends map a name to their library's own constant and judge capabilities from here;
 * parsing, `brdfit methods`, the usage text and tradeoff's --methods read the same table. */
#include "brdfit/solve.h"
#include "base/sized.h"

#include <stdio.h>
#include <string.h>
#include <strings.h>

#define ALL_CAN (BF_METHOD_BOUNDS | BF_METHOD_LOSSES) /* robust losses come from the fused pass */

static const bf_method_info methods[] = {
    {"lm", BF_BACKEND_CERES, ALL_CAN | BF_METHOD_GRADIENT | BF_METHOD_DEFAULT,
     "Levenberg-Marquardt trust region on the Gauss-Newton model (J'J, J'r)"},
    {"dogleg", BF_BACKEND_CERES, ALL_CAN | BF_METHOD_GRADIENT, "Powell's dogleg trust region"},
    {"LD_LBFGS", BF_BACKEND_NLOPT, ALL_CAN | BF_METHOD_GRADIENT | BF_METHOD_LOCAL | BF_METHOD_DEFAULT,
     "low-storage BFGS quasi-Newton"},
    {"LD_SLSQP", BF_BACKEND_NLOPT, ALL_CAN | BF_METHOD_GRADIENT | BF_METHOD_CONSTRAINTS | BF_METHOD_LOCAL,
     "sequential least-squares quadratic programming"},
    {"LD_MMA", BF_BACKEND_NLOPT, ALL_CAN | BF_METHOD_GRADIENT | BF_METHOD_CONSTRAINTS | BF_METHOD_LOCAL,
     "method of moving asymptotes"},
    {"LN_BOBYQA", BF_BACKEND_NLOPT, ALL_CAN | BF_METHOD_LOCAL, "derivative-free, quadratic models in a trust region"},
    {"LN_COBYLA", BF_BACKEND_NLOPT, ALL_CAN | BF_METHOD_CONSTRAINTS | BF_METHOD_LOCAL,
     "derivative-free, linear approximations, constraints"},
    {"LN_NELDERMEAD", BF_BACKEND_NLOPT, ALL_CAN | BF_METHOD_LOCAL, "derivative-free Nelder-Mead simplex"},
    {"LN_SBPLX", BF_BACKEND_NLOPT, ALL_CAN | BF_METHOD_LOCAL, "derivative-free subplex (Nelder-Mead on subspaces)"},
    {"GN_DIRECT_L", BF_BACKEND_NLOPT, ALL_CAN | BF_METHOD_GLOBAL, "global, deterministic: locally biased DIRECT"},
    {"GN_CRS2_LM", BF_BACKEND_NLOPT, ALL_CAN | BF_METHOD_GLOBAL, "global, stochastic: controlled random search"},
    {"GN_ISRES", BF_BACKEND_NLOPT, ALL_CAN | BF_METHOD_GLOBAL | BF_METHOD_CONSTRAINTS,
     "global, stochastic: evolution strategy with constraints"},
    {"G_MLSL_LDS", BF_BACKEND_NLOPT, ALL_CAN | BF_METHOD_GLOBAL,
     "global: multi-level single linkage, a local method (--local) from low-discrepancy starts"},
};
enum { NMETHODS = sizeof methods / sizeof methods[0] };

int bf_method_count(void)
{
    return NMETHODS;
}

const bf_method_info *bf_method_get(int i)
{
    return i >= 0 && i < NMETHODS ? &methods[i] : NULL;
}

const char *bf_backend_name(bf_backend b)
{
    return b == BF_BACKEND_NLOPT ? "nlopt" : "ceres";
}

bf_status bf_backend_parse(const char *text, bf_backend *out, bf_error *err)
{
    if (text && !strcmp(text, "ceres"))
        *out = BF_BACKEND_CERES;
    else if (text && !strcmp(text, "nlopt"))
        *out = BF_BACKEND_NLOPT;
    else
        return bf_fail(err, BF_ERR_ARG, "unknown back end '%s' (ceres, nlopt)", text ? text : "");
    return BF_OK;
}

const bf_method_info *bf_method_default(bf_backend backend)
{
    for (int i = 0; i < NMETHODS; i++)
        if (methods[i].backend == backend && (methods[i].caps & BF_METHOD_DEFAULT))
            return &methods[i];
    return NULL;
}

const bf_method_info *bf_method_find(bf_backend backend, const char *name)
{
    if (!name || !*name)
        return bf_method_default(backend);
    /* Ceres' own name of its default; NLopt's names in any case, as NLopt spells them. */
    if (backend == BF_BACKEND_CERES && !strcmp(name, "levenberg_marquardt"))
        name = "lm";
    for (int i = 0; i < NMETHODS; i++)
        if (methods[i].backend == backend &&
            (backend == BF_BACKEND_NLOPT ? !strcasecmp(name, methods[i].name) : !strcmp(name, methods[i].name)))
            return &methods[i];
    return NULL;
}

size_t bf_method_list(bf_backend backend, unsigned need, unsigned avoid, char *buf, size_t size)
{
    size_t used = 0;
    if (size)
        buf[0] = '\0';
    for (int i = 0; i < NMETHODS; i++) {
        if (methods[i].backend != backend || (methods[i].caps & need) != need || (methods[i].caps & avoid))
            continue;
        int w = snprintf(buf + used, size - used, "%s%s", used ? ", " : "", methods[i].name);
        if (w < 0 || (size_t)w >= size - used)
            break;
        used += (size_t)w;
    }
    return used;
}

bf_status bf_method_parse(const char *text, bf_backend *backend, const bf_method_info **method, bf_error *err)
{
    if (!text || !*text)
        return bf_fail(err, BF_ERR_ARG, "empty method name");
    const char *colon = strchr(text, ':');
    bf_backend b;
    const char *name = text;
    if (colon) { /* BACKEND:NAME */
        char head[16];
        snprintf(head, sizeof head, "%.*s", (int)(colon - text < 15 ? colon - text : 15), text);
        if (bf_backend_parse(head, &b, err) != BF_OK)
            return bf_fail(err, BF_ERR_ARG, "method \"%s\": unknown back end '%s' (ceres, nlopt)", text, head);
        name = colon + 1;
    } else if (bf_backend_parse(text, &b, NULL) == BF_OK) { /* a back end alone: its default */
        name = NULL;
    } else { /* a method name alone: whichever back end has it */
        b = bf_method_find(BF_BACKEND_CERES, text) ? BF_BACKEND_CERES : BF_BACKEND_NLOPT;
    }
    const bf_method_info *m = bf_method_find(b, name);
    if (!m) {
        char ceres[128], nlopt[256];
        bf_method_list(BF_BACKEND_CERES, 0, 0, ceres, sizeof ceres);
        bf_method_list(BF_BACKEND_NLOPT, 0, 0, nlopt, sizeof nlopt);
        return bf_fail(err, BF_ERR_ARG, "unknown method \"%s\" (ceres: %s; nlopt: %s)", text, ceres, nlopt);
    }
    *backend = b;
    *method = m;
    return BF_OK;
}

bf_status bf_solver_options_check(const bf_solver_options *o, bf_error *err)
{
    char list[256];
    if (bf_sized_check(o, sizeof *o, "bf_solver_options", err) != BF_OK)
        return BF_ERR_ARG;
    const bf_method_info *m = bf_method_find(o->backend, o->algorithm);
    if (!m) {
        bf_method_list(o->backend, 0, 0, list, sizeof list);
        return bf_fail(err, BF_ERR_ARG, "unknown %s method \"%s\" (known: %s)", bf_backend_name(o->backend),
                       o->algorithm, list);
    }
    if (!strcmp(m->name, "G_MLSL_LDS")) { /* the only method that runs a local one (else ignored) */
        const bf_method_info *local = bf_method_find(BF_BACKEND_NLOPT, o->local_algorithm);
        if (!o->local_algorithm || !*o->local_algorithm)
            local = bf_method_find(BF_BACKEND_NLOPT, "LD_LBFGS");
        if (!local || !(local->caps & BF_METHOD_LOCAL)) {
            bf_method_list(BF_BACKEND_NLOPT, BF_METHOD_LOCAL, 0, list, sizeof list);
            return bf_fail(err, BF_ERR_ARG, "G_MLSL_LDS: \"%s\" is not a local NLopt method (known: %s)",
                           o->local_algorithm, list);
        }
    }
    if (o->use_constraint && !(m->caps & BF_METHOD_CONSTRAINTS)) {
        char nl[256];
        bf_method_list(BF_BACKEND_NLOPT, BF_METHOD_CONSTRAINTS, 0, nl, sizeof nl);
        return bf_fail(err, BF_ERR_ARG, "%s method %s does not take constraints (those that do: %s)",
                       bf_backend_name(o->backend), m->name, nl);
    }
    return BF_OK;
}
