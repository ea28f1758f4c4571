/* brdfit convert IN OUT [data options] [--to csv|merl]: read any supported format,
 * optionally preprocess, write CSV or MERL binary. */
#include <stdio.h>
#include <string.h>

#include "brdfit/formats.h"
#include "brdfit/samples.h"
#include "args.h"
#include "cli.h"
#include "commands.h"
#include "data_options.h"

/* What the command line asked for. */
typedef struct convert_args {
    bf_options *o;
    const char *paths[2]; /* IN, OUT */
    int npaths;
    bf_format to;
} convert_args;

static int take_to(void *target, const cli_option *o, const char *v, const char *cmd)
{
    (void)o;
    if (strcmp(v, "csv") && strcmp(v, "merl")) {
        fprintf(stderr, "%s: --to takes csv or merl, got '%s'\n", cmd, v);
        return -1;
    }
    ((convert_args *)target)->to = v[0] == 'c' ? BF_FORMAT_CSV : BF_FORMAT_MERL;
    return 0;
}

static const cli_option own[] = {
    {"--to", 0, "csv|merl", "output format (default: by OUT's extension, .csv or .binary)", NULL, CLI_CALLS(take_to)},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group, &data_options_reading, &data_options_preprocessing};
const cli_command cli_convert = {
    "brdfit",
    "convert",
    "IN OUT [data options] [--to csv|merl]",
    "convert between data formats",
    "Reads IN in any supported format (- for standard input), applies the data options, and writes OUT as CSV or "
    "MERL binary (- for standard output, with --to). MERL output needs 3 channels at MERL cell centres; a MERL "
    "table written back keeps the bytes of the cells it does not change. Whatever convert writes, brdfit reads "
    "back to the same samples.",
    "file",
    groups,
    sizeof groups / sizeof groups[0],
};

/* The operands: IN, then OUT. */
static int take_path(void *ctx, const char *v, const char *cmd)
{
    convert_args *c = ctx;
    if (c->npaths == 2) {
        fprintf(stderr, "%s: too many arguments ('%s')\n", cmd, v);
        return -1;
    }
    c->paths[c->npaths++] = v;
    return 0;
}

/* After parsing: checks, reads, writes; the exit status. */
static int convert(convert_args *c)
{
    const char *const *paths = c->paths;
    bf_format to = c->to;
    if (c->npaths != 2) {
        fprintf(stderr, "brdfit convert: needs IN and OUT (see brdfit convert --help)\n");
        return 2;
    }
    if (to == BF_FORMAT_AUTO && (to = bf_format_for_writing(paths[1])) == BF_FORMAT_AUTO) {
        fprintf(stderr, "brdfit convert: %s: cannot tell the output format (use .csv, .binary or --to)\n", paths[1]);
        return 2;
    }
    /* Never over the input (under any name), and a writable output before reading. */
    char scene[4096];
    const bf_path_use in[] = {{"input", paths[0]}, {"--scene file", data_options_scene(c->o, scene, sizeof scene)}},
                      out[] = {{"output", paths[1]}};
    int bad = args_check_outputs("brdfit convert", in, 2, out, 1);
    if (bad)
        return bad;
    /* A MERL table written back keeps the bytes of the cells it does not change. */
    bf_options_keep_origin(c->o, to == BF_FORMAT_MERL);
    bf_load_report rep;
    bf_samples *s = data_options_load(c->o, paths[0], &rep, NULL, "brdfit convert");
    if (!s)
        return 1;
    bf_error err;
    int rc = bf_samples_write(s, paths[1], to, &err);
    if (rc != BF_OK)
        fprintf(stderr, "brdfit convert: %s\n", err.msg);
    else if (!cli_quiet()) /* on stderr when the data goes to standard output */
        fprintf(strcmp(paths[1], "-") ? stdout : stderr,
                "%s: %zu samples, %d channels (read %zu; dropped %zu below the horizon, %zu non-finite, "
                "%zu above max theta, %zu outside the scene, %zu by subsampling)\n",
                paths[1], s->n, s->channels, rep.read, rep.below_horizon, rep.nonfinite, rep.above_max_theta,
                rep.scene_in - rep.scene_kept, rep.subsampled_out);
    bf_samples_free(s);
    return rc == BF_OK ? 0 : 1;
}

int cmd_convert(int argc, char **argv)
{
    convert_args c = {.to = BF_FORMAT_AUTO};
    if (!(c.o = cmd_options_new(BF_TASK_READ, "brdfit convert")))
        return 1;
    cli_args args;
    int p = cli_parse(&cli_convert, argc, argv, &args);
    if (p != CLI_OK) {
        bf_options_free(c.o);
        return p == CLI_EXIT ? 0 : 2;
    }
    void *const targets[] = {&c, &c.o, &c.o};
    int bad = cli_take(&cli_convert, targets, CLI_COUNT(targets), &args, take_path, &c, "brdfit convert");
    cli_args_free(&args);
    int status = bad ? 2 : convert(&c);
    bf_options_free(c.o);
    return status;
}
