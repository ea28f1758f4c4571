/* brdfit methods [--json]: the optimizer methods of every back end and what each can do,
 * from the library's method registry (solve.h). */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/solve.h"
#include "cli.h"
#include "commands.h"

typedef struct methods_args {
    int json;
} methods_args;

static const cli_option own[] = {
    {"--json", 0, NULL, "the same as JSON", NULL, CLI_SETS(methods_args, json, 1)},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group};
const cli_command cli_methods = {
    "brdfit",
    "methods",
    "[--json]",
    "list the optimizer methods and what each can do",
    "Every method of every back end (--backend ceres|nlopt --algorithm NAME; brdfit tradeoff --methods): whether "
    "it uses the gradient, takes the energy constraint (--constrain-energy), searches globally (finite bounds, "
    "many evaluations), can be G_MLSL_LDS's local method (--local), and which is its back end's default. Every "
    "method keeps parameters inside their bounds and minimises the robust losses (--loss).",
    NULL,
    groups,
    sizeof groups / sizeof groups[0],
};

static const struct {
    unsigned bit;
    const char *name;
} caps[] = {
    {BF_METHOD_GRADIENT, "gradient"}, {BF_METHOD_BOUNDS, "bounds"}, {BF_METHOD_CONSTRAINTS, "constraints"},
    {BF_METHOD_GLOBAL, "global"},     {BF_METHOD_LOSSES, "losses"}, {BF_METHOD_LOCAL, "local"},
    {BF_METHOD_DEFAULT, "default"},
};

static void print_json(void)
{
    cJSON *root = cJSON_CreateObject(), *arr = cJSON_AddArrayToObject(root, "methods");
    for (int i = 0; i < bf_method_count(); i++) {
        const bf_method_info *m = bf_method_get(i);
        cJSON *o = cJSON_CreateObject(), *c = cJSON_CreateArray();
        cJSON_AddStringToObject(o, "name", m->name);
        cJSON_AddStringToObject(o, "backend", bf_backend_name(m->backend));
        cJSON_AddStringToObject(o, "summary", m->summary);
        for (size_t k = 0; k < sizeof caps / sizeof caps[0]; k++)
            if (m->caps & caps[k].bit)
                cJSON_AddItemToArray(c, cJSON_CreateString(caps[k].name));
        cJSON_AddItemToObject(o, "capabilities", c);
        cJSON_AddItemToArray(arr, o);
    }
    char *text = cJSON_Print(root);
    puts(text);
    free(text);
    cJSON_Delete(root);
}

static void print_text(void)
{
    for (int i = 0; i < bf_method_count(); i++) {
        const bf_method_info *m = bf_method_get(i);
        char list[128] = "";
        for (size_t k = 0; k < sizeof caps / sizeof caps[0]; k++)
            if ((m->caps & caps[k].bit) && caps[k].bit != BF_METHOD_BOUNDS && caps[k].bit != BF_METHOD_LOSSES)
                snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", *list ? ", " : "", caps[k].name);
        printf("%-6s %-14s %s%s%s%s\n", bf_backend_name(m->backend), m->name, m->summary, *list ? " (" : "", list,
               *list ? ")" : "");
    }
}

int cmd_methods(int argc, char **argv)
{
    methods_args m = {0};
    cli_args args;
    int p = cli_parse(&cli_methods, argc, argv, &args);
    if (p != CLI_OK)
        return p == CLI_EXIT ? 0 : 2;
    void *const targets[] = {&m};
    int bad = cli_take(&cli_methods, targets, CLI_COUNT(targets), &args, NULL, NULL, "brdfit methods");
    cli_args_free(&args);
    if (bad)
        return 2;
    if (m.json)
        print_json();
    else
        print_text();
    return 0;
}
