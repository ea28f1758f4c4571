/* brdfit eval --params P.json --dirs D.csv [-o OUT.csv]: a model's values at given
 * direction pairs, one column per channel. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "brdfit/formats.h"
#include "brdfit/io.h"
#include "brdfit/model.h"
#include "args.h"
#include "cli.h"
#include "commands.h"

static const char *const angle_cols[4] = {"theta_i", "phi_i", "theta_o", "phi_o"};

/* What the command line asked for. */
typedef struct eval_args {
    const char *params_path, *dirs_path, *out_path;
} eval_args;

static const cli_option own[] = {
    {"--params", 0, "FILE", "the model and its parameters (a brdfit fit result; - for standard input)", "file",
     CLI_STRING_AT(eval_args, params_path)},
    {"--dirs", 0, "FILE", "CSV of direction pairs: theta_i,phi_i,theta_o,phi_o in degrees (- for standard input)",
     "file", CLI_STRING_AT(eval_args, dirs_path)},
    {"--output", 'o', "FILE", "the values as CSV (default and -: standard output)", "file",
     CLI_STRING_AT(eval_args, out_path)},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group};
const cli_command cli_eval = {
    "brdfit",
    "eval",
    "--params P.json --dirs D.csv [-o OUT.csv]",
    "evaluate a model at direction pairs",
    "The output repeats the direction columns of D.csv and adds one column per channel (value, or r,g,b, or "
    "c0..cN-1).",
    NULL,
    groups,
    sizeof groups / sizeof groups[0],
};

static void channel_name(int C, int c, char *buf, size_t size)
{
    static const char *const rgb[3] = {"r", "g", "b"};
    if (C == 1)
        snprintf(buf, size, "value");
    else if (C == 3)
        snprintf(buf, size, "%s", rgb[c]);
    else
        snprintf(buf, size, "c%d", c);
}

static void write_table(FILE *fp, const bf_csv *t, const int *col, int C, const double *v)
{
    char buf[40];
    fprintf(fp, "theta_i,phi_i,theta_o,phi_o");
    for (int c = 0; c < C; c++) {
        channel_name(C, c, buf, sizeof buf);
        fprintf(fp, ",%s", buf);
    }
    fputc('\n', fp);
    for (size_t r = 0; r < t->nrows; r++) {
        for (int k = 0; k < 4; k++)
            fprintf(fp, "%s%s", k ? "," : "",
                    bf_format_double(t->data[r * t->ncols + (size_t)col[k]], buf, sizeof buf));
        for (int c = 0; c < C; c++)
            fprintf(fp, ",%s", bf_format_double(v[r * (size_t)C + (size_t)c], buf, sizeof buf));
        fputc('\n', fp);
    }
}

/* Takes the parsed command line into a: 0, or 2 after a one-line error. */
static int take_args(const cli_args *args, eval_args *a)
{
    void *const targets[] = {a};
    if (cli_take(&cli_eval, targets, CLI_COUNT(targets), args, NULL, NULL, "brdfit eval") < 0)
        return 2;
    if (!a->params_path || !a->dirs_path) {
        fprintf(stderr, "brdfit eval: --params and --dirs are required (see brdfit eval --help)\n");
        return 2;
    }
    return 0;
}

/* The four angle columns of the direction table, and at least one row: 0, or -1 after a
 * one-line error. */
static int find_columns(const bf_csv *t, const char *dirs_path, int *col)
{
    for (int k = 0; k < 4; k++)
        if ((col[k] = bf_csv_column(t, angle_cols[k])) < 0) {
            fprintf(stderr, "brdfit eval: %s: missing column %s (need theta_i,phi_i,theta_o,phi_o)\n", dirs_path,
                    angle_cols[k]);
            return -1;
        }
    if (t->nrows == 0) {
        fprintf(stderr, "brdfit eval: %s: no direction rows\n", dirs_path);
        return -1;
    }
    return 0;
}

/* The model's values at every row of t (row-major, channels last) into values: 0, or -1
 * after a one-line error. */
static int evaluate(const bf_model *m, const double *x, const bf_csv *t, const int *col, double *values)
{
    bf_error err;
    size_t n = t->nrows;
    double *ang = malloc(4 * n * sizeof *ang);
    if (!ang) {
        fprintf(stderr, "brdfit eval: out of memory for %zu directions\n", n);
        return -1;
    }
    for (size_t r = 0; r < n; r++)
        for (int k = 0; k < 4; k++)
            ang[(size_t)k * n + r] = t->data[r * t->ncols + (size_t)col[k]] * (M_PI / 180.0);
    bf_geometry *g = NULL;
    bf_geometry_from_angles(n, ang, ang + n, ang + 2 * n, ang + 3 * n, &g, &err);
    free(ang);
    if (!g) {
        fprintf(stderr, "brdfit eval: %s\n", err.msg);
        return -1;
    }
    bf_model_eval(m, x, g, values, NULL);
    bf_geometry_free(g);
    return 0;
}

/* The table to out_path (standard output when NULL or -): 0, or -1 after the error. */
static int write_output(const char *out_path, const bf_csv *t, const int *col, int C, const double *values)
{
    bf_error err;
    bf_outfile out;
    if (bf_outfile_open(&out, out_path, &err) != BF_OK) {
        fprintf(stderr, "brdfit eval: %s\n", err.msg);
        return -1;
    }
    write_table(out.fp, t, col, C, values);
    if (bf_outfile_commit(&out, &err) != BF_OK) { /* checks every write */
        fprintf(stderr, "brdfit eval: %s\n", err.msg);
        return -1;
    }
    return 0;
}

int cmd_eval(int argc, char **argv)
{
    eval_args a = {NULL, NULL, NULL};
    cli_args args;
    int p = cli_parse(&cli_eval, argc, argv, &args);
    if (p != CLI_OK)
        return p == CLI_EXIT ? 0 : 2;
    int bad = take_args(&args, &a);
    cli_args_free(&args);
    if (bad)
        return bad;
    const char *params_path = a.params_path, *dirs_path = a.dirs_path, *out_path = a.out_path;
    const bf_path_use in[] = {{"--params file", params_path}, {"--dirs file", dirs_path}}, outs[] = {{"-o", out_path}};
    if ((bad = args_check_outputs("brdfit eval", in, 2, outs, 1)) != 0)
        return bad;

    bf_error err;
    bf_model *m = NULL;
    double *x = NULL, *values = NULL;
    bf_csv *t = NULL;
    int status = 1, col[4];
    if (bf_params_read(params_path, &m, &x, &err) != BF_OK || bf_csv_read(dirs_path, &t, &err) != BF_OK) {
        fprintf(stderr, "brdfit eval: %s\n", err.msg);
        goto done;
    }
    if (find_columns(t, dirs_path, col) < 0)
        goto done;
    int C = bf_model_channels(m);
    if (!(values = malloc(t->nrows * (size_t)C * sizeof *values))) {
        fprintf(stderr, "brdfit eval: out of memory for %zu directions\n", t->nrows);
        goto done;
    }
    if (evaluate(m, x, t, col, values) == 0 && write_output(out_path, t, col, C, values) == 0)
        status = 0;
done:
    bf_csv_free(t);
    bf_model_free(m);
    free(x);
    free(values);
    return status;
}
