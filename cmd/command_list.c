/* The brdfit subcommands, for dispatch (main.c) and the generated pages (doc_main.c). */
#include "commands.h"

const command commands[] = {
    {&cli_models, cmd_models},
    {&cli_methods, cmd_methods},
    {&cli_eval, cmd_eval},
    {&cli_info, cmd_info},
    {&cli_convert, cmd_convert},
    {&cli_fit, cmd_fit},
    {&cli_compare, cmd_compare},
    {&cli_render, cmd_render},
    {&cli_tradeoff, cmd_tradeoff},
    {&cli_select, cmd_select},
    {&cli_regress, cmd_regress},
    {&cli_export, cmd_export},
    {&cli_batch, cmd_batch},
    {&cli_report, cmd_report},
    {&cli_merge, cmd_merge},
    {&cli_fit_images, cmd_fit_images},
    {&cli_merge_images, cmd_merge_images},
};
const int ncommands = sizeof commands / sizeof commands[0];
