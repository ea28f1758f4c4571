/* Internal: a parameter file's object already parsed, for readers of files that hold
 * several (the study layer's reference sets). */
#ifndef BF_IO_PARAMS_JSON_H
#define BF_IO_PARAMS_JSON_H

#include <cjson/cJSON.h>

#include "brdfit/error.h"
#include "brdfit/model.h"

/* Where the object came from, for messages: the file as named, its whole text (lines
 * are counted from its start) and where the object starts in it (NULL: the start), so
 * that a key is looked for in this object rather than in an earlier one. */
typedef struct bf_params_src {
    const char *path, *text, *from;
} bf_params_src;

/* bf_params_parse on the object root. check_bounds 0 takes finite values outside the
 * parameters' bounds (a published fit is what it is; the caller says which are
 * outside); 1 refuses them, as a parameter file does. */
bf_status bf_params_from_json(const bf_params_src *s, const cJSON *root, int check_bounds, bf_model **model, double **x,
                              bf_error *err);

#endif
