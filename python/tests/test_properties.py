"""Property-based tests of the input checks: arbitrary arrays, shapes, dtypes, NaN and
Inf given to Samples, Samples.from_angles and Model.eval never crash the interpreter;
each call either gives a result that is right for its input or raises ValueError or
brdfit.Error."""

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import brdfit

SETTINGS = settings(max_examples=80, deadline=None, database=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

DTYPES = st.sampled_from([np.float64, np.float32, np.float16, np.int64, np.int32, np.int8, np.uint8, np.uint64,
                          np.dtype(">f8"), np.longdouble])
ACCEPTED = (ValueError, brdfit.Error)

# NaN, Inf and huge inputs make NumPy warn on the way (overflow in a norm): no matter
pytestmark = pytest.mark.filterwarnings("ignore::RuntimeWarning")


def _elements(dtype):
    dtype = np.dtype(dtype)
    if dtype.kind == "f":
        return hnp.from_dtype(dtype, allow_nan=True, allow_infinity=True)
    return hnp.from_dtype(dtype)


@st.composite
def arrays(draw, n_choices, second_dims=(None, 1, 2, 3, 4)):
    dtype = draw(DTYPES)
    n = draw(st.sampled_from(n_choices))
    second = draw(st.sampled_from(second_dims))
    shape = (n,) if second is None else (n, second)
    if draw(st.integers(0, 9)) == 0:
        shape = shape + (draw(st.integers(0, 2)),)  # an extra axis now and then
    return draw(hnp.arrays(dtype, shape, elements=_elements(dtype)))


@st.composite
def unit_vectors(draw, n):
    """Valid directions above the horizon, float64."""
    a = draw(hnp.arrays(np.float64, (n, 3), elements=st.floats(-1.0, 1.0)))
    a[:, 2] = np.abs(a[:, 2]) + 0.05
    return a / np.linalg.norm(a, axis=1, keepdims=True)


def _as64(a):
    return np.asarray(a).astype(np.float64)


@SETTINGS
@given(st.data())
def test_samples_any_arrays(data):
    n = data.draw(st.sampled_from([0, 1, 2, 5]))
    ns = (n, n, n, n + 1) if n else (0, 1)
    wi = data.draw(arrays(ns, (3, 3, 3, 2, None)))
    wo = data.draw(arrays(ns, (3, 3, 3, 4)))
    values = data.draw(arrays(ns))
    weights = data.draw(st.one_of(st.none(), arrays(ns, (None, None, 1))))
    try:
        s = brdfit.Samples(wi, wo, values, weights=weights)
    except ACCEPTED:
        return
    # taken: the shapes were consistent and the result holds the input converted
    m = wi.shape[0]
    assert wi.shape == (m, 3) and wo.shape == (m, 3) and values.shape[0] == m and values.ndim in (1, 2)
    assert weights is None or weights.shape in ((m,), (m, 1))
    v = np.asarray(s.values)
    k = v.shape[0]
    assert k <= m  # samples the library cannot use (below the horizon, NaN) may be dropped
    assert np.asarray(s.wi).shape == (k, 3) and np.asarray(s.wo).shape == (k, 3)
    if k == m:
        np.testing.assert_array_equal(v.reshape(m, -1), _as64(values).reshape(m, -1))
        if weights is not None and s.weights is not None:
            np.testing.assert_array_equal(np.asarray(s.weights).reshape(m), _as64(weights).reshape(m))


@SETTINGS
@given(st.data())
def test_from_angles_any_arrays(data):
    n = data.draw(st.sampled_from([0, 1, 3]))
    ns = (n, n, n, n + 2)
    angles = [data.draw(arrays(ns, (None, None, None, 1))) for _ in range(4)]
    values = data.draw(arrays(ns, (None, 1, 3)))
    degrees = data.draw(st.booleans())
    try:
        s = brdfit.Samples.from_angles(*angles, values, degrees=degrees)
    except ACCEPTED:
        return
    m = np.asarray(s.values).shape[0]
    assert np.asarray(s.wi).shape == (m, 3) and np.asarray(s.wo).shape == (m, 3)


@st.composite
def params_for(draw, entry, channels):
    out = {}
    wild = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10, 10))
    for p in entry["params"]:
        lo, hi = p["lower"], p["upper"]
        sane = st.floats(lo, min(hi, lo + 10.0), allow_nan=False)
        el = draw(st.sampled_from([sane, sane, wild]))
        if p["kind"] == "colour":
            k = draw(st.sampled_from([channels, channels, channels, 1, channels + 1, 0]))
            out[p["name"]] = [draw(el) for _ in range(k)]
        else:
            out[p["name"]] = draw(el)
    if out and draw(st.integers(0, 9)) == 0:
        out.pop(next(iter(out)))  # a missing parameter now and then
    return out


REGISTRY = None


def _registry():
    global REGISTRY
    if REGISTRY is None:
        m = brdfit.models()
        REGISTRY = m["models"] if isinstance(m, dict) else list(m)
    return REGISTRY


@SETTINGS
@given(st.data())
def test_eval_any_input(data):
    entry = data.draw(st.sampled_from([e for e in _registry()
                                       if e["name"] in ("lambert", "walter", "disney", "ward", "cook_torrance",
                                                        "oren_nayar", "lafortune", "gltf")]))
    channels = data.draw(st.sampled_from([1, 3]))
    model = brdfit.Model(entry["name"], channels=channels)
    n = data.draw(st.sampled_from([0, 1, 4]))
    if data.draw(st.booleans()):
        wi, wo = data.draw(unit_vectors(max(n, 1))), data.draw(unit_vectors(max(n, 1)))
    else:
        wi = data.draw(arrays((n, n, n + 1), (3, 3, 2)))
        wo = data.draw(arrays((n, n, n + 1), (3, 3, 4)))
    params = data.draw(params_for(entry, channels))
    gradient = data.draw(st.booleans())
    try:
        out = model.eval(wi, wo, params, gradient=gradient)
    except ACCEPTED:
        return
    except KeyError:
        assert len(params) < len(entry["params"])  # a missing parameter may be a KeyError
        return
    values = np.asarray(out[0] if gradient else out)
    assert values.shape == (np.asarray(wi).shape[0], channels)
    assert values.dtype == np.float64


@SETTINGS
@given(st.data())
def test_eval_valid_input_is_finite(data):
    """Directions above the horizon and parameters inside the bounds give finite,
    non-negative values."""
    entry = data.draw(st.sampled_from([e for e in _registry() if e["name"] in ("lambert", "walter", "ward_iso",
                                                                             "cook_torrance", "oren_nayar")]))
    channels = data.draw(st.sampled_from([1, 3]))
    n = data.draw(st.integers(1, 20))
    wi, wo = data.draw(unit_vectors(n)), data.draw(unit_vectors(n))
    params = {}
    for p in entry["params"]:
        lo, hi = p["lower"], min(p["upper"], p["lower"] + 1000.0)
        lo_in = lo + 1e-3 * (hi - lo)
        f = st.floats(lo_in, hi - 1e-3 * (hi - lo))
        params[p["name"]] = [data.draw(f) for _ in range(channels)] if p["kind"] == "colour" else data.draw(f)
    v = np.asarray(brdfit.Model(entry["name"], channels=channels).eval(wi, wo, params))
    assert v.shape == (n, channels)
    assert np.isfinite(v).all() and (v >= 0).all()


@SETTINGS
@given(spec=st.text(max_size=40), channels=st.integers(-3, 300))
def test_model_any_spec(spec, channels):
    try:
        m = brdfit.Model(spec, channels=channels)
    except ACCEPTED:
        return
    assert 1 <= channels
    assert len(list(m.param_names)) >= 1
