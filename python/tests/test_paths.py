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


def test_arguments_out_of_range_are_usage_errors():
    # As the command's exit status 2: the caller's values, refused by the library's checks.
    import numpy as np
    for call in (lambda: brdfit.fit(CAYMAN, "walter", rgb=True, fix={"alpha": 5}),
                 lambda: brdfit.fit(CAYMAN, "walter", rgb=True, bound={"alpha": (0, 2)}),
                 lambda: brdfit.fit(CAYMAN, "walter", rgb=True, bound={"alpha": ("a", "b")}),
                 lambda: brdfit.Model("walter").eval([0, 0, 1], [0, 0, 1], {"alpha": -1}),
                 lambda: brdfit.Model("walter").eval([0, 0, 1], [0, 0, 1], gradient="no"),
                 lambda: brdfit.Model("lambert", channels=20000),
                 lambda: brdfit.compare([CAYMAN], None),
                 lambda: brdfit.Samples(np.zeros((0, 3)), np.zeros((0, 3)), np.zeros((0, 1)))):
        with pytest.raises(brdfit.UsageError):
            call()
    # The library's limits, not the package's: more than 1024 channels are a model.
    assert brdfit.Model("lambert", channels=2000).channels == 2000
    # A tiny vector is a direction.
    f = brdfit.Model("lambert").eval(np.array([0, 0, 1e-300]), [0, 0, 1])
    assert f.shape == (1,) and np.isfinite(f).all() and f[0] > 0  # one (3,) pair: (channels,)
    # A per-channel fix takes a sequence, as params do.
    r = brdfit.fit(CAYMAN, "walter", rgb=True, fix={"rho_d": [0.1, 0.2, 0.3]}, threads=1, starts=1)
    assert r.params["rho_d"] == [0.1, 0.2, 0.3]


def test_samples_memory_is_read_only():
    s = brdfit.read(CAYMAN, rgb=True)
    with pytest.raises(ValueError):
        s.values[0, 0] = float("nan")
    t = brdfit.Samples([[0, 0, 1]], [[0, 0, 1]], [0.1], weights=[2.0])
    with pytest.raises(ValueError):
        t.weights[0] = -1.0


def test_start():
    # A fit from a fit's own optimum, with no other start, stays there; a Model given
    # parameters starts from them; a start for another channel count is refused.
    first = brdfit.fit(CAYMAN, "walter", rgb=True, threads=1)
    again = brdfit.fit(CAYMAN, "walter", rgb=True, threads=1, starts=1, start=first.params)
    assert again.params == first.params
    same = brdfit.fit(CAYMAN, first.model, rgb=True, threads=1, starts=1)
    assert same.params == first.params
    with pytest.raises(brdfit.UsageError, match="channels"):
        brdfit.fit(CAYMAN, first.model, luminance=True)
    # The model vector (value_names order) and a Model holding parameters are starts too;
    # a vector of the wrong length or outside the bounds is the caller's error.
    vec = first.model.vector()
    assert brdfit.fit(CAYMAN, "walter", rgb=True, threads=1, starts=1, start=vec).params == first.params
    assert brdfit.fit(CAYMAN, "walter", rgb=True, threads=1, starts=1, start=first.model).params == first.params
    with pytest.raises(brdfit.UsageError, match="start"):
        brdfit.fit(CAYMAN, "walter", rgb=True, start=vec[:-1])
    with pytest.raises(brdfit.UsageError, match="start"):
        brdfit.fit(CAYMAN, "walter", rgb=True, start=-vec)
    with pytest.raises(brdfit.UsageError, match="no parameters"):
        brdfit.fit(CAYMAN, "walter", rgb=True, start=brdfit.Model("walter", 3))
