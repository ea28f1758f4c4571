/* Internal: lookup of model families by name. */
#ifndef BF_REGISTRY_H
#define BF_REGISTRY_H

#include <stddef.h>
#include "models/family.h"

const bf_family *bf_registry_find(const char *name, size_t len);

#endif
