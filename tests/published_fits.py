#!/usr/bin/python3
"""brdfit evaluates every published fit as its paper's model does.

    tests/published_fits.py BRDFIT [TABLE...]      (default: every table)

For every table in data/published/bbm and every material in it, the converted parameter
file (data/published/brdfit/TABLE.json, checked first to be the converter's output) is
evaluated by `brdfit eval` at hand-picked directions, and compared with an independent
implementation of the published model (tests/published/ref_<model>.py, written from the
paper and bbm's definition, sharing nothing with brdfit or the converter's mappings).
A fit with a parameter outside the family's bounds is refused by `brdfit eval` (bounds are
the fit's, docs/published.md says which fits and why the bounds stay); it is listed, not
failed, and `brdfit compare --reference` still evaluates it (tests/cli_reference.sh).
"""
import importlib.util
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import convert_published  # noqa: E402  (the .fit parser only; the mappings are under test)

REL = 1e-9  # relative agreement asked of every value
FLOOR = 1e-12  # ... above this fraction of the material's largest value (underflow aside)


def directions():
    """(theta_i, phi_i, theta_o, phi_o) in degrees: a grid over the hemisphere, and the
    mirror direction with small offsets, where the sharp published lobes (roughness down
    to 1e-3) have all their value."""
    d = []
    for ti in (0.0, 10.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0):
        for to, dp in ((0.0, 0.0), (20.0, 90.0), (40.0, 180.0), (70.0, 45.0), (80.0, 170.0)):
            d.append((ti, 30.0, to, 30.0 + dp))
        for off in (0.0, 0.05, 0.2, 0.5, 1.0, 2.0, 5.0, 10.0):
            if ti + off < 90.0:
                d.append((ti, 0.0, ti + off, 180.0))
            d.append((ti, 0.0, ti, 180.0 - 2 * off))
    return d


def unit(theta, phi):
    t, p = np.radians(theta), np.radians(phi)
    return np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1)


def load_ref(model):
    path = os.path.join(HERE, "published", "ref_" + model.lower() + ".py")
    spec = importlib.util.spec_from_file_location("ref_" + model.lower(), path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def fits(path):
    """(material, kd, p) of each line of a .fit file."""
    with open(path, encoding="utf-8") as f:
        for lineno, text in enumerate(f, 1):
            if text.strip() and not text.lstrip().startswith("#"):
                yield convert_published.parse_line(path, lineno, text)


def brdfit_eval(brdfit, params, dirs_csv, tmp):
    pfile = os.path.join(tmp, "p.json")
    with open(pfile, "w") as f:
        json.dump(params, f)
    out = os.path.join(tmp, "out.csv")
    r = subprocess.run([brdfit, "eval", "--params", pfile, "--dirs", dirs_csv, "-o", out, "-q"],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(r.stderr.strip())
    rows = [ln.split(",") for ln in open(out) if ln.strip() and not ln.startswith(("#", "theta"))]
    return np.array([[float(v) for v in row[4:]] for row in rows])


def main(argv):
    brdfit, only = argv[0], argv[1:]
    if not only and convert_published.main(["--check"]) != 0:
        return 1
    d = directions()
    dirs = np.array(d)
    L, V = unit(dirs[:, 0], dirs[:, 1]), unit(dirs[:, 2], dirs[:, 3])
    bad = checked = outside = 0
    src = os.path.join(ROOT, "data", "published", "bbm")
    with tempfile.TemporaryDirectory() as tmp:
        dirs_csv = os.path.join(tmp, "dirs.csv")
        with open(dirs_csv, "w") as f:
            f.write("theta_i,phi_i,theta_o,phi_o\n")
            for row in d:
                f.write(",".join(repr(v) for v in row) + "\n")
        for fn in sorted(os.listdir(src)):
            if not fn.endswith(".fit") or (only and fn[:-4] not in only):
                continue
            table = json.load(open(os.path.join(ROOT, "data", "published", "brdfit", fn[:-4] + ".json")))
            worst, refs = 0.0, {}
            for name, kd, p in fits(os.path.join(src, fn)):
                ref = refs.get(p["model"]) or refs.setdefault(p["model"], load_ref(p["model"]))
                want = np.asarray(ref.evaluate(kd, p, L, V), dtype=float)
                try:
                    got = brdfit_eval(brdfit, table["materials"][name], dirs_csv, tmp)
                except RuntimeError as e:
                    if "is outside [" in str(e):
                        print(f"outside brdfit's bounds: {fn} {name}: {str(e).rsplit(':1: ', 1)[-1]}")
                        outside += 1
                        continue
                    print(f"FAIL {fn} {name}: {e}")
                    bad += 1
                    continue
                except KeyError as e:
                    print(f"FAIL {fn} {name}: not in the converted table ({e})")
                    bad += 1
                    continue
                scale = np.max(np.abs(want)) if want.size else 0.0
                err = np.abs(got - want) / (np.maximum(np.abs(want), FLOOR * scale / REL) + 1e-300)
                i = np.unravel_index(np.argmax(err), err.shape)
                worst = max(worst, float(err[i]))
                checked += 1
                if not np.all(np.isfinite(got)) or err[i] > REL:
                    bad += 1
                    print(f"FAIL {fn} {name}: at {d[i[0]]} channel {i[1]}: brdfit {got[i]!r}, "
                          f"the paper's model {want[i]!r} (relative {err[i]:.3g})")
            print(f"{fn}: {len(table['materials'])} materials, worst relative difference {worst:.3g}")
    print(f"{checked} published fits evaluated at {len(d)} directions, {outside} outside brdfit's bounds, "
          f"{bad} failed")
    return 1 if bad or checked == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
