/* brdfit info DATA [data options] [--json]: what a data file holds once read and
 * preprocessed as a fit would see it: samples, channels, angle coverage, what the
 * preprocessing dropped or clamped, and value ranges per channel. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/load.h"
#include "commands.h"
#include "data_options.h"

static const char cmd[] = "brdfit info";

/* What the command line asked for. */
typedef struct info_args {
    bf_options *o;
    const char *path;
    int json;
} info_args;

static const cli_option own[] = {
    {"--json", 0, NULL, "the same as JSON", NULL, CLI_SETS(info_args, json, 1)},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group, &data_options_reading, &data_options_preprocessing};
const cli_command cli_info = {
    "brdfit",
    "info",
    "DATA [data options] [--json]",
    "describe what a data file holds",
    "Format, samples, channels, angle ranges, values and weights of DATA (- for standard input) after the data "
    "options: what a fit of it would see.",
    "file",
    groups,
    sizeof groups / sizeof groups[0],
};

/* Loads the data and prints what it holds: the exit status. */
static int describe(const info_args *a)
{
    const char *path = a->path;
    if (!path) {
        fprintf(stderr, "%s: no data file (usage: brdfit info DATA [data options] [--json])\n", cmd);
        return 2;
    }
    bf_load_report report;
    bf_samples *s = data_options_load(a->o, path, &report, NULL, cmd);
    if (!s)
        return 1;
    /* The report's layout and words are the library's (bf_samples_info_json, _text). */
    bf_error err;
    char *text = NULL;
    bf_status rc = a->json ? bf_samples_info_json(s, &report, a->o, path, &text, &err)
                           : bf_samples_info_text(s, &report, a->o, path, &text, &err);
    bf_samples_free(s);
    if (rc != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return 1;
    }
    fputs(text, stdout);
    bf_free(text);
    return 0;
}

/* The operand: the one data file. */
static int take_path(void *ctx, const char *v, const char *c)
{
    info_args *a = ctx;
    if (a->path) {
        fprintf(stderr, "%s: one data file at a time ('%s' and '%s')\n", c, a->path, v);
        return -1;
    }
    a->path = v;
    return 0;
}

int cmd_info(int argc, char **argv)
{
    info_args a;
    memset(&a, 0, sizeof a);
    if (!(a.o = cmd_options_new(BF_TASK_READ, cmd)))
        return 1;
    cli_args args;
    int p = cli_parse(&cli_info, argc, argv, &args);
    if (p != CLI_OK) {
        bf_options_free(a.o);
        return p == CLI_EXIT ? 0 : 2;
    }
    void *const targets[] = {&a, &a.o, &a.o};
    int bad = cli_take(&cli_info, targets, CLI_COUNT(targets), &args, take_path, &a, cmd);
    cli_args_free(&args);
    int status = bad ? 2 : describe(&a);
    bf_options_free(a.o);
    return status;
}
