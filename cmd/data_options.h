/* The library's reading and preprocessing options (brdfit/options.h) as command-line
 * groups, and loading data (bf_samples_load) with its errors printed. */
#ifndef BRDFIT_DATA_OPTIONS_H
#define BRDFIT_DATA_OPTIONS_H

#include "brdfit/load.h"
#include "brdfit/options.h"
#include "brdfit/samples.h"
#include "cli.h"

/* The options, for a command's tables (cli.h): how to read, what to do to the samples.
 * Both take a bf_options * as their cli_take target. */
extern const cli_group data_options_reading, data_options_preprocessing;

/* A command's options for task, messages spelled as on the command line; NULL after a
 * one-line error (out of memory). */
bf_options *cmd_options_new(bf_task task, const char *cmd);

/* The data file operand v: taken into *data when it is the first; a second is bad
 * usage (returns -1 after printing the one-line error, prefix cmd); 0 otherwise. */
int data_options_take_file(const char **data, const char *v, const char *cmd);

/* bf_samples_load, its error printed ("CMD: message") and what it did said under
 * --verbose; NULL on failure, with the error in err when err is not NULL (a message to
 * keep: a JUnit report, a batch item). report may be NULL. */
bf_samples *data_options_load(const bf_options *o, const char *path, bf_load_report *report, bf_error *err,
                              const char *cmd);

/* The scene file of o, or NULL. */
const char *data_options_scene(const bf_options *o, char *buf, size_t size);

#endif
