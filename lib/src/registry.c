/* The one place that lists every model family. */
#include "registry.h"

#include <string.h>

extern const bf_family bf_family_lambert;
extern const bf_family bf_family_oren_nayar;
extern const bf_family bf_family_phong;
extern const bf_family bf_family_blinn_phong;
extern const bf_family bf_family_cook_torrance;
extern const bf_family bf_family_ward;
extern const bf_family bf_family_ward_iso;
extern const bf_family bf_family_lafortune;
extern const bf_family bf_family_lafortune_aniso;
extern const bf_family bf_family_ashikhmin_shirley;
extern const bf_family bf_family_ashikhmin_shirley_iso;
extern const bf_family bf_family_walter;
extern const bf_family bf_family_walter_aniso;
extern const bf_family bf_family_kurt;
extern const bf_family bf_family_nishino;
extern const bf_family bf_family_abc;
extern const bf_family bf_family_brady;
extern const bf_family bf_family_disney;
extern const bf_family bf_family_gaussian;
extern const bf_family bf_family_heidrich_seidel;
extern const bf_family bf_family_microfacet;
extern const bf_family bf_family_gltf;
extern const bf_family bf_family_blender_principled;
extern const bf_family bf_family_mitsuba_principled;

static const bf_family *const families[] = {
    &bf_family_lambert,
    &bf_family_oren_nayar,
    &bf_family_phong,
    &bf_family_blinn_phong,
    &bf_family_cook_torrance,
    &bf_family_ward,
    &bf_family_ward_iso,
    &bf_family_lafortune,
    &bf_family_lafortune_aniso,
    &bf_family_ashikhmin_shirley,
    &bf_family_ashikhmin_shirley_iso,
    &bf_family_walter,
    &bf_family_walter_aniso,
    &bf_family_kurt,
    &bf_family_nishino,
    &bf_family_abc,
    &bf_family_brady,
    &bf_family_disney,
    &bf_family_gaussian,
    &bf_family_heidrich_seidel,
    &bf_family_microfacet,
    &bf_family_gltf,
    &bf_family_blender_principled,
    &bf_family_mitsuba_principled,
};

enum { NFAMILIES = sizeof families / sizeof families[0] };

int bf_family_count(void) { return NFAMILIES; }

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
