"""Model evaluation over NumPy arrays: direction pairs broadcast, several parameter sets
in one call, and the gradient as the library's dense Jacobian or per channel."""
from __future__ import annotations

from typing import Any, Dict, List, Mapping, Optional, Protocol, Tuple, Union

import numpy as np

from ._args import Array, Index, _array, _direction_pairs
from ._brdfit import ffi, lib
from ._errors import UsageError, _check



class Evaluable(Protocol):
    """What evaluation takes of a brdfit.Model (_model.py, which calls this module: the
    model is described here rather than imported, so that the two do not import each
    other)."""

    _m: Any
    _params: Optional[Array]

    @property
    def channels(self) -> int: ...

    def _color(self, i: int) -> bool: ...

    def _find(self, key: Any) -> int: ...

    def _vector(self, params: Optional[Mapping[str, Any]], base: Optional[Array] = None) -> Array: ...

# The per-channel gradient comes from the dense Jacobian a block of samples at a time:
# at most this many doubles of it at once (32 MiB; one sample's rows at least).
_CHANNEL_BLOCK = 1 << 22

Result = Union[Array, Tuple[Array, Array]]


def _gradient_mode(gradient: Any) -> Optional[str]:
    """None (values only), "dense" (gradient=True) or "channel"."""
    if isinstance(gradient, (bool, np.bool_)):
        return "dense" if gradient else None
    if isinstance(gradient, str) and gradient == "channel":
        return "channel"
    raise UsageError("gradient: needs True, False or 'channel', got %r" % (gradient,))


def _param_sets(m: Evaluable, params: Optional[Mapping[str, Any]]) -> Tuple[Array, Optional[int]]:
    """The model vectors of params, (K, nvalues), and K, or None for one set (then one
    row): the model's own parameters (a fit's; else the defaults) with params over them.
    A scalar parameter of shape (K,) or a colour one of shape (K, C) or (K, 1) gives K
    sets, every given K alike; each set is checked against the bounds by the library."""
    x0 = m._params.copy() if m._params is not None else m._vector(None)
    if params is None:
        params = {}
    if not isinstance(params, Mapping):
        raise UsageError("params: needs a dict of parameter name -> value, got %s" % type(params).__name__)
    C = m.channels
    given: List[Tuple[int, bool, Array]] = []
    sets: Dict[str, int] = {}
    for key, value in params.items():
        i = m._find(key)
        color = m._color(i)
        shapes: List[Tuple[Optional[int], ...]] = [(), (C,), (None, C), (None, 1)] if color else [(), (None,)]
        arr = _array("params[%r]" % key, value, list(dict.fromkeys(shapes)), any_name="K")
        if arr.ndim == (2 if color else 1):
            sets[key] = arr.shape[0]
        given.append((lib.bf_model_param_offset(m._m, i), color, arr))
    if len(set(sets.values())) > 1:
        raise UsageError("params: %s give different numbers of parameter sets (%s)" % (
            ", ".join(sets), ", ".join("%s %d" % kv for kv in sets.items())))
    K = next(iter(sets.values())) if sets else None
    X = np.tile(x0, (1 if K is None else K, 1))
    for o, color, arr in given:
        if color:
            X[:, o:o + C] = arr  # (), (C,), (K, C) and (K, 1) broadcast over the sets and channels
        else:
            X[:, o] = arr
    err = ffi.new("bf_error *")
    for k in range(X.shape[0]):
        _check(lib.bf_model_check(m._m, ffi.from_buffer("double[]", X[k]), err), err,
               "params" if K is None else "params (set %d)" % k, usage=True)
    return X, K


def _channel_columns(m: Evaluable) -> Tuple[Index, Index]:
    """Indices into a dense Jacobian (n, C, nvalues) that give d value[c] / d parameter:
    rows (C, 1) and columns (C, nparams), a colour parameter's column being channel c's."""
    C, nparams = m.channels, lib.bf_model_nparams(m._m)
    cols = np.empty((C, nparams), dtype=np.intp)
    for j in range(nparams):
        o = lib.bf_model_param_offset(m._m, j)
        cols[:, j] = o + np.arange(C) if m._color(j) else o
    return np.arange(C)[:, None], cols


def _eval_channel(m: Evaluable, x: Array, g: Any, values: Array, out: Array) -> None:
    """values (n, C) and out (n, C, nparams) of one parameter set: the library's analytic
    Jacobian of a block of samples at a time, of which only the per-channel columns stay."""
    n, C = values.shape
    P = x.size
    block = max(1, _CHANNEL_BLOCK // (C * P))
    rows, cols = _channel_columns(m)
    dense = np.empty((min(block, n), C, P))
    xp = ffi.from_buffer("double[]", x)
    for i0 in range(0, n, block):
        i1 = min(n, i0 + block)
        lib.bf_model_eval_range(m._m, xp, g, i0, i1, ffi.from_buffer("double[]", values[i0:i1]),
                                ffi.from_buffer("double[]", dense))
        out[i0:i1] = dense[:i1 - i0][:, rows, cols]


def evaluate(m: Evaluable, wi: Any, wo: Any, params: Optional[Mapping[str, Any]], gradient: Any) -> Result:
    mode = _gradient_mode(gradient)
    L, V, lead = _direction_pairs(wi, wo)
    X, K = _param_sets(m, params)
    n, C, P = L.shape[0], m.channels, X.shape[1]
    values = np.zeros((X.shape[0], n, C))
    grad = None
    if mode == "dense":
        grad = np.zeros((X.shape[0], n, C, P))
    elif mode == "channel":
        grad = np.zeros((X.shape[0], n, C, lib.bf_model_nparams(m._m)))
    if n and X.shape[0]:
        err = ffi.new("bf_error *")
        g = ffi.new("bf_geometry **")
        _check(lib.bf_geometry_from_vectors(n, ffi.from_buffer("double[]", L), ffi.from_buffer("double[]", V), g,
                                            err), err)
        try:
            for k in range(X.shape[0]):
                if mode == "channel":
                    assert grad is not None
                    _eval_channel(m, X[k], g[0], values[k], grad[k])
                else:
                    lib.bf_model_eval(m._m, ffi.from_buffer("double[]", X[k]), g[0],
                                      ffi.from_buffer("double[]", values[k]),
                                      ffi.NULL if grad is None else ffi.from_buffer("double[]", grad[k]))
        finally:
            lib.bf_geometry_free(g[0])
    shape = (() if K is None else (K,)) + lead
    if grad is None:
        return values.reshape(shape + (C,))
    return values.reshape(shape + (C,)), grad.reshape(shape + (C, grad.shape[-1]))
