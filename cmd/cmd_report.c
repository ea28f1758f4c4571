/* brdfit report RESULTS.db [--json F] [--csv F] [--html DIR]: the rankings and outputs of
 * brdfit compare, from a brdfit batch database.
 *
 * Decisions:
 *  - The rows become compare's table (bf_compare, each fit's result rebuilt from its
 *    row: batch_rows.h), ranked by bf_compare_rank and written by compare's own writers
 *    and table printer, so the tables, JSON and CSV are those compare writes for the
 *    same fits, to the byte. The ranking options (--rank, --folds, --error, --tolerance,
 *    --timing) are the manifest's, stored in the database.
 *  - Items not run yet (a run still going, interrupted, or a shard's database) are
 *    "not_run" with "interrupted": true, as compare writes an interrupted comparison,
 *    and the exit status is 1 with a line saying how many.
 *  - The HTML report has the tables and plots of the fitted models, without the
 *    measurement's overlays: the data files are not read again.
 *  - Exit: 0 every item ok; 1 some failed or not run, or an unusable database; 2 bad
 *    usage. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "batch/batch_db.h"
#include "batch/batch_manifest.h"
#include "brdfit/render.h"
#include "cli.h"
#include "commands.h"
#include "compare_print.h"

static const char cmd[] = "brdfit report";

typedef struct report_args {
    cli_args args;
    const char *db, *json_path, *csv_path, *html_dir;
    int plot_format;
} report_args;

static int take_plot_format(void *target, const cli_option *o, const char *v, const char *c)
{
    (void)o;
    return compare_plot_format(c, v, &((report_args *)target)->plot_format);
}

static const cli_option own[] = {
    {"--json", 0, "FILE", "everything, machine-readable (as brdfit compare; - for standard output)", "file",
     CLI_STRING_AT(report_args, json_path)},
    {"--csv", 0, "FILE", "one row per material x model (as brdfit compare; - for standard output)", "file",
     CLI_STRING_AT(report_args, csv_path)},
    {"--html", 0, "DIR",
     "a report to read in a browser (as brdfit compare, without the\n"
     "measurement's overlays)",
     "dir", CLI_STRING_AT(report_args, html_dir)},
    {"--plot-format", 0, "png|svg|pdf", "the report's plots (as brdfit compare)", NULL, CLI_CALLS(take_plot_format)},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group};
const cli_command cli_report = {
    "brdfit",
    "report",
    "RESULTS.db [--json R.json] [--csv R.csv] [--html DIR]",
    "compare's rankings and outputs from a batch database",
    "Reads the results database of brdfit batch (or brdfit merge), ranks the models per material and across "
    "materials with the manifest's ranking options, prints compare's tables and writes its JSON, CSV and HTML "
    "report.",
    "file",
    groups,
    sizeof groups / sizeof groups[0],
};

/* The operand: the one database. */
static int take_db(void *ctx, const char *v, const char *c)
{
    report_args *a = ctx;
    if (a->db) {
        fprintf(stderr, "%s: one database only (brdfit merge joins several)\n", c);
        return -1;
    }
    a->db = v;
    return 0;
}

static int parse(report_args *a, int argc, char **argv)
{
    memset(a, 0, sizeof *a);
    int p = cli_parse(&cli_report, argc, argv, &a->args);
    if (p != CLI_OK)
        return p == CLI_EXIT ? 0 : 2;
    void *const targets[] = {a};
    if (cli_take(&cli_report, targets, CLI_COUNT(targets), &a->args, take_db, a, cmd) < 0)
        return 2;
    if (!a->db) {
        fprintf(stderr, "%s: a results database is required (see brdfit report --help)\n", cmd);
        return 2;
    }
    bf_error err;
    if (a->html_dir && bf_compare_html_check(a->html_dir, &err) != BF_OK) {
        fprintf(stderr, "%s: --html %s\n", cmd, err.msg);
        return err.code == BF_ERR_ARG ? 2 : 1;
    }
    const bf_path_use in[] = {{"database", a->db}}, out[] = {{"--json", a->json_path}, {"--csv", a->csv_path}};
    int status = args_check_outputs(cmd, in, 1, out, 2);
    return status ? status : -1;
}

/* One row into its slot of c. */
static bf_status fill(void *ctx, const batch_row *r, bf_error *err)
{
    bf_compare *c = ctx;
    if (r->material < 0 || r->material >= c->nmaterials || r->model < 0 || r->model >= c->nmodels)
        return bf_fail(err, BF_ERR_PARSE, "item %d names no material or model of its manifest", r->item);
    bf_compare_material *mat = &c->materials[r->material];
    if (!r->pending && r->channels > 0) {
        mat->samples = r->samples;
        mat->channels = r->channels;
    }
    const size_t slot = (size_t)r->material * (size_t)c->nmodels + (size_t)r->model;
    if (!c->results[slot] && !(c->results[slot] = malloc(sizeof *c->results[slot])))
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for item %d's result", r->item);
    bf_fit_result_init(c->results[slot]);
    return batch_row_to_fit(r, &mat->fits[r->model], c->results[slot], err);
}

/* The comparison from the database: names, options, every row. 0, or 1 after an error. */
static int load(batch_db *db, bf_compare **out)
{
    bf_compare *c = NULL;
    bf_error err;
    char *text = NULL;
    batch_manifest m = {0};
    char **data = NULL;
    int status = 1;
    if (batch_db_meta(db, "manifest", &text, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return 1;
    }
    if (batch_manifest_read(NULL, text, &m, cmd) < 0)
        goto done;
    if (!(data = calloc((size_t)m.nmaterials, sizeof *data))) {
        fprintf(stderr, "%s: out of memory\n", cmd);
        goto done;
    }
    for (int i = 0; i < m.nmaterials; i++)
        if (batch_db_material(db, i, &data[i], &err) != BF_OK) {
            fprintf(stderr, "%s: %s\n", cmd, err.msg);
            goto done;
        }
    if (bf_compare_new(m.nmaterials, (const char *const *)data, m.nmodels, (const char *const *)m.models, &c, &err) !=
            BF_OK ||
        !(c->results = calloc((size_t)m.nmaterials * (size_t)m.nmodels, sizeof *c->results))) {
        fprintf(stderr, "%s: %s\n", cmd, c ? "out of memory" : err.msg);
        goto done;
    }
    if (bf_compare_set_options(c, m.o, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        goto done;
    }
    if (batch_db_rows(db, fill, c, &err) != BF_OK) {
        fprintf(stderr, "%s: %s: %s\n", cmd, "reading the results", err.msg);
        goto done;
    }
    c->interrupted = bf_compare_count(c, BF_CMP_NOT_RUN) > 0;
    status = 0;
done:
    if (status == 0)
        *out = c;
    else
        bf_compare_free(c);
    for (int i = 0; data && i < m.nmaterials; i++)
        free(data[i]);
    free(data);
    free(text);
    batch_manifest_clear(&m);
    return status;
}

static int write_outputs(const report_args *a, const bf_compare *c)
{
    bf_error err;
    bf_report_options o;
    bf_report_options_init(&o);
    o.format = a->plot_format;
    if (a->html_dir && bf_compare_write_report(c, &o, a->html_dir, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return 1;
    }
    return compare_write_tables(cmd, c, a->json_path, a->csv_path);
}

static int outcome(const bf_compare *c)
{
    int total, not_run, bad;
    compare_counts(c, &total, &not_run, &bad);
    if (not_run)
        fprintf(stderr, "%s: %d of %d items not run yet (brdfit batch resumes them)\n", cmd, not_run, total);
    if (bad)
        fprintf(stderr, "%s: %d of %d fits failed\n", cmd, bad, total);
    return not_run || bad ? 1 : 0;
}

int cmd_report(int argc, char **argv)
{
    report_args a;
    int status = parse(&a, argc, argv);
    if (status < 0) {
        batch_db *db;
        bf_error err;
        bf_compare *c = NULL;
        if (batch_db_open(a.db, BATCH_DB_READ, &db, &err) != BF_OK) {
            fprintf(stderr, "%s: %s\n", cmd, err.msg);
            status = 1;
        } else {
            status = load(db, &c);
            batch_db_close(db);
        }
        if (status == 0) {
            bf_compare_rank(c);
            compare_print_tables(stdout, c);
            status = write_outputs(&a, c);
        }
        if (status == 0)
            status = outcome(c);
        bf_compare_free(c);
    }
    cli_args_free(&a.args);
    return status;
}
