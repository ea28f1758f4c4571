/* brdfit merge A.db B.db ... -o ALL.db: the databases of brdfit batch --shard runs (or
 * of any runs of one manifest) joined into one.
 *
 * Decisions:
 *  - Refused, with nothing written, unless every input was made by the same manifest,
 *    brdfit version and schema, and unless an item finished in two inputs has the same
 *    result in both (every column but the wall times): results are never silently
 *    mixed or chosen between.
 *  - The output is new (an existing file is refused) and written under a temporary name
 *    renamed into place at the end: a failed merge leaves no partial database.
 *  - The merged database is shard "all": brdfit batch on it, with the same manifest and
 *    no --shard, runs whatever no input finished; brdfit report reads it.
 *  - Exit: 0 merged; 1 an input refused or unreadable, or the output not writable; 2 bad
 *    usage. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "args.h"
#include "batch/batch_db.h"
#include "cli.h"
#include "commands.h"

static const char cmd[] = "brdfit merge";

/* What the command line asked for: the databases in command-line order. */
typedef struct merge_args {
    const char *out;
    const char **inputs; /* room for every argument */
    int n;
} merge_args;

static const cli_option own[] = {
    {"--output", 'o', "FILE", "the merged database (must not exist)", "file", CLI_STRING_AT(merge_args, out)},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group};
const cli_command cli_merge = {
    "brdfit",
    "merge",
    "A.db B.db ... -o ALL.db",
    "join the databases of brdfit batch --shard runs",
    "Joins results databases of one manifest and brdfit version into a new one, refusing inputs of another manifest "
    "or version and items finished twice with different results.",
    "file",
    groups,
    sizeof groups / sizeof groups[0],
};

/* The merge into tmp, then renamed to out. 0, or 1 after a one-line error. */
static int merge(const char *const *inputs, int n, const char *out)
{
    char tmp[4096];
    batch_db *db;
    bf_error err;
    if (access(out, F_OK) == 0) {
        fprintf(stderr, "%s: %s exists; merge writes a new database\n", cmd, out);
        return 1;
    }
    snprintf(tmp, sizeof tmp, "%s.merging-%ld", out, (long)getpid());
    if (batch_db_open(tmp, BATCH_DB_CREATE, &db, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return 1;
    }
    bf_status rc = batch_db_merge(db, inputs, n, &err);
    batch_db_close(db);
    if (rc == BF_OK && rename(tmp, out) != 0)
        rc = bf_fail(&err, BF_ERR_IO, "%s: cannot write it", out);
    if (rc != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        unlink(tmp);
        return 1;
    }
    return 0;
}

/* Each operand, in order: a database to merge. */
static int take_input(void *ctx, const char *v, const char *c)
{
    merge_args *a = ctx;
    (void)c;
    a->inputs[a->n++] = v;
    return 0;
}

int cmd_merge(int argc, char **argv)
{
    cli_args args;
    int p = cli_parse(&cli_merge, argc, argv, &args);
    if (p != CLI_OK)
        return p == CLI_EXIT ? 0 : 2;
    merge_args a = {NULL, calloc((size_t)argc, sizeof *a.inputs), 0};
    void *const targets[] = {&a};
    int status = 0;
    if (!a.inputs) {
        fprintf(stderr, "%s: out of memory\n", cmd);
        status = 1;
    } else if (cli_take(&cli_merge, targets, CLI_COUNT(targets), &args, take_input, &a, cmd) < 0) {
        status = 2;
    }
    const char *out = a.out, **inputs = a.inputs;
    const int n = a.n;
    if (status == 0 && (n == 0 || !out)) {
        fprintf(stderr, "%s: %s (see brdfit merge --help)\n", cmd,
                n == 0 ? "at least one database to merge is required" : "-o ALL.db is required");
        status = 2;
    }
    if (status == 0) {
        bf_path_use *in = calloc((size_t)n, sizeof *in);
        const bf_path_use o[] = {{"-o", out}};
        for (int i = 0; in && i < n; i++)
            in[i] = (bf_path_use){"database", inputs[i]};
        status = in ? args_check_outputs(cmd, in, n, o, 1) : 1;
        free(in);
    }
    if (status == 0)
        status = merge(inputs, n, out);
    free(inputs);
    cli_args_free(&args);
    return status;
}
