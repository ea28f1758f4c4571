/* brdfit: fit parametric BRDF models to measured reflectance. Dispatches subcommands;
 * `brdfit help [COMMAND]` and `brdfit --version`. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/io.h"
#include "brdfit/tool.h"
#include "brdfit/limits.h"
#include "brdfit/version.h"
#include "commands.h"

static void usage(FILE *out)
{
    fprintf(out, "usage: brdfit COMMAND [options]   (brdfit help COMMAND, or brdfit COMMAND --help)\n");
    for (int i = 0; i < ncommands; i++)
        fprintf(out, "  %-10s %s\n", commands[i].cli->name, commands[i].cli->summary);
    fprintf(out, "  %-10s %s\n", "help", "this list, or a command's options");
    fprintf(out, "options: --version, --help\n"
                 "environment: BRDFIT_MEMORY=BYTES[K|M|G|T]   the most memory large arrays may take\n"
                 "docs: man brdfit-COMMAND, docs/ in the source\n");
}

static const command *find(const char *name)
{
    for (int i = 0; i < ncommands; i++)
        if (!strcmp(name, commands[i].cli->name))
            return &commands[i];
    return NULL;
}

/* brdfit help [COMMAND] */
static int help(int argc, char **argv)
{
    if (argc == 1) {
        usage(stdout);
        return 0;
    }
    const command *c = argc == 2 ? find(argv[1]) : NULL;
    if (!c) {
        fprintf(stderr, "brdfit help: %s (one of the commands brdfit help lists)\n",
                argc == 2 ? "unknown command" : "one command at most");
        return 2;
    }
    cli_help(c->cli, stdout);
    return 0;
}

int main(int argc, char **argv)
{
    /* A run ended by a signal (Ctrl-C, kill, a file size limit) leaves no temporary. */
    bf_remove_temporaries_on_signals();
    const char *memory = getenv("BRDFIT_MEMORY");
    size_t bytes;
    if (memory && *memory && bf_bytes_parse(memory, &bytes, NULL) != BF_OK) {
        fprintf(stderr, "brdfit: BRDFIT_MEMORY='%.40s' is not a byte count (such as 4G, 512M or 1000000)\n", memory);
        return 2;
    }
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    if (!strcmp(argv[1], "-h") || !strcmp(argv[1], "--help")) {
        usage(stdout);
        return 0;
    }
    if (!strcmp(argv[1], "--version")) {
        printf("brdfit %s\n", bf_version());
        return 0;
    }
    if (!strcmp(argv[1], "help"))
        return help(argc - 1, argv + 1);
    const command *c = find(argv[1]);
    if (c)
        return c->run(argc - 1, argv + 1);
    fprintf(stderr, "brdfit: unknown command '%.64s' (try brdfit --help)\n", argv[1]);
    return 2;
}
