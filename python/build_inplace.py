"""Builds the package into a folder (the CMake target brdfit_python: build/python), so
that `PYTHONPATH=build/python /usr/bin/python3 -c "import brdfit"` works without
installing: the extension compiled against the headers and shared library named by
BRDFIT_INCLUDE_DIRS and BRDFIT_LIBRARY_DIRS (brdfit/_build.py), and the package's Python
files copied beside it.

    python3 build_inplace.py OUTDIR
"""
import os
import shutil
import sys

here = os.path.dirname(os.path.abspath(__file__))
out = os.path.abspath(sys.argv[1])
sys.path.insert(0, os.path.join(here, "brdfit"))
import _build  # noqa: E402  (the builder lives inside the package, as setup.py names it)

pkg = os.path.join(out, "brdfit")
os.makedirs(pkg, exist_ok=True)
_build.ffibuilder.compile(tmpdir=out, verbose=False)
wanted = [n for n in sorted(os.listdir(os.path.join(here, "brdfit"))) if n.endswith((".py", ".pyi")) or n == "py.typed"]
for name in os.listdir(pkg):  # a module the package no longer has must not stay importable
    if name.endswith((".py", ".pyi")) and name not in wanted:
        os.remove(os.path.join(pkg, name))
for name in wanted:
    shutil.copy2(os.path.join(here, "brdfit", name), os.path.join(pkg, name))
