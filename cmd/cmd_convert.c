/* brdfit convert IN OUT [data options] [--to csv|merl]: read any supported format,
 * optionally preprocess, write CSV or MERL binary. */
#include <stdio.h>
#include <string.h>

#include "brdfit/samples.h"
#include "args.h"
#include "commands.h"
#include "data_options.h"

static void usage(FILE *out)
{
    fprintf(out, "usage: brdfit convert IN OUT [options]\n"
                 "  writes OUT as CSV (.csv) or MERL binary (.binary); --to csv|merl overrides\n"
                 "  the extension. MERL output needs 3 channels at MERL cell centres.\n%s",
            data_options_usage);
}

int cmd_convert(int argc, char **argv)
{
    data_options opt = {0};
    const char *paths[2] = {NULL, NULL};
    bf_format to = BF_FORMAT_AUTO;
    int npaths = 0;
    for (int i = 1; i < argc; i++) {
        int r = data_options_parse(&opt, argc, argv, &i, "brdfit convert");
        if (r < 0)
            return 2;
        if (r > 0)
            continue;
        if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
            usage(stdout);
            return 0;
        }
        if (!strcmp(argv[i], "--to") && i + 1 < argc) {
            const char *v = argv[++i];
            if (strcmp(v, "csv") && strcmp(v, "merl")) {
                fprintf(stderr, "brdfit convert: --to takes csv or merl, got '%s'\n", v);
                return 2;
            }
            to = v[0] == 'c' ? BF_FORMAT_CSV : BF_FORMAT_MERL;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            fprintf(stderr, "brdfit convert: unknown option '%s'\n", argv[i]);
            return 2;
        } else if (npaths < 2) {
            paths[npaths++] = argv[i];
        } else {
            fprintf(stderr, "brdfit convert: too many arguments ('%s')\n", argv[i]);
            return 2;
        }
    }
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
    else
        printf("%s: %zu samples, %d channels (read %zu; dropped %zu below the horizon, %zu non-finite, "
               "%zu above max theta, %zu outside the scene, %zu by subsampling)\n",
               paths[1], s->n, s->channels, rep.read, rep.below_horizon, rep.nonfinite,
               rep.above_max_theta, scene.in - scene.kept, rep.subsampled_out);
    bf_samples_free(s);
    return rc == BF_OK ? 0 : 1;
}
