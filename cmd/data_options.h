/* Command-line options shared by every command that reads data: how to read the file
 * (format, CSV column mapping) and what to do to the samples (bf_prep). */
#ifndef BRDFIT_DATA_OPTIONS_H
#define BRDFIT_DATA_OPTIONS_H

#include "brdfit/prep.h"
#include "brdfit/samples.h"

typedef struct data_options {
    bf_read_options read;
    bf_prep prep;
    char angles_buf[256]; /* storage for --angles names */
} data_options;

/* Usage lines for the options below, for a command's --help. */
extern const char data_options_usage[];

/* If argv[*i] is one of the data options, consumes it (and its value) and returns 1;
 * returns 0 if it is not one; -1 after printing a one-line error (prefix: cmd). */
int data_options_parse(data_options *o, int argc, char **argv, int *i, const char *cmd);

/* Reads path and applies the preprocessing; prints a one-line error on failure. */
bf_samples *data_options_load(const data_options *o, const char *path, bf_prep_report *report,
                              const char *cmd);

#endif
