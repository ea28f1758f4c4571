/* brdfit eval --params P.json --dirs D.csv [-o OUT.csv] */
#include <stdio.h>

#include "commands.h"

int cmd_eval(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    fprintf(stderr, "brdfit eval: not built yet\n");
    return 2;
}
