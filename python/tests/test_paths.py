"""File names as Python has them: a NUL is refused (it would cut the name short in C),
and a name that is not UTF-8 (as os.listdir returns it) is read as it is."""

import os
import shutil

import pytest

import brdfit
from _support import CAYMAN, EXAMPLES


def test_nul_is_refused():
    with pytest.raises(brdfit.UsageError, match="NUL"):
        brdfit.read(str(CAYMAN) + "\0junk")
    with pytest.raises(brdfit.UsageError, match="NUL"):
        brdfit.read(CAYMAN, scene=str(EXAMPLES / "scenes" / "turntable.json") + "\0x")
    with pytest.raises(brdfit.UsageError):
        brdfit.fit(CAYMAN, "walter\0x")
    fit = brdfit.fit(CAYMAN, "lambert", rgb=True, threads=1, starts=1)
    with pytest.raises(brdfit.UsageError, match="NUL"):
        brdfit.export(fit, "gltf", path="x.gltf\0y")


def test_non_utf8_file_name(tmp_path):
    raw = os.fsencode(str(tmp_path)) + b"/caym\xe9n.brdf"
    shutil.copy(CAYMAN, raw)
    (name,) = os.listdir(tmp_path)  # with a surrogate for the byte
    path = os.path.join(tmp_path, name)
    s = brdfit.read(path, rgb=True)
    assert len(s) == 1439 and s.path == path
    r = brdfit.fit(path, "lambert", rgb=True, threads=1, starts=1)
    assert r.ok and r.json["data"] == path
