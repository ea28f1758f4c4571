/* Internal: what the JSON readers (parameter files, scenes, regression baselines) check
 * beyond cJSON, which keeps every member of an object, repeated keys included, and
 * answers lookups with the first: a second "channels" or "rho_s" would be ignored by
 * the reader but kept by a rewrite, so a repeated key is an error. */
#ifndef BF_JSON_KEYS_H
#define BF_JSON_KEYS_H

#include <cjson/cJSON.h>

/* A key that obj (an object) holds more than once: 1 with *key set, 0 if none, -1 out
 * of memory. n log n in the member count. */
int bf_json_repeated_key(const cJSON *obj, const char **key);

#endif
