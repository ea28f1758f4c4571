/* brdfit export --to blender: a Python script for Blender 3.4 (`blender --background
 * --python FILE`) that builds the material as a Principled BSDF and, unless the script's
 * PREVIEW is set to False, a preview scene: a sphere, one sun lamp, a black world and a
 * camera, rendered by Cycles on the CPU with a fixed seed. The blender_principled
 * model's parameters are the node's inputs (docs/export.md), so the mapping is a copy;
 * the node's distribution is set to GGX, the single-scattering lobe the model holds. */
#include <stdio.h>

#include "brdfit/io.h"
#include "export_impl.h"

static void put(FILE *fp, const char *socket, double v)
{
    char buf[40];
    fprintf(fp, "bsdf.inputs[\"%s\"].default_value = %s\n", socket, bf_format_double(v, buf, sizeof buf));
}

bf_status bf_export_write_blender(const bf_export_material *e, FILE *fp, bf_error *err)
{
    char b[3][40];
    fprintf(fp, "# Written by brdfit export: a Blender 3.4 Principled BSDF (Cycles, GGX).\n");
    fprintf(fp, "# Run: blender --background --python THIS_FILE\n");
    fprintf(fp, "# Source model: %s (%s)\n", e->source, e->converted ? "converted" : "exact");
    if (e->converted) {
        fputs("# ", fp);
        bf_export_conversion_note(e, fp);
        fputc('\n', fp);
    }
    fprintf(fp, "import bpy\n\nPREVIEW = True\n\n");
    fprintf(fp, "mat = bpy.data.materials.new(\"brdfit\")\nmat.use_nodes = True\n");
    fprintf(fp, "bsdf = mat.node_tree.nodes[\"Principled BSDF\"]\n");
    fprintf(fp, "bsdf.distribution = \"GGX\"\n");
    fprintf(fp, "bsdf.inputs[\"Base Color\"].default_value = (%s, %s, %s, 1.0)\n",
            bf_format_double(bf_export_param(e, "base_color", 0), b[0], sizeof b[0]),
            bf_format_double(bf_export_param(e, "base_color", 1), b[1], sizeof b[1]),
            bf_format_double(bf_export_param(e, "base_color", 2), b[2], sizeof b[2]));
    put(fp, "Subsurface", 0.0);
    put(fp, "Metallic", bf_export_param(e, "metallic", 0));
    put(fp, "Specular", bf_export_param(e, "specular", 0));
    put(fp, "Specular Tint", bf_export_param(e, "specular_tint", 0));
    put(fp, "Roughness", bf_export_param(e, "roughness", 0));
    put(fp, "Anisotropic", 0.0);
    put(fp, "Sheen", bf_export_param(e, "sheen", 0));
    put(fp, "Sheen Tint", bf_export_param(e, "sheen_tint", 0));
    put(fp, "Clearcoat", bf_export_param(e, "clearcoat", 0));
    put(fp, "Clearcoat Roughness", bf_export_param(e, "clearcoat_roughness", 0));
    put(fp, "Transmission", 0.0);
    fputs("\nif PREVIEW:\n"
          "    for ob in list(bpy.data.objects):\n"
          "        bpy.data.objects.remove(ob, do_unlink=True)\n"
          "    scene = bpy.context.scene\n"
          "    bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, radius=1.0)\n"
          "    sphere = bpy.context.active_object\n"
          "    bpy.ops.object.shade_smooth()\n"
          "    sphere.data.materials.append(mat)\n"
          "    sun = bpy.data.objects.new(\"sun\", bpy.data.lights.new(\"sun\", type=\"SUN\"))\n"
          "    sun.data.energy = 3.0\n"
          "    sun.data.angle = 0.0\n"
          "    sun.rotation_euler = (0.7853981634, 0.0, 0.0)\n"
          "    scene.collection.objects.link(sun)\n"
          "    cam = bpy.data.objects.new(\"camera\", bpy.data.cameras.new(\"camera\"))\n"
          "    cam.location = (0.0, -6.0, 0.0)\n"
          "    cam.rotation_euler = (1.5707963268, 0.0, 0.0)\n"
          "    scene.collection.objects.link(cam)\n"
          "    scene.camera = cam\n"
          "    world = bpy.data.worlds.new(\"black\")\n"
          "    world.use_nodes = True\n"
          "    world.node_tree.nodes[\"Background\"].inputs[\"Color\"].default_value = (0.0, 0.0, 0.0, 1.0)\n"
          "    scene.world = world\n"
          "    scene.render.engine = \"CYCLES\"\n"
          "    scene.cycles.device = \"CPU\"\n"
          "    scene.cycles.seed = 0\n"
          "    scene.cycles.samples = 256\n"
          "    scene.view_settings.view_transform = \"Standard\"\n",
          fp);
    (void)err;
    return BF_OK;
}
