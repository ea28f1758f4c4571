"""New sample sets from others: a subset in order through the library's copy (which keeps
what the samples know of their origin), and sets built anew from arrays (reordered,
repeated or joined samples, and unpickled ones)."""
from __future__ import annotations

from typing import Any, List, Optional, Sequence, Tuple

import numpy as np

from ._args import Array, Index, _array, _view
from ._brdfit import ffi, lib
from ._errors import UsageError, _check

# What a set built anew carries: channel names, MERL cells (n,) or None, the four angle
# arrays in degrees (n,) (for cells, the library's angles of them), values (n, C),
# weights (n,) or None.
Arrays = Tuple[List[str], Optional[Array], Tuple[Array, ...], Array, Optional[Array]]


def _owned(ptr: Any) -> Any:
    return ffi.gc(ptr, lib.bf_samples_free)


def indices(key: Any, n: int) -> Index:
    """The sample indices (0 <= i < n) that key (a slice, a boolean mask of length n or an
    array of indices, negative ones from the end) selects, in its order."""
    if isinstance(key, slice):
        idx = np.arange(n)[key]
    elif isinstance(key, (bool, np.bool_, int, np.integer)):
        raise UsageError("index: %r picks one sample, and a Samples holds a set: use samples[i:i + 1]" % (key,))
    else:
        try:
            arr = np.asarray(key)
        except Exception as e:  # ragged lists and the like
            raise UsageError("index: not an index array (%s)" % e) from None
        if arr.ndim != 1 or not (arr.dtype == np.bool_ or np.issubdtype(arr.dtype, np.integer) or arr.size == 0):
            raise UsageError("index: needs a slice, a boolean mask of length %d or a 1-D array of sample indices, "
                             "got %s of shape %s" % (n, arr.dtype, arr.shape))
        if arr.dtype == np.bool_:
            if arr.size != n:
                raise UsageError("index: a boolean mask needs one entry per sample (%d), got %d" % (n, arr.size))
            idx = np.flatnonzero(arr)
        else:
            idx = arr.astype(np.intp)
            bad = (idx < -n) | (idx >= n)
            if np.any(bad):
                raise UsageError("index: %d is out of range for %d samples" % (idx[np.argmax(bad)], n))
            idx = np.where(idx < 0, idx + n, idx)
    if idx.size == 0:
        raise UsageError("index: selects no sample (a sample set needs at least one)")
    return idx


def in_order(idx: Index) -> bool:
    """Whether idx selects samples in their order, each once (a keep mask says it)."""
    return bool(np.all(np.diff(idx) > 0))


def copy_kept(s: Any, idx: Index) -> Any:
    """The library's copy of samples s with the samples idx (in order) kept."""
    keep = np.zeros(int(s.n), dtype=np.uint8)
    keep[idx] = 1
    err = ffi.new("bf_error *")
    out = ffi.new("bf_samples **")
    _check(lib.bf_samples_copy(s, ffi.from_buffer("unsigned char[]", keep), out, err), err)
    return _owned(out[0])


def _refuse_what_arrays_lose(s: Any, what: str, hint: str) -> None:
    """Wavelengths and a scene's weights cannot be given to new samples (the library has
    no function for it), and a fit without them could differ: such samples are refused."""
    lost = [w for w, p in (("wavelengths", s.wavelength), ("a scene's weights", s.scene_weight)) if p != ffi.NULL]
    if lost:
        raise UsageError("%s: these samples carry %s, which samples made anew from arrays cannot be given yet%s"
                         % (what, " and ".join(lost), hint))


def arrays(s: Any, idx: Optional[Index], what: str, hint: str = "") -> Arrays:
    """What a set built anew takes from samples s (the samples idx, or all), as copies;
    what and hint word the refusal of samples with more than that."""
    _refuse_what_arrays_lose(s, what, hint)
    n, C = int(s.n), int(s.channels)
    sel: Any = slice(None) if idx is None else idx
    names = [ffi.string(s.channel_names[c]).decode("utf-8", "surrogateescape") for c in range(C)]
    values = np.array(_view(s, s.value, (n, C))[sel])
    weights = None if s.weight == ffi.NULL else np.array(_view(s, s.weight, (n,))[sel])
    cells = None
    if s.theta_i == ffi.NULL:  # directions by MERL cells
        cells = np.frombuffer(ffi.buffer(s.merl.cell, n * 4), dtype=np.int32)[sel].copy()
    buf = np.empty(4 * n)
    d = ffi.new("const double *[4]")
    lib.bf_samples_angle_block(s, 0, n, ffi.from_buffer("double[]", buf), d)
    angles = tuple(np.array(_view(buf, d[k], (n,))[sel]) for k in range(4))
    return names, cells, angles, values, weights


def join(parts: Sequence[Arrays]) -> Arrays:
    """One set of several: MERL cells when every part has them, else angles; weights when
    some part has them (1 for the others: what no weights means)."""
    names = parts[0][0]
    values = np.concatenate([p[3] for p in parts])
    weights = None
    if any(p[4] is not None for p in parts):
        weights = np.concatenate([np.ones(p[3].shape[0]) if p[4] is None else p[4] for p in parts])
    cells = None
    if all(p[1] is not None for p in parts):
        cells = np.concatenate([p[1] for p in parts if p[1] is not None])
    return names, cells, tuple(np.concatenate([p[2][k] for p in parts]) for k in range(4)), values, weights


def build(a: Arrays) -> Any:
    """New samples (the library's memory) from arrays, checked as Samples(...) checks its
    arguments: finite angles and values, finite non-negative weights, cells of the MERL
    table, names without NUL."""
    names, cells, angles, values, weights = a
    values = _array("values", values, [(None, None)])
    n, C = values.shape
    if n == 0 or C == 0:
        raise UsageError("values: no samples or no channels (a sample set needs at least one of each)")
    if len(names) != C or not all(isinstance(nm, str) and "\0" not in nm for nm in names):
        raise UsageError("channel names: needs %d names without NUL, got %r" % (C, names))
    if weights is not None:
        weights = _array("weights", weights, [(n,)])
        if np.any(weights < 0):
            raise UsageError("weights: must be >= 0")
    err = ffi.new("bf_error *")
    out = ffi.new("bf_samples **")
    if cells is not None:
        cells = np.ascontiguousarray(cells, dtype=np.int32)
        if cells.shape != (n,) or np.any(cells < 0) or np.any(cells >= lib.BF_MERL_CELLS):
            raise UsageError("cells: needs %d MERL cells (0 to %d)" % (n, lib.BF_MERL_CELLS - 1))
        _check(lib.bf_samples_new_cells(n, C, out, err), err)
        s = _owned(out[0])
        ffi.memmove(s.merl.cell, ffi.from_buffer("int32_t[]", cells), n * 4)
    else:
        if len(angles) != 4:
            raise UsageError("angles: needs theta_i, phi_i, theta_o and phi_o")
        cols = [_array(nm, v, [(n,)]) for nm, v in zip(("theta_i", "phi_i", "theta_o", "phi_o"), angles)]
        _check(lib.bf_samples_new(n, C, out, err), err)
        s = _owned(out[0])
        for dst, src in zip((s.theta_i, s.phi_i, s.theta_o, s.phi_o), cols):
            ffi.memmove(dst, ffi.from_buffer("double[]", src), n * 8)
    ffi.memmove(s.value, ffi.from_buffer("double[]", values), n * C * 8)
    if weights is not None:
        _check(lib.bf_samples_add_weights(s, err), err)
        ffi.memmove(s.weight, ffi.from_buffer("double[]", weights), n * 8)
    for c, nm in enumerate(names):
        _check(lib.bf_samples_set_channel_name(s, c, nm.encode("utf-8", "surrogateescape"), err), err)
    return s
