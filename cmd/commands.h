/* Subcommands of the brdfit command. Each returns the process exit status. */
#ifndef BRDFIT_COMMANDS_H
#define BRDFIT_COMMANDS_H

int cmd_models(int argc, char **argv);
int cmd_eval(int argc, char **argv);
int cmd_info(int argc, char **argv);
int cmd_convert(int argc, char **argv);
int cmd_fit(int argc, char **argv);
int cmd_compare(int argc, char **argv);
int cmd_render(int argc, char **argv);
int cmd_tradeoff(int argc, char **argv);
int cmd_select(int argc, char **argv);
int cmd_regress(int argc, char **argv);

#endif
