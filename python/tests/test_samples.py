"""brdfit.read with data options, brdfit.Samples and Samples.from_angles: contents equal
what `brdfit convert` writes, array views, dtypes (float32 is never read as doubles, int
is converted), wrong shapes raise ValueError naming the argument."""

import numpy as np
import pytest

import brdfit
from _support import (CAYMAN, CAYMAN_SAMPLES, PAPER_WHITE, PTFE, PTFE_CLI, PTFE_KW, cli, nsamples,
                      read_csv_table, values2d, vectors_from_angles, weights_or_ones)


def _converted(tmp_path, data, *options):
    """`brdfit convert DATA out.csv OPTIONS`: (angles n x 4 in degrees, values n x C, header)."""
    out = tmp_path / "converted.csv"
    cli("convert", data, out, *options, "-q")
    header, t = read_csv_table(out)
    return t[:, :4], t[:, 4:], header


def _assert_samples_match(s, angles, values):
    n = angles.shape[0]
    assert nsamples(s) == n
    np.testing.assert_array_equal(values2d(s), values)
    wi, wo = np.asarray(s.wi), np.asarray(s.wo)
    assert wi.shape == (n, 3) and wo.shape == (n, 3)
    assert wi.dtype == np.float64 and wo.dtype == np.float64
    np.testing.assert_allclose(wi, vectors_from_angles(angles[:, 0], angles[:, 1]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(wo, vectors_from_angles(angles[:, 2], angles[:, 3]), rtol=0, atol=1e-12)


def _rng_dirs(n, seed=0):
    rng = np.random.default_rng(seed)
    ti, to = rng.uniform(0, 80, n), rng.uniform(0, 80, n)
    pi, po = rng.uniform(0, 360, n), rng.uniform(0, 360, n)
    return ti, pi, to, po


# --- read ----------------------------------------------------------------------------

def test_read_cornell_rgb_equals_convert(tmp_path):
    s = brdfit.read(str(CAYMAN), rgb=True)
    angles, values, header = _converted(tmp_path, CAYMAN, "--rgb")
    assert header[4:] == ["r", "g", "b"]
    assert values.shape == (CAYMAN_SAMPLES, 3)
    _assert_samples_match(s, angles, values)
    np.testing.assert_array_equal(weights_or_ones(s.weights, CAYMAN_SAMPLES), 1.0)
    assert np.asarray(s.values).dtype == np.float64


def test_read_cornell_spectral(tmp_path):
    s = brdfit.read(str(CAYMAN))
    angles, values, header = _converted(tmp_path, CAYMAN)
    assert values.shape == (CAYMAN_SAMPLES, 31)
    _assert_samples_match(s, angles, values)


def test_read_subsample_equals_convert(tmp_path):
    s = brdfit.read(str(CAYMAN), rgb=True, subsample=500)
    angles, values, _ = _converted(tmp_path, CAYMAN, "--rgb", "--subsample", "500")
    assert values.shape[0] == 500
    _assert_samples_match(s, angles, values)


def test_read_seed_changes_subsample(tmp_path):
    a = brdfit.read(str(CAYMAN), rgb=True, subsample=300, seed=1)
    angles, values, _ = _converted(tmp_path, CAYMAN, "--rgb", "--subsample", "300", "--seed", "1")
    _assert_samples_match(a, angles, values)
    b = brdfit.read(str(CAYMAN), rgb=True, subsample=300)
    assert not np.array_equal(values2d(a), values2d(b))


def test_read_csv_column_options(tmp_path):
    s = brdfit.read(str(PTFE), **PTFE_KW)
    angles, values, header = _converted(tmp_path, PTFE, *PTFE_CLI)
    assert values.shape == (1760, 1)
    _assert_samples_match(s, angles, values)
    # the value column itself, exactly as written in the file
    raw_header, raw = read_csv_table(PTFE)
    np.testing.assert_array_equal(values2d(s)[:, 0], raw[:, raw_header.index("f_r11")])


def test_read_preprocessing_options(tmp_path):
    s = brdfit.read(str(PTFE), max_theta=60, **PTFE_KW)
    angles, values, _ = _converted(tmp_path, PTFE, *PTFE_CLI, "--max-theta", "60")
    assert 0 < values.shape[0] < 1760
    _assert_samples_match(s, angles, values)
    assert (angles[:, [0, 2]] <= 60).all()

    lum = brdfit.read(str(CAYMAN), luminance=True)
    angles, values, _ = _converted(tmp_path, CAYMAN, "--luminance")
    assert values.shape == (CAYMAN_SAMPLES, 1)
    _assert_samples_match(lum, angles, values)


def test_read_radians_and_weight_columns(tmp_path):
    ti, pi, to, po = _rng_dirs(50, seed=4)
    rng = np.random.default_rng(9)
    vals = rng.uniform(0.01, 2.0, 50)
    w = rng.uniform(0.5, 2.0, 50)
    path = tmp_path / "rad.csv"
    with open(path, "w") as f:
        f.write("ti,pi,to,po,brdf,wt\n")
        for row in zip(np.radians(ti), np.radians(pi), np.radians(to), np.radians(po), vals, w):
            f.write(",".join(repr(float(x)) for x in row) + "\n")
    s = brdfit.read(str(path), angles="ti,pi,to,po", radians=True, values="brdf", weight="wt")
    assert nsamples(s) == 50
    np.testing.assert_array_equal(values2d(s)[:, 0], vals)
    np.testing.assert_array_equal(np.asarray(s.weights).reshape(50), w)
    np.testing.assert_allclose(np.asarray(s.wi), vectors_from_angles(ti, pi), atol=1e-12)
    np.testing.assert_allclose(np.asarray(s.wo), vectors_from_angles(to, po), atol=1e-12)


def test_read_rgl_grid(tmp_path):
    s = brdfit.read(str(PAPER_WHITE), grid="uniform:8")
    angles, values, _ = _converted(tmp_path, PAPER_WHITE, "--grid", "uniform:8")
    assert values.shape == (512, 3)
    _assert_samples_match(s, angles, values)


def test_read_rgl_merl_grid_subsample(tmp_path):
    s = brdfit.read(str(PAPER_WHITE), grid="merl", subsample=2000)
    angles, values, _ = _converted(tmp_path, PAPER_WHITE, "--grid", "merl", "--subsample", "2000")
    assert values.shape == (2000, 3)
    assert nsamples(s) == 2000
    np.testing.assert_array_equal(values2d(s), values)
    np.testing.assert_allclose(np.asarray(s.wi), vectors_from_angles(angles[:, 0], angles[:, 1]), atol=1e-9)
    np.testing.assert_allclose(np.asarray(s.wo), vectors_from_angles(angles[:, 2], angles[:, 3]), atol=1e-9)


# --- Samples from arrays ------------------------------------------------------------

def test_samples_round_trip():
    ti, pi, to, po = _rng_dirs(40)
    wi, wo = vectors_from_angles(ti, pi), vectors_from_angles(to, po)
    vals = np.random.default_rng(1).uniform(0, 3, (40, 3))
    w = np.linspace(0.5, 1.5, 40)
    s = brdfit.Samples(wi, wo, vals, weights=w)
    assert nsamples(s) == 40
    np.testing.assert_array_equal(values2d(s), vals)
    assert np.asarray(s.values).shape == (40, 3)
    np.testing.assert_array_equal(np.asarray(s.weights).reshape(40), w)
    np.testing.assert_allclose(np.asarray(s.wi), wi, atol=1e-14)
    np.testing.assert_allclose(np.asarray(s.wo), wo, atol=1e-14)
    s2 = brdfit.Samples(wi, wo, vals)
    np.testing.assert_array_equal(weights_or_ones(s2.weights, 40), 1.0)


def test_samples_one_channel_from_1d_values():
    ti, pi, to, po = _rng_dirs(10)
    vals = np.linspace(0.1, 1.0, 10)
    s = brdfit.Samples(vectors_from_angles(ti, pi), vectors_from_angles(to, po), vals)
    assert values2d(s).shape == (10, 1)
    np.testing.assert_array_equal(values2d(s)[:, 0], vals)


def test_samples_normalise_directions():
    ti, pi, to, po = _rng_dirs(20, seed=2)
    wi, wo = vectors_from_angles(ti, pi), vectors_from_angles(to, po)
    s = brdfit.Samples(wi * 3.0, wo * 0.5, np.ones((20, 1)))
    np.testing.assert_allclose(np.asarray(s.wi), wi, atol=1e-14)
    np.testing.assert_allclose(np.asarray(s.wo), wo, atol=1e-14)
    np.testing.assert_allclose(np.linalg.norm(np.asarray(s.wi), axis=1), 1.0, atol=1e-14)


def test_from_angles_degrees_and_radians():
    ti, pi, to, po = _rng_dirs(25, seed=3)
    vals = np.random.default_rng(2).uniform(0, 1, (25, 3))
    a = brdfit.Samples.from_angles(ti, pi, to, po, vals)
    b = brdfit.Samples.from_angles(ti, pi, to, po, vals, degrees=True)
    c = brdfit.Samples.from_angles(np.radians(ti), np.radians(pi), np.radians(to), np.radians(po), vals,
                                   degrees=False)
    for s in (a, b, c):
        assert nsamples(s) == 25
        np.testing.assert_array_equal(values2d(s), vals)
        np.testing.assert_allclose(np.asarray(s.wi), vectors_from_angles(ti, pi), atol=1e-12)
        np.testing.assert_allclose(np.asarray(s.wo), vectors_from_angles(to, po), atol=1e-12)
    np.testing.assert_array_equal(np.asarray(a.wi), np.asarray(b.wi))


def test_from_angles_matches_read(tmp_path):
    """The same angles read from a CSV or given as arrays make the same samples."""
    angles, values, _ = _converted(tmp_path, CAYMAN, "--rgb", "--subsample", "200")
    s = brdfit.Samples.from_angles(angles[:, 0], angles[:, 1], angles[:, 2], angles[:, 3], values)
    r = brdfit.read(str(CAYMAN), rgb=True, subsample=200)
    np.testing.assert_array_equal(values2d(s), values2d(r))
    np.testing.assert_allclose(np.asarray(s.wi), np.asarray(r.wi), atol=1e-15)
    np.testing.assert_allclose(np.asarray(s.wo), np.asarray(r.wo), atol=1e-15)


# --- views ------------------------------------------------------------------------

def test_values_and_weights_are_views():
    """values (n x C doubles) and weights (n doubles) have the library's layout: the
    arrays are views of the samples' memory, not fresh copies."""
    ti, pi, to, po = _rng_dirs(30, seed=6)
    s = brdfit.Samples(vectors_from_angles(ti, pi), vectors_from_angles(to, po),
                       np.ones((30, 3)), weights=np.full(30, 2.0))
    v1, v2 = s.values, s.values
    assert isinstance(v1, np.ndarray)
    assert np.shares_memory(v1, v2)
    w1, w2 = s.weights, s.weights
    assert isinstance(w1, np.ndarray)
    assert np.shares_memory(w1, w2)
    assert isinstance(s.wi, np.ndarray) and isinstance(s.wo, np.ndarray)


def test_read_values_are_views(cayman):
    a, b = cayman.values, cayman.values
    assert isinstance(a, np.ndarray) and np.shares_memory(a, b)
    assert a.shape == (CAYMAN_SAMPLES, 3)


# --- dtypes -------------------------------------------------------------------------

def test_float32_is_converted_not_reinterpreted():
    ti, pi, to, po = _rng_dirs(16, seed=10)
    wi32 = vectors_from_angles(ti, pi).astype(np.float32)
    wo32 = vectors_from_angles(to, po).astype(np.float32)
    vals32 = np.linspace(0.1, 1.7, 48, dtype=np.float32).reshape(16, 3)
    w32 = np.linspace(0.3, 3.0, 16, dtype=np.float32)
    s = brdfit.Samples(wi32, wo32, vals32, weights=w32)
    assert nsamples(s) == 16
    v = values2d(s)
    assert v.dtype == np.float64
    np.testing.assert_array_equal(v, vals32.astype(np.float64))
    np.testing.assert_array_equal(np.asarray(s.weights).reshape(16), w32.astype(np.float64))
    wi64 = wi32.astype(np.float64)
    np.testing.assert_allclose(np.asarray(s.wi), wi64 / np.linalg.norm(wi64, axis=1, keepdims=True), atol=1e-14)


@pytest.mark.parametrize("dtype", [np.int8, np.int16, np.int32, np.int64, np.uint8, np.uint16, np.uint32,
                                   np.uint64, np.float16, np.float32, np.float64, np.longdouble, ">f8", "<i4"])
def test_any_int_or_float_dtype(dtype):
    wi = np.array([[0, 0, 1], [1, 0, 1], [0, 2, 2], [3, 0, 4]]).astype(dtype)
    wo = np.array([[0, 0, 1], [0, 1, 1], [2, 0, 2], [0, 3, 4]]).astype(dtype)
    vals = np.array([[1, 2], [3, 4], [5, 6], [7, 8]]).astype(dtype)
    w = np.array([1, 2, 3, 4]).astype(dtype)
    s = brdfit.Samples(wi, wo, vals, weights=w)
    np.testing.assert_array_equal(values2d(s), vals.astype(np.float64))
    np.testing.assert_array_equal(np.asarray(s.weights).reshape(4), [1, 2, 3, 4])
    ref = wi.astype(np.float64)
    np.testing.assert_allclose(np.asarray(s.wi), ref / np.linalg.norm(ref, axis=1, keepdims=True), atol=1e-15)
    t = brdfit.Samples.from_angles(np.array([0, 30, 45, 60]).astype(dtype), np.array([0, 90, 10, 20]).astype(dtype),
                                   np.array([10, 20, 30, 40]).astype(dtype), np.array([0, 0, 0, 0]).astype(dtype),
                                   vals)
    np.testing.assert_allclose(np.asarray(t.wi), vectors_from_angles([0, 30, 45, 60], [0, 90, 10, 20]), atol=1e-12)


def test_array_likes_and_strided_arrays():
    wi = [[0.0, 0.0, 1.0], [0.6, 0.0, 0.8]]
    wo = ((0.0, 0.0, 1.0), (0.0, 0.8, 0.6))
    s = brdfit.Samples(wi, wo, [[0.5], [0.25]])
    np.testing.assert_array_equal(values2d(s)[:, 0], [0.5, 0.25])
    np.testing.assert_allclose(np.asarray(s.wo), np.array(wo), atol=1e-15)

    big = np.random.default_rng(0).uniform(0.1, 1.0, (20, 8))
    wi_s = big[::2, 0:6:2]            # strided rows and columns
    wo_f = np.asfortranarray(big[:10, 3:6])
    vals = big[::-2, 6:8]             # negative strides
    s = brdfit.Samples(wi_s, wo_f, vals)
    np.testing.assert_array_equal(values2d(s), np.ascontiguousarray(vals))
    np.testing.assert_allclose(np.asarray(s.wi), wi_s / np.linalg.norm(wi_s, axis=1, keepdims=True), atol=1e-15)
    np.testing.assert_allclose(np.asarray(s.wo), wo_f / np.linalg.norm(wo_f, axis=1, keepdims=True), atol=1e-15)


def test_eval_takes_float32_and_int():
    m = brdfit.Model("lambert")
    wi = np.array([[0, 0, 1], [0, 3, 4]], dtype=np.int32)
    wo = np.array([[0, 0, 1], [4, 0, 3]], dtype=np.float32)
    v = np.asarray(m.eval(wi, wo, {"rho_d": np.float32(0.5)}))
    assert v.shape == (2, 1) and v.dtype == np.float64
    np.testing.assert_allclose(v[:, 0], float(np.float32(0.5)) / np.pi, rtol=1e-15)


# --- wrong shapes -------------------------------------------------------------------

def _valid(n=6):
    ti, pi, to, po = _rng_dirs(n, seed=12)
    return vectors_from_angles(ti, pi), vectors_from_angles(to, po), np.ones((n, 3)), np.ones(n)


def _raises_naming(name, fn, *args, **kwargs):
    with pytest.raises(ValueError) as e:
        fn(*args, **kwargs)
    assert name in str(e.value), f"ValueError does not name {name!r}: {e.value}"


def test_wrong_shapes_name_the_argument():
    wi, wo, vals, w = _valid()
    _raises_naming("wi", brdfit.Samples, wi[:, :2], wo, vals)
    _raises_naming("wi", brdfit.Samples, wi.reshape(6, 3, 1), wo, vals)
    _raises_naming("wi", brdfit.Samples, wi.ravel(), wo, vals)
    _raises_naming("wo", brdfit.Samples, wi, wo[:5], vals)
    _raises_naming("wo", brdfit.Samples, wi, np.ones((6, 4)), vals)
    _raises_naming("values", brdfit.Samples, wi, wo, vals[:5])
    _raises_naming("values", brdfit.Samples, wi, wo, np.ones((6, 3, 2)))
    _raises_naming("weights", brdfit.Samples, wi, wo, vals, weights=w[:4])
    _raises_naming("weights", brdfit.Samples, wi, wo, vals, weights=np.ones((6, 2)))


def test_wrong_shapes_from_angles():
    t = np.linspace(0, 60, 6)
    vals = np.ones((6, 1))
    _raises_naming("phi_o", brdfit.Samples.from_angles, t, t, t, t[:5], vals)
    _raises_naming("theta_i", brdfit.Samples.from_angles, np.ones((6, 2)), t, t, t, vals)
    _raises_naming("values", brdfit.Samples.from_angles, t, t, t, t, np.ones((7, 1)))


def test_wrong_shapes_in_eval():
    m = brdfit.Model("walter", channels=3)
    p = {"rho_d": [0.5, 0.5, 0.5], "rho_s": [0.5, 0.5, 0.5], "alpha": 0.2, "f0": 0.04}
    wi, wo, _, _ = _valid()
    _raises_naming("wi", m.eval, wi[:, :2], wo, p)
    _raises_naming("wo", m.eval, wi, wo[:4], p)
    _raises_naming("wo", m.eval, wi, np.ones((6, 3, 1)), p)
    with pytest.raises(ValueError) as e:
        m.eval(wi, wo, {**p, "rho_d": [0.5, 0.5]})  # a colour parameter needs 3 values
    assert "rho_d" in str(e.value) or "params" in str(e.value)


def test_non_numeric_input_is_refused():
    wi, wo, vals, _ = _valid()
    with pytest.raises((ValueError, TypeError)):
        brdfit.Samples(np.array([["a", "b", "c"]] * 6), wo, vals)
    with pytest.raises((ValueError, TypeError)):
        brdfit.Samples(wi, wo, np.array([[object()] * 3] * 6, dtype=object))
