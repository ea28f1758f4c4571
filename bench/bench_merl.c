/* MERL table speed: reading a full table (the file read alone against
 * bf_samples_read_merl, with and without keeping the raw table), preparing it for a fit
 * (preprocessing and a walter objective with the log residual: geometry, weights,
 * measurement terms), and writing it (with the raw table, and without: invalid cells
 * written as -1). The table is generated in a temporary directory with MERL's layout:
 * cells below the horizon -1, the others random.
 * usage: bench_merl [repeats] [directory] */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "brdfit/formats.h"
#include "brdfit/objective.h"
#include "brdfit/load.h"
#include "brdfit/prep.h"
#include "brdfit/samples.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void die(const char *what, const bf_error *err)
{
    fprintf(stderr, "bench_merl: %s: %s\n", what, err ? err->msg : "failed");
    exit(1);
}

/* Raw table as MERL's files hold it (this host is assumed little-endian, as theirs). */
static void generate(const char *path)
{
    const size_t N = BF_MERL_CELLS;
    double *raw = malloc(3 * N * sizeof *raw);
    unsigned long long s = 88172645463325252ULL;
    for (size_t c = 0; c < N; c++) {
        double ti, pi_, to, po;
        bf_merl_cell_directions((int32_t)c, &ti, &pi_, &to, &po);
        for (int p = 0; p < 3; p++) {
            s ^= s << 13, s ^= s >> 7, s ^= s << 17;
            raw[(size_t)p * N + c] = ti >= 90 || to >= 90 ? -1.0 : (double)(s >> 11) / 9007199254740992.0 * 500;
        }
    }
    const int32_t dims[3] = {BF_MERL_TH, BF_MERL_TD, BF_MERL_PD};
    FILE *fp = fopen(path, "wb");
    if (!fp || fwrite(dims, 4, 3, fp) != 3 || fwrite(raw, 8, 3 * N, fp) != 3 * N || fclose(fp) != 0)
        die(path, NULL);
    free(raw);
}

int main(int argc, char **argv)
{
    int reps = argc > 1 ? atoi(argv[1]) : 5;
    const char *dir = argc > 2 ? argv[2] : "/tmp";
    char in[4096], out[4096];
    snprintf(in, sizeof in, "%s/bench_merl_%ld.binary", dir, (long)getpid());
    snprintf(out, sizeof out, "%s/bench_merl_%ld_out.binary", dir, (long)getpid());
    generate(in);

    size_t bytes = 12 + 3 * (size_t)BF_MERL_CELLS * 8;
    char *buf = malloc(bytes);
    bf_error err;
    bf_samples *s = NULL;
    bf_model *m = NULL;
    if (bf_model_new("walter", 3, &m, &err) != BF_OK)
        die("model", &err);
    double best_file = 1e30, best_read = 1e30, best_raw = 1e30, best_prep = 1e30, best_write = 1e30;
    double best_write_plain = 1e30;
    for (int r = 0; r < reps; r++) {
        double t0 = now();
        FILE *fp = fopen(in, "rb");
        if (!fp || fread(buf, 1, bytes, fp) != bytes)
            die(in, NULL);
        fclose(fp);
        double t1 = now();
        bf_samples_free(s);
        if (bf_samples_read_merl(in, 0, &s, &err) != BF_OK)
            die("read", &err);
        double t2 = now();
        bf_options *po = NULL;
        bf_objective_options oo;
        bf_objective_options_init(&oo);
        oo.residual = BF_RESIDUAL_LOG;
        oo.use_weights = 0; /* unweighted, as the timings so far were taken */
        oo.threads = 2;
        bf_objective *obj;
        if (bf_options_new(BF_TASK_READ, &po, &err) != BF_OK || bf_samples_prepare(s, po, NULL, &err) != BF_OK ||
            bf_objective_new(m, s, &oo, &obj, &err) != BF_OK)
            die("prepare", &err);
        bf_options_free(po);
        bf_objective_free(obj);
        double t3 = now();
        if (bf_samples_write_merl(s, out, &err) != BF_OK)
            die("write", &err);
        double t4 = now();
        bf_samples_free(s);
        if (bf_samples_read_merl(in, 1, &s, &err) != BF_OK)
            die("read with the raw table", &err);
        double t5 = now();
        if (bf_samples_write_merl(s, out, &err) != BF_OK)
            die("write with the raw table", &err);
        double t6 = now();
        best_file = fmin(best_file, t1 - t0);
        best_read = fmin(best_read, t2 - t1);
        best_prep = fmin(best_prep, t3 - t2);
        best_write_plain = fmin(best_write_plain, t4 - t3);
        best_raw = fmin(best_raw, t5 - t4);
        best_write = fmin(best_write, t6 - t5);
    }
    printf("MERL table: %zu bytes, %zu valid samples of %d cells; best of %d\n", bytes, s->n, BF_MERL_CELLS, reps);
    printf("  file read alone (fread)             %7.3f s\n", best_file);
    printf("  bf_samples_read_merl                %7.3f s  (%.2f x the file read)\n", best_read, best_read / best_file);
    printf("  bf_samples_read_merl, raw kept      %7.3f s\n", best_raw);
    printf("  prep + walter objective (log, 2 threads) %7.3f s\n", best_prep);
    printf("  read + prepare                      %7.3f s\n", best_read + best_prep);
    printf("  bf_samples_write_merl (raw table)   %7.3f s\n", best_write);
    printf("  bf_samples_write_merl (no raw)      %7.3f s\n", best_write_plain);
    bf_model_free(m);
    bf_samples_free(s);
    free(buf);
    remove(in);
    remove(out);
    return 0;
}
