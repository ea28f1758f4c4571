/* brdfit-doc (built, not installed): writes the man pages and the bash completion
 * scripts of brdfit and brdfit-synth from their option tables, so that --help, the pages
 * and the completion never disagree.
 *
 *   brdfit-doc OUTDIR VERSION
 *     OUTDIR/man1/brdfit.1, brdfit-COMMAND.1 for each command, brdfit-synth.1
 *     OUTDIR/completions/brdfit, OUTDIR/completions/brdfit-synth */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "brdfit/model.h"
#include "brdfit/solve.h"
#include "commands.h"
#include "synth_cli.h"

static FILE *open_out(const char *dir, const char *sub, const char *name)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, sub);
    if (mkdir(path, 0755) != 0 && errno != EEXIST) {
        fprintf(stderr, "brdfit-doc: %s: %s\n", path, strerror(errno));
        exit(1);
    }
    snprintf(path, sizeof path, "%s/%s/%s", dir, sub, name);
    FILE *fp = fopen(path, "w");
    if (!fp) {
        fprintf(stderr, "brdfit-doc: %s: %s\n", path, strerror(errno));
        exit(1);
    }
    return fp;
}

static void close_out(FILE *fp)
{
    if (ferror(fp) | fclose(fp)) {
        fprintf(stderr, "brdfit-doc: write error\n");
        exit(1);
    }
}

/* brdfit(1): what the tool is, and its commands, each with its own page. */
static void overview(const char *version, FILE *out)
{
    fprintf(out,
            ".TH BRDFIT 1 \"\" \"brdfit %s\" \"brdfit manual\"\n.SH NAME\nbrdfit \\- fit parametric BRDF models "
            "to measured reflectance\n.SH SYNOPSIS\n.B brdfit\n\\fICOMMAND\\fR [\\fIoptions\\fR]\n.br\n"
            ".B brdfit help\n[\\fICOMMAND\\fR]\n.br\n.B brdfit \\-\\-version\n.SH DESCRIPTION\n"
            "brdfit fits analytic BRDF models (Lambert, Phong, Cook\\-Torrance, Ward, GGX and many more) to "
            "measured reflectance: MERL tables, goniometer CSV files, Cornell and ALTA files, or synthetic "
            "samples from brdfit\\-synth(1). It reports each fit's parameters and errors and ranks models by "
            "their error against their number of parameters.\n.PP\nEvery command takes \\-h/\\-\\-help, "
            "\\-q/\\-\\-quiet and \\-v/\\-\\-verbose; long options take \\fB\\-\\-name value\\fR or "
            "\\fB\\-\\-name=value\\fR, short ones \\fB\\-m value\\fR or \\fB\\-mvalue\\fR; \\fB\\-\\-\\fR ends "
            "the options; \\fB\\-\\fR is standard input or output.\n.SH COMMANDS\n",
            version);
    for (int i = 0; i < ncommands; i++)
        fprintf(out, ".TP\n.BR brdfit\\-%s (1)\n%s.\n", commands[i].cli->name, commands[i].cli->summary);
    fputs(".SH ENVIRONMENT\n.TP\n.B BRDFIT_MEMORY\nThe most memory large arrays may take (bytes, or with a K, M, G "
          "or T suffix); lower than what the machine, its control group and ulimit allow.\n.TP\n"
          ".B BRDFIT_PLUGIN_DIR\nWhere to look for the image module (libbrdfit\\-oiio.so) first.\n"
          ".SH EXIT STATUS\n0: done; 1: a failure; 2: bad usage.\n.SH SEE ALSO\nbrdfit\\-synth(1); the models, "
          "formulas and formats: docs/ in the brdfit sources.\n",
          out);
}

/* Completion words from the registries: model names (and "all" for compare), the
 * optimizer methods, the methods that can be G_MLSL_LDS's local one. */
static const char *registry_words(const char *kind)
{
    static char buf[4096];
    buf[0] = '\0';
    size_t used = 0;
    if (!strcmp(kind, "model")) {
        used = (size_t)snprintf(buf, sizeof buf, "all");
        for (int f = 0; f < bf_family_count() && used < sizeof buf; f++)
            used += (size_t)snprintf(buf + used, sizeof buf - used, "|%s", bf_family_get(f)->name);
        return buf;
    }
    if (!strcmp(kind, "method") || !strcmp(kind, "local_method")) {
        for (int i = 0; i < bf_method_count() && used < sizeof buf; i++) {
            const bf_method_info *m = bf_method_get(i);
            if (!strcmp(kind, "method") || (m->caps & BF_METHOD_LOCAL))
                used += (size_t)snprintf(buf + used, sizeof buf - used, "%s%s", used ? "|" : "", m->name);
        }
        return buf;
    }
    return NULL;
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: brdfit-doc OUTDIR VERSION\n");
        return 2;
    }
    const char *dir = argv[1], *version = argv[2];
    if (mkdir(dir, 0755) != 0 && errno != EEXIST) {
        fprintf(stderr, "brdfit-doc: %s: %s\n", dir, strerror(errno));
        return 1;
    }
    FILE *fp = open_out(dir, "man1", "brdfit.1");
    overview(version, fp);
    close_out(fp);
    /* Every option of every command bound to its variable: a table that is not fails the
     * build here. */
    int unbound = cli_check_bound(&cli_synth);
    for (int i = 0; i < ncommands; i++)
        unbound |= cli_check_bound(commands[i].cli);
    if (unbound)
        return 1;
    const cli_command *cmds[64];
    for (int i = 0; i < ncommands; i++) {
        char name[64];
        snprintf(name, sizeof name, "brdfit-%s.1", commands[i].cli->name);
        fp = open_out(dir, "man1", name);
        cli_man(commands[i].cli, version, "brdfit(1)", fp);
        close_out(fp);
        cmds[i] = commands[i].cli;
    }
    fp = open_out(dir, "man1", "brdfit-synth.1");
    cli_man(&cli_synth, version, "brdfit(1), brdfit-eval(1)", fp);
    close_out(fp);

    fp = open_out(dir, "completions", "brdfit");
    cli_completion(cmds, ncommands, registry_words, fp);
    close_out(fp);
    const cli_command *synth[] = {&cli_synth};
    fp = open_out(dir, "completions", "brdfit-synth");
    cli_completion(synth, 1, registry_words, fp);
    close_out(fp);
    return 0;
}
