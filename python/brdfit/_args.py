"""Plain arguments (not run options) checked and converted: arrays of numbers, directions,
flags, strings and file names. Each refusal is a UsageError naming the argument."""
from __future__ import annotations

import os
from typing import Any, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

from ._brdfit import ffi
from ._errors import UsageError

# The arrays the package hands out and takes: float64, as the library's doubles.
Array = npt.NDArray[np.float64]
Index = npt.NDArray[np.intp]


def _array(name: str, a: Any, ndim_shapes: Sequence[Tuple[Optional[int], ...]], any_name: str = "n") -> Array:
    """a as a C-contiguous float64 array of one of the shapes (None: any length, called
    any_name in the message): values of any integer or float dtype are converted (never
    reinterpreted); anything else, or another shape, or a NaN / Inf, is a ValueError
    naming the argument."""
    try:
        arr = np.asarray(a)
    except Exception as e:  # ragged lists and the like
        raise UsageError("%s: not an array of numbers (%s)" % (name, e)) from None
    if arr.dtype == np.bool_ or not (np.issubdtype(arr.dtype, np.integer) or np.issubdtype(arr.dtype, np.floating)):
        raise UsageError("%s: needs numbers (an integer or float array), got dtype %s" % (name, arr.dtype))
    for shape in ndim_shapes:
        if arr.ndim == len(shape) and all(w is None or w == h for w, h in zip(shape, arr.shape)):
            break
    else:
        want = " or ".join("(%s)" % ", ".join(any_name if w is None else str(w) for w in s) for s in ndim_shapes)
        raise UsageError("%s: needs shape %s, got %s" % (name, want, arr.shape))
    out = np.ascontiguousarray(arr, dtype=np.float64).reshape(arr.shape)  # ascontiguousarray makes () (1,)
    if not np.all(np.isfinite(out)):
        raise UsageError("%s: has NaN or infinite values" % name)
    return out


def _directions(name: str, a: Any) -> Array:
    return _direction_array(name, a)[0]


def _direction_array(name: str, a: Any) -> Tuple[Array, bool]:
    """Unit vectors (n, 3) of a, an (n, 3) or (3,) array, and whether a was one (3,)."""
    arr = _array(name, a, [(None, 3), (3,)])
    single = arr.ndim == 1
    v = arr.reshape(-1, 3)
    # Scaled first: a tiny vector (1e-300) is a direction too, and its square underflows.
    big = np.max(np.abs(v), axis=1)
    if np.any(big == 0.0):
        raise UsageError("%s: has a zero vector (directions are unit vectors)" % name)
    v = v / big[:, None]
    return np.ascontiguousarray(v / np.linalg.norm(v, axis=1)[:, None]), single


def _direction_pairs(wi: Any, wo: Any) -> Tuple[Array, Array, Tuple[int, ...]]:
    """wi and wo as n pairs of unit vectors, (n, 3) each, broadcast as NumPy does: one
    direction (a (3,) or (1, 3) array) goes with every direction of the other. The third
    item is the leading shape of a result: () when both are (3,), else (n,)."""
    L, one_l = _direction_array("wi", wi)
    V, one_v = _direction_array("wo", wo)
    nl, nv = L.shape[0], V.shape[0]
    if nl != nv:
        if nl != 1 and nv != 1:
            raise UsageError("wi and wo: need the same number of directions, or one direction for all, got %d and %d"
                             % (nl, nv))
        n = nv if nl == 1 else nl  # NumPy's rule: (1, 3) with (0, 3) is (0, 3)
        L, V = (np.ascontiguousarray(np.broadcast_to(d, (n, 3))) for d in (L, V))
    return L, V, (() if one_l and one_v else (L.shape[0],))


class _View:
    """Exposes library memory to NumPy without a copy, keeping its owner alive."""

    def __init__(self, owner: Any, ptr: Any, shape: Tuple[int, ...]):
        self._owner = owner
        # Read-only: the library checked these values when they came in, and keeps
        # relying on them (a NaN or a negative weight written here would reach the fits).
        self.__array_interface__ = {"shape": shape, "typestr": "<f8", "version": 3,
                                    "data": (int(ffi.cast("uintptr_t", ptr)), True)}


def _view(owner: Any, ptr: Any, shape: Tuple[int, ...]) -> Array:
    if 0 in shape:
        z = np.zeros(shape)
        z.flags.writeable = False
        return z
    return np.asarray(_View(owner, ptr, shape))


def _flag(name: str, v: Any) -> bool:
    if not isinstance(v, (bool, np.bool_)):
        raise UsageError("%s: needs True or False, got %r" % (name, v))
    return bool(v)


def _text(name: str, v: Any) -> str:
    if not isinstance(v, str):
        raise UsageError("%s: needs a string, got %r" % (name, v))
    return v


def _path_text(p: Any) -> str:
    s = os.fsdecode(os.fsencode(p))
    if "\0" in s:
        raise UsageError("%r: a NUL character cannot be in a file name" % (p,))
    return s
