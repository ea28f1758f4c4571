/* Internal: positions in JSON text. cJSON keeps no positions, so the readers that name
 * the line of a bad value (scenes, regression baselines) walk the text, already parsed
 * and valid, along the path of the value. */
#ifndef BF_JSON_POS_H
#define BF_JSON_POS_H

#include <stddef.h>

#include "brdfit/error.h"

/* Past spaces, tabs and line ends. */
const char *bf_json_skip_ws(const char *p);
/* Past the value that starts at p (after any white space). */
const char *bf_json_skip_value(const char *p);
/* The value of member key (klen bytes) of the object at p, or its key with want_key;
 * NULL when p is not an object or has no such member. */
const char *bf_json_member(const char *p, const char *key, size_t klen, int want_key);
/* Element k of the array at p; NULL when p is not an array or is shorter. */
const char *bf_json_element(const char *p, long k);
/* 1-based line of pos in text (NULL pos: line 1). */
int bf_json_line(const char *text, const char *pos);
/* The line of the value at path ("cases/3/expected/params/alpha": members by name,
 * elements by number) in text; the deepest value found when the path ends early. */
int bf_json_line_of_path(const char *text, const char *path);

/* The error for text that cJSON could not parse, end where it stopped: "PATH:LINE:
 * malformed JSON in or just before '...'" (the line quoted), or "... unexpected end of
 * file". Returns BF_ERR_PARSE. */
bf_status bf_json_parse_failure(const char *text, const char *end, const char *path, bf_error *err);
#endif
