"""Images in the tests: what the commands wrote (EXR, PNG) read back with OpenImageIO's
oiiotool, and synthetic photometric stacks (a JSON stack file of PFM images) rendered with
brdfit.Model, so that fit-images runs on a stack whose truth is known."""

import json
import re
import shutil
import subprocess

import numpy as np
import pytest

import brdfit

_HEAD = re.compile(r":\s+(\d+)\s+x\s+(\d+),\s+(\d+) channel")
_PIXEL = re.compile(r"\s*Pixel \((\d+), (\d+)\):\s*(.*)")


def read_images(*paths):
    """The pixels of image files as float64 arrays (height, width, channels), rows from the
    top, from one `oiiotool --dumpdata` (floats with 9 decimals; 8-bit codes as they are)."""
    tool = shutil.which("oiiotool")
    if tool is None:
        pytest.fail("oiiotool not found: install openimageio-tools (a build dependency's tools)")
    out = subprocess.run([tool, "--dumpdata"] + [str(p) for p in paths], capture_output=True, text=True,
                         check=True).stdout
    images = []
    for ln in out.splitlines():
        m = _PIXEL.match(ln)
        if m:
            values = m.group(3).split("(")[0].split()  # PNG: "255 (1)", the code then its value
            images[-1][int(m.group(2)), int(m.group(1))] = [float(v) for v in values]
        elif ln.strip():  # a file's header line
            w, h, c = map(int, _HEAD.search(ln).groups())
            images.append(np.full((h, w, c), np.nan))
    assert len(images) == len(paths)
    for p, img in zip(paths, images):
        assert not np.isnan(img).any(), f"{p}: not every pixel was dumped"
    return images


def read_image(path):
    return read_images(path)[0]


def assert_image_equal(got, want, what):
    """got (an array from the package) equals want (read back from a file) to 1e-6, relative
    to the values' size (the dump's 9 decimals are below that)."""
    got = np.asarray(got, dtype=np.float64).reshape(want.shape)
    scale = np.maximum(1.0, np.abs(want))
    worst = float(np.max(np.abs(got - want) / scale)) if want.size else 0.0
    assert worst <= 1e-6, f"{what}: differs by up to {worst:.3g} (relative)"


def write_pfm(path, img):
    """A PFM file (float32; 1 or 3 channels), which OpenImageIO reads: rows bottom-up."""
    img = np.asarray(img, dtype="<f4")
    h, w = img.shape[:2]
    grey = img.ndim == 2 or img.shape[2] == 1
    with open(path, "wb") as f:
        f.write(b"%s\n%d %d\n-1.0\n" % (b"Pf" if grey else b"PF", w, h))
        f.write(np.ascontiguousarray(img[::-1]).tobytes())


def make_stack(folder, size=16, lights=20, model="walter", params=None, checker=False):
    """A shiny sphere of `model` (3 channels) seen orthographically from +z under `lights`
    directional lights (theta 10 to 60 degrees, spread in phi), as a JSON stack file with
    a mask: value = f(l, v) (n . l) at each pixel's normal, in the frame photo.h uses
    (tangent: world x projected on the tangent plane). checker: the diffuse colour halved
    on a 4 x 4 checker (two materials). Returns the stack file's path."""
    folder.mkdir(parents=True, exist_ok=True)
    m = brdfit.Model(model, 3)
    base = dict(params or {})
    j, i = np.mgrid[0:size, 0:size]
    sx, sy = 2 * (i + 0.5) / size - 1, 1 - 2 * (j + 0.5) / size
    inside = sx ** 2 + sy ** 2 < 0.9
    n = np.stack([sx, sy, np.sqrt(np.clip(1 - sx ** 2 - sy ** 2, 0, 1))], -1)[inside]
    t = np.array([1.0, 0.0, 0.0]) - n[:, :1] * n
    t /= np.linalg.norm(t, axis=1)[:, None]
    b = np.cross(n, t)
    dark = ((4 * i // size + 4 * j // size) % 2 == 1)[inside] if checker else np.zeros(n.shape[0], bool)
    images = []
    for k in range(lights):
        th, ph = np.radians(10 + 50 * k / lights), 2 * np.pi * k * 0.618
        L = np.array([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)])
        V = np.array([0.0, 0.0, 1.0])
        Ll = np.stack([t @ L, b @ L, n @ L], 1)
        Vl = np.stack([t @ V, b @ V, n @ V], 1)
        lit = (Ll[:, 2] > 1e-3) & (Vl[:, 2] > 1e-3)
        vals = np.zeros((n.shape[0], 3))
        for half, sel in ((False, lit & ~dark), (True, lit & dark)):
            if sel.any():
                p = dict(base)
                if half:
                    p["rho_d"] = [0.5 * v for v in np.broadcast_to(p.get("rho_d", m.defaults["rho_d"]), (3,))]
                vals[sel] = m.eval(Ll[sel], Vl[sel], p) * Ll[sel, 2:3]
        img = np.zeros((size, size, 3))
        img[inside] = vals
        name = "light_%03d.pfm" % k
        write_pfm(folder / name, img)
        images.append({"file": name, "light": {"direction": L.tolist(), "intensity": [1, 1, 1]}})
    write_pfm(folder / "mask.pfm", inside.astype(np.float32))
    stack = folder / "stack.json"
    stack.write_text(json.dumps({"images": images, "mask": "mask.pfm", "transfer": "linear"}))
    return stack
