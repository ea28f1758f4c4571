/* The registry of model families: the table of models/families.def, the one list of them. */
#include "registry.h"

#include <string.h>

/* The families of models/families.def: their definitions, then the table. */
#define BF_FAMILY(name) extern const bf_family bf_family_##name;
#include "models/families.def"
#undef BF_FAMILY

static const bf_family *const families[] = {
#define BF_FAMILY(name) &bf_family_##name,
#include "models/families.def"
#undef BF_FAMILY
};

enum { NFAMILIES = sizeof families / sizeof families[0] };

int bf_family_count(void)
{
    return NFAMILIES;
}

const bf_family_info *bf_family_get(int i)
{
    return (i >= 0 && i < NFAMILIES) ? &families[i]->info : NULL;
}

const bf_family *bf_registry_find(const char *name, size_t len)
{
    for (int i = 0; i < NFAMILIES; i++)
        if (strlen(families[i]->info.name) == len && strncmp(families[i]->info.name, name, len) == 0)
            return families[i];
    return NULL;
}
