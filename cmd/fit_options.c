/* The library's fitting options as command-line groups, model lists and the usage
 * checks (fit_options.h). */
#include "fit_options.h"

#include "brdfit/model.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const cli_group fit_options_accuracy = CLI_LIBRARY_GROUP("accuracy", 0);
const cli_group fit_options_fitting = CLI_LIBRARY_GROUP("fitting", 0);
const cli_group fit_options_optimizer = CLI_LIBRARY_GROUP("optimizer", 0);

int fit_options_split_models(const char *list, char **specs, int n, int max, const char *cmd)
{
    bf_error err;
    char **split = NULL;
    int count = 0;
    if (bf_model_list_split(list, &split, &count, &err) != BF_OK) {
        fprintf(stderr, "%s: -m: %s\n", cmd, err.msg);
        return -1;
    }
    for (int k = 0; k < count; k++) {
        if (n >= max) {
            fprintf(stderr, "%s: more than %d models\n", cmd, max);
            bf_free(split);
            return -1;
        }
        if (!(specs[n] = strdup(split[k]))) {
            fprintf(stderr, "%s: out of memory\n", cmd);
            bf_free(split);
            return -1;
        }
        n++;
    }
    bf_free(split);
    return n;
}

int fit_options_check(const bf_options *o, char *const *specs, int n, const char *cmd)
{
    bf_error err;
    if (bf_options_check_models(o, (const char *const *)specs, n, &err) != BF_OK ||
        bf_options_check(o, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return -1;
    }
    return 0;
}
