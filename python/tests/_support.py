"""Shared helpers of the brdfit Python tests: paths, the command-line reference tools,
and comparisons of results with what the command line writes.

The command-line tools are found through the environment (BRDFIT_CMD for brdfit,
BRDFIT_SYNTH for brdfit-synth, BRDFIT_BUILD_DIR for the build tree), else in the build
tree next to this repository (<repo>/build)."""

import csv
import json
import os
import re
import subprocess
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[2]
BUILD_DIR = Path(os.environ.get("BRDFIT_BUILD_DIR") or (REPO / "build"))
BRDFIT_CMD = Path(os.environ.get("BRDFIT_CMD") or (BUILD_DIR / "cmd" / "brdfit"))
BRDFIT_SYNTH = Path(os.environ.get("BRDFIT_SYNTH") or (BUILD_DIR / "data_synth" / "brdfit-synth"))

EXAMPLES = REPO / "examples"
DATA = REPO / "tests" / "data"
CAYMAN = EXAMPLES / "cornell" / "cayman.brdf"
GARNET = EXAMPLES / "cornell" / "garnet_red.brdf"
WALTER_RGB = EXAMPLES / "walter_rgb.json"
DIRS_IN_PLANE = EXAMPLES / "dirs_in_plane.csv"
DIRS_SMALL = DATA / "dirs_small.csv"
LAMBERT_RGB = DATA / "lambert_rgb.json"
PTFE = DATA / "nist_ptfe" / "PTFE.data.random.csv"
PTFE_HEAD = DATA / "nist_ptfe" / "PTFE.data.random.head40.csv"
PAPER_WHITE = EXAMPLES / "rgl" / "paper_white_rgb.bsdf"
# The PTFE file's own column names, as the command line takes them.
PTFE_CLI = ["--angles", "thetai,phi,thetar,phir", "--values", "f_r11"]
PTFE_KW = {"angles": "thetai,phi,thetar,phir", "values": "f_r11"}

CAYMAN_SAMPLES = 1439


def _tool(path, what):
    if not path.is_file() or not os.access(path, os.X_OK):
        pytest.fail(f"{what} not found at {path}: build the project or set the environment variable")
    return str(path)


def cli(*args, ok=True, timeout=120):
    """Runs brdfit with args (str() of each); returns the CompletedProcess (text).
    With ok, the exit status must be 0."""
    cmd = [_tool(BRDFIT_CMD, "brdfit (BRDFIT_CMD)")] + [str(a) for a in args]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    if ok:
        assert p.returncode == 0, f"{' '.join(cmd)} exited {p.returncode}: {p.stderr}"
    return p


def synth(*args, timeout=120):
    cmd = [_tool(BRDFIT_SYNTH, "brdfit-synth (BRDFIT_SYNTH)")] + [str(a) for a in args]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    assert p.returncode == 0, f"{' '.join(cmd)} exited {p.returncode}: {p.stderr}"
    return p


def cli_fit(tmp_path, data, model, *options, name="cli_fit.json"):
    """`brdfit fit DATA -m MODEL OPTIONS -o FILE`: (the file's text, its parsed JSON, path)."""
    out = Path(tmp_path) / name
    cli("fit", data, "-m", model, *options, "-q", "-o", out)
    text = out.read_text()
    return text, json.loads(text), out


_VERSION_GIT = re.compile(r'("brdfit_version":\s*"[^"(]*?)\s*\((?:git|commit)[^)]*\)')


def normalize_json_text(text):
    """The text of a result file but for wall times: lines holding a "seconds" key are
    dropped, and the build's git description in "brdfit_version" (which names the commit
    and tree state the binary was built from) is removed, keeping the version number."""
    lines = [ln for ln in text.splitlines() if '"seconds"' not in ln]
    return "\n".join(_VERSION_GIT.sub(r"\1", ln) for ln in lines).rstrip("\n")


def flat(v):
    """A parameter value (float, sequence, array, None for JSON null) as a 1-D float64
    array with NaN for null."""
    if v is None:
        return np.array([np.nan])
    if isinstance(v, (list, tuple)):
        return np.array([np.nan if x is None else float(x) for x in v], dtype=np.float64)
    a = np.asarray(v)
    if a.dtype == object:
        return np.array([np.nan if x is None else float(x) for x in a.ravel()], dtype=np.float64)
    return a.astype(np.float64).ravel()


def assert_params_identical(got, want, what="params"):
    """got (a result's dict) holds exactly want's (parsed JSON) names, in order, and values
    bit for bit (null and NaN alike)."""
    assert list(got.keys()) == list(want.keys()), f"{what}: names {list(got)} != {list(want)}"
    for k in want:
        g, w = flat(got[k]), flat(want[k])
        assert g.shape == w.shape, f"{what}[{k}]: {g} vs {w}"
        same = (g == w) | (np.isnan(g) & np.isnan(w))
        assert same.all(), f"{what}[{k}]: {g.tolist()} != {w.tolist()}"


def read_csv_table(path):
    """A CSV with '#' comment lines: (header list, float64 array rows x columns)."""
    with open(path, newline="") as f:
        rows = [r for r in csv.reader(ln for ln in f if not ln.startswith("#") and ln.strip())]
    header, body = rows[0], rows[1:]
    return header, np.array([[float(x) for x in r] for r in body], dtype=np.float64).reshape(len(body), len(header))


def write_dirs_csv(path, ti, pi, to, po):
    with open(path, "w") as f:
        f.write("theta_i,phi_i,theta_o,phi_o\n")
        for row in zip(ti, pi, to, po):
            f.write(",".join(repr(float(x)) for x in row) + "\n")


def vectors_from_angles(theta, phi, degrees=True):
    """Unit vectors (n, 3) as the library makes them: (sin t cos p, sin t sin p, cos t)."""
    theta = np.asarray(theta, dtype=np.float64)
    phi = np.asarray(phi, dtype=np.float64)
    if degrees:
        theta = theta * (np.pi / 180.0)
        phi = phi * (np.pi / 180.0)
    s = np.sin(theta)
    return np.stack([s * np.cos(phi), s * np.sin(phi), np.cos(theta)], axis=1)


def weights_or_ones(w, n):
    """A samples' weights: None (no weights) counts as all ones."""
    if w is None:
        return np.ones(n)
    return np.asarray(w, dtype=np.float64).reshape(n)


def nsamples(s):
    return np.asarray(s.values).shape[0]


def values2d(s):
    v = np.asarray(s.values)
    return v.reshape(v.shape[0], -1)


def models_list(m):
    """brdfit.models() as the list of model entries, whether it returns the whole
    `brdfit models --json` object or its "models" list."""
    if isinstance(m, dict):
        return m["models"]
    return list(m)


def cli_models():
    return json.loads(cli("models", "--json").stdout)


def interior_params(entry, channels):
    """A dict of parameter values strictly inside the bounds of a `models --json` entry:
    the default where it lies well inside, else a point a quarter into the range."""
    out = {}
    for p in entry["params"]:
        lo, hi, d = p["lower"], p["upper"], p["default"]
        span = hi - lo
        margin = 1e-3 * min(span, 1.0)
        if not (lo + margin < d < hi - margin):
            d = lo + 0.25 * min(span, 4.0)
        out[p["name"]] = [d] * channels if p["kind"] == "colour" else d
    return out


def default_params(entry, channels):
    return {p["name"]: ([p["default"]] * channels if p["kind"] == "colour" else p["default"])
            for p in entry["params"]}


def param_vector_names(entry, channels):
    """The model vector's entries in order: a colour parameter gives one per channel."""
    names = []
    for p in entry["params"]:
        if p["kind"] == "colour":
            names += [(p["name"], c) for c in range(channels)]
        else:
            names.append((p["name"], None))
    return names


def message_line(exc):
    """The exception's message: one non-empty line."""
    msg = str(exc)
    assert msg.strip(), f"{type(exc).__name__} with an empty message"
    assert "\n" not in msg.strip(), f"message is not one line: {msg!r}"
    return msg


# How soon an interrupt or a cancel must be answered: 1 s, more in the sanitizer build's
# suite, whose instrumented library is slower (python/CMakeLists.txt sets it).
INTERRUPT_SECONDS = float(os.environ.get("BRDFIT_INTERRUPT_SECONDS", "1.0"))
