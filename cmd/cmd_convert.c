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

static const cli_option own[] = {
    {"--to", 0, "csv|merl", "output format (default: by OUT's extension, .csv or .binary)", NULL},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group, &data_options_reading, &data_options_preprocessing};
const cli_command cli_convert = {
    "brdfit", "convert", "IN OUT [data options] [--to csv|merl]", "convert between data formats",
    "Reads IN in any supported format (- for standard input), applies the data options, and writes OUT as CSV or "
    "MERL binary (- for standard output, with --to). MERL output needs 3 channels at MERL cell centres; a MERL "
    "table written back keeps the bytes of the cells it does not change. Whatever convert writes, brdfit reads "
    "back to the same samples.",
    "file", groups, sizeof groups / sizeof groups[0],
};

int cmd_convert(int argc, char **argv)
{
    data_options opt = {0};
    const char *paths[2] = {NULL, NULL};
    bf_format to = BF_FORMAT_AUTO;
    int npaths = 0;
    cli_args args;
    int p = cli_parse(&cli_convert, argc, argv, &args);
    if (p != CLI_OK)
        return p == CLI_EXIT ? 0 : 2;
    for (int i = 0; i < args.n; i++) {
        const char *a = args.v[i].name, *v = args.v[i].value;
        int r = a ? data_options_parse(&opt, a, v, "brdfit convert") : 0;
        if (r < 0)
            goto usage;
        if (r > 0)
            continue;
        if (a) { /* --to */
            if (strcmp(v, "csv") && strcmp(v, "merl")) {
                fprintf(stderr, "brdfit convert: --to takes csv or merl, got '%s'\n", v);
                goto usage;
            }
            to = v[0] == 'c' ? BF_FORMAT_CSV : BF_FORMAT_MERL;
        } else if (npaths < 2) {
            paths[npaths++] = v;
        } else {
            fprintf(stderr, "brdfit convert: too many arguments ('%s')\n", v);
            goto usage;
        }
    }
    cli_args_free(&args);
    if (npaths != 2) {
        fprintf(stderr, "brdfit convert: needs IN and OUT (see brdfit convert --help)\n");
        return 2;
    }
    if (to == BF_FORMAT_AUTO && (to = bf_format_for_writing(paths[1])) == BF_FORMAT_AUTO) {
        fprintf(stderr, "brdfit convert: %s: cannot tell the output format (use .csv, .binary or --to)\n", paths[1]);
        return 2;
    }
    /* Never over the input (under any name), and a writable output before reading. */
    const bf_path_use in[] = {{"input", paths[0]}, {"--scene file", opt.scene}}, out[] = {{"output", paths[1]}};
    int bad = args_check_outputs("brdfit convert", in, 2, out, 1);
    if (bad)
        return bad;
    /* A MERL table written back keeps the bytes of the cells it does not change. */
    opt.read.keep_origin = to == BF_FORMAT_MERL;
    bf_prep_report rep;
    data_scene_report scene;
    bf_samples *s = data_options_load_scene(&opt, paths[0], &rep, &scene, "brdfit convert");
    if (!s)
        return 1;
    bf_error err;
    int rc = bf_samples_write(s, paths[1], to, &err);
    if (rc != BF_OK)
        fprintf(stderr, "brdfit convert: %s\n", err.msg);
    else if (!cli_quiet()) /* on stderr when the data goes to standard output */
        fprintf(strcmp(paths[1], "-") ? stdout : stderr, "%s: %zu samples, %d channels (read %zu; dropped %zu below the horizon, %zu non-finite, "
               "%zu above max theta, %zu outside the scene, %zu by subsampling)\n",
               paths[1], s->n, s->channels, rep.read, rep.below_horizon, rep.nonfinite,
               rep.above_max_theta, scene.in - scene.kept, rep.subsampled_out);
    bf_samples_free(s);
    return rc == BF_OK ? 0 : 1;
usage:
    cli_args_free(&args);
    return 2;
}
