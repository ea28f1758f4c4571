/* brdfit export --to mitsuba: a Mitsuba 3 scene (XML, version 3.0.0) with the material as
 * a `principled` BSDF on a unit sphere, lit by one directional emitter and seen by a
 * perspective camera. The mitsuba_principled model's parameters are the plugin's own
 * (docs/export.md), so the mapping is a copy; `specular` is written, not `eta` (Mitsuba
 * takes one or the other). The text holds only numbers and the model spec, so it is
 * written directly; the spec has no "--" to break the XML comment. */
#include <stdio.h>

#include "brdfit/io.h"
#include "export_impl.h"

static void put_float(FILE *fp, const char *name, double v)
{
    char buf[40];
    fprintf(fp, "            <float name=\"%s\" value=\"%s\"/>\n", name, bf_format_double(v, buf, sizeof buf));
}

bf_status bf_export_write_mitsuba(const bf_export_material *e, FILE *fp, bf_error *err)
{
    static const char *const scalars[] = {"metallic",   "specular", "spec_tint", "roughness",      "sheen",
                                          "sheen_tint", "flatness", "clearcoat", "clearcoat_gloss"};
    char b[3][40];
    fprintf(fp, "<?xml version=\"1.0\" encoding=\"utf-8\"?>\n");
    fprintf(fp, "<!-- Written by brdfit export: Mitsuba 3 principled BSDF. Source model: %s (%s).", e->source,
            e->converted ? "converted" : "exact");
    if (e->converted) {
        fputc(' ', fp);
        bf_export_conversion_note(e, fp);
        fputc('.', fp);
    }
    fprintf(fp, " -->\n<scene version=\"3.0.0\">\n");
    fprintf(fp, "    <integrator type=\"path\"/>\n"
                "    <sensor type=\"perspective\">\n"
                "        <float name=\"fov\" value=\"30\"/>\n"
                "        <transform name=\"to_world\">\n"
                "            <lookat origin=\"0, 0, 6\" target=\"0, 0, 0\" up=\"0, 1, 0\"/>\n"
                "        </transform>\n"
                "        <sampler type=\"independent\">\n"
                "            <integer name=\"sample_count\" value=\"256\"/>\n"
                "            <integer name=\"seed\" value=\"0\"/>\n"
                "        </sampler>\n"
                "        <film type=\"hdrfilm\">\n"
                "            <integer name=\"width\" value=\"256\"/>\n"
                "            <integer name=\"height\" value=\"256\"/>\n"
                "        </film>\n"
                "    </sensor>\n"
                "    <emitter type=\"directional\">\n"
                "        <vector name=\"direction\" value=\"0, -0.7071067811865476, -0.7071067811865476\"/>\n"
                "        <rgb name=\"irradiance\" value=\"3\"/>\n"
                "    </emitter>\n"
                "    <shape type=\"sphere\">\n"
                "        <bsdf type=\"principled\">\n");
    fprintf(fp, "            <rgb name=\"base_color\" value=\"%s, %s, %s\"/>\n",
            bf_format_double(bf_export_param(e, "base_color", 0), b[0], sizeof b[0]),
            bf_format_double(bf_export_param(e, "base_color", 1), b[1], sizeof b[1]),
            bf_format_double(bf_export_param(e, "base_color", 2), b[2], sizeof b[2]));
    for (size_t k = 0; k < sizeof scalars / sizeof scalars[0]; k++)
        put_float(fp, scalars[k], bf_export_param(e, scalars[k], 0));
    fprintf(fp, "        </bsdf>\n    </shape>\n</scene>\n");
    (void)err;
    return BF_OK;
}
