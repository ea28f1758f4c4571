"""pip install --no-build-isolation ./python (docs/python.md): the package over an installed
libbrdfit, found through BRDFIT_PREFIX or pkg-config (brdfit/_build.py). Everything comes
from Debian's packages (python3-cffi, python3-numpy, python3-setuptools, python3-dev);
nothing is fetched."""
import re
import subprocess

from setuptools import setup
from setuptools.command.build_ext import build_ext


class BuildAlways(build_ext):
    """pip builds in python/build, where an extension of an earlier build would count as up
    to date although it was linked against another libbrdfit (another BRDFIT_PREFIX, its
    run path): always compile it again (a few seconds)."""

    def finalize_options(self):
        super().finalize_options()
        self.force = True


def _version():
    """The library's version (brdfit --version's number), from pkg-config or the prefix."""
    import os
    prefix = os.environ.get("BRDFIT_PREFIX")
    if prefix:
        with open(os.path.join(prefix, "include", "brdfit", "version.h"), encoding="utf-8") as f:
            m = re.search(r'#define BRDFIT_VERSION "([^"]+)"', f.read())
            if m:
                return m.group(1)
    try:
        return subprocess.run(["pkg-config", "--modversion", "brdfit"], check=True, capture_output=True,
                              text=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "0"


setup(
    name="brdfit",
    version=_version(),
    description="Fit parametric BRDF models to measured reflectance (Python bindings of libbrdfit)",
    packages=["brdfit"],
    package_data={"brdfit": ["py.typed", "_brdfit.pyi"]},
    setup_requires=["cffi"],
    install_requires=["cffi", "numpy"],
    cffi_modules=["brdfit/_build.py:ffibuilder"],
    cmdclass={"build_ext": BuildAlways},
    python_requires=">=3.9",
    zip_safe=False,
)
