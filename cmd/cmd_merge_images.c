/* brdfit merge-images: the outputs of `brdfit fit-images --tile I/N` runs (one folder
 * per tile, e.g. from a job array) merged into the whole image's outputs, the same as
 * one run of the whole image writes (brdfit/photo.h: bf_photo_merge).
 * Exit 2 for bad usage, 1 for tiles that do not belong together or an unwritable output. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/photo.h"
#include "args.h"
#include "cli.h"
#include "commands.h"

static const char cmd[] = "brdfit merge-images";

typedef struct merge_images_args {
    const char *out;
    const char **dirs;
    int ndirs;
} merge_images_args;

static const cli_option own[] = {
    {"--output", 'o', "DIR", "the merged output folder", "dir", CLI_STRING_AT(merge_images_args, out)},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group};
const cli_command cli_merge_images = {
    "brdfit",
    "merge-images",
    "TILE_DIR... -o OUTDIR",
    "merge the tiles of a fit-images run into the whole image",
    "Each TILE_DIR is the output of `brdfit fit-images STACK --tile I/N` for one I; every tile of the run must be "
    "given once. The tiles start from the same whole-image subsample, so the merged folder holds what one run of "
    "the whole image writes: every map, the counts and relit errors summed, and the previews drawn anew.",
    "dir",
    groups,
    sizeof groups / sizeof groups[0],
};

static int take_dir(void *ctx, const char *v, const char *c)
{
    (void)c;
    merge_images_args *a = ctx;
    a->dirs[a->ndirs++] = v;
    return 0;
}

int cmd_merge_images(int argc, char **argv)
{
    merge_images_args a = {0};
    if (!(a.dirs = calloc((size_t)argc + 1, sizeof *a.dirs))) {
        fprintf(stderr, "%s: out of memory\n", cmd);
        return 1;
    }
    cli_args args;
    int p = cli_parse(&cli_merge_images, argc, argv, &args);
    if (p != CLI_OK) {
        free(a.dirs);
        return p == CLI_EXIT ? 0 : 2;
    }
    void *const targets[] = {&a};
    int bad = cli_take(&cli_merge_images, targets, CLI_COUNT(targets), &args, take_dir, &a, cmd) < 0 ? 2 : 0;
    cli_args_free(&args);
    if (!bad && (!a.out || !a.ndirs)) {
        fprintf(stderr, "%s: %s is required (see %s --help)\n", cmd, !a.ndirs ? "TILE_DIR" : "-o OUTDIR", cmd);
        bad = 2;
    }
    if (bad) {
        free(a.dirs);
        return bad;
    }
    char *line = NULL;
    args_append_word(&line, "brdfit");
    for (int i = 0; i < argc; i++)
        args_append_word(&line, argv[i]);
    bf_error err;
    int status = 0;
    if (bf_photo_check_output(a.out, &err) != BF_OK || bf_photo_merge(a.dirs, a.ndirs, a.out, line, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        status = 1;
    } else if (!cli_quiet())
        fprintf(stderr, "%s: %d tiles -> %s\n", cmd, a.ndirs, a.out);
    free(line);
    free(a.dirs);
    return status;
}
