"""docs/python.md's walk-through and examples/python/fit_and_plot.py run as written, each
in a fresh folder (with the repository's examples/ beside it, as from the checkout)."""

import os
import re
import subprocess
import sys

from _support import REPO

PYTHON = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable


def _env():
    import brdfit
    return dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(brdfit.__file__)))


def test_walk_through_runs_as_written(tmp_path):
    text = (REPO / "docs" / "python.md").read_text()
    section = text.split("## Walk-through", 1)[1].split("\n## ", 1)[0]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    (tmp_path / "examples").symlink_to(REPO / "examples")
    (tmp_path / "walk.py").write_text(code)
    p = subprocess.run([PYTHON, "walk.py"], cwd=tmp_path, env=_env(), capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert "walter" in p.stdout and "(9, 3, 8)" in p.stdout
    assert (tmp_path / "walter_cayman.json").stat().st_size > 1000
    assert (tmp_path / "cayman.gltf").read_text().startswith("{")


def test_example_fit_and_plot(tmp_path):
    out = tmp_path / "cayman.png"
    p = subprocess.run([PYTHON, str(REPO / "examples" / "python" / "fit_and_plot.py"), str(out)], cwd=tmp_path,
                       env=dict(_env(), MPLBACKEND="Agg"), capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert "rmse_log" in p.stdout
    # Every measured point it draws is on the log axis (sRGB's negative red was not).
    drawn = re.search(r"measured points drawn: (\d+) per channel, (\d+) hidden", p.stdout)
    assert drawn and int(drawn.group(1)) > 40 and int(drawn.group(2)) == 0, p.stdout
    data = out.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20000
