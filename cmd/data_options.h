/* Command-line options shared by every command that reads data: how to read the file
 * (format, CSV column mapping) and what to do to the samples (bf_prep). */
#ifndef BRDFIT_DATA_OPTIONS_H
#define BRDFIT_DATA_OPTIONS_H

#include "brdfit/formats.h"
#include "brdfit/prep.h"
#include "brdfit/samples.h"
#include "cli.h"

typedef struct data_options {
    bf_read_options read;
    bf_prep prep;
    char angles_buf[256]; /* storage for --angles names */
    const char *scene;    /* --scene FILE (brdfit/scene.h), read when data is loaded; NULL: none */
    const char *spectral_opt; /* the option that chose what spectral data becomes
                                 (--rgb, --color, --rgb-bands, --luminance); NULL: none */
    int subsample_given;  /* --subsample was on the command line (an --accuracy preset's
                             subsample then gives way) */
} data_options;

/* What --scene did to one data set: the samples it was given (after preprocessing's
 * drops, before subsampling) and those inside the scene. */
typedef struct data_scene_report {
    size_t in, kept;
} data_scene_report;

/* The options, for a command's tables (cli.h): how to read, what to do to the samples.
 * Both are bound to a data_options: its cli_take target. */
extern const cli_group data_options_reading, data_options_preprocessing;

/* The data file operand v: taken into *data when it is the first; a second is bad
 * usage (returns -1 after printing the one-line error, prefix cmd); 0 otherwise. */
int data_options_take_file(const char **data, const char *v, const char *cmd);

/* Reads path and applies the preprocessing, then the scene (drops and weights; before
 * any subsampling, so --subsample N gives N samples inside the scene); prints a one-line
 * error on failure ("cmd: FILE:LINE: problem" for a bad scene file). report->kept and
 * ->subsampled_out describe the final set. */
bf_samples *data_options_load(const data_options *o, const char *path, bf_prep_report *report,
                              const char *cmd);
/* The same, and what the scene kept (scene may be NULL; zeroed without --scene). */
bf_samples *data_options_load_scene(const data_options *o, const char *path, bf_prep_report *report,
                                    data_scene_report *scene, const char *cmd);

/* Why path did not load (after data_options_load failed and said it on stderr): reads
 * it once more, only then, for a message to keep (a JUnit report, a batch item), into
 * msg. */
void data_options_load_reason(const data_options *o, const char *path, char *msg, size_t size);

/* 1 when --scene was given: error should then be reported over the scene's directions
 * (bf_fit_options.weighted_metrics). */
int data_options_has_scene(const data_options *o);

#endif
