/* brdfit models [--json]: every model with its parameters, options and sizes. */
#include <stdio.h>
#include <stdlib.h>

#include "brdfit/model.h"
#include "cli.h"
#include "commands.h"

static void print_text(const bf_family_info *fi)
{
    bf_model *m1 = NULL, *m3 = NULL;
    if (bf_model_new(fi->name, 1, &m1, NULL) != BF_OK || bf_model_new(fi->name, 3, &m3, NULL) != BF_OK) {
        bf_model_free(m1);
        fprintf(stderr, "brdfit models: out of memory\n");
        return;
    }
    printf("%s  (%s; %s)\n", fi->name, fi->summary, fi->reference);
    printf("  %s, %s, %s%s; free parameters: %d for 1 channel, %d for 3\n",
           fi->anisotropic ? "anisotropic" : "isotropic", bf_model_reciprocal(m1) ? "reciprocal" : "not reciprocal",
           bf_model_energy_conserving(m1) ? "energy conserving" : "not energy conserving", fi->lobes ? ", lobes=K" : "",
           bf_model_nvalues(m1), bf_model_nvalues(m3));
    for (int i = 0; i < bf_model_nparams(m1); i++) {
        const bf_param_info *p = bf_model_param(m1, i);
        printf("  %-16s %-6s %-20s %c%g, %g%c default %g%s\n", p->name, p->color ? "colour" : "scalar",
               bf_param_role_name(p->role), p->lo_open ? '(' : '[', p->lo, p->hi, p->hi_open ? ')' : ']', p->def,
               p->scale == BF_SCALE_LINEAR ? ""
               : p->scale == BF_SCALE_LOG  ? " (log scale)"
                                           : " (log1p scale)");
    }
    for (int k = 0; fi->options && fi->options[k].name; k++) {
        printf("  option %s=", fi->options[k].name);
        for (int v = 0; fi->options[k].values[v]; v++)
            printf("%s%s", v ? "|" : "", fi->options[k].values[v]);
        printf(" (default %s)\n", fi->options[k].values[0]);
    }
    bf_model_free(m1);
    bf_model_free(m3);
}

typedef struct models_args {
    int json, names;
} models_args;

static const cli_option own[] = {
    {"--json", 0, NULL, "the same as JSON: parameters with bounds, defaults, scales; options", NULL,
     CLI_SETS(models_args, json, 1)},
    {"--names", 0, NULL, "the model names alone, one a line (for scripts and completion)", NULL,
     CLI_SETS(models_args, names, 1)},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group};
const cli_command cli_models = {
    "brdfit",
    "models",
    "[--json|--names]",
    "list the models, their parameters, bounds and options",
    "Every model family brdfit fits, with its parameters (colour or scalar, bounds, default, the scale the "
    "optimizer works in) and its options (MODEL:option=value). docs/models.md gives the formulas.",
    NULL,
    groups,
    sizeof groups / sizeof groups[0],
};

int cmd_models(int argc, char **argv)
{
    cli_args args;
    int p = cli_parse(&cli_models, argc, argv, &args);
    if (p != CLI_OK)
        return p == CLI_EXIT ? 0 : 2;
    models_args a = {0, 0};
    void *const targets[] = {&a};
    int bad = cli_take(&cli_models, targets, CLI_COUNT(targets), &args, NULL, NULL, "brdfit models");
    cli_args_free(&args);
    if (bad)
        return 2;
    if (a.json && a.names) {
        fprintf(stderr, "brdfit models: --json and --names exclude each other\n");
        return 2;
    }
    if (a.names) {
        for (int f = 0; f < bf_family_count(); f++)
            puts(bf_family_get(f)->name);
        return 0;
    }
    if (!a.json) {
        for (int f = 0; f < bf_family_count(); f++)
            print_text(bf_family_get(f));
        printf("All models: option mono=specular|all|NAME[+NAME...] ties colour parameters across channels\n"
               "  (specular: every colour parameter but the diffuse colour; one value for all channels)\n");
        return 0;
    }
    char *s = bf_models_json();
    if (!s) {
        fprintf(stderr, "brdfit models: out of memory\n");
        return 1;
    }
    puts(s);
    free(s);
    return 0;
}
