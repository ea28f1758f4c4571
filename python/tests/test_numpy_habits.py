"""Model and Samples as NumPy users expect them: eval broadcasts directions and takes K
parameter sets, a per-channel gradient without the dense block, bounds, vectors and
dicts, Model.from_file; Samples sliced, masked, indexed, joined and written."""

import math
import tracemalloc

import numpy as np
import pytest

import brdfit
import brdfit._eval
from _support import CAYMAN, PAPER_WHITE, PTFE_HEAD, PTFE_KW, WALTER_RGB, cli_models, vectors_from_angles

WALTER_P = {"rho_d": [0.3, 0.2, 0.1], "rho_s": [0.5, 0.6, 0.7], "alpha": 0.15, "f0": 0.04}


def _dirs(n, seed):
    rng = np.random.default_rng(seed)
    ti, to = rng.uniform(0, 80, n), rng.uniform(0, 80, n)
    pi, po = rng.uniform(0, 360, n), rng.uniform(0, 360, n)
    return vectors_from_angles(ti, pi), vectors_from_angles(to, po)


@pytest.fixture(scope="module")
def walter():
    return brdfit.Model("walter", channels=3)


# --- eval broadcasts -----------------------------------------------------------------

def test_one_direction_with_many_equals_the_loop(walter):
    wi, wo = _dirs(7, 1)
    got = walter.eval(wi[2], wo, WALTER_P)
    assert got.shape == (7, 3)
    loop = np.stack([walter.eval(wi[2:3], wo[k:k + 1], WALTER_P)[0] for k in range(7)])
    np.testing.assert_array_equal(got, loop)
    # The other way round, and as a (1, 3) array (NumPy's broadcasting).
    np.testing.assert_array_equal(walter.eval(wi, wo[4], WALTER_P),
                                  np.stack([walter.eval(wi[k:k + 1], wo[4:5], WALTER_P)[0] for k in range(7)]))
    np.testing.assert_array_equal(walter.eval(wi[2:3], wo, WALTER_P), got)
    v, g = walter.eval(wi[2], wo, WALTER_P, gradient=True)
    v1, g1 = walter.eval(np.tile(wi[2], (7, 1)), wo, WALTER_P, gradient=True)
    assert g.shape == (7, 3, 8)
    np.testing.assert_array_equal(v, v1)
    np.testing.assert_array_equal(g, g1)


def test_one_pair_gives_channels(walter):
    wi, wo = _dirs(1, 2)
    v = walter.eval(wi[0], wo[0], WALTER_P)
    assert v.shape == (3,) and v.dtype == np.float64
    np.testing.assert_array_equal(v, walter.eval(wi, wo, WALTER_P)[0])
    v, g = walter.eval(list(wi[0]), tuple(wo[0]), WALTER_P, gradient=True)
    assert g.shape == (3, 8)
    np.testing.assert_array_equal(g, walter.eval(wi, wo, WALTER_P, gradient=True)[1][0])
    # A (1, 3) array is an array of one pair: (1, channels), as before.
    assert walter.eval(wi, wo[0], WALTER_P).shape == (1, 3)


def test_direction_counts_must_agree_or_be_one(walter):
    wi, wo = _dirs(5, 3)
    with pytest.raises(brdfit.UsageError) as e:
        walter.eval(wi, wo[:4])
    assert "wi" in str(e.value) and "wo" in str(e.value) and "5" in str(e.value) and "4" in str(e.value)
    assert walter.eval(wi[:0], wo[0]).shape == (0, 3)


# --- K parameter sets ----------------------------------------------------------------

def test_parameter_sets_equal_separate_calls(walter):
    wi, wo = _dirs(9, 4)
    alpha = [0.05, 0.1, 0.3, 0.6]
    rho_d = [[0.1, 0.2, 0.3], [0.4, 0.5, 0.6], [0.7, 0.8, 0.9], [0.0, 0.5, 1.0]]
    p = {"alpha": alpha, "rho_d": rho_d, "f0": 0.1}
    v, g = walter.eval(wi, wo, p, gradient=True)
    assert v.shape == (4, 9, 3) and g.shape == (4, 9, 3, 8)
    for k in range(4):
        one = {"alpha": alpha[k], "rho_d": rho_d[k], "f0": 0.1}
        vk, gk = walter.eval(wi, wo, one, gradient=True)
        np.testing.assert_array_equal(v[k], vk)
        np.testing.assert_array_equal(g[k], gk)
    # One direction pair: (K, channels).
    v1 = walter.eval(wi[3], wo[3], p)
    assert v1.shape == (4, 3)
    np.testing.assert_array_equal(v1, v[:, 3])


def test_color_sets_and_one_value_per_set(walter):
    wi, wo = _dirs(4, 5)
    # (K, 1): one value for every channel of each set; a colour's (C,) stays one set.
    v = walter.eval(wi, wo, {"rho_s": [[0.2], [0.4]]})
    assert v.shape == (2, 4, 3)
    np.testing.assert_array_equal(v[1], walter.eval(wi, wo, {"rho_s": 0.4}))
    assert walter.eval(wi, wo, {"rho_s": [0.2, 0.3, 0.4]}).shape == (4, 3)
    # A scalar given as (1,) is one set of K = 1: the axis stays, as NumPy keeps it.
    one = walter.eval(wi, wo, {"alpha": [0.2]})
    assert one.shape == (1, 4, 3)
    np.testing.assert_array_equal(one[0], walter.eval(wi, wo, {"alpha": 0.2}))


def test_a_fitted_model_broadcasts_its_parameters_over_the_sets():
    m = brdfit.Model.from_file(WALTER_RGB)
    wi, wo = _dirs(3, 6)
    v = m.eval(wi, wo, {"alpha": [0.1, 0.2]})
    np.testing.assert_array_equal(v[0], m.eval(wi, wo))  # the file's alpha is 0.1
    np.testing.assert_array_equal(v[1], m.eval(wi, wo, {"alpha": 0.2}))


def test_parameter_sets_must_agree(walter):
    wi, wo = _dirs(3, 7)
    with pytest.raises(brdfit.UsageError) as e:
        walter.eval(wi, wo, {"alpha": [0.1, 0.2, 0.3], "rho_d": [[0.1, 0.1, 0.1]] * 2})
    msg = str(e.value)
    assert "alpha" in msg and "rho_d" in msg and "3" in msg and "2" in msg
    with pytest.raises(brdfit.UsageError) as e:
        walter.eval(wi, wo, {"rho_d": [0.1, 0.2]})  # neither (C,) nor (K, C)
    assert "rho_d" in str(e.value)


def test_each_set_is_checked_by_the_library(walter):
    wi, wo = _dirs(3, 8)
    with pytest.raises(brdfit.UsageError) as e:
        walter.eval(wi, wo, {"alpha": [0.1, 0.2, 5.0]})
    assert "set 2" in str(e.value) and "alpha" in str(e.value)
    with pytest.raises(brdfit.UsageError):
        walter.eval(wi, wo, {"alpha": [0.1, math.nan]})


# --- per-channel gradient ------------------------------------------------------------

def _diagonal_blocks(m, dense):
    """d value[c] / d parameter out of the dense Jacobian, by the model's own table."""
    out = np.empty(dense.shape[:-1] + (len(m.param_names),))
    for j, name in enumerate(m.param_names):
        for c in range(m.channels):
            k = m.value_names.index("%s[%d]" % (name, c)) if "%s[%d]" % (name, c) in m.value_names \
                else m.value_names.index(name)
            out[..., c, j] = dense[..., c, k]
    return out


@pytest.mark.parametrize("spec", ["walter", "walter:mono=specular", "disney", "ward"])
def test_channel_gradient_is_the_dense_ones_diagonal(spec, monkeypatch):
    m = brdfit.Model(spec, channels=3)
    wi, wo = _dirs(11, 9)
    p = {m.param_names[0]: [[0.2, 0.3, 0.4], [0.5, 0.4, 0.3]]}
    v, dense = m.eval(wi, wo, p, gradient=True)
    for block in (brdfit._eval._CHANNEL_BLOCK, 1):  # all at once, and one sample at a time
        monkeypatch.setattr(brdfit._eval, "_CHANNEL_BLOCK", block)
        vc, gc = m.eval(wi, wo, p, gradient="channel")
        assert gc.shape == (2, 11, 3, len(m.param_names))
        np.testing.assert_array_equal(vc, v)
        np.testing.assert_array_equal(gc, _diagonal_blocks(m, dense))
    assert np.any(gc != 0)


def test_channel_gradient_of_2000_channels_without_the_dense_block():
    C = 2000
    m = brdfit.Model("walter", channels=C)
    rng = np.random.default_rng(10)
    p = {"rho_d": rng.uniform(0.05, 0.9, C), "rho_s": rng.uniform(0.05, 0.9, C), "alpha": 0.2, "f0": 0.05}
    wi, wo = _dirs(16, 11)
    one_sample_block = C * len(m.value_names) * 8  # bytes of one sample's dense rows
    tracemalloc.start()
    try:
        v, g = m.eval(wi[0], wo, p, gradient="channel")
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert v.shape == (16, C) and g.shape == (16, C, 4)
    assert peak < 2 * one_sample_block < 16 * one_sample_block  # the dense block is 16 of them
    # Each channel is the 1-channel model with that channel's values (walter's channels
    # are independent): the library's analytic gradient, evaluated another way.
    m1 = brdfit.Model("walter", channels=1)
    for c in (0, 1, 977, C - 1):
        pc = {"rho_d": p["rho_d"][c], "rho_s": p["rho_s"][c], "alpha": 0.2, "f0": 0.05}
        v1, g1 = m1.eval(wi[0], wo, pc, gradient=True)
        np.testing.assert_allclose(v[:, c], v1[:, 0], rtol=1e-13, atol=0)
        np.testing.assert_allclose(g[:, c, :], g1[:, 0, :], rtol=1e-13, atol=1e-300)


def test_gradient_takes_true_false_or_channel(walter):
    wi, wo = _dirs(2, 12)
    for bad in ("dense", "yes", 1, None):
        with pytest.raises(brdfit.UsageError) as e:
            walter.eval(wi, wo, gradient=bad)
        assert "gradient" in str(e.value)


# --- bounds, vectors, dicts ----------------------------------------------------------

def test_bounds_are_the_librarys_table():
    for entry in cli_models()["models"]:
        for channels in (1, 3):
            m = brdfit.Model(entry["name"], channels=channels)
            got = m.bounds
            assert got == {p["name"]: (float(p["lower"]), float(p["upper"])) for p in entry["params"]}, entry["name"]
            assert all(type(lo) is float and type(hi) is float for lo, hi in got.values())
            d = m.defaults
            assert d == {p["name"]: ([float(p["default"])] * channels if p["kind"] == "colour"
                                     else float(p["default"])) for p in entry["params"]}
            assert all(type(x) is float for v in d.values() for x in (v if isinstance(v, list) else [v]))


def test_vector_and_params_round_trip(walter):
    x = walter.vector(WALTER_P)
    assert x.shape == (8,) and x.dtype == np.float64
    assert dict(zip(walter.value_names, x.tolist())) == {
        "rho_d[0]": 0.3, "rho_d[1]": 0.2, "rho_d[2]": 0.1, "rho_s[0]": 0.5, "rho_s[1]": 0.6, "rho_s[2]": 0.7,
        "alpha": 0.15, "f0": 0.04}
    assert walter.params_from(x) == WALTER_P
    np.testing.assert_array_equal(walter.vector(walter.params_from(x)), x)
    # Missing parameters: the defaults, or the model's own.
    np.testing.assert_array_equal(walter.vector(), walter.vector(walter.defaults))
    fitted = brdfit.Model.from_file(WALTER_RGB)
    assert fitted.params_from(fitted.vector({"alpha": 0.3}))["rho_d"] == [0.8, 0.5, 0.2]
    for bad in (np.zeros(7), np.full(8, math.nan), np.r_[x[:6], 5.0, x[7]]):
        with pytest.raises(brdfit.UsageError) as e:
            walter.params_from(bad)
        assert "vector" in str(e.value)


def test_fit_results_hold_floats_and_nan(cayman):
    r = brdfit.fit(cayman, "walter", threads=1, starts=1)
    # rho_d[0] sits at its bound 0 (sRGB's red of this paint is negative): the JSON says
    # 0 and null, Python float 0.0 and NaN.
    assert r.json["params"]["rho_d"][0] == 0 and r.json["stderr"]["rho_d"][0] is None
    for d in (r.params, r.stderr):
        assert all(type(x) is float for v in d.values() for x in (v if isinstance(v, list) else [v]))
    assert r.params["rho_d"][0] == 0.0 and math.isnan(r.stderr["rho_d"][0])


# --- Model.from_file, repr, equality -------------------------------------------------

def test_from_file_holds_the_files_parameters(tmp_path, cayman):
    m = brdfit.Model.from_file(WALTER_RGB)
    assert m.spec == brdfit.Model("walter:fresnel=schlick", channels=3).spec and m.channels == 3
    assert m.params == {"rho_d": [0.8, 0.5, 0.2], "rho_s": [0.9, 0.9, 0.9], "alpha": 0.1, "f0": 0.04}
    r = brdfit.fit(cayman[::7], "lambert", threads=1, starts=1)
    path = tmp_path / "fit.json"
    path.write_text(r.to_json())
    again = brdfit.Model.from_file(path)
    assert again == r.model and again.params == r.params
    wi, wo = _dirs(5, 13)
    np.testing.assert_array_equal(again.eval(wi, wo), r.model.eval(wi, wo))
    with pytest.raises(brdfit.Error):
        brdfit.Model.from_file(tmp_path / "missing.json")
    with pytest.raises(brdfit.UsageError):
        brdfit.Model.from_file(3)


def test_repr_and_equality(walter):
    assert repr(walter) == "brdfit.Model(%r, channels=3)" % walter.spec
    held = brdfit.Model("walter", channels=3, params=WALTER_P)
    assert repr(held) == "brdfit.Model(%r, channels=3, params=...)" % walter.spec
    assert brdfit.Model("walter:fresnel=schlick", channels=3) == walter  # canonical specs
    assert held != walter and held == brdfit.Model("walter", channels=3, params=WALTER_P)
    assert held != brdfit.Model("walter", channels=3, params={**WALTER_P, "alpha": 0.16})
    assert brdfit.Model("walter", channels=1) != brdfit.Model("walter", channels=3)
    assert len({held, brdfit.Model("walter", channels=3, params=WALTER_P), walter}) == 2


# --- Samples: slices, masks, indices -------------------------------------------------

def _same_samples(a, b, rows=slice(None)):
    np.testing.assert_array_equal(a.values, np.asarray(b.values)[rows])
    for x, y in zip(a.angles(), b.angles()):
        np.testing.assert_array_equal(x, y[rows])
    assert a.channel_names == b.channel_names
    assert (a.weights is None) == (b.weights is None)
    if a.weights is not None:
        np.testing.assert_array_equal(a.weights, np.asarray(b.weights)[rows])


def _weighted(n=40, seed=14):
    rng = np.random.default_rng(seed)
    wi, wo = _dirs(n, seed)
    return brdfit.Samples(wi, wo, rng.uniform(0.01, 2.0, (n, 2)), weights=rng.uniform(0.5, 2.0, n))


def test_slices_masks_and_indices(cayman):
    s = _weighted()
    for key in (slice(3, 17), slice(None, None, 3), slice(-5, None), slice(30, 2, -4)):
        sub = s[key]
        assert isinstance(sub, brdfit.Samples) and len(sub) == len(range(40)[key])
        _same_samples(sub, s, key)
    mask = np.asarray(s.values)[:, 0] > 1.0
    _same_samples(s[mask], s, mask)
    for idx in ([5, 2, 2, 39, -1], np.array([0, 1, 7], dtype=np.int16), [1]):
        _same_samples(s[idx], s, np.asarray(idx))
    sub = cayman[100:200]
    assert sub.path == cayman.path and len(sub) == 100
    _same_samples(sub, cayman, slice(100, 200))


def test_selections_stay_read_only():
    s = _weighted()
    for sub in (s[2:9], s[[3, 1]], brdfit.Samples.concat([s, s])):
        with pytest.raises(ValueError):
            sub.values[0, 0] = -1.0
        with pytest.raises(ValueError):
            sub.weights[0] = math.nan


def test_bad_selections_are_usage_errors():
    s = _weighted()
    for key in (5, True, slice(4, 4), [], np.zeros(39, dtype=bool), np.zeros(40, dtype=bool), [40], [-41],
                [0.5], np.zeros((2, 2), dtype=int), "a"):
        with pytest.raises(brdfit.UsageError) as e:
            s[key]
        assert "index" in str(e.value)


def test_a_selection_in_order_keeps_the_origin():
    # Spectral samples keep their wavelengths through the library's copy: prepared to
    # sRGB, a slice equals the same slice of the samples read as sRGB.
    spectral = brdfit.read(CAYMAN)
    rgb = brdfit.read(CAYMAN, rgb=True)
    a = brdfit.fit(spectral[::5], "lambert", rgb=True, threads=1, starts=1)
    b = brdfit.fit(rgb[::5], "lambert", threads=1, starts=1)
    assert a.params == b.params
    # Reordering builds new samples from arrays, which cannot carry wavelengths yet.
    with pytest.raises(brdfit.UsageError) as e:
        spectral[::-1]
    assert "wavelengths" in str(e.value)


def test_merl_cells_stay_cells(tmp_path):
    s = brdfit.read(PAPER_WHITE, grid="merl", subsample=600)
    sub = s[np.arange(0, 600, 2)]
    back = s[np.arange(598, -1, -2)]  # the same samples, reversed
    for t, x in (("sub", sub), ("back", back)):
        x.write(tmp_path / (t + ".binary"))  # the MERL writer needs samples at cell centres
    a = brdfit.read(tmp_path / "sub.binary")
    b = brdfit.read(tmp_path / "back.binary")
    assert len(a) == len(b) == 300
    # The two hold the same cells: the same table.
    np.testing.assert_array_equal(a.values, b.values)


# --- concat --------------------------------------------------------------------------

def test_concat():
    s = _weighted()
    wi, wo = _dirs(5, 15)
    plain = brdfit.Samples(wi, wo, np.full((5, 2), 0.5))
    c = brdfit.Samples.concat([s[:10], plain, s[30:]])
    assert len(c) == 25 and c.path is None
    np.testing.assert_array_equal(c.values, np.concatenate([s.values[:10], plain.values, s.values[30:]]))
    np.testing.assert_array_equal(c.weights, np.concatenate([s.weights[:10], np.ones(5), s.weights[30:]]))
    for x, a, p in zip(c.angles(), s.angles(), plain.angles()):
        np.testing.assert_array_equal(x, np.concatenate([a[:10], p, a[30:]]))
    one = brdfit.Samples.concat((s,))
    assert one is not s
    _same_samples(one, s)


def test_concat_needs_the_same_channels(cayman):
    s = _weighted()
    wi, wo = _dirs(5, 16)
    for other in (brdfit.Samples(wi, wo, np.ones((5, 3))), brdfit.Samples(wi, wo, np.ones((5, 1)))):
        with pytest.raises(brdfit.UsageError) as e:
            brdfit.Samples.concat([s, other])
        assert "parts[1]" in str(e.value) and "channels" in str(e.value)
    # Same count, other names: PTFE's f_r11 against "value", the name Samples gives one.
    ptfe = brdfit.read(PTFE_HEAD, **PTFE_KW)
    assert ptfe.channel_names == ["f_r11"]
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.Samples.concat([ptfe, brdfit.Samples(wi, wo, np.ones(5))])
    assert "f_r11" in str(e.value) and "value" in str(e.value)
    for bad in ([], s, [s, 3], None):
        with pytest.raises(brdfit.UsageError):
            brdfit.Samples.concat(bad)
    both = brdfit.Samples.concat([cayman[:3], cayman[5:6]])
    assert both.path == cayman.path and both.channel_names == ["r", "g", "b"]


# --- write ---------------------------------------------------------------------------

def test_write_csv_reads_back(tmp_path, cayman):
    for s in (_weighted(), cayman[::3]):
        path = tmp_path / "out.csv"
        s.write(path)
        back = brdfit.read(path)
        assert len(back) == len(s) and back.channel_names == s.channel_names
        np.testing.assert_allclose(back.values, s.values, rtol=1e-12, atol=0)
        for x, y in zip(back.angles(), s.angles()):
            np.testing.assert_allclose(x, y, rtol=1e-12, atol=1e-12)
        assert (back.weights is None) == (s.weights is None)
        if s.weights is not None:
            np.testing.assert_allclose(back.weights, s.weights, rtol=1e-12, atol=0)
    _weighted().write(str(tmp_path / "named"), format="csv")
    assert len(brdfit.read(tmp_path / "named", format="csv")) == 40


def test_write_refuses_what_the_library_refuses(tmp_path):
    s = _weighted()
    with pytest.raises(brdfit.UsageError) as e:
        s.write(tmp_path / "x.brdf")
    assert "cannot write" in str(e.value)
    with pytest.raises(brdfit.UsageError) as e:
        s.write(tmp_path / "x.csv", format="cornell")
    assert "cornell" in str(e.value)
    with pytest.raises(brdfit.UsageError) as e:
        s.write(tmp_path / "x.csv", format="jpeg")
    assert "format" in str(e.value) and "jpeg" in str(e.value)
    with pytest.raises(brdfit.UsageError):
        s.write(tmp_path / "x.binary")  # MERL needs 3 channels at cell centres
    with pytest.raises(brdfit.UsageError):
        s.write(None)
    assert not any(tmp_path.iterdir())
