/* Batch evaluation speed of every model (default options, 3 channels): values only,
 * and values with the full Jacobian, over a MERL-sized set of direction pairs.
 * usage: bench_eval [samples] [repeats] [model,model,...] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "brdfit/geometry.h"
#include "brdfit/model.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int selected(const char *list, const char *name)
{
    if (!list)
        return 1;
    size_t n = strlen(name);
    for (const char *p = list; (p = strstr(p, name)); p += n)
        if ((p == list || p[-1] == ',') && (p[n] == '\0' || p[n] == ','))
            return 1;
    return 0;
}

int main(int argc, char **argv)
{
    size_t n = argc > 1 ? (size_t)atol(argv[1]) : 1100000;
    int reps = argc > 2 ? atoi(argv[2]) : 3;
    const char *only = argc > 3 ? argv[3] : NULL;
    const int C = 3;
    double *a = malloc(4 * n * sizeof *a);
    unsigned long long s = 88172645463325252ULL;
    for (size_t i = 0; i < 4 * n; i++) { /* xorshift: uniform angles above the horizon */
        s ^= s << 13, s ^= s >> 7, s ^= s << 17;
        double u = (double)(s >> 11) / 9007199254740992.0;
        a[i] = (i / n) % 2 ? 2.0 * M_PI * u : acos(u);
    }
    double t0 = now();
    bf_geometry *g = NULL;
    bf_geometry_from_angles(n, a, a + n, a + 2 * n, a + 3 * n, &g, NULL);
    printf("geometry: %zu samples in %.3f s\n", n, now() - t0);
    printf("%-24s %4s %14s %18s\n", "model", "P", "values Ms/s", "values+grad Ms/s");
    double *v = malloc(n * C * sizeof *v);
    for (int f = 0; f < bf_family_count(); f++) {
        const char *name = bf_family_get(f)->name;
        if (!selected(only, name))
            continue;
        bf_model *m = NULL;
        bf_model_new(name, C, &m, NULL);
        int P = bf_model_nvalues(m);
        double *x = malloc((size_t)P * sizeof *x);
        double *jac = malloc(n * C * (size_t)P * sizeof *jac);
        bf_model_defaults(m, x);
        double best_v = 1e30, best_g = 1e30;
        for (int r = 0; r < reps; r++) {
            t0 = now();
            bf_model_eval(m, x, g, v, NULL);
            double t1 = now();
            bf_model_eval(m, x, g, v, jac);
            double t2 = now();
            best_v = fmin(best_v, t1 - t0);
            best_g = fmin(best_g, t2 - t1);
        }
        printf("%-24s %4d %14.1f %18.1f\n", name, P, n / best_v * 1e-6, n / best_g * 1e-6);
        free(jac);
        free(x);
        bf_model_free(m);
    }
    free(v);
    free(a);
    bf_geometry_free(g);
    return 0;
}
