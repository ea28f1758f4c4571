/* Internal: a whole (small) text file in memory, for the JSON readers (parameter
 * files, scenes, regression baselines). */
#ifndef BF_READ_TEXT_H
#define BF_READ_TEXT_H

#include <stddef.h>

#include "brdfit/error.h"

/* *text: the file's bytes plus a terminating NUL (malloc'd; *len = bytes read), or NULL
 * with err set ("PATH: cannot open: reason", "PATH: cannot read", "PATH:LINE: not a
 * text file (a NUL byte)"). */
bf_status bf_read_text(const char *path, char **text, size_t *len, bf_error *err);

#endif
