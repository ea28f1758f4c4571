/* Scene weights on a data set: the time bf_scene_weights takes for each scene file (best
 * of the repeats) and how many samples each keeps; on a full MERL table this is the cost
 * --scene adds to every command.
 * usage: bench_scene DATA [repeats] SCENE.json...   (DATA in any format brdfit reads) */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "brdfit/formats.h"
#include "brdfit/scene.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: bench_scene DATA [repeats] SCENE.json...\n");
        return 2;
    }
    bf_error err;
    bf_samples *s;
    if (bf_samples_read(argv[1], NULL, &s, &err) != BF_OK) {
        fprintf(stderr, "bench_scene: %s\n", err.msg);
        return 1;
    }
    int first = 2, repeats = 5;
    char *end;
    long r = strtol(argv[2], &end, 10);
    if (!*end && r > 0) {
        repeats = (int)r;
        first = 3;
    }
    double *w = malloc((s->n + 1) * sizeof *w);
    int status = w ? 0 : 1;
    for (int k = first; k < argc && status == 0; k++) {
        bf_scene *sc;
        if (bf_scene_read(argv[k], &sc, &err) != BF_OK) {
            fprintf(stderr, "bench_scene: %s\n", err.msg);
            status = 1;
            break;
        }
        double best = 1e300;
        for (int t = 0; t < repeats && status == 0; t++) {
            double t0 = now();
            status = bf_scene_weights(sc, s, w, &err) != BF_OK;
            double dt = now() - t0;
            best = dt < best ? dt : best;
        }
        size_t kept = 0;
        for (size_t i = 0; i < s->n; i++)
            kept += w[i] > 0.0;
        printf("%s: %zu of %zu samples in the scene; bf_scene_weights %.4f s (best of %d)\n", argv[k], kept, s->n, best,
               repeats);
        bf_scene_free(sc);
    }
    free(w);
    bf_samples_free(s);
    return status;
}
