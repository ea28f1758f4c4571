#!/usr/bin/python3
"""Converts the literature's published per-material fits of the MERL database
(data/published/bbm/*.fit, as the BRDF benchmark project bbm ships them) into brdfit
reference sets (data/published/brdfit/*.json), which `brdfit compare --reference` reads
and `brdfit eval --params` evaluates one material at a time (docs/published.md).

    scripts/convert_published.py [--check] [SRC_DIR [OUT_DIR]]

A .fit line reads `name = Aggregate(Lambertian(albedo = [r, g, b]), Model(param = value or
[r, g, b], ...))`; '#' lines are comments. Each bbm model's mapping to a brdfit family is
its own module, scripts/published/<model in lower case>.py, with `to_brdfit(kd, p)`: kd the
Lambertian albedo, p the model's parameters as written (plus "model"). --check converts into
memory and fails, naming the file, when the committed output differs (the test suite runs
it so the data and the converter cannot drift apart).
"""
import ast
import importlib.util
import json
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

# Table (file stem) -> where the fits come from and which error the authors minimised.
SOURCES = {
    "ngan": "Ngan, Durand & Matusik 2005, Experimental analysis of BRDF models (EGSR)",
    "low": "Low, Kronander, Ynnerman & Unger 2012, BRDF models for accurate and efficient "
    "rendering of glossy surfaces (ACM TOG 31(1))",
    "bagher": "Bagher, Soler & Holzschuch 2012, Accurate fitting of measured reflectances "
    "using a Shifted Gamma micro-facet distribution (CGF 31(4))",
}

LINE = re.compile(r"^\s*([^=\s]+)\s*=\s*Aggregate\(\s*Lambertian\(\s*albedo\s*=\s*(\[[^\]]*\])\s*\)\s*,"
                  r"\s*(\w+)\((.*)\)\s*\)\s*$")
KEY = re.compile(r"(?<![\w.])([A-Za-z_]\w*)\s*=")


class FitError(Exception):
    pass


def parse_line(path, lineno, text):
    """(material, kd, p) of one .fit line."""
    m = LINE.match(text)
    if not m:
        raise FitError(f"{path}:{lineno}: not 'name = Aggregate(Lambertian(albedo = [...]), Model(...))'")
    name, kd_text, model, args = m.groups()
    try:
        kd = ast.literal_eval(kd_text)
        # param = value, ... -> {"param": value, ...}: the values are numbers and lists only.
        p = ast.literal_eval("{" + KEY.sub(r'"\1":', args) + "}")
    except (ValueError, SyntaxError) as e:
        raise FitError(f"{path}:{lineno}: bad value: {e}") from None
    if not isinstance(p, dict) or len(kd) != 3:
        raise FitError(f"{path}:{lineno}: expected an RGB albedo and named parameters")
    p["model"] = model
    return name, [float(v) for v in kd], p


def load_mapper(model):
    path = os.path.join(HERE, "published", model.lower() + ".py")
    if not os.path.exists(path):
        raise FitError(f"no mapping for bbm model {model}: {path} is missing")
    spec = importlib.util.spec_from_file_location("published_" + model.lower(), path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def convert_table(path):
    """The reference set of one .fit file."""
    stem = os.path.splitext(os.path.basename(path))[0]
    materials, mappers = {}, {}
    with open(path, encoding="utf-8") as f:
        for lineno, text in enumerate(f, 1):
            if not text.strip() or text.lstrip().startswith("#"):
                continue
            name, kd, p = parse_line(path, lineno, text)
            if name in materials:
                raise FitError(f"{path}:{lineno}: {name} listed twice")
            mapper = mappers.get(p["model"]) or mappers.setdefault(p["model"], load_mapper(p["model"]))
            materials[name] = mapper.to_brdfit(kd, p)
    paper = stem.split("_")[0]
    return {
        "source": SOURCES[paper] + ", as published in bsdfbenchmark/bbm fits/" + stem + ".fit",
        "table": stem,
        "materials": dict(sorted(materials.items())),
    }


def dump(ref):
    """A reference set as JSON text, one material a line (readable, and diffs name the material)."""
    rows = [f" {json.dumps(k)}: {json.dumps(v)}" for k, v in ref["materials"].items()]
    head = ",\n".join(f" {json.dumps(k)}: {json.dumps(v)}" for k, v in ref.items() if k != "materials")
    return "{\n" + head + ',\n "materials": {\n' + ",\n".join(rows) + "\n }\n}\n"


def main(argv):
    check = "--check" in argv
    args = [a for a in argv if a != "--check"]
    src = args[0] if args else os.path.join(ROOT, "data", "published", "bbm")
    out = args[1] if len(args) > 1 else os.path.join(ROOT, "data", "published", "brdfit")
    stale = []
    try:
        for fn in sorted(os.listdir(src)):
            if not fn.endswith(".fit"):
                continue
            text = dump(convert_table(os.path.join(src, fn)))
            dest = os.path.join(out, fn[:-4] + ".json")
            if check:
                old = open(dest, encoding="utf-8").read() if os.path.exists(dest) else None
                if old != text:
                    stale.append(dest)
            else:
                os.makedirs(out, exist_ok=True)
                with open(dest, "w", encoding="utf-8") as f:
                    f.write(text)
    except (FitError, OSError) as e:
        print(f"convert_published: {e}", file=sys.stderr)
        return 1
    for d in stale:
        print(f"convert_published: {d}: differs from the converter's output (run scripts/convert_published.py)",
              file=sys.stderr)
    return 1 if stale else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
