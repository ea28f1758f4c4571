"""brdfit.read_all: the data files of a folder (by the extensions the library knows) or of
a glob pattern, in sorted order, each read as brdfit.read reads it; no match is a
UsageError."""

import shutil

import numpy as np
import pytest

import brdfit
from _support import CAYMAN, DATA, GARNET, PAPER_WHITE


def _same(a, b):
    assert a.path == b.path and a.channel_names == b.channel_names
    assert np.array_equal(a.values, b.values)
    assert all(np.array_equal(x, y) for x, y in zip(a.angles(), b.angles()))


@pytest.fixture
def folder(tmp_path):
    d = tmp_path / "materials"
    d.mkdir()
    shutil.copy(GARNET, d / "garnet_red.brdf")
    shutil.copy(CAYMAN, d / "Cayman.BRDF")  # the extension in any case
    shutil.copy(PAPER_WHITE, d / "paper.bsdf")
    shutil.copy(DATA / "alta" / "pink-felt-1d.alta", d / "felt.alta")
    (d / "README.txt").write_text("not data\n")
    (d / "notes").write_text("no extension: not listed\n")
    (d / "sub.csv").mkdir()  # a folder, whatever its name
    return d


def test_a_folders_data_files_in_sorted_order(folder):
    got = brdfit.read_all(folder, luminance=True, subsample=100, seed=2)
    names = ["Cayman.BRDF", "felt.alta", "garnet_red.brdf", "paper.bsdf"]
    assert [s.path for s in got] == [str(folder / n) for n in names]
    for s, n in zip(got, names):
        _same(s, brdfit.read(folder / n, luminance=True, subsample=100, seed=2))
        assert s.n <= 100


def test_a_glob_pattern(folder):
    got = brdfit.read_all(str(folder / "*.brdf"), rgb=True)
    assert [s.path for s in got] == [str(folder / "garnet_red.brdf")]
    _same(got[0], brdfit.read(folder / "garnet_red.brdf", rgb=True))
    got = brdfit.read_all(str(folder / "[Cg]*"), luminance=True)
    assert [s.path for s in got] == [str(folder / "Cayman.BRDF"), str(folder / "garnet_red.brdf")]
    assert all(s.channels == 1 for s in got)


def test_no_match_and_bad_options(folder, tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    (empty / "a.txt").write_text("x\n")
    with pytest.raises(brdfit.UsageError, match="no data file"):
        brdfit.read_all(empty)
    with pytest.raises(brdfit.UsageError, match="matches no file"):
        brdfit.read_all(str(tmp_path / "*.binary"))
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.read_all(folder, max_theta=95)
    assert str(e.value) == "max_theta needs degrees in (0, 90], got '95'"
    with pytest.raises(brdfit.UsageError):
        brdfit.read_all(3)
    # A file that does not read: the library's error, naming it.
    (folder / "broken.csv").write_text("theta_i,phi_i\n1,2\n")
    with pytest.raises(brdfit.Error) as e:
        brdfit.read_all(folder, luminance=True)
    assert "broken.csv" in str(e.value)
