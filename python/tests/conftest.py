"""pytest configuration of the brdfit Python tests.

Run from the repository root after the build:
    PYTHONPATH=build/python /usr/bin/python3 -m pytest -q python/tests
When brdfit is not importable as is, the build tree's package (BRDFIT_BUILD_DIR, default
<repo>/build, then its python/ folder) is tried."""

import os
import sys
import tempfile
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parent
if str(HERE) not in sys.path:
    sys.path.insert(0, str(HERE))

try:
    import brdfit  # noqa: F401
except ImportError:
    _build = Path(os.environ.get("BRDFIT_BUILD_DIR") or (HERE.parents[1] / "build"))
    if (_build / "python" / "brdfit").is_dir():
        sys.path.insert(0, str(_build / "python"))


def pytest_configure(config):
    config.addinivalue_line("markers", "slow: a test that takes long (a pip install, a build); run by default")
    # Hypothesis keeps caches in ./.hypothesis: keep them out of the source tree (the
    # tests use no example database either)
    if not os.environ.get("HYPOTHESIS_STORAGE_DIRECTORY"):
        try:
            from hypothesis.configuration import set_hypothesis_home_dir
        except ImportError:
            return
        config._brdfit_hypothesis_home = tempfile.TemporaryDirectory(prefix="brdfit-hypothesis-")
        set_hypothesis_home_dir(config._brdfit_hypothesis_home.name)


def pytest_unconfigure(config):
    home = getattr(config, "_brdfit_hypothesis_home", None)
    if home is not None:
        home.cleanup()


@pytest.fixture
def cayman():
    """The bundled Cornell cayman paint as linear sRGB (read afresh for each test, so
    that no test sees another's changes)."""
    import brdfit
    from _support import CAYMAN
    return brdfit.read(str(CAYMAN), rgb=True)
