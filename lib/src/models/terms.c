#include "terms.h"

#include <stddef.h>

const char *const bf_fresnel_values[] = {"schlick", "dielectric", "none", NULL};
