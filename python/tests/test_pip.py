"""The pip route: the library installed with `cmake --install`, then
`pip install --no-build-isolation --no-index <repo>/python` into a fresh venv made with
`/usr/bin/python3 -m venv --system-site-packages`, the library found through
BRDFIT_PREFIX; the installed package imports and fits from outside the repository."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from _support import BUILD_DIR, CAYMAN, REPO, cli_fit, normalize_json_text

PYTHON = "/usr/bin/python3" if Path("/usr/bin/python3").exists() else sys.executable

CHECK = """
import json, sys
import numpy as np
import brdfit
print(json.dumps({"file": brdfit.__file__, "version": brdfit.__version__}))
s = brdfit.read(sys.argv[1], rgb=True)
r = brdfit.fit(s, "walter", starts=1)
open("result.json", "w").write(r.to_json())
v = brdfit.Model("lambert").eval(np.array([[0.0, 0.0, 1.0]]), np.array([[0.0, 0.0, 1.0]]), {"rho_d": 0.5})
assert abs(v[0, 0] - 0.5 / np.pi) < 1e-15
"""


def _run(cmd, **kw):
    p = subprocess.run([str(c) for c in cmd], capture_output=True, text=True, timeout=600, **kw)
    assert p.returncode == 0, f"{' '.join(str(c) for c in cmd)} exited {p.returncode}\n{p.stdout}\n{p.stderr}"
    return p


@pytest.mark.slow
def test_pip_install_into_a_fresh_venv(tmp_path):
    if not (BUILD_DIR / "cmake_install.cmake").is_file():
        pytest.fail(f"no configured build tree at {BUILD_DIR} (set BRDFIT_BUILD_DIR)")
    env = {k: v for k, v in os.environ.items()
           if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV", "PKG_CONFIG_PATH", "BRDFIT_PREFIX")}
    env["PIP_NO_INDEX"] = "1"
    env["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"

    prefix = tmp_path / "prefix"
    _run(["cmake", "--install", BUILD_DIR, "--prefix", prefix], env=env)
    assert any((prefix / d / "pkgconfig" / "brdfit.pc").is_file() for d in ("lib", "lib64")) or \
        list(prefix.glob("lib/*/pkgconfig/brdfit.pc"))

    venv = tmp_path / "venv"
    _run([PYTHON, "-m", "venv", "--system-site-packages", venv], env=env)
    pip_env = dict(env, BRDFIT_PREFIX=str(prefix))
    # pip builds in the source folder (python/build): a copy keeps the checkout clean
    src = tmp_path / "src"
    shutil.copytree(REPO / "python", src, ignore=shutil.ignore_patterns("tests", "build", "*.egg-info", "__pycache__"))
    _run([venv / "bin" / "pip", "install", "--no-build-isolation", "--no-index", src], env=pip_env,
         cwd=str(tmp_path))

    # from a folder outside the repository, with no PYTHONPATH or BRDFIT_PREFIX
    work = tmp_path / "elsewhere"
    work.mkdir()
    (work / "check.py").write_text(CHECK)
    p = _run([venv / "bin" / "python", "check.py", CAYMAN], env=env, cwd=str(work))
    info = json.loads(p.stdout.splitlines()[0])
    assert Path(info["file"]).resolve().is_relative_to(venv.resolve()), info["file"]
    assert not Path(info["file"]).resolve().is_relative_to(REPO.resolve())

    # the installed package fits as the command line does
    text, want, _ = cli_fit(tmp_path, CAYMAN, "walter", "--rgb", "--starts", "1")
    assert normalize_json_text((work / "result.json").read_text()) == normalize_json_text(text)
