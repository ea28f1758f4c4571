"""Samples: directions, values and weights in the library's memory."""
from __future__ import annotations

import os
import threading
from typing import Any, Iterable, List, Optional, Tuple, Union

import numpy as np

from . import _samples_build as build
from ._args import Array, _array, _directions, _path_text, _text, _view
from ._brdfit import ffi, lib
from ._errors import UsageError, _check


def _angles_of(v: Array) -> Tuple[Array, Array]:
    theta = np.degrees(np.arccos(np.clip(v[:, 2], -1.0, 1.0)))
    phi = np.degrees(np.arctan2(v[:, 1], v[:, 0]))
    return theta, phi


def _vectors_of(theta: Array, phi: Array) -> Array:
    t, p = np.radians(theta), np.radians(phi)
    return np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=1)


def _restore(arrays: build.Arrays, path: Optional[str]) -> "Samples":
    """Pickled Samples made again (Samples.__reduce__)."""
    return Samples._owned(build.build(arrays), path)


class Samples:
    """Measured or synthetic samples: directions, values (n, channels) and optional weights.

    `Samples(wi, wo, values, weights=None)` from unit vectors, `Samples.from_angles(...)`
    from angles, or `brdfit.read(path, ...)` from a file. `samples[i:j]`, `samples[mask]`
    and `samples[indices]` are new Samples, `Samples.concat([a, b])` joins sets,
    `.write(path)` writes a CSV or MERL file, and Samples pickle."""

    def __init__(self, wi: Any, wo: Any, values: Any, weights: Any = None):
        L, V = _directions("wi", wi), _directions("wo", wo)
        if L.shape[0] != V.shape[0]:
            raise UsageError("wo: needs as many directions as wi (%d), got %d" % (L.shape[0], V.shape[0]))
        ti, pi_ = _angles_of(L)
        to, po = _angles_of(V)
        self._init(ti, pi_, to, po, values, weights, "wi")

    @classmethod
    def from_angles(cls, theta_i: Any, phi_i: Any, theta_o: Any, phi_o: Any, values: Any, weights: Any = None,
                    degrees: bool = True) -> "Samples":
        """Samples from the four angles (degrees, or radians with degrees=False), the
        convention of brdfit's CSV files (docs/formats.md)."""
        s = cls.__new__(cls)
        arrs = [_array(nm, a, [(None,), ()]).reshape(-1)
                for nm, a in (("theta_i", theta_i), ("phi_i", phi_i), ("theta_o", theta_o), ("phi_o", phi_o))]
        if len({a.size for a in arrs}) != 1:
            raise UsageError("theta_i, phi_i, theta_o, phi_o: need the same length, got %s" % [a.size for a in arrs])
        if not degrees:
            arrs = [np.degrees(a) for a in arrs]
        s._init(arrs[0], arrs[1], arrs[2], arrs[3], values, weights, "theta_i")
        return s

    def _init(self, ti: Array, pi_: Array, to: Array, po: Array, values: Any, weights: Any, first: str) -> None:
        n = ti.size
        if n == 0:
            raise UsageError("%s: no directions (a sample set needs at least one sample)" % first)
        vals = _array("values", values, [(n,), (n, None)])
        vals = vals.reshape(n, -1)
        C = vals.shape[1]
        if C < 1:
            raise UsageError("values: needs at least one channel")
        w = None if weights is None else _array("weights", weights, [(n,)])
        if w is not None and np.any(w < 0):
            raise UsageError("weights: must be >= 0")
        err = ffi.new("bf_error *")
        out = ffi.new("bf_samples **")
        _check(lib.bf_samples_new(n, C, out, err), err)
        s = ffi.gc(out[0], lib.bf_samples_free)
        for dst, src in ((s.theta_i, ti), (s.phi_i, pi_), (s.theta_o, to), (s.phi_o, po)):
            ffi.memmove(dst, ffi.from_buffer("double[]", np.ascontiguousarray(src)), n * 8)
        ffi.memmove(s.value, ffi.from_buffer("double[]", vals), n * C * 8)
        if w is not None:
            _check(lib.bf_samples_add_weights(s, err), err)
            ffi.memmove(s.weight, ffi.from_buffer("double[]", w), n * 8)
        self._s = s
        self.path: Optional[str] = None

    @classmethod
    def _wrap(cls, ptr: Any, path: Optional[str]) -> "Samples":
        """Samples of the library's samples ptr, freed with them."""
        return cls._owned(ffi.gc(ptr, lib.bf_samples_free), path)

    @classmethod
    def _owned(cls, s_owned: Any, path: Optional[str]) -> "Samples":
        s = cls.__new__(cls)
        s._s = s_owned
        s.path = path
        return s

    def __getitem__(self, key: Any) -> "Samples":
        """New Samples of the samples key selects: a slice, a boolean mask of length n, or
        an array of indices. A selection in order (a slice with a positive step, a mask,
        increasing indices) is the library's copy, which keeps what the samples know of
        their origin (MERL cells, wavelengths, a scene's weights); one that reorders or
        repeats is built from the arrays (directions, values, weights, channel names)."""
        idx = build.indices(key, self.n)
        if build.in_order(idx):
            return Samples._owned(build.copy_kept(self._s, idx), self.path)
        return Samples._owned(build.build(build.arrays(self._s, idx, "index", ": select them in their order (a "
                                                       "slice, a boolean mask or increasing indices) to keep them")),
                              self.path)

    @staticmethod
    def concat(parts: Iterable["Samples"]) -> "Samples":
        """One Samples of several, in order: the same channels with the same names (else a
        UsageError); weights where any part has them (1 for the others); MERL cells when
        every part has them, else angles. Its path is the parts' when they share one."""
        if isinstance(parts, (Samples, str, bytes)) or not hasattr(parts, "__iter__"):
            raise UsageError("parts: needs a sequence of brdfit.Samples, got %s" % type(parts).__name__)
        ps = list(parts)
        if not ps:
            raise UsageError("parts: needs at least one brdfit.Samples")
        for i, p in enumerate(ps):
            if not isinstance(p, Samples):
                raise UsageError("parts[%d]: needs brdfit.Samples, got %s" % (i, type(p).__name__))
            if p.channel_names != ps[0].channel_names:
                raise UsageError("parts[%d]: has the channels %s, parts[0] %s (concat needs the same channels)"
                                 % (i, ", ".join(p.channel_names), ", ".join(ps[0].channel_names)))
        paths = {p.path for p in ps}
        path = ps[0].path if len(paths) == 1 else None
        if len(ps) == 1:
            return Samples._owned(build.copy_kept(ps[0]._s, np.arange(ps[0].n)), path)
        return Samples._owned(build.build(build.join([build.arrays(p._s, None, "parts[%d]" % i)
                                                      for i, p in enumerate(ps)])), path)

    def write(self, path: Union[str, bytes, "os.PathLike[Any]"], format: Optional[str] = None) -> None:
        """Writes the samples through the library's writer, as `brdfit convert` does: format
        is a format's name ("csv", "merl"), or None for the one the path's extension names;
        a format the library cannot write is refused with its message. The file appears
        only when whole."""
        if not isinstance(path, (str, bytes, os.PathLike)):
            raise UsageError("path: needs a file name, got %r" % (path,))
        p = _path_text(path)
        err = ffi.new("bf_error *")
        f = ffi.new("bf_format *", lib.BF_FORMAT_AUTO)
        if format is not None:
            _check(lib.bf_format_parse(_text("format", format).encode(), f, err), err, "format", usage=True)
        _check(lib.bf_samples_write(self._s, os.fsencode(p), f[0], err), err)

    def __reduce__(self) -> Tuple[Any, Tuple[Any, ...]]:
        # Arrays, not the library's memory: directions (MERL cells, or angles in degrees as
        # held), values, weights and channel names, bit for bit.
        return _restore, (build.arrays(self._s, None, "pickle", ": pass the data file's name instead"), self.path)

    _geometry_lock = threading.Lock()

    def _ready(self) -> None:
        """The geometry, made once before any fit: the library makes it on first use, and
        two fits of the same samples in two threads must not both make it."""
        with Samples._geometry_lock:
            err = ffi.new("bf_error *")
            g = ffi.new("const bf_geometry **")
            _check(lib.bf_samples_geometry(self._s, g, err), err, self.path or "samples")

    def __len__(self) -> int:
        return int(self._s.n)

    @property
    def n(self) -> int:
        return int(self._s.n)

    @property
    def channels(self) -> int:
        return int(self._s.channels)

    @property
    def channel_names(self) -> List[str]:
        return [ffi.string(self._s.channel_names[c]).decode() for c in range(self.channels)]

    @property
    def values(self) -> Array:
        """(n, channels) values in 1/sr: the library's own memory (no copy)."""
        return _view(self, self._s.value, (self.n, self.channels))

    @property
    def weights(self) -> Optional[Array]:
        """(n,) weights (no copy), or None when every sample weighs 1."""
        return None if self._s.weight == ffi.NULL else _view(self, self._s.weight, (self.n,))

    def angles(self) -> Tuple[Array, Array, Array, Array]:
        """theta_i, phi_i, theta_o, phi_o in degrees (copies)."""
        n = self.n
        if n == 0:
            z = np.zeros(0)
            return z, z.copy(), z.copy(), z.copy()
        buf = np.empty(4 * n)  # MERL cells: the library computes them here
        d = ffi.new("const double *[4]")
        lib.bf_samples_angle_block(self._s, 0, n, ffi.from_buffer("double[]", buf), d)
        ti, pi_, to, po = (np.array(_view(buf, d[k], (n,))) for k in range(4))
        return ti, pi_, to, po

    @property
    def wi(self) -> Array:
        """(n, 3) unit vectors towards the light (computed from the angles)."""
        t, p, _, _ = self.angles()
        return _vectors_of(t, p)

    @property
    def wo(self) -> Array:
        """(n, 3) unit vectors towards the viewer (computed from the angles)."""
        _, _, t, p = self.angles()
        return _vectors_of(t, p)

    def __repr__(self) -> str:
        return "brdfit.Samples(%d samples x %d channels%s)" % (self.n, self.channels,
                                                                ", from %r" % self.path if self.path else "")
