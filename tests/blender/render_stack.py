"""Renders a photometric stereo stack with known normals and material for `brdfit fit-images`
(docs/images.md): one image per sun lamp, the JSON stack file, the mask, the true normals and
the true material.

Run: blender --background --factory-startup --python-exit-code 1 \
         --python tests/blender/render_stack.py -- OUTDIR SHAPE [SIZE] [SAMPLES] [LIGHTS]

SHAPE is "sphere", "plane" or "heightfield"; SIZE (default 64) is the image's width and
height in pixels, SAMPLES (default 64) Cycles' samples per pixel, LIGHTS (default 16, at
least 3) the number of lamps. OUTDIR (created if missing) gets:

  light_000.exr ...  one linear float RGB EXR per lamp, lit by that lamp alone
  stack.json         the stack in docs/images.md's JSON format (directional lights, the
                     sun's strength as intensity, orthographic camera, mask, linear transfer)
  mask.png           8-bit greyscale (no alpha channel), 255 where the object is (Cycles'
                     alpha over 0.5), 0 elsewhere
  normals_true.exr   float RGB: the unit normal (x, y, z) in the camera frame, 0 off the mask
  truth.json         the material as a brdfit params file (model blender_principled, the
                     Principled BSDF's inputs under brdfit's names; `brdfit eval --params
                     truth.json` and `brdfit render --params truth.json` read it; extra keys
                     are ignored) and, under "scene", the scene and the script's own checks

The scene is render_sphere.py's, in docs/images.md's frame: an orthographic camera at +z
looking down -z with no roll, so Blender's world x, y, z are the camera frame's (x right,
y up, z towards the camera); sun lamps of angle 0 (a direction, no penumbra) whose strength
is the irradiance E in W/m^2, so that a pixel's value is E f(l, v) max(0, n.l) (as
tests/cli_blender.sh checks against brdfit render for the same Principled BSDF); a black
world; direct light only (max bounces 0); Cycles on the CPU, no denoising, no adaptive
sampling, fixed seed; the Standard view transform; linear float EXR. The object is
invisible to shadow rays: no shape here can cast a shadow on itself, and attached shadows
are max(0, n.l)'s.

Pixels are point samples: the pixel filter is a Gaussian 0.01 pixels wide (Cycles ignores
the width of its box filter), so a sample of pixel (i, j) hits the surface at the pixel's
centre, ((i + 0.5 - W/2) S, -(j + 0.5 - H/2) S) with S = ortho_scale / SIZE as
docs/images.md places it, and the pixel's value, normal and mask all belong to that one
point (no blur across the sphere's limb or a bump's slope). With a delta light and no
bounces there is no noise either: at 1 sample the images are exactly the point samples
(measured: every sample within 5e-5 pixels of the centre). At more samples Cycles puts the
odd sample (about 1 in 64 in some pixels) up to half a pixel off the centre, which moves
those pixels by a little of the change across half a pixel (measured at 64 samples: 0.3%
at most in a highlight, 1/64 of the alpha at a few limb pixels). SAMPLES mainly costs time.

Shapes:
  sphere       a unit sphere (smooth UV sphere, 256 x 128, as render_sphere.py) at the
               origin, filling 91% of the frame (ortho_scale 2.2). normals_true.exr holds
               the analytic normal (x, y, sqrt(1 - x^2 - y^2)) at each pixel centre; the
               script checks it against Cycles' Normal pass (measured: 0.12 degrees at most,
               at the limb, 0.01 on average) and the mask against the disc (no difference).
  plane        a flat square (2.4 wide) under a frame of ortho_scale 2, so every pixel is
               on it; its Principled BSDF takes a tangent-space normal map (a 512 x 512
               float image made here from a height field of Gaussian bumps and dents, slopes
               up to 35 degrees, through a Normal Map node). normals_true.exr holds Cycles'
               Normal pass (world space = camera frame here), normalised per pixel; the
               script checks that it shows the bumps (it leaves +z by up to 35 degrees) and
               that it agrees with the height field's own normals (0.05 degrees at most).
               CAUTION: these images are not E f max(0, n.l) exactly. Cycles multiplies a
               diffuse closure whose normal is not the surface's (a normal or bump map) by
               its bump shadowing term (Chiang, Li, Burley 2019, "Taming the Shadow
               Terminator"): T(g) = g + g^2 - g^3 for g = (N.l) / ((n.l) (N.n)) < 1, with N
               the unmapped normal (+z) and n the mapped one, 1 when n leans away from l.
               Here T goes down to 0.87 (mean 0.99), on the Principled diffuse only, not on
               its specular; with T the images match brdfit's blender_principled to 0.25%.
  heightfield  the same kind of relief (slopes up to 30 degrees, below the lamps' lowest
               elevation of 35 degrees, so nothing casts a shadow) as real geometry: a
               320 x 320 grid displaced by the height field, smooth shaded, no normal map.
               normals_true.exr holds Cycles' Normal pass, normalised, as for the plane
               (0.07 degrees at most from the height field's normals). The images are
               E f max(0, n.l) for blender_principled to float precision at 1 sample.

Lamps: LIGHTS directions on rings between 15 and 55 degrees from +z (one ring for fewer
than 6 lamps at 35 degrees, two for fewer than 12, else three), lamps per ring in
proportion to the ring's circumference, evenly spread in azimuth, alternate rings turned by
half a step; strength 3 W/m^2 each. One Blender process renders them all, each image with
only its own lamp enabled.

The material is a uniform dielectric Principled BSDF (GGX): base colour (0.6, 0.35, 0.2),
metallic 0, specular 0.5, roughness 0.35, everything else at Blender's defaults (sheen 0,
sheen tint 0.5, clearcoat 0, clearcoat roughness 0.03, no subsurface or transmission).

Debian's Blender runs Debian's Python and NumPy, which this script uses."""
import json
import math
import os
import shutil
import struct
import sys
import tempfile
import time
import zlib

import bpy
import numpy as np
from mathutils import Vector

started = time.time()
argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
if len(argv) < 2 or argv[1] not in ("sphere", "plane", "heightfield"):
    raise SystemExit("usage: blender --background --factory-startup --python-exit-code 1 "
                     "--python render_stack.py -- OUTDIR sphere|plane|heightfield "
                     "[SIZE] [SAMPLES] [LIGHTS]")
outdir = os.path.abspath(argv[0])
shape = argv[1]
size = int(argv[2]) if len(argv) > 2 else 64
samples = int(argv[3]) if len(argv) > 3 else 64
n_lights = int(argv[4]) if len(argv) > 4 else 16
if size < 8 or samples < 1 or n_lights < 3:
    raise SystemExit("render_stack.py: SIZE must be at least 8, SAMPLES at least 1, "
                     "LIGHTS at least 3")
os.makedirs(outdir, exist_ok=True)

STRENGTH = 3.0  # each sun's irradiance, W/m^2
PARAMS = {  # brdfit's blender_principled names, Blender's Principled BSDF inputs
    "base_color": [0.6, 0.35, 0.2],
    "metallic": 0.0,
    "specular": 0.5,
    "specular_tint": 0.0,
    "roughness": 0.35,
    "sheen": 0.0,
    "sheen_tint": 0.5,
    "clearcoat": 0.0,
    "clearcoat_roughness": 0.03,
}
ORTHO_SCALE = 2.2 if shape == "sphere" else 2.0
PLANE_SIZE = 2.4
# The relief's steepest slope, degrees: for the normal map, safely inside Cycles' limit of 45
# degrees (a view along the geometric normal must reflect above the surface); for the
# height field, below the lamps' lowest elevation (35 degrees), so that nothing casts a shadow.
MAX_TILT = 35.0 if shape == "plane" else 30.0

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene


# ---- lamp directions ----------------------------------------------------------------------
def light_directions(n):
    """n unit vectors (towards the lights) on rings 15..55 degrees from +z, deterministic."""
    rings = 1 if n < 6 else 2 if n < 12 else 3
    thetas = [35.0] if rings == 1 else list(np.linspace(15.0, 55.0, rings))
    weights = [math.sin(math.radians(t)) for t in thetas]
    exact = [n * w / sum(weights) for w in weights]
    counts = [max(1, int(math.floor(e))) for e in exact]
    # Largest remainders take the lamps left over (or give back any excess).
    order = sorted(range(rings), key=lambda r: exact[r] - math.floor(exact[r]), reverse=True)
    k = 0
    while sum(counts) < n:
        counts[order[k % rings]] += 1
        k += 1
    while sum(counts) > n:
        r = max(range(rings), key=lambda r: counts[r])
        counts[r] -= 1
    dirs = []
    for r, (theta, count) in enumerate(zip(thetas, counts)):
        t = math.radians(theta)
        for k in range(count):
            phi = 2.0 * math.pi * (k + 0.5 * (r % 2)) / count
            dirs.append((math.sin(t) * math.cos(phi), math.sin(t) * math.sin(phi), math.cos(t)))
    return dirs


directions = light_directions(n_lights)

# ---- material -----------------------------------------------------------------------------
material = bpy.data.materials.new("stack")
material.use_nodes = True
nodes = material.node_tree.nodes
bsdf = nodes["Principled BSDF"]
bsdf.distribution = "GGX"  # as brdfit export --to blender writes it (not multiscatter)
bsdf.inputs["Base Color"].default_value = tuple(PARAMS["base_color"]) + (1.0,)
bsdf.inputs["Subsurface"].default_value = 0.0
bsdf.inputs["Metallic"].default_value = PARAMS["metallic"]
bsdf.inputs["Specular"].default_value = PARAMS["specular"]
bsdf.inputs["Specular Tint"].default_value = PARAMS["specular_tint"]
bsdf.inputs["Roughness"].default_value = PARAMS["roughness"]
bsdf.inputs["Anisotropic"].default_value = 0.0
bsdf.inputs["Sheen"].default_value = PARAMS["sheen"]
bsdf.inputs["Sheen Tint"].default_value = PARAMS["sheen_tint"]
bsdf.inputs["Clearcoat"].default_value = PARAMS["clearcoat"]
bsdf.inputs["Clearcoat Roughness"].default_value = PARAMS["clearcoat_roughness"]
bsdf.inputs["Transmission"].default_value = 0.0


def height_field(seed, max_tilt):
    """Gaussian bumps and dents (fixed seed) over the plane, their heights scaled so that the
    steepest slope of h(x, y) is max_tilt degrees. Returns the bumps and h's gradient."""
    rng = np.random.default_rng(seed)
    bumps = []
    for _ in range(14):
        bumps.append({"center": [float(c) for c in rng.uniform(-1.1, 1.1, 2)],
                      "sigma": float(rng.uniform(0.12, 0.3)),
                      "height": float(rng.choice([-1.0, 1.0]) * rng.uniform(0.5, 1.0))})

    def gradient(x, y):
        hx, hy = np.zeros_like(x), np.zeros_like(x)
        for b in bumps:
            dx, dy = x - b["center"][0], y - b["center"][1]
            g = b["height"] * np.exp(-(dx * dx + dy * dy) / (2.0 * b["sigma"] ** 2))
            hx -= g * dx / b["sigma"] ** 2
            hy -= g * dy / b["sigma"] ** 2
        return hx, hy
    u = (np.arange(1024) + 0.5) / 1024 - 0.5
    hx, hy = gradient(*np.meshgrid(u * PLANE_SIZE, u * PLANE_SIZE))
    gain = math.tan(math.radians(max_tilt)) / float(np.sqrt(hx * hx + hy * hy).max())
    for b in bumps:
        b["height"] *= gain
    return bumps, gradient


def height(bumps, x, y):
    h = np.zeros_like(x)
    for b in bumps:
        h += b["height"] * np.exp(-((x - b["center"][0]) ** 2 + (y - b["center"][1]) ** 2)
                                  / (2.0 * b["sigma"] ** 2))
    return h


bumps = []
if shape == "sphere":
    bpy.ops.mesh.primitive_uv_sphere_add(segments=256, ring_count=128, radius=1.0)
    obj = bpy.context.active_object
    bpy.ops.object.shade_smooth()
elif shape == "plane":
    bpy.ops.mesh.primitive_plane_add(size=PLANE_SIZE)
    obj = bpy.context.active_object
    # The height field's normal (-h_x, -h_y, 1) is also the tangent-space normal, since the
    # plane's UV map runs u along +x and v along +y (the Normal pass check below confirms).
    bumps, height_gradient = height_field(20240611, MAX_TILT)
    tex = 512
    u = (np.arange(tex) + 0.5) / tex  # texel centres; the image's row 0 is v = 0 (bottom)
    hx, hy = height_gradient(*np.meshgrid((u - 0.5) * PLANE_SIZE, (u - 0.5) * PLANE_SIZE))
    nmap = np.stack([-hx, -hy, np.ones_like(hx)], axis=-1)
    nmap /= np.linalg.norm(nmap, axis=-1, keepdims=True)
    rgba = np.concatenate([0.5 * (nmap + 1.0), np.ones((tex, tex, 1))], axis=-1)
    image = bpy.data.images.new("normal_map", tex, tex, alpha=False, float_buffer=True)
    image.colorspace_settings.name = "Non-Color"
    image.pixels.foreach_set(rgba.astype(np.float32).ravel())
    image.pack()
    tex_node = nodes.new("ShaderNodeTexImage")
    tex_node.image = image
    tex_node.interpolation = "Linear"
    nm_node = nodes.new("ShaderNodeNormalMap")
    nm_node.space = "TANGENT"
    nm_node.uv_map = obj.data.uv_layers[0].name
    nm_node.inputs["Strength"].default_value = 1.0
    material.node_tree.links.new(tex_node.outputs["Color"], nm_node.inputs["Color"])
    material.node_tree.links.new(nm_node.outputs["Normal"], bsdf.inputs["Normal"])
else:  # heightfield: the same kind of relief as real, smooth-shaded geometry
    grid = 320
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=grid, y_subdivisions=grid, size=PLANE_SIZE)
    obj = bpy.context.active_object
    bumps, height_gradient = height_field(20240611, MAX_TILT)
    mesh = obj.data
    co = np.empty(3 * len(mesh.vertices))
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    co[:, 2] = height(bumps, co[:, 0], co[:, 1])
    mesh.vertices.foreach_set("co", co.ravel())
    mesh.update()
    bpy.ops.object.shade_smooth()
obj.data.materials.append(material)
# No shape here can cast a shadow on itself (the sphere is convex, the plane flat, the height
# field's slopes stay below the lamps' elevations), so shadow rays need not see it: this only
# removes the odd shadow ray that hits the mesh it leaves (measured on the height field: one
# pixel of one image black at 1 sample), and leaves attached shadows to max(0, n.l).
obj.visible_shadow = False

# ---- camera, lamps, world -----------------------------------------------------------------
camera = bpy.data.cameras.new("camera")
camera.type = "ORTHO"
camera.ortho_scale = ORTHO_SCALE
camera.clip_start, camera.clip_end = 0.1, 100.0
camera_object = bpy.data.objects.new("camera", camera)
camera_object.location = (0.0, 0.0, 10.0)  # no rotation: looks down -z, image x = +x, y = +y
scene.collection.objects.link(camera_object)
scene.camera = camera_object

suns = []
for k, d in enumerate(directions):
    sun = bpy.data.lights.new("sun_%03d" % k, type="SUN")
    sun.energy = STRENGTH
    sun.angle = 0.0
    sun_object = bpy.data.objects.new("sun_%03d" % k, sun)
    sun_object.rotation_mode = "QUATERNION"
    # A sun shines along its local -z: its +z is the direction towards the light.
    sun_object.rotation_quaternion = Vector(d).to_track_quat("Z", "Y")
    scene.collection.objects.link(sun_object)
    suns.append(sun_object)

world = bpy.data.worlds.new("black")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
scene.world = world

# ---- render settings ----------------------------------------------------------------------
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = samples
scene.cycles.use_denoising = False
scene.cycles.use_adaptive_sampling = False
scene.cycles.seed = 0
scene.cycles.use_animated_seed = False
scene.cycles.max_bounces = 0  # direct light only
for bounces in ("diffuse_bounces", "glossy_bounces", "transmission_bounces",
                "volume_bounces", "transparent_max_bounces"):
    setattr(scene.cycles, bounces, 0)
scene.cycles.caustics_reflective = scene.cycles.caustics_refractive = False
scene.cycles.sample_clamp_direct = scene.cycles.sample_clamp_indirect = 0.0
scene.cycles.pixel_filter_type = "GAUSSIAN"  # Cycles ignores the width of BOX (always 1 pixel)
scene.cycles.filter_width = 0.01  # point samples at the pixel centres (see above)
scene.render.film_transparent = True  # alpha = coverage, for the mask
scene.render.use_persistent_data = True  # one BVH for all the lamps
scene.render.resolution_x = scene.render.resolution_y = size
scene.render.resolution_percentage = 100
scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0
scene.view_settings.view_transform = "Standard"
scene.view_settings.look = "None"
scene.view_settings.exposure = 0.0
scene.view_settings.gamma = 1.0
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_mode = "RGB"
scene.render.image_settings.color_depth = "32"
scene.render.image_settings.exr_codec = "ZIP"
scene.frame_set(1)

# The Normal and Alpha passes go through the compositor to a scratch folder, once.
view_layer = scene.view_layers[0]
view_layer.use_pass_normal = True
scene.use_nodes = True
scene.render.use_compositing = True
tree = scene.node_tree
for node in list(tree.nodes):
    tree.nodes.remove(node)
layers = tree.nodes.new("CompositorNodeRLayers")
composite = tree.nodes.new("CompositorNodeComposite")
tree.links.new(layers.outputs["Image"], composite.inputs["Image"])
scratch = tempfile.mkdtemp(prefix="render_stack_")
aux = tree.nodes.new("CompositorNodeOutputFile")
aux.base_path = scratch + os.sep
aux.format.file_format = "OPEN_EXR"
aux.format.color_mode = "RGB"
aux.format.color_depth = "32"
aux.file_slots[0].path = "normal"  # (file_slots.clear() leaks a block in Blender 3.4)
aux.file_slots.new("alpha")
tree.links.new(layers.outputs["Normal"], aux.inputs[0])
tree.links.new(layers.outputs["Alpha"], aux.inputs[1])


def load_exr(path):
    """An EXR as a float64 array [row from the top, column, RGB]."""
    image = bpy.data.images.load(path)
    image.colorspace_settings.name = "Non-Color"
    w, h = image.size
    px = np.empty(w * h * 4, dtype=np.float32)
    image.pixels.foreach_get(px)
    bpy.data.images.remove(image)
    return px.reshape(h, w, 4)[::-1, :, :3].astype(np.float64)  # Blender's rows run bottom-up


def save_exr(path, rgb):
    """A float RGB array [row from the top, column, channel] as a 32-bit float RGB EXR."""
    h, w = rgb.shape[:2]
    image = bpy.data.images.new("out", w, h, alpha=True, float_buffer=True)
    image.colorspace_settings.name = "Non-Color"
    rgba = np.concatenate([rgb, np.ones((h, w, 1))], axis=-1)[::-1]
    image.pixels.foreach_set(rgba.astype(np.float32).ravel())
    image.save_render(path, scene=scene)  # the scene's EXR settings: RGB, float 32, linear
    bpy.data.images.remove(image)


def save_png_grey(path, grey):
    """An 8-bit greyscale PNG (no alpha: every channel of it is the mask)."""
    h, w = grey.shape
    raw = b"".join(b"\x00" + bytes(grey[j].astype(np.uint8).tolist()) for j in range(h))

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def render(path, lamp):
    for k, sun in enumerate(suns):
        sun.hide_render = k != lamp
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)


# Pass 0, no lamp: the Normal and Alpha passes (they do not depend on the light).
setup_s = time.time() - started
render(os.path.join(scratch, "dark.exr"), -1)
normal_pass = load_exr(os.path.join(scratch, "normal0001.exr"))
alpha = load_exr(os.path.join(scratch, "alpha0001.exr"))[:, :, 0]
aux.mute = True
timings = []
files = []
for k in range(len(directions)):
    t0 = time.time()
    name = "light_%03d.exr" % k
    render(os.path.join(outdir, name), k)
    files.append(name)
    timings.append(time.time() - t0)
shutil.rmtree(scratch, ignore_errors=True)

# ---- mask and true normals ----------------------------------------------------------------
pixel_size = ORTHO_SCALE / size
c = (np.arange(size) + 0.5 - size / 2.0) * pixel_size
px_x, px_y = np.meshgrid(c, -c)  # pixel centres, row 0 at the top
mask = alpha > 0.5
length = np.linalg.norm(normal_pass, axis=-1)
pass_unit = normal_pass / np.maximum(length, 1e-12)[..., None]
checks = {}
if shape == "sphere":
    r2 = px_x ** 2 + px_y ** 2
    analytic = np.stack([px_x, px_y, np.sqrt(np.maximum(0.0, 1.0 - r2))], axis=-1)
    checks["mask_pixels_off_the_analytic_disc"] = int(np.count_nonzero(mask != (r2 < 1.0)))
    mask &= r2 < 1.0
    truth = analytic
    source = "analytic: (x, y, sqrt(1 - x^2 - y^2)) at the pixel centre"
    cosang = np.clip(np.sum(analytic * pass_unit, axis=-1), -1.0, 1.0)
    angle = np.degrees(np.arccos(cosang))[mask]
    checks["normal_pass_vs_analytic_deg"] = {"max": float(angle.max()), "mean": float(angle.mean())}
    if angle.max() > 0.5:
        raise SystemExit("render_stack.py: Cycles' Normal pass differs from the analytic "
                         "sphere normal by %.3f degrees" % angle.max())
else:
    truth = pass_unit
    source = "Cycles' Normal pass (world space = camera frame), normalised per pixel"
    hx, hy = height_gradient(px_x, px_y)
    field = np.stack([-hx, -hy, np.ones_like(hx)], axis=-1)
    field /= np.linalg.norm(field, axis=-1, keepdims=True)
    cosang = np.clip(np.sum(field * pass_unit, axis=-1), -1.0, 1.0)
    angle = np.degrees(np.arccos(cosang))[mask]
    tilt = np.degrees(np.arccos(np.clip(pass_unit[..., 2], -1.0, 1.0)))[mask]
    checks["normal_pass_vs_height_field_deg"] = {"max": float(angle.max()),
                                                 "mean": float(angle.mean())}
    checks["normal_pass_tilt_deg"] = {"max": float(tilt.max()), "mean": float(tilt.mean()),
                                      "over_5_deg": float(np.mean(tilt > 5.0))}
    if tilt.max() < 10.0 or np.mean(tilt > 5.0) < 0.2:
        raise SystemExit("render_stack.py: the Normal pass hardly leaves +z (max tilt %.2f "
                         "degrees): the relief is not in it" % tilt.max())
    if angle.max() > 2.0:
        raise SystemExit("render_stack.py: the Normal pass differs from the height field's "
                         "normals by %.3f degrees" % angle.max())
if not mask.any():
    raise SystemExit("render_stack.py: the mask is empty")
truth = np.where(mask[..., None], truth, 0.0)
save_exr(os.path.join(outdir, "normals_true.exr"), truth)
save_png_grey(os.path.join(outdir, "mask.png"), np.where(mask, 255, 0))

# ---- stack.json and truth.json ------------------------------------------------------------
stack = {
    "images": [{"file": f,
                "light": {"direction": [round(v, 12) for v in d], "intensity": [STRENGTH] * 3},
                "exposure": 1.0} for f, d in zip(files, directions)],
    "camera": {"type": "orthographic", "pixel_size": pixel_size, "center": [0.0, 0.0, 0.0]},
    "mask": "mask.png",
    "transfer": "linear",
    "black_level": 0.0,
    "scale": 1,
}
with open(os.path.join(outdir, "stack.json"), "w") as f:
    # One image a line.
    text = json.dumps(dict(stack, images=["@%d" % k for k in range(len(files))]), indent=1)
    for k, entry in enumerate(stack["images"]):
        text = text.replace('"@%d"' % k, json.dumps(entry))
    f.write(text + "\n")

scene_info = {
    "shape": shape,
    "size": size,
    "samples": samples,
    "lights": len(directions),
    "sun_strength": STRENGTH,
    "ortho_scale": ORTHO_SCALE,
    "pixel_size": pixel_size,
    "mask_pixels": int(np.count_nonzero(mask)),
    "normals": "normals_true.exr",
    "normals_source": source,
    "blender": bpy.app.version_string,
    "checks": checks,
}
if shape == "sphere":
    scene_info["sphere"] = {"center": [0.0, 0.0, 0.0], "radius": 1.0,
                            "mesh": "UV sphere 256 x 128, smooth"}
else:
    scene_info[shape] = {
        "size": PLANE_SIZE, "max_tilt_deg": MAX_TILT,
        "height_field": "h(x, y) = sum of height * exp(-|(x, y) - center|^2 / (2 sigma^2))",
        "bumps": bumps}
    if shape == "plane":
        scene_info[shape]["normal_map"] = "tangent space, 512 x 512 float, linear, of h's normals"
        scene_info["image_formation"] = (
            "NOT exactly E f max(0, n.l): Cycles multiplies the diffuse closure of a normal-mapped "
            "surface by its bump shadowing term (Chiang, Li, Burley 2019) T(g) = g + g^2 - g^3 "
            "for g = (N.l) / ((n.l) (N.n)) < 1, N = +z the unmapped normal, n the mapped one; "
            "1 when n leans away from l, down to about 0.87 here. The specular closure is not "
            "scaled. The heightfield shape has the same relief without this.")
    else:
        scene_info[shape]["mesh"] = "grid %d x %d displaced by h, smooth" % (grid, grid)
        scene_info["image_formation"] = ("E f max(0, n.l); no cast shadows (slopes below the "
                                         "lamps' elevations)")
truth_json = {
    "model": "blender_principled",
    "channels": 3,
    "params": PARAMS,
    "note": "Blender 3.4 Principled BSDF inputs (distribution GGX, subsurface 0, "
            "anisotropic 0, transmission 0) under brdfit's blender_principled names",
    "scene": scene_info,
}
with open(os.path.join(outdir, "truth.json"), "w") as f:
    json.dump(truth_json, f, indent=1)
    f.write("\n")

print("render_stack.py: %s, %d x %d, %d samples, %d lamps: setup %.1f s, %.2f s per lamp, "
      "%.1f s in all; checks %s" % (shape, size, size, samples, len(directions), setup_s,
                                     sum(timings) / len(timings), time.time() - started,
                                     json.dumps(checks)))
