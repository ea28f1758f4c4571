"""The Python API over libbrdfit (docs/python.md). Every keyword option has the name of
the command-line option of the same meaning, "-" written "_"; values are checked by the
library's own parsers, so they mean and refuse what the command line does."""
from __future__ import annotations

import json
import os
import tempfile
import threading
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from ._brdfit import ffi, lib

__all__ = ["Error", "UsageError", "Model", "Samples", "FitResult", "CompareResult", "models", "read", "fit",
           "compare", "export", "version"]


class Error(Exception):
    """A failure the library reports: its one-line message, and .code, the bf_status name."""

    def __init__(self, message: str, code: str = "error"):
        super().__init__(message)
        self.message = message
        self.code = code


class UsageError(Error, ValueError):
    """Bad usage (a bad option, model spec or argument): also a ValueError."""

    def __init__(self, message: str, code: str = "arg"):
        super().__init__(message, code)


_CODES = {lib.BF_ERR_ARG: "arg", lib.BF_ERR_IO: "io", lib.BF_ERR_PARSE: "parse", lib.BF_ERR_RANGE: "range",
          lib.BF_ERR_NOMEM: "nomem"}


def _raise(err, what: str = "") -> None:
    msg = ffi.string(err.msg).decode("utf-8", "replace")
    if what:
        msg = "%s: %s" % (what, msg)
    cls = UsageError if err.code == lib.BF_ERR_ARG else Error
    raise cls(msg, _CODES.get(err.code, "error"))


def _check(rc: int, err, what: str = "") -> None:
    if rc != lib.BF_OK:
        _raise(err, what)


def version() -> str:
    """The library's version, as `brdfit --version` says it."""
    return ffi.string(lib.bf_version()).decode()


def models() -> List[Dict[str, Any]]:
    """Every model family with its parameters, options and sizes: the "models" list of
    `brdfit models --json`."""
    p = lib.bf_models_json()
    if p == ffi.NULL:
        raise MemoryError("brdfit: out of memory")
    try:
        return json.loads(ffi.string(p).decode())["models"]
    finally:
        lib.free(p)


# ---- Arrays ------------------------------------------------------------------------

def _array(name: str, a: Any, ndim_shapes: Sequence[Tuple[Optional[int], ...]]) -> np.ndarray:
    """a as a C-contiguous float64 array of one of the shapes (None: any length): values
    of any integer or float dtype are converted (never reinterpreted); anything else, or
    another shape, or a NaN / Inf, is a ValueError naming the argument."""
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
        want = " or ".join("(%s)" % ", ".join("n" if w is None else str(w) for w in s) for s in ndim_shapes)
        raise UsageError("%s: needs shape %s, got %s" % (name, want, arr.shape))
    out = np.ascontiguousarray(arr, dtype=np.float64)
    if not np.all(np.isfinite(out)):
        raise UsageError("%s: has NaN or infinite values" % name)
    return out


def _directions(name: str, a: Any) -> np.ndarray:
    v = _array(name, a, [(None, 3), (3,)]).reshape(-1, 3)
    norm = np.linalg.norm(v, axis=1)
    if np.any(norm == 0.0):
        raise UsageError("%s: has a zero vector (directions are unit vectors)" % name)
    return np.ascontiguousarray(v / norm[:, None])


class _View:
    """Exposes library memory to NumPy without a copy, keeping its owner alive."""

    def __init__(self, owner: Any, ptr, shape: Tuple[int, ...]):
        self._owner = owner
        self.__array_interface__ = {"shape": shape, "typestr": "<f8", "version": 3,
                                    "data": (int(ffi.cast("uintptr_t", ptr)), False)}


def _view(owner: Any, ptr, shape: Tuple[int, ...]) -> np.ndarray:
    if 0 in shape:
        return np.zeros(shape)
    return np.asarray(_View(owner, ptr, shape))


# ---- Models -------------------------------------------------------------------------

class Model:
    """A configured model: `Model("walter", channels=3)`, or any spec `brdfit fit -m` takes
    ("microfacet:D=ggx,lobes=2")."""

    def __init__(self, spec: str, channels: int = 1, params: Optional[Mapping[str, Any]] = None):
        if not isinstance(spec, str):
            raise UsageError("spec: needs a model spec (a string), got %r" % (spec,))
        if isinstance(channels, bool) or not isinstance(channels, (int, np.integer)) or not 1 <= channels <= 1024:
            raise UsageError("channels: needs an integer from 1 to 1024, got %r" % (channels,))
        err = ffi.new("bf_error *")
        out = ffi.new("bf_model **")
        _check(lib.bf_model_new(spec.encode(), int(channels), out, err), err)
        self._m = ffi.gc(out[0], lib.bf_model_free)
        self._params = None
        if params is not None:
            self._params = self._vector(params)

    @classmethod
    def _from_ptr(cls, m) -> "Model":
        return cls(ffi.string(lib.bf_model_spec(m)).decode(), lib.bf_model_channels(m))

    @property
    def spec(self) -> str:
        """The canonical spec, every option written out."""
        return ffi.string(lib.bf_model_spec(self._m)).decode()

    @property
    def name(self) -> str:
        """The family's name ("walter")."""
        return ffi.string(lib.bf_model_name(self._m)).decode()

    @property
    def channels(self) -> int:
        return lib.bf_model_channels(self._m)

    @property
    def param_names(self) -> List[str]:
        """The parameters' names, in the model's order."""
        return [ffi.string(lib.bf_model_param(self._m, i).name).decode() for i in range(lib.bf_model_nparams(self._m))]

    @property
    def value_names(self) -> List[str]:
        """The model vector's entries ("rho_d[0]", "alpha"): the gradient's last axis."""
        buf = ffi.new("char[]", 128)
        return [ffi.string(lib.bf_model_entry_name(self._m, k, buf, 128)).decode()
                for k in range(lib.bf_model_nvalues(self._m))]

    def _colour(self, i: int) -> bool:
        return bool(lib.bf_model_param(self._m, i).colour)

    @property
    def defaults(self) -> Dict[str, Any]:
        """Each parameter's default value (a list of channels values for a colour)."""
        x = np.empty(lib.bf_model_nvalues(self._m))
        lib.bf_model_defaults(self._m, ffi.from_buffer("double[]", x))
        return self._dict(x)

    @property
    def params(self) -> Optional[Dict[str, Any]]:
        """The parameters this model was given (a fit's result: the fitted ones), or None."""
        return None if self._params is None else self._dict(self._params)

    def _dict(self, x: np.ndarray) -> Dict[str, Any]:
        out: Dict[str, Any] = {}
        C = self.channels
        for i in range(lib.bf_model_nparams(self._m)):
            o = lib.bf_model_param_offset(self._m, i)
            name = ffi.string(lib.bf_model_param(self._m, i).name).decode()
            out[name] = [float(v) for v in x[o:o + C]] if self._colour(i) else float(x[o])
        return out

    def _vector(self, params: Optional[Mapping[str, Any]]) -> np.ndarray:
        """The model vector: the defaults with params over them, checked against the bounds."""
        x = np.empty(lib.bf_model_nvalues(self._m))
        lib.bf_model_defaults(self._m, ffi.from_buffer("double[]", x))
        if params is None:
            return x
        if not isinstance(params, Mapping):
            raise UsageError("params: needs a dict of parameter name -> value, got %s" % type(params).__name__)
        C = self.channels
        for key, value in params.items():
            i = lib.bf_model_find_param(self._m, str(key).encode()) if isinstance(key, str) else -1
            if i < 0:
                raise UsageError("params: %s has no parameter %r (it has %s)" % (self.spec, key,
                                                                                  ", ".join(self.param_names)))
            o = lib.bf_model_param_offset(self._m, i)
            n = C if self._colour(i) else 1
            v = _array("params[%r]" % key, value, [(), (n,)]).reshape(-1)
            x[o:o + n] = v if v.size == n else np.repeat(v, n)
        err = ffi.new("bf_error *")
        _check(lib.bf_model_check(self._m, ffi.from_buffer("double[]", x), err), err, "params")
        return x

    def eval(self, wi: Any, wo: Any, params: Optional[Mapping[str, Any]] = None, gradient: bool = False):
        """The BRDF (1/sr) at direction pairs: wi, wo unit vectors of shape (n, 3) (towards the
        light and the viewer, z the normal). params: name -> value (a sequence of channels
        values for a colour parameter); missing ones take the model's own (a fit's result:
        the fitted values; else the defaults). Returns an (n, channels) array, and with
        gradient=True also the analytic Jacobian, (n, channels, len(value_names))."""
        L, V = _directions("wi", wi), _directions("wo", wo)
        if L.shape[0] != V.shape[0]:
            raise UsageError("wi and wo: need the same number of directions, got %d and %d" % (L.shape[0], V.shape[0]))
        if self._params is not None:
            base = self._dict(self._params)
            base.update(params or {})
            params = base
        x = self._vector(params)
        n, C, P = L.shape[0], self.channels, x.size
        values = np.zeros((n, C))
        grad = np.zeros((n, C, P)) if gradient else None
        if n:
            err = ffi.new("bf_error *")
            g = ffi.new("bf_geometry **")
            _check(lib.bf_geometry_from_vectors(n, ffi.from_buffer("double[]", L), ffi.from_buffer("double[]", V), g,
                                                err), err)
            try:
                lib.bf_model_eval(self._m, ffi.from_buffer("double[]", x), g[0], ffi.from_buffer("double[]", values),
                                  ffi.from_buffer("double[]", grad) if gradient else ffi.NULL)
            finally:
                lib.bf_geometry_free(g[0])
        return (values, grad) if gradient else values

    def __repr__(self) -> str:
        return "brdfit.Model(%r, channels=%d)" % (self.spec, self.channels)


# ---- Samples ------------------------------------------------------------------------

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


# ---- Options ------------------------------------------------------------------------

def _flag(name: str, v: Any) -> bool:
    if not isinstance(v, (bool, np.bool_)):
        raise UsageError("%s: needs True or False, got %r" % (name, v), "arg")
    return bool(v)


def _int(name: str, v: Any, lo: int, hi: int) -> int:
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, np.integer)) or not lo <= v <= hi:
        raise UsageError("%s: needs an integer from %d to %d, got %r" % (name, lo, hi, v), "arg")
    return int(v)


def _number(name: str, v: Any, lo: float, hi: float, open_lo: bool = False) -> float:
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, (int, float, np.integer, np.floating)) or \
            not np.isfinite(v) or not (lo < v if open_lo else lo <= v) or not v <= hi:
        raise UsageError("%s: needs a number in %s%g, %g], got %r" % (name, "(" if open_lo else "[", lo, hi, v), "arg")
    return float(v)


def _text(name: str, v: Any) -> str:
    if isinstance(v, (list, tuple)):
        v = ",".join(str(x) for x in v)
    if not isinstance(v, str):
        raise UsageError("%s: needs a string, got %r" % (name, v), "arg")
    return v


class _Keep:
    """C strings handed to option structs, alive as long as the options are."""

    def __init__(self):
        self.items: List[Any] = []

    def s(self, text: str):
        p = ffi.new("char[]", text.encode())
        self.items.append(p)
        return p


DATA_OPTIONS = ("format", "grid", "angles", "radians", "values", "weight", "channels", "rgb", "color", "illuminant",
                "rgb_bands", "luminance", "max_theta", "negative", "subsample", "seed", "scene")


def _data_options(opts: Dict[str, Any], keep: _Keep):
    """bf_read_options and bf_prep from the data keywords (they are taken out of opts),
    and the scene path (or None)."""
    ro = ffi.new("bf_read_options *")
    prep = ffi.new("bf_prep *")
    scene = None
    spectral = None
    for key in [k for k in DATA_OPTIONS if k in opts]:
        v = opts.pop(key)
        if v is None or v is False and key in ("radians", "rgb", "rgb_bands", "luminance"):
            continue
        if key == "format":
            f = lib.bf_format_from_name(_text(key, v).encode())
            if f < 0:
                raise UsageError("format: unknown format %r (csv, merl, cornell, alta, rgl, mbsdf)" % v, "arg")
            ro.format = f
        elif key == "grid":
            ro.grid = keep.s(_text(key, v))
        elif key == "angles":
            names = _text(key, v).split(",")
            if len(names) != 4 or not all(names):
                raise UsageError("angles: needs four column names, got %r" % (v,), "arg")
            for k, nm in enumerate(names):
                ro.csv.angle_cols[k] = keep.s(nm)
        elif key == "radians":
            ro.csv.radians = int(_flag(key, v))
        elif key == "values":
            ro.csv.channels = keep.s(_text(key, v))
        elif key == "weight":
            ro.csv.weight_col = keep.s(_text(key, v))
        elif key == "channels":
            prep.channels = keep.s(_text(key, v))
        elif key in ("rgb", "color", "rgb_bands", "luminance"):
            if key == "color":
                c = lib.bf_color_from_name(_text(key, v).encode())
                if c < 0:
                    raise UsageError("color: takes srgb, acescg or xyz, got %r" % (v,), "arg")
            elif not _flag(key, v):
                continue
            else:
                c = lib.BF_COLOR_SRGB if key == "rgb" else None
            if spectral and not (c is not None and c == prep.color and spectral in ("rgb", "color")):
                raise UsageError("%s and %s exclude each other" % (spectral, key), "arg")
            spectral = key
            if key == "rgb_bands":
                prep.to_bands = 1
            elif key == "luminance":
                prep.to_luminance = 1
            else:
                prep.color = c
        elif key == "illuminant":
            k = lib.bf_illuminant_from_name(_text(key, v).encode())
            if k < 0:
                raise UsageError("illuminant: takes d65, e, a or d50, got %r" % (v,), "arg")
            prep.illuminant = k
        elif key == "max_theta":
            prep.max_theta = _number(key, v, 0.0, 90.0, open_lo=True)
        elif key == "negative":
            modes = {"keep": lib.BF_NEGATIVE_KEEP, "drop": lib.BF_NEGATIVE_DROP, "clamp": lib.BF_NEGATIVE_CLAMP}
            if v not in modes:
                raise UsageError("negative: takes keep, drop or clamp, got %r" % (v,), "arg")
            prep.negative = modes[v]
        elif key == "subsample":
            prep.subsample = 0 if v == "all" else _int(key, v, 1, 10 ** 12)
        elif key == "seed":
            prep.seed = _int(key, v, 0, 2 ** 64 - 1)
        elif key == "scene":
            scene = _text(key, v)
    return ro, prep, scene


def _prepare(s, prep, scene: Optional[str], path: str) -> None:
    """Preprocessing, then the scene, then the subsample (so subsample=N gives N samples
    inside the scene), as the command line does."""
    err = ffi.new("bf_error *")
    sub = prep.subsample
    if scene:
        prep.subsample = 0
    _check(lib.bf_samples_prep(s, prep, ffi.NULL, err), err, path)
    if scene:
        sc = ffi.new("bf_scene **")
        _check(lib.bf_scene_read(scene.encode(), sc, err), err)
        try:
            _check(lib.bf_scene_apply(sc[0], s, ffi.NULL, err), err, "%s: scene %s" % (path, scene))
        finally:
            lib.bf_scene_free(sc[0])
        p2 = ffi.new("bf_prep *")
        p2.subsample, p2.seed = sub, prep.seed
        _check(lib.bf_samples_prep(s, p2, ffi.NULL, err), err, path)


def _no_extra(opts: Mapping[str, Any], what: str) -> None:
    if opts:
        raise UsageError("%s: unknown option%s %s (see help(brdfit.%s))" % (
            what, "s" if len(opts) > 1 else "", ", ".join(sorted(opts)), what), "arg")


def read(path: Union[str, os.PathLike], **data_options: Any) -> Samples:
    """Reads a data file (CSV, MERL .binary, Cornell, ALTA, RGL .bsdf, .mbsdf) and applies the
    data options, named as on the command line: format, grid ("merl", "uniform:N" or a
    file), angles ("ti,pi,to,po" or four names), radians, values, weight, channels, rgb,
    color ("srgb", "acescg", "xyz"), illuminant, rgb_bands, luminance, max_theta, negative
    ("keep", "drop", "clamp"), subsample (N or "all"), seed, scene (a scene file)."""
    path = os.fspath(path)
    if not isinstance(path, str):
        raise UsageError("path: needs a file name, got %r" % (path,))
    keep = _Keep()
    opts = dict(data_options)
    ro, prep, scene = _data_options(opts, keep)
    _no_extra(opts, "read")
    err = ffi.new("bf_error *")
    out = ffi.new("bf_samples **")
    _check(lib.bf_samples_read(path.encode(), ro, out, err), err)
    s = Samples._wrap(out[0], path)
    _prepare(s._s, prep, scene, path)
    return s


FIT_OPTIONS = ("residual", "loss", "fix", "bound", "solid_angle", "no_weights", "constrain_energy", "backend",
               "algorithm", "local", "max_iterations", "starts", "screen", "presolve", "threads", "seed", "accuracy",
               "subsample")


def _overrides(name: str, v: Any) -> List[str]:
    """--fix NAME=VALUE / --bound NAME=LO:HI as a dict, a list of such strings, or one string."""
    if isinstance(v, str):
        return [v]
    if isinstance(v, Mapping):
        out = []
        for k, x in v.items():
            if name == "bound":
                if not isinstance(x, (tuple, list)) or len(x) != 2:
                    raise UsageError("bound: %s needs (lo, hi), got %r" % (k, x), "arg")
                out.append("%s=%r:%r" % (k, float(x[0]), float(x[1])))
            else:
                out.append("%s=%r" % (k, float(x)))
        return out
    if isinstance(v, (list, tuple)) and all(isinstance(t, str) for t in v):
        return list(v)
    raise UsageError("%s: needs a dict (name -> value) or a list of 'NAME=...' strings, got %r" % (name, v), "arg")


class _FitOptions:
    """bf_fit_options from the fit keywords (taken out of opts), with --accuracy applied."""

    def __init__(self, opts: Dict[str, Any], keep: _Keep):
        self.fo = fo = ffi.new("bf_fit_options *")
        lib.bf_fit_options_init(fo)
        err = ffi.new("bf_error *")
        given = 0
        accuracy = lib.BF_ACCURACY_NONE
        self.subsample: Optional[int] = None
        fixes: List[str] = []
        bounds: List[str] = []
        for key in [k for k in FIT_OPTIONS if k in opts]:
            v = opts.pop(key)
            if v is None:
                continue
            if key == "residual":
                r = ffi.new("bf_residual *")
                _check(lib.bf_residual_parse(_text(key, v).encode(), r, err), err, key)
                fo.objective.residual = r[0]
                given |= lib.BF_FIT_GIVEN_RESIDUAL
            elif key == "loss":
                _check(lib.bf_loss_parse(_text(key, v).encode(), ffi.addressof(fo.solver, "loss"), err), err, key)
            elif key == "fix":
                fixes += _overrides(key, v)
            elif key == "bound":
                bounds += _overrides(key, v)
            elif key == "solid_angle":
                fo.objective.solid_angle = int(_flag(key, v))
            elif key == "no_weights":
                fo.objective.use_weights = 0 if _flag(key, v) else 1
            elif key == "constrain_energy":
                fo.solver.use_constraint = int(_flag(key, v))
            elif key == "backend":
                b = ffi.new("bf_backend *")
                if lib.bf_backend_parse(_text(key, v).encode(), b, ffi.NULL) != lib.BF_OK:
                    raise UsageError("backend: takes ceres or nlopt, got %r" % (v,), "arg")
                fo.solver.backend = b[0]
                given |= lib.BF_FIT_GIVEN_BACKEND
            elif key == "algorithm":
                fo.solver.algorithm = keep.s(_text(key, v))
                given |= lib.BF_FIT_GIVEN_ALGORITHM
            elif key == "local":
                fo.solver.local_algorithm = keep.s(_text(key, v))
            elif key == "max_iterations":
                fo.solver.max_iterations = _int(key, v, 1, 10000000)
                given |= lib.BF_FIT_GIVEN_MAX_ITERATIONS
            elif key == "starts":
                fo.starts = _int(key, v, 1, 10000)
                given |= lib.BF_FIT_GIVEN_STARTS
            elif key == "screen":
                fo.screen = _int(key, v, 0, 10000)
                given |= lib.BF_FIT_GIVEN_SCREEN
            elif key == "presolve":
                fo.presolve = -1 if v == "off" else _int(key, v, 64, 1000000000)
            elif key == "threads":
                fo.solver.threads = _int(key, v, 1, 1024)
            elif key == "seed":
                fo.seed = _int(key, v, 0, 2 ** 64 - 1)
            elif key == "accuracy":
                a = ffi.new("bf_fit_accuracy *")
                if lib.bf_fit_accuracy_parse(_text(key, v).encode(), a, ffi.NULL) != lib.BF_OK:
                    raise UsageError("accuracy: takes fast, balanced or best, got %r" % (v,), "arg")
                accuracy = a[0]
            elif key == "subsample":
                self.subsample = 0 if v == "all" else _int(key, v, 1, 10 ** 12)
                given |= lib.BF_FIT_GIVEN_SUBSAMPLE
        sub = ffi.new("size_t *", 0)
        lib.bf_fit_options_apply_accuracy(fo, accuracy, given, sub)
        if self.subsample is None and sub[0] > 0:
            self.subsample = int(sub[0])
        n = len(fixes) + len(bounds)
        self.ov = ffi.new("bf_override[]", max(n, 1))
        for k, text in enumerate(fixes + bounds):
            parse = lib.bf_override_parse_fix if k < len(fixes) else lib.bf_override_parse_bound
            _check(parse(keep.s(text), self.ov + k, err), err, "fix" if k < len(fixes) else "bound")
        fo.objective.overrides = self.ov
        fo.objective.noverrides = n
        _check(lib.bf_solver_options_check(ffi.addressof(fo, "solver"), err), err)

    def check_model(self, spec: str, channels: int) -> None:
        err = ffi.new("bf_error *")
        m = ffi.new("bf_model **")
        _check(lib.bf_model_new(spec.encode(), channels, m, err), err)
        try:
            _check(lib.bf_overrides_check(m[0], 0, self.ov, self.fo.objective.noverrides, err), err)
        finally:
            lib.bf_model_free(m[0])

    def samples(self, s: "Samples") -> "Samples":
        """s, or its seeded subsample (subsample=, or --accuracy fast's) as a new set."""
        if not self.subsample:
            return s
        err = ffi.new("bf_error *")
        out = ffi.new("bf_samples **")
        _check(lib.bf_samples_copy(s._s, ffi.NULL, out, err), err)
        sub = Samples._wrap(out[0], s.path)
        p = ffi.new("bf_prep *")
        p.subsample, p.seed = self.subsample, self.fo.seed
        _check(lib.bf_samples_prep(sub._s, p, ffi.NULL, err), err, s.path or "samples")
        return sub


# ---- Running: threads, progress, Ctrl-C -------------------------------------------------

class _Run:
    """One library call in a worker thread, so that the calling thread stays in Python:
    Ctrl-C (KeyboardInterrupt) there sets the library's cancel flag and is raised once the
    call has stopped; the progress callback runs in the worker (with the GIL), and an
    exception it raises stops the call and is raised here."""

    def __init__(self, progress: Optional[Callable[[int, float], Any]]):
        if progress is not None and not callable(progress):
            raise UsageError("progress: needs a callable (iteration, cost) -> bool, got %r" % (progress,))
        self.progress = progress
        self.cancel = ffi.new("int *", 0)
        self.error: Optional[BaseException] = None
        self.handle = ffi.new_handle(self)

    def hook(self, solver) -> None:
        solver.cancel = self.cancel
        if self.progress is not None:
            solver.progress = lib._brdfit_progress
            solver.progress_user = self.handle

    def __call__(self, fn: Callable[[], Any]) -> Any:
        box: Dict[str, Any] = {}

        def work():
            try:
                box["rc"] = fn()
            except BaseException as e:  # surfaced in the calling thread
                box["exc"] = e

        t = threading.Thread(target=work, name="brdfit", daemon=True)
        t.start()
        interrupted = None
        while t.is_alive():
            try:
                t.join(0.05)
            except KeyboardInterrupt as e:
                self.cancel[0] = 1
                interrupted = e
        if interrupted is not None:
            raise interrupted
        if self.error is not None:
            raise self.error
        if "exc" in box:
            raise box["exc"]
        return box["rc"]


@ffi.def_extern()
def _brdfit_progress(user, iteration, cost):
    run = ffi.from_handle(user)
    if run.error is not None:
        return 1
    try:
        return 1 if run.progress(int(iteration), float(cost)) else 0
    except BaseException as e:
        run.error = e
        return 1


# ---- Fitting ------------------------------------------------------------------------

def _read_text(path: str) -> str:
    with open(path, encoding="utf-8") as f:
        return f.read()


class FitResult:
    """A fit: .params and .stderr (name -> value, a list per channel for a colour), .metrics,
    .warnings, .ok, .cancelled, .model (a Model holding the fitted parameters, to evaluate),
    .json (the result as a dict) and .to_json() (the text `brdfit fit -o` writes)."""

    def __init__(self, text: Optional[str], model: Model, ok: bool, cancelled: bool, start: Dict[str, Any]):
        self._text = text
        self.json: Dict[str, Any] = json.loads(text) if text else {}
        self.ok = ok
        self.cancelled = cancelled
        self.params: Dict[str, Any] = self.json.get("params", start)
        self.stderr: Dict[str, Any] = self.json.get("stderr", {})
        self.metrics: Dict[str, Any] = self.json.get("metrics", {})
        self.warnings: List[str] = self.json.get("warnings", ["the fit was cancelled"] if cancelled else [])
        self.model = Model(model.spec, model.channels, params=self.params)

    @property
    def spec(self) -> str:
        return self.model.spec

    def to_json(self) -> str:
        """The result file's text, as `brdfit fit DATA -m MODEL -o FILE` writes it."""
        if self._text is None:
            raise Error("the fit was cancelled: no result to write", "arg")
        return self._text

    def __repr__(self) -> str:
        return "brdfit.FitResult(%r, ok=%s, rmse_log=%s)" % (self.spec, self.ok, self.metrics.get("rmse_log"))


def _samples_arg(samples: Any, opts: Dict[str, Any], what: str) -> "Samples":
    if isinstance(samples, Samples):
        return samples
    if isinstance(samples, (str, os.PathLike)):
        data = {k: opts.pop(k) for k in list(opts) if k in DATA_OPTIONS and k not in ("seed", "subsample")}
        if "seed" in opts:
            data["seed"] = opts["seed"]
        return read(samples, **data)
    raise UsageError("%s: needs brdfit.Samples or a data file name, got %s" % (what, type(samples).__name__))


def fit(samples: Any, model: Union[str, Model], progress: Optional[Callable[[int, float], Any]] = None,
        **fit_options: Any) -> FitResult:
    """Fits model (a spec or a Model) to samples (brdfit.Samples, or a file name read with
    the data options given here). The options are `brdfit fit`'s: residual, loss, fix
    ({"name": value}), bound ({"name": (lo, hi)}), solid_angle, no_weights,
    constrain_energy, backend, algorithm, local, max_iterations, starts, screen, presolve
    (N or "off"), threads, seed, accuracy ("fast", "balanced", "best"), subsample.
    progress(iteration, cost) is called as the solver goes; returning True stops the fit
    (the result then says .cancelled). Ctrl-C stops it and raises KeyboardInterrupt."""
    opts = dict(fit_options)
    s = _samples_arg(samples, opts, "samples")
    spec = model.spec if isinstance(model, Model) else model
    if not isinstance(spec, str):
        raise UsageError("model: needs a model spec or brdfit.Model, got %r" % (model,))
    keep = _Keep()
    fo = _FitOptions(opts, keep)
    _no_extra(opts, "fit")
    fo.check_model(spec, s.channels)
    data = fo.samples(s)
    data._ready()
    run = _Run(progress)
    run.hook(fo.fo.solver)
    r = ffi.new("bf_fit_result *")
    err = ffi.new("bf_error *")
    rc = run(lambda: lib.bf_fit(data._s, spec.encode(), fo.fo, r, err))
    _check(rc, err, spec)
    try:
        m = Model._from_ptr(r.model)
        cancelled = r.solution.stop == lib.BF_STOP_CANCELLED
        x = np.array(ffi.unpack(r.x, lib.bf_model_nvalues(r.model)))
        text = None
        if not cancelled:
            with tempfile.TemporaryDirectory(prefix="brdfit-") as d:
                out = os.path.join(d, "result.json")
                _check(lib.bf_fit_write_json(r, s.path.encode() if s.path else ffi.NULL, out.encode(), err), err)
                text = _read_text(out)
        return FitResult(text, m, bool(r.ok), cancelled, m._dict(x))
    finally:
        lib.bf_fit_result_clear(r)


# ---- Comparing ----------------------------------------------------------------------

class CompareResult:
    """A comparison: .rows (one dict per material x model: "data" and the fit's fields of
    `brdfit compare --json`), .json (all of it) and .to_json() (its text)."""

    def __init__(self, text: str):
        self._text = text
        self.json: Dict[str, Any] = json.loads(text)
        self.rows: List[Dict[str, Any]] = [dict(f, data=mat["data"]) for mat in self.json["materials"]
                                           for f in mat["fits"]]

    def to_json(self) -> str:
        return self._text


def _split_models(text: str) -> List[str]:
    """A -m list as the command line splits it: a comma starts a new model only where the
    next token has no '=' or has a ':' of its own, so option lists stay whole
    ("microfacet:D=ggx,G=smith_ggx,walter" is two models)."""
    specs: List[str] = []
    for tok in text.split(","):
        if specs and "=" in tok and ":" not in tok:
            specs[-1] += "," + tok
        else:
            specs.append(tok)
    return specs


COMPARE_OPTIONS = ("rank", "folds", "timing", "error", "tolerance", "jobs")


def compare(samples_list: Sequence[Any], models: Union[str, Sequence[str]], progress=None,
            **options: Any) -> CompareResult:
    """Fits every model to every sample set and ranks them, as `brdfit compare`: models is a
    list of specs, or one string as -m takes it ("lambert,walter", "all"); options: rank ("bic", "aic", "aicc", "cv", "error"), folds,
    timing, error ("rmse", "rmse_log", "rmse_cos", "rmse_rel"), tolerance, jobs, and the
    fit options of brdfit.fit (and, for file names, the data options)."""
    opts = dict(options)
    if isinstance(samples_list, (Samples, str, os.PathLike)) or not isinstance(samples_list, Iterable):
        raise UsageError("samples_list: needs a list of brdfit.Samples (or data file names)")
    sets = [_samples_arg(x, dict(opts), "samples_list[%d]" % i) for i, x in enumerate(samples_list)]
    for k in [k for k in DATA_OPTIONS if k in opts and k not in ("seed", "subsample")]:
        opts.pop(k)
    if not sets:
        raise UsageError("samples_list: needs at least one sample set")
    if isinstance(models, str):
        models = [m["name"] for m in globals()["models"]()] if models == "all" else _split_models(models)
    specs = [m.spec if isinstance(m, Model) else m for m in models]
    if not specs or not all(isinstance(m, str) for m in specs):
        raise UsageError("models: needs a list of model specs")
    err = ffi.new("bf_error *")
    c = ffi.new("bf_compare *")
    rank = opts.pop("rank", None)
    folds = opts.pop("folds", None)
    timing = opts.pop("timing", False)
    metric = opts.pop("error", None)
    tolerance = opts.pop("tolerance", None)
    jobs = _int("jobs", opts.pop("jobs", 1), 1, 1024)
    keep = _Keep()
    fo = _FitOptions(opts, keep)
    _no_extra(opts, "compare")
    for spec in specs:
        fo.check_model(spec, sets[0].channels)
    data = [fo.samples(s) for s in sets]
    for d in data:
        d._ready()
    names = [keep.s(s.path or "samples %d" % i) for i, s in enumerate(sets)]
    cspecs = [keep.s(m) for m in specs]
    _check(lib.bf_compare_init(c, len(data), names, len(cspecs), cspecs, err), err)
    try:
        c.metric = lib.BF_CMP_RMSE_LOG
        if metric is not None:
            _check(lib.bf_compare_metric_parse(_text("error", metric).encode(), ffi.addressof(c, "metric"), err), err,
                   "error")
        if rank is not None:
            _check(lib.bf_compare_rank_parse(_text("rank", rank).encode(), ffi.addressof(c, "rank_by"), err), err,
                   "rank")
        c.tolerance = 0.05 if tolerance is None else _number("tolerance", tolerance, 0.0, float("inf"))
        k = 5 if folds is None else _int("folds", folds, 2, 20)
        c.folds = k if c.rank_by == lib.BF_RANK_CV else 0  # as brdfit compare: folds only for rank="cv"
        c.timing = int(_flag("timing", timing))
        c.residual = lib.bf_residual_name(fo.fo.objective.residual)
        ro = ffi.new("bf_compare_run_options *")
        ro.jobs = jobs
        run = _Run(progress)
        run.hook(fo.fo.solver)
        ptrs = ffi.new("bf_samples *[]", [d._s for d in data])
        rc = run(lambda: lib.bf_compare_run(c, ptrs, fo.fo, ro, err))
        _check(rc, err)
        lib.bf_compare_rank(c)
        with tempfile.TemporaryDirectory(prefix="brdfit-") as d:
            out = os.path.join(d, "compare.json")
            _check(lib.bf_compare_write_json(c, out.encode(), err), err)
            return CompareResult(_read_text(out))
    finally:
        lib.bf_compare_clear(c)


# ---- Export -------------------------------------------------------------------------

def export(result: Union[FitResult, str, os.PathLike], to: str, path: Optional[Union[str, os.PathLike]] = None,
           convert: bool = False) -> str:
    """Writes a fit (a FitResult, or a result file) as a renderer's material, as `brdfit
    export`: to "gltf", "blender" or "mitsuba"; convert=True converts any model (else only
    isotropic one-lobe ones). Writes path (atomically) and returns it, or returns the text
    when path is None."""
    t = lib.bf_export_target_find(_text("to", to).encode())
    if t == ffi.NULL:
        raise UsageError("to: %r is not a target (gltf, blender, mitsuba)" % (to,), "arg")
    err = ffi.new("bf_error *")
    with tempfile.TemporaryDirectory(prefix="brdfit-") as d:
        if isinstance(result, FitResult):
            src_path = os.path.join(d, "result.json")
            with open(src_path, "w", encoding="utf-8") as f:
                f.write(result.to_json())
        elif isinstance(result, (str, os.PathLike)):
            src_path = os.fspath(result)
        else:
            raise UsageError("result: needs a brdfit.FitResult or a result file, got %s" % type(result).__name__)
        m = ffi.new("bf_model **")
        x = ffi.new("double **")
        _check(lib.bf_params_read(src_path.encode(), m, x, err), err)
        fit_r = ffi.new("bf_fit_result *")
        try:
            _check(lib.bf_export_check(t, m[0], int(_flag("convert", convert)), err), err)
            e = ffi.new("bf_export_material *")
            _check(lib.bf_export_prepare(t, m[0], x[0], e, fit_r, err), err)
            out = os.fspath(path) if path is not None else os.path.join(d, "export.out")
            _check(lib.bf_export_write(t, e, out.encode(), err), err)
            return out if path is not None else _read_text(out)
        finally:
            lib.bf_fit_result_clear(fit_r)
            lib.bf_model_free(m[0])
            lib.free(x[0])
