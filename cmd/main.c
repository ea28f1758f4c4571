/* brdfit: fit parametric BRDF models to measured reflectance. Dispatches subcommands. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/io.h"
#include "brdfit/limits.h"
#include "commands.h"

static const struct {
    const char *name;
    int (*run)(int, char **);
    const char *usage;
} commands[] = {
    {"models", cmd_models, "models [--json]                  list models, parameters, bounds, options"},
    {"eval", cmd_eval, "eval --params P.json --dirs D.csv [-o OUT.csv]   evaluate a model"},
    {"info", cmd_info, "info DATA [data options] [--json]      what a data file holds"},
    {"convert", cmd_convert, "convert IN OUT [data options] [--to csv|merl]   between formats"},
    {"fit", cmd_fit, "fit DATA -m MODEL[,MODEL...] [options] [-o RESULT.json]   fit models to data"},
    {"compare", cmd_compare, "compare DATA... -m MODEL,...|all [options] [--json R.json] [--csv R.csv] [--html DIR]   rank models"},
    {"render", cmd_render, "render --params P.json [--slice|--half-diff] [options] -o OUT.png|OUT.exr   pictures"},
    {"tradeoff", cmd_tradeoff, "tradeoff DATA -m MODEL [options] [--json T.json] [--csv T.csv] [--plot T.png]   fitting time against accuracy"},
    {"select", cmd_select, "select DATA [--models ...] [--tolerance T] [--scene SCENE.json]   the smallest model that serves"},
    {"regress", cmd_regress, "regress BASELINE.json [--update] [--junit OUT.xml]   re-run fits and compare with a baseline"},
};

static void usage(FILE *out)
{
    fprintf(out, "usage: brdfit COMMAND [options]\n");
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        fprintf(out, "  brdfit %s\n", commands[i].usage);
    fprintf(out, "environment: BRDFIT_MEMORY=BYTES[K|M|G|T]   the most memory large arrays may take\n");
}

int main(int argc, char **argv)
{
    /* A run ended by a signal (Ctrl-C, kill, a file size limit) leaves no temporary. */
    bf_remove_temporaries_on_signals();
    const char *memory = getenv("BRDFIT_MEMORY");
    size_t bytes;
    if (memory && *memory && !bf_parse_bytes(memory, &bytes)) {
        fprintf(stderr, "brdfit: BRDFIT_MEMORY='%.40s' is not a byte count (such as 4G, 512M or 1000000)\n", memory);
        return 2;
    }
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    if (strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "--help") == 0) {
        usage(stdout);
        return 0;
    }
    for (size_t i = 0; i < sizeof commands / sizeof commands[0]; i++)
        if (strcmp(argv[1], commands[i].name) == 0)
            return commands[i].run(argc - 1, argv + 1);
    fprintf(stderr, "brdfit: unknown command '%s' (try brdfit --help)\n", argv[1]);
    return 2;
}
