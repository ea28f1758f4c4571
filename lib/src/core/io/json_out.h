/* Internal: what every JSON writer of the library shares (cJSON): finite numbers or
 * null, parameters by name as in a parameter file, and writing a document through
 * bf_outfile so that a failure leaves no partial file. */
#ifndef BF_JSON_OUT_H
#define BF_JSON_OUT_H

#include <cjson/cJSON.h>

#include "brdfit/error.h"
#include "brdfit/model.h"

/* v, or null when v is NaN or infinite (JSON has no such numbers). Written with the
 * digits that read back exactly (a raw item: build output with it, do not read it). */
cJSON *bf_json_number(double v);
void bf_json_add_number(cJSON *o, const char *key, double v);
/* s, or null. */
void bf_json_add_string(cJSON *o, const char *key, const char *s);
/* "brdfit_version": bf_version(), the build that wrote the document (every document the
 * library writes names it; readers ignore it). */
void bf_json_add_version(cJSON *o);
/* {name: value or [per channel]} from a model vector x; null when m or x is NULL. */
cJSON *bf_json_params(const bf_model *m, const double *x);
/* root's text (formatted, with a final newline: what bf_json_write writes) into *out
 * (malloc'd; bf_free), and root deleted. what names the document in messages. */
bf_status bf_json_text(cJSON *root, const char *what, char **out, bf_error *err);
/* Prints root (formatted) to path ("-" or NULL: stdout) and deletes it. what names the
 * document in messages ("the comparison"). */
bf_status bf_json_write(cJSON *root, const char *path, const char *what, bf_error *err);

#endif
