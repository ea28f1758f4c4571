/* Command-line helpers every subcommand shares (see args.h). */
#include "args.h"

#include <stdio.h>
#include <string.h>

const char *args_value(int argc, char **argv, int *i, const char *const *valued, size_t n, const char *cmd)
{
    const char *a = argv[*i];
    size_t k = 0;
    while (k < n && strcmp(a, valued[k]))
        k++;
    if (k == n) {
        fprintf(stderr, "%s: unknown option '%s' (see %s --help)\n", cmd, a, cmd);
        return NULL;
    }
    if (*i + 1 >= argc) {
        fprintf(stderr, "%s: %s needs a value\n", cmd, a);
        return NULL;
    }
    return argv[++*i];
}

int args_check_outputs(const char *cmd, const bf_path_use *inputs, int ninputs, const bf_path_use *outputs,
                       int noutputs)
{
    bf_error err;
    int rc = bf_outputs_check(inputs, ninputs, outputs, noutputs, &err);
    if (rc == BF_OK)
        return 0;
    fprintf(stderr, "%s: %s\n", cmd, err.msg);
    return rc == BF_ERR_ARG ? 2 : 1;
}
