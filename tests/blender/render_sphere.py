"""Renders a material script from `brdfit export --to blender` on the sphere `brdfit render`
draws, and compares the two images region by region.

Run: blender --background --factory-startup --python render_sphere.py -- \
         MATERIAL.py|MATERIAL.gltf BRDFIT.exr OUT.json [SIZE] [SAMPLES]

MATERIAL.gltf goes through Blender's own glTF importer (its material on this sphere).

The scene is brdfit render's, in Blender's terms: a unit sphere (smooth UV sphere, fine
enough that interpolated normals stand for the true ones) seen by an orthographic camera
down -z whose frame spans [-1, 1] (image right +x, up +y, as brdfit's view 0,0), one sun
lamp of strength 1 (irradiance 1 W/m^2, as brdfit's unit light) towards theta 45, phi 0
(brdfit's default light), a black world, no bounces beyond the direct light (brdfit draws
direct light only), Cycles on the CPU, no denoising, fixed seed, the Standard view
transform and a linear float EXR. Both images then hold radiance f cos(theta_i).

Regions (brdfit's pixel centres; Blender's pixel filter blurs only the disc's edge, which
no region touches): centre (r < 0.2), highlight (within 0.08 of where the half vector of
light and view meets the sphere), lit limb (0.80 < r < 0.92 with n.L > 0.2). OUT.json gets
each region's mean RGB in both images and the pixel counts."""
import json
import math
import sys

import bpy

argv = sys.argv[sys.argv.index("--") + 1:]
material_script, brdfit_exr, out_json = argv[0], argv[1], argv[2]
size = int(argv[3]) if len(argv) > 3 else 128
samples = int(argv[4]) if len(argv) > 4 else 64

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene

if material_script.endswith(".gltf"):
    # A glTF export through Blender's own importer: its material, on our sphere (the
    # file's own sphere mesh is removed).
    # Debian's Blender 3.4 importer still says np.bool, which Debian's NumPy (1.24) has
    # removed; the alias it meant is the builtin.
    import numpy
    if not hasattr(numpy, "bool"):
        numpy.bool = bool
    bpy.ops.import_scene.gltf(filepath=material_script)
    material = next(ob.active_material for ob in bpy.data.objects if ob.type == "MESH")
    for ob in list(bpy.data.objects):
        bpy.data.objects.remove(ob, do_unlink=True)
else:
    # The exported script builds the material "brdfit"; its preview scene is not wanted.
    source = open(material_script).read().replace("PREVIEW = True", "PREVIEW = False", 1)
    exec(compile(source, material_script, "exec"), {"__name__": "brdfit_material"})
    material = bpy.data.materials["brdfit"]

bpy.ops.mesh.primitive_uv_sphere_add(segments=256, ring_count=128, radius=1.0)
sphere = bpy.context.active_object
bpy.ops.object.shade_smooth()
sphere.data.materials.append(material)

camera = bpy.data.cameras.new("camera")
camera.type = "ORTHO"
camera.ortho_scale = 2.0
camera_object = bpy.data.objects.new("camera", camera)
camera_object.location = (0.0, 0.0, 10.0)
scene.collection.objects.link(camera_object)
scene.camera = camera_object

sun = bpy.data.lights.new("sun", type="SUN")
sun.energy = 1.0
sun.angle = 0.0
sun_object = bpy.data.objects.new("sun", sun)
sun_object.rotation_euler = (0.0, math.radians(45.0), 0.0)  # +z turned to (sin 45, 0, cos 45)
scene.collection.objects.link(sun_object)

world = bpy.data.worlds.new("black")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
scene.world = world

scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = samples
scene.cycles.use_denoising = False
scene.cycles.use_adaptive_sampling = False
scene.cycles.seed = 0
scene.cycles.max_bounces = 0
scene.render.resolution_x = scene.render.resolution_y = size
scene.render.resolution_percentage = 100
scene.view_settings.view_transform = "Standard"
scene.view_settings.look = "None"
scene.view_settings.exposure = 0.0
scene.view_settings.gamma = 1.0
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
scene.render.filepath = out_json + ".exr"
bpy.ops.render.render(write_still=True)


def pixels(path):
    image = bpy.data.images.load(path)
    w, h = image.size
    px = list(image.pixels)
    # Blender stores rows bottom-up; brdfit's row 0 is the top.
    return w, h, lambda i, j: px[4 * ((h - 1 - j) * w + i):4 * ((h - 1 - j) * w + i) + 3]


wb, hb, blender_px = pixels(scene.render.filepath)
wr, hr, brdfit_px = pixels(brdfit_exr)
if (wb, hb) != (wr, hr):
    raise SystemExit("image sizes differ: blender %dx%d, brdfit %dx%d" % (wb, hb, wr, hr))

light = (math.sin(math.radians(45.0)), 0.0, math.cos(math.radians(45.0)))
half = [light[0], light[1], light[2] + 1.0]
norm = math.sqrt(sum(c * c for c in half))
half = [c / norm for c in half]


def region(sx, sy, r2):
    nz = math.sqrt(1.0 - r2)
    ndotl = sx * light[0] + sy * light[1] + nz * light[2]
    if r2 < 0.2 ** 2:
        return "centre"
    if (sx - half[0]) ** 2 + (sy - half[1]) ** 2 < 0.08 ** 2:
        return "highlight"
    if 0.80 ** 2 < r2 < 0.92 ** 2 and ndotl > 0.2:
        return "limb"
    return None


sums = {}
for j in range(hb):
    for i in range(wb):
        sx, sy = 2.0 * (i + 0.5) / wb - 1.0, 1.0 - 2.0 * (j + 0.5) / hb
        r2 = sx * sx + sy * sy
        name = region(sx, sy, r2) if r2 < 1.0 else None
        if name is None:
            continue
        s = sums.setdefault(name, {"pixels": 0, "blender": [0.0] * 3, "brdfit": [0.0] * 3})
        s["pixels"] += 1
        for c, (a, b) in enumerate(zip(blender_px(i, j), brdfit_px(i, j))):
            s["blender"][c] += a
            s["brdfit"][c] += b
for s in sums.values():
    for k in ("blender", "brdfit"):
        s[k] = [v / s["pixels"] for v in s[k]]
with open(out_json, "w") as f:
    json.dump(sums, f, indent=1, sort_keys=True)
