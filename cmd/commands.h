/* Subcommands of the brdfit command: each declares its options (cli.h) and runs,
 * returning the process exit status. */
#ifndef BRDFIT_COMMANDS_H
#define BRDFIT_COMMANDS_H

#include "cli.h"

extern const cli_command cli_models, cli_methods, cli_eval, cli_info, cli_convert, cli_fit, cli_compare, cli_render,
    cli_tradeoff, cli_select, cli_regress, cli_export, cli_batch, cli_report, cli_merge, cli_fit_images,
    cli_merge_images;

int cmd_models(int argc, char **argv);
int cmd_methods(int argc, char **argv);
int cmd_eval(int argc, char **argv);
int cmd_info(int argc, char **argv);
int cmd_convert(int argc, char **argv);
int cmd_fit(int argc, char **argv);
int cmd_compare(int argc, char **argv);
int cmd_render(int argc, char **argv);
int cmd_tradeoff(int argc, char **argv);
int cmd_select(int argc, char **argv);
int cmd_regress(int argc, char **argv);
int cmd_export(int argc, char **argv);
int cmd_batch(int argc, char **argv);
int cmd_report(int argc, char **argv);
int cmd_merge(int argc, char **argv);
int cmd_fit_images(int argc, char **argv);
int cmd_merge_images(int argc, char **argv);

/* The subcommands in the order brdfit --help lists them (command_list.c). */
typedef struct command {
    const cli_command *cli;
    int (*run)(int argc, char **argv);
} command;
extern const command commands[];
extern const int ncommands;

#endif
