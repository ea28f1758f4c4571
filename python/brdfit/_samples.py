"""Samples: directions, values and weights in the library's memory."""
from __future__ import annotations

import threading
from typing import Any, List, Optional, Tuple

import numpy as np

from ._args import _array, _directions, _view
from ._brdfit import ffi, lib
from ._errors import UsageError, _check


def _angles_of(v: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    theta = np.degrees(np.arccos(np.clip(v[:, 2], -1.0, 1.0)))
    phi = np.degrees(np.arctan2(v[:, 1], v[:, 0]))
    return theta, phi


def _vectors_of(theta: np.ndarray, phi: np.ndarray) -> np.ndarray:
    t, p = np.radians(theta), np.radians(phi)
    return np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=1)


class Samples:
    """Measured or synthetic samples: directions, values (n, channels) and optional weights.

    `Samples(wi, wo, values, weights=None)` from unit vectors, `Samples.from_angles(...)`
    from angles, or `brdfit.read(path, ...)` from a file."""

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
        s._init(*arrs, values, weights, "theta_i")
        return s

    def _init(self, ti, pi_, to, po, values, weights, first: str) -> None:
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
    def _wrap(cls, ptr, path: Optional[str]) -> "Samples":
        s = cls.__new__(cls)
        s._s = ffi.gc(ptr, lib.bf_samples_free)
        s.path = path
        return s

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
    def values(self) -> np.ndarray:
        """(n, channels) values in 1/sr: the library's own memory (no copy)."""
        return _view(self, self._s.value, (self.n, self.channels))

    @property
    def weights(self) -> Optional[np.ndarray]:
        """(n,) weights (no copy), or None when every sample weighs 1."""
        return None if self._s.weight == ffi.NULL else _view(self, self._s.weight, (self.n,))

    def angles(self) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """theta_i, phi_i, theta_o, phi_o in degrees (copies)."""
        n = self.n
        if n == 0:
            return tuple(np.zeros(0) for _ in range(4))
        buf = np.empty(4 * n)  # MERL cells: the library computes them here
        d = ffi.new("const double *[4]")
        lib.bf_samples_angle_block(self._s, 0, n, ffi.from_buffer("double[]", buf), d)
        return tuple(np.array(_view(buf, d[k], (n,))) for k in range(4))

    @property
    def wi(self) -> np.ndarray:
        """(n, 3) unit vectors towards the light (computed from the angles)."""
        t, p, _, _ = self.angles()
        return _vectors_of(t, p)

    @property
    def wo(self) -> np.ndarray:
        """(n, 3) unit vectors towards the viewer (computed from the angles)."""
        _, _, t, p = self.angles()
        return _vectors_of(t, p)

    def __repr__(self) -> str:
        return "brdfit.Samples(%d samples x %d channels%s)" % (self.n, self.channels,
                                                                ", from %r" % self.path if self.path else "")
