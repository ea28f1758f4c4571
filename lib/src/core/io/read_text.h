/* Internal: a whole (small) text file in memory, for the JSON readers (parameter
 * files, scenes, regression baselines); a text file line by line, for the readers of
 * tables (Cornell, ALTA). */
#ifndef BF_READ_TEXT_H
#define BF_READ_TEXT_H

#include <stddef.h>
#include <stdio.h>

#include "brdfit/error.h"

/* *text: the file's bytes plus a terminating NUL (malloc'd; *len = bytes read), or NULL
 * with err set ("PATH: cannot open: reason", "PATH: cannot read", "PATH:LINE: not a
 * text file (a NUL byte)"). */
bf_status bf_read_text(const char *path, char **text, size_t *len, bf_error *err);

/* What a line-by-line reader does with one line: the line as read (its newline kept),
 * len bytes; BF_OK to go on. */
typedef bf_status (*bf_line_fn)(void *user, char *line, size_t len);

/* Every line of fp (named path in messages) to each(user, ...), *lineno counting them
 * (from the caller's value), until each fails; the cancel flag (NULL: none) looked at
 * before every line ("PATH: reading cancelled"), and a read error said ("PATH: read
 * error after line N"). */
bf_status bf_read_lines(FILE *fp, const char *path, const bf_cancel_flag *cancel, size_t *lineno, bf_line_fn each,
                        void *user, bf_error *err);

#endif
