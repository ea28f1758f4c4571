/* brdfit export RESULT.json --to gltf|blender|mitsuba [-o OUT] [--convert]: a fitted material as
 * a renderer's file, through the library's export (brdfit/export.h: the targets, the
 * conversion fit, the writers). This file is the command line and its messages. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/export.h"
#include "brdfit/io.h"
#include "args.h"
#include "cli.h"
#include "commands.h"

/* What the command line asked for (the target is looked up after parsing). */
typedef struct export_args {
    const char *in, *to_name, *out_path;
    int convert;
} export_args;

static const cli_option own[] = {
    {"--to", 0, "gltf|blender|mitsuba",
     "the renderer: glTF 2.0 (.gltf with a sphere), Blender 3.4 (a Python script) or\nMitsuba 3 (scene XML)", NULL,
     CLI_STRING_AT(export_args, to_name)},
    {"--output", 'o', "FILE", "the file (default and -: standard output)", "file",
     CLI_STRING_AT(export_args, out_path)},
    {"--convert", 0, NULL,
     "convert an anisotropic or multi-lobe source too (the target holds one isotropic\n"
     "lobe: the conversion error says what is lost)",
     NULL, CLI_SETS(export_args, convert, 1)},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group};
const cli_command cli_export = {
    "brdfit",
    "export",
    "RESULT.json --to gltf|blender|mitsuba [-o OUT] [--convert]",
    "write a fitted material for a renderer",
    "A result whose model is the target's own (gltf for glTF, blender_principled for Blender, mitsuba_principled for "
    "Mitsuba) is written exactly. "
    "Any other model is converted: the target's model is fitted to the source's values at 11664 direction pairs "
    "(theta 2.5..87.5 by 5 degrees, phi_o 0..350 by 10; phi_i 0..150 by 30 for an anisotropic source), and the "
    "conversion's metrics go to standard error and into the file (glTF asset.extras.brdfit, a comment in the "
    "script or the XML). Colours need 1 or 3 channels. Parameter conventions: docs/export.md.",
    "file",
    groups,
    sizeof groups / sizeof groups[0],
};

/* The operand: the one result file. */
static int take_in(void *ctx, const char *v, const char *c)
{
    export_args *a = ctx;
    if (a->in) {
        fprintf(stderr, "%s: one result file, not '%s' too (see brdfit export --help)\n", c, v);
        return -1;
    }
    a->in = v;
    return 0;
}

/* Takes the parsed command line into a and the target: 0, or 2 after a one-line error. */
static int take_args(const cli_args *args, export_args *a, const bf_export_target **to)
{
    void *const targets[] = {a};
    if (cli_take(&cli_export, targets, CLI_COUNT(targets), args, take_in, a, "brdfit export") < 0)
        return 2;
    if (!a->in || !a->to_name) {
        fprintf(stderr, "brdfit export: a result file and --to are required (see brdfit export --help)\n");
        return 2;
    }
    if (!(*to = bf_export_target_find(a->to_name))) {
        fprintf(stderr, "brdfit export: --to '%s': not a target (gltf, blender, mitsuba)\n", a->to_name);
        return 2;
    }
    return 0;
}

int cmd_export(int argc, char **argv)
{
    export_args a = {NULL, NULL, NULL, 0};
    const bf_export_target *to = NULL;
    cli_args args;
    int p = cli_parse(&cli_export, argc, argv, &args);
    if (p != CLI_OK)
        return p == CLI_EXIT ? 0 : 2;
    int bad = take_args(&args, &a, &to);
    cli_args_free(&args);
    if (bad)
        return bad;
    const char *in = a.in, *out_path = a.out_path;
    const bf_path_use ins[] = {{"result file", in}}, outs[] = {{"-o", out_path}};
    if ((bad = args_check_outputs("brdfit export", ins, 1, outs, 1)) != 0)
        return bad;

    bf_error err;
    bf_model *src = NULL;
    double *xs = NULL;
    bf_fit_result fit;
    bf_fit_result_init(&fit);
    bf_export_material e;
    bf_export_material_init(&e);
    int status = 1;
    if (bf_params_read(in, &src, &xs, &err) != BF_OK) {
        fprintf(stderr, "brdfit export: %s\n", err.msg);
        goto done;
    }
    if (bf_export_check(to, src, a.convert, &err) != BF_OK) {
        fprintf(stderr, "brdfit export: %s: %s\n", in, err.msg);
        goto done;
    }
    if (bf_export_prepare(to, src, xs, &e, &fit, &err) != BF_OK) {
        fprintf(stderr, "brdfit export: %s\n", err.msg);
        goto done;
    }
    if (e.converted) {
        fprintf(stderr, "brdfit export: converted %s to %s, ", bf_model_spec(src), to->model);
        bf_export_conversion_note(&e, stderr);
        fputc('\n', stderr);
    }
    if (bf_export_write(to, &e, out_path, &err) != BF_OK) {
        fprintf(stderr, "brdfit export: %s\n", err.msg);
        goto done;
    }
    status = 0;
done:
    bf_fit_result_clear(&fit);
    bf_model_free(src);
    free(xs);
    return status;
}
