"""The Python API over libbrdfit (docs/python.md). Every keyword option has the name of
the command-line option of the same meaning, "-" written "_"; values are checked by the
library's own parsers, so they mean and refuse what the command line does."""
from __future__ import annotations

import json
import os
import re
import threading
from typing import Any, Callable, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from ._brdfit import ffi, lib

__all__ = ["Error", "UsageError", "Model", "Samples", "FitResult", "CompareResult", "SelectResult", "models",
           "options", "read", "fit", "compare", "select", "export", "version"]


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


def _raise(err, what: str = "", usage: bool = False) -> None:
    msg = ffi.string(err.msg).decode("utf-8", "replace")
    if what:
        msg = "%s: %s" % (what, msg)
    cls = UsageError if usage or err.code == lib.BF_ERR_ARG else Error
    raise cls(msg, ffi.string(lib.bf_status_name(err.code)).decode())


def _check(rc: int, err, what: str = "", usage: bool = False) -> None:
    """Raises the library's error: UsageError (a ValueError) for bad usage, and for any
    error of a check of the caller's arguments (usage: a value out of its range is the
    caller's, as the command's exit status 2 says); Error otherwise."""
    if rc != lib.BF_OK:
        _raise(err, what, usage)


def version() -> str:
    """The library's version, as `brdfit --version` says it."""
    return ffi.string(lib.bf_version()).decode()


def models() -> List[Dict[str, Any]]:
    """Every model family with its parameters, options and sizes: the "models" list of
    `brdfit models --json`."""
    p = lib.bf_models_json()
    if p == ffi.NULL:
        raise MemoryError("brdfit: out of memory")
    return json.loads(_take_text(p))["models"]


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
    # Scaled first: a tiny vector (1e-300) is a direction too, and its square underflows.
    big = np.max(np.abs(v), axis=1)
    if np.any(big == 0.0):
        raise UsageError("%s: has a zero vector (directions are unit vectors)" % name)
    v = v / big[:, None]
    return np.ascontiguousarray(v / np.linalg.norm(v, axis=1)[:, None])


class _View:
    """Exposes library memory to NumPy without a copy, keeping its owner alive."""

    def __init__(self, owner: Any, ptr, shape: Tuple[int, ...]):
        self._owner = owner
        # Read-only: the library checked these values when they came in, and keeps
        # relying on them (a NaN or a negative weight written here would reach the fits).
        self.__array_interface__ = {"shape": shape, "typestr": "<f8", "version": 3,
                                    "data": (int(ffi.cast("uintptr_t", ptr)), True)}


def _view(owner: Any, ptr, shape: Tuple[int, ...]) -> np.ndarray:
    if 0 in shape:
        z = np.zeros(shape)
        z.flags.writeable = False
        return z
    return np.asarray(_View(owner, ptr, shape))


# ---- Models -------------------------------------------------------------------------

class Model:
    """A configured model: `Model("walter", channels=3)`, or any spec `brdfit fit -m` takes
    ("microfacet:D=ggx,lobes=2")."""

    def __init__(self, spec: str, channels: int = 1, params: Optional[Mapping[str, Any]] = None):
        if not isinstance(spec, str):
            raise UsageError("spec: needs a model spec (a string), got %r" % (spec,))
        if isinstance(channels, bool) or not isinstance(channels, (int, np.integer)):
            raise UsageError("channels: needs an integer, got %r" % (channels,))
        if "\0" in spec:
            raise UsageError("spec: %r: a NUL character cannot be in a spec" % (spec,))
        err = ffi.new("bf_error *")
        out = ffi.new("bf_model **")
        count = int(channels) if -2 ** 31 < int(channels) < 2 ** 31 else 0  # the library says the range
        _check(lib.bf_model_new(spec.encode(), count, out, err), err, usage=True)
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
        _check(lib.bf_model_check(self._m, ffi.from_buffer("double[]", x), err), err, "params", usage=True)
        return x

    def eval(self, wi: Any, wo: Any, params: Optional[Mapping[str, Any]] = None, gradient: bool = False):
        """The BRDF (1/sr) at direction pairs: wi, wo unit vectors of shape (n, 3) (towards the
        light and the viewer, z the normal). params: name -> value (a sequence of channels
        values for a colour parameter); missing ones take the model's own (a fit's result:
        the fitted values; else the defaults). Returns an (n, channels) array, and with
        gradient=True also the analytic Jacobian, (n, channels, len(value_names))."""
        gradient = _flag("gradient", gradient)
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


# ---- Plain arguments (not options) ---------------------------------------------------------

def _flag(name: str, v: Any) -> bool:
    if not isinstance(v, (bool, np.bool_)):
        raise UsageError("%s: needs True or False, got %r" % (name, v))
    return bool(v)


def _text(name: str, v: Any) -> str:
    if not isinstance(v, str):
        raise UsageError("%s: needs a string, got %r" % (name, v))
    return v


# ---- Options: the library's table -------------------------------------------------------

_TASKS = {"read": lib.BF_TASK_READ, "fit": lib.BF_TASK_FIT, "compare": lib.BF_TASK_COMPARE,
          "select": lib.BF_TASK_SELECT}


def _str(p) -> Optional[str]:
    return None if p == ffi.NULL else ffi.string(p).decode()


def _table() -> List[Dict[str, Any]]:
    """The library's option table (brdfit/options.h), as dicts."""
    out = []
    for i in range(lib.bf_option_count()):
        d = lib.bf_option_get(i)
        out.append({"name": _str(d.name), "group": _str(d.group), "tasks": d.tasks, "type": int(d.type),
                    "arg": _str(d.arg), "help": _str(d.help), "default": _str(getattr(d, "def")),
                    "range": _str(d.range)})
    return out


def options(task: str) -> List[Dict[str, Any]]:
    """The keyword options a function takes ("read", "fit", "compare" or "select"), as the
    library declares them: name, group, type, arg, help, default (text, or None for none
    or automatic) and range (in words, or None)."""
    if task not in _TASKS:
        raise UsageError("task: one of %s, got %r" % (", ".join(_TASKS), task))
    seen = set()
    out = []
    for d in _table():
        if d["tasks"] & _TASKS[task] and d["name"] not in seen:
            seen.add(d["name"])
            out.append(d)
    return out


def _keyword_help(text: str) -> str:
    """Help text with the command line's option names as keywords ("--max-theta" ->
    max_theta)."""
    return re.sub(r"--([a-z][a-z-]*)", lambda m: m.group(1).replace("-", "_"), text)


def _doc(task: str, groups: Optional[Sequence[str]] = None) -> str:
    lines = []
    for d in options(task):
        if groups is not None and d["group"] not in groups:
            continue
        head = "  %s=%s" % (d["name"], d["arg"] or "True")
        body = _keyword_help(d["help"] or "").replace("\n", " ")
        lines.append("%-28s %s" % (head, body))
    return "\n".join(lines)


def _value_texts(d, name: str, v: Any) -> List[Optional[str]]:
    """A keyword's value as the texts the library takes (Python types to text only: the
    library checks and refuses)."""
    if int(d.type) == lib.BF_OPTION_LIST:
        if isinstance(v, str):
            return [v]
        if isinstance(v, Mapping):
            out: List[Optional[str]] = []
            for k, x in v.items():
                if name == "bound" and isinstance(x, (tuple, list)) and len(x) == 2:
                    out.append("%s=%s:%s" % (k, _one_text(x[0]), _one_text(x[1])))
                elif isinstance(x, (tuple, list, np.ndarray)):  # one value per channel
                    out.extend("%s[%d]=%s" % (k, c, _one_text(xc)) for c, xc in enumerate(x))
                else:
                    out.append("%s=%s" % (k, _one_text(x)))
            return out
        if isinstance(v, (list, tuple)) and all(isinstance(t, str) for t in v):
            return list(v)
        raise UsageError("%s: needs a dict (name -> value) or a list of 'NAME=...' strings, got %r" % (name, v))
    if isinstance(v, (list, tuple)):
        return [",".join(_one_text(x) for x in v)]
    return [_one_text(v)]


def _one_text(v: Any) -> str:
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        return repr(float(v))
    if isinstance(v, str):
        if "\0" in v:
            raise UsageError("%r: a NUL character cannot be in a value" % (v,))
        return v
    if isinstance(v, os.PathLike):
        return _path_text(v)
    raise UsageError("needs a string, a number or True/False, got %r" % (v,))


def _path_text(p: Any) -> str:
    s = os.fsdecode(os.fsencode(p))
    if "\0" in s:
        raise UsageError("%r: a NUL character cannot be in a file name" % (p,))
    return s


class _Options:
    """A set of the library's run options for a task, from keyword arguments: each
    keyword is set by the library (bf_options_set), which checks it and says what is
    wrong, naming the keyword."""

    def __init__(self, task: str, keywords: Mapping[str, Any], what: str):
        err = ffi.new("bf_error *")
        out = ffi.new("bf_options **")
        _check(lib.bf_options_new(_TASKS[task], out, err), err)
        self.o = ffi.gc(out[0], lib.bf_options_free)
        lib.bf_options_set_spelling(self.o, lib.BF_SPELL_KEYWORD)
        self.given = []
        for name, v in keywords.items():
            if v is None:
                continue
            d = lib.bf_option_find(name.encode(), _TASKS[task])
            if d == ffi.NULL:  # the library's message: unknown, or another task's
                _check(lib.bf_options_set(self.o, name.encode(), ffi.NULL, err), err)
            try:
                texts = _value_texts(d, name, v)
            except UsageError as e:
                raise UsageError("%s: %s" % (name, e.message)) from None
            for t in texts:
                _check(lib.bf_options_set(self.o, name.encode(), os.fsencode(t) if t is not None else ffi.NULL, err), err)
            self.given.append((name, _str(d.group)))

    def check(self, specs: Sequence[str] = ()) -> None:
        err = ffi.new("bf_error *")
        keep = [ffi.new("char[]", s.encode()) for s in specs]
        arr = ffi.new("const char *[]", keep) if keep else ffi.NULL
        _check(lib.bf_options_check_models(self.o, arr, len(keep), err), err, usage=True)
        _check(lib.bf_options_check(self.o, err), err, usage=True)

    def reading_given(self) -> List[str]:
        return [n for n, g in self.given if g == "reading"]


def _load(path: Union[str, os.PathLike], opts: _Options) -> "Samples":
    p = _path_text(path)
    err = ffi.new("bf_error *")
    out = ffi.new("bf_samples **")
    _check(lib.bf_samples_load(os.fsencode(p), opts.o, out, ffi.NULL, err), err)
    return Samples._wrap(out[0], p)


def read(path: Union[str, os.PathLike], **data_options: Any) -> "Samples":
    if not isinstance(path, (str, os.PathLike)):
        raise UsageError("path: needs a file name, got %r" % (path,))
    return _load(path, _Options("read", data_options, "read"))


read.__doc__ = """Reads a data file (CSV, MERL .binary, Cornell, ALTA, RGL .bsdf, .mbsdf) and prepares
its samples as the command line does (read, preprocess, scene, subsample), with the data
options as keywords:

""" + _doc("read")


def _prepared(x: Any, opts: _Options, what: str) -> "Samples":
    """Samples for a fit: a file loaded with the options, or a copy of given samples
    prepared with them (the preprocessing, scene and subsample; bf_samples_prepare)."""
    if isinstance(x, (str, os.PathLike)):
        return _load(x, opts)
    if not isinstance(x, Samples):
        raise UsageError("%s: needs brdfit.Samples or a data file name, got %s" % (what, type(x).__name__))
    if opts.reading_given():
        raise UsageError("%s: %s read a file; these samples are read already" % (
            what, ", ".join(opts.reading_given())))
    err = ffi.new("bf_error *")
    out = ffi.new("bf_samples **")
    _check(lib.bf_samples_copy(x._s, ffi.NULL, out, err), err)
    s = Samples._wrap(out[0], x.path)
    _check(lib.bf_samples_prepare(s._s, opts.o, ffi.NULL, err), err, x.path or what)
    return s


# ---- Running: threads, progress, Ctrl-C -------------------------------------------------

# How often the calling thread looks up from waiting (Ctrl-C is seen at once regardless).
_POLL_SECONDS = 0.025


class _Run:
    """One library call in a worker thread, so that the calling thread stays in Python.
    An exception there (Ctrl-C's KeyboardInterrupt, a signal handler's TimeoutError) sets
    the library's cancel flag, and the call's memory stays alive until the call has
    returned; then the exception is raised. The progress callback runs in the worker (with
    the GIL); an exception it raises, or True, stops the call."""

    def __init__(self, progress: Optional[Callable[[int, float], Any]]):
        if progress is not None and not callable(progress):
            raise UsageError("progress: needs a callable (iteration, cost) -> bool, got %r" % (progress,))
        self.progress = progress
        self.cancel = ffi.new("bf_cancel_flag *", 0)
        self.error: Optional[BaseException] = None
        self.handle = ffi.new_handle(self)

    def hook(self, opts: _Options) -> None:
        lib.bf_options_set_cancel(opts.o, self.cancel, ffi.NULL)
        if self.progress is not None:
            lib.bf_options_set_progress(opts.o, lib._brdfit_progress, self.handle)

    def __call__(self, fn: Callable[[], Any]) -> Any:
        box: Dict[str, Any] = {}
        done = threading.Event()

        def work():
            try:
                box["rc"] = fn()
            except BaseException as e:  # surfaced in the calling thread
                box["exc"] = e
            finally:
                done.set()

        t = threading.Thread(target=work, name="brdfit", daemon=True)
        t.start()
        interrupted = None
        while True:
            try:
                if done.wait(_POLL_SECONDS):
                    break
            except BaseException as e:  # the call still runs: stop it, wait for it
                self.cancel[0] = 1
                if interrupted is None:
                    interrupted = e
        t.join()
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
    if run.error is not None or run.cancel[0]:
        return 1
    try:
        stop = bool(run.progress(int(iteration), float(cost)))
    except BaseException as e:
        run.error = e
        stop = True
    if stop:  # the whole call stops, not only this solve
        run.cancel[0] = 1
        return 1
    return 0


# ---- Fitting ------------------------------------------------------------------------

def _take_text(p) -> str:
    """A text the library made (bf_free'd here)."""
    try:
        return ffi.string(p).decode("utf-8", "surrogateescape")  # a non-UTF-8 file name as Python names it
    finally:
        lib.bf_free(p)


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
        self.model = model
        self.model._params = model._vector(self.params)

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


def _spec_of(model: Any, what: str) -> str:
    spec = model.spec if isinstance(model, Model) else model
    if not isinstance(spec, str) or "\0" in spec:
        raise UsageError("%s: needs a model spec or brdfit.Model, got %r" % (what, model))
    return spec


def fit(samples: Any, model: Union[str, Model], progress: Optional[Callable[[int, float], Any]] = None,
        start: Optional[Mapping[str, Any]] = None, **options: Any) -> FitResult:
    spec = _spec_of(model, "model")
    opts = _Options("fit", options, "fit")
    opts.check([spec])
    data = _prepared(samples, opts, "samples")
    # The start: start= (name -> value), else the parameters a Model was given (a fit's
    # result), for the data's channels.
    if isinstance(model, Model) and model.channels != data.channels:
        raise UsageError("model: %s has %d channels, the data %d" % (spec, model.channels, data.channels))
    if start is None and isinstance(model, Model) and model._params is not None:
        start = model.params
    err = ffi.new("bf_error *")
    if start is not None:
        x0 = Model(spec, data.channels)._vector(start)
        _check(lib.bf_options_set_start(opts.o, ffi.from_buffer("double[]", x0), x0.size, err), err, "start")
    data._ready()
    run = _Run(progress)
    run.hook(opts)
    r = ffi.new("bf_fit_result *")
    lib.bf_fit_result_init(r)
    try:
        rc = run(lambda: lib.bf_fit(data._s, spec.encode(), opts.o, r, err))
        _check(rc, err, spec)
        m = Model._from_ptr(r.model)
        cancelled = r.solution.stop == lib.BF_STOP_CANCELLED
        x = np.array(ffi.unpack(r.x, lib.bf_model_nvalues(r.model)))
        text = None
        if not cancelled:
            out = ffi.new("char **")
            _check(lib.bf_fit_result_json(r, os.fsencode(data.path) if data.path else ffi.NULL, out, err), err)
            text = _take_text(out[0])
        return FitResult(text, m, bool(r.ok), cancelled, m._dict(x))
    finally:
        lib.bf_fit_result_clear(r)


fit.__doc__ = """Fits model (a spec or a Model) to samples (brdfit.Samples, or a data file name), as
`brdfit fit` does. start (name -> value, as Model params take them) replaces the
data-driven start; a Model given parameters (a fit's .model) starts from them. The search
still adds its own starts unless starts=1. progress(iteration, cost) is called as the
solver goes; returning True stops the fit (the result then says .cancelled). Ctrl-C stops
it and raises KeyboardInterrupt. The options are brdfit fit's, as keywords:

""" + _doc("fit") + """

With brdfit.Samples, the data options other than the reading ones apply to a copy of them
(preprocessing, scene, subsample)."""


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


def _model_list(models: Any) -> List[str]:
    """A list of specs, or one string split as -m splits it (bf_model_list_split)."""
    if isinstance(models, str):
        err = ffi.new("bf_error *")
        specs = ffi.new("char ***")
        n = ffi.new("int *")
        _check(lib.bf_model_list_split(models.encode(), specs, n, err), err, "models")
        try:
            return [ffi.string(specs[0][k]).decode() for k in range(n[0])]
        finally:
            lib.bf_free(specs[0])
    if isinstance(models, Model) or not isinstance(models, Iterable):
        raise UsageError("models: needs a list of model specs, or one string as -m takes it")
    out = [_spec_of(m, "models") for m in models]
    if not out:
        raise UsageError("models: needs at least one model")
    return out


def compare(samples_list: Sequence[Any], models: Union[str, Sequence[Any]], progress=None,
            **options: Any) -> CompareResult:
    if isinstance(samples_list, (Samples, str, os.PathLike)) or not isinstance(samples_list, Iterable):
        raise UsageError("samples_list: needs a list of brdfit.Samples (or data file names)")
    samples_list = list(samples_list)
    if not samples_list:
        raise UsageError("samples_list: needs at least one sample set")
    specs = _model_list(models)
    opts = _Options("compare", options, "compare")
    opts.check(specs)
    data = [_prepared(x, opts, "samples_list[%d]" % i) for i, x in enumerate(samples_list)]
    for d in data:
        d._ready()
    err = ffi.new("bf_error *")
    out = ffi.new("bf_compare **")
    keep = [ffi.new("char[]", os.fsencode(d.path or "samples %d" % i)) for i, d in enumerate(data)]
    cspecs = [ffi.new("char[]", m.encode()) for m in specs]
    _check(lib.bf_compare_new(len(data), keep, len(cspecs), cspecs, out, err), err)
    c = out[0]
    run = _Run(progress)
    run.hook(opts)
    ptrs = ffi.new("bf_samples *[]", [d._s for d in data])
    try:
        rc = run(lambda: lib.bf_compare_run(c, ptrs, opts.o, ffi.NULL, ffi.NULL, err))
        _check(rc, err)
        lib.bf_compare_rank(c)
        text = ffi.new("char **")
        _check(lib.bf_compare_json(c, text, err), err)
        return CompareResult(_take_text(text[0]))
    finally:
        lib.bf_compare_free(c)


compare.__doc__ = """Fits every model to every sample set and ranks them, as `brdfit compare`: models is a
list of specs, or one string as -m takes it ("lambert,walter", "all"); samples_list holds
brdfit.Samples or data file names. progress(iteration, cost) sees every solve; returning
True stops the comparison. The options are brdfit compare's, as keywords:

""" + _doc("compare")


# ---- Selecting ----------------------------------------------------------------------

class SelectResult:
    """A selection: .chosen (the chosen spec, or None when nothing could be fitted), .fit
    (its FitResult), .json (every candidate and the choice, as `brdfit select --json`
    writes it) and .to_json() (that text)."""

    def __init__(self, text: str, fit: Optional[FitResult]):
        self._text = text
        self.json: Dict[str, Any] = json.loads(text)
        self.fit = fit
        self.chosen: Optional[str] = fit.spec if fit is not None else None

    def to_json(self) -> str:
        return self._text

    def __repr__(self) -> str:
        return "brdfit.SelectResult(chosen=%r)" % (self.chosen,)


def select(samples: Any, models: Optional[Union[str, Sequence[Any]]] = None, progress=None,
           **options: Any) -> SelectResult:
    opts = _Options("select", options, "select")
    data = _prepared(samples, opts, "samples")
    if models is None:  # the library's default candidates for the data's channels
        arr = ffi.new("const char ***")
        n = lib.bf_select_default_candidates(data.channels, arr)
        if n < 0:
            raise MemoryError("brdfit: out of memory")
        try:
            specs = [ffi.string(arr[0][k]).decode() for k in range(n)]
        finally:
            lib.bf_free(arr[0])
    else:
        specs = _model_list(models)
    opts.check(specs)
    data._ready()
    err = ffi.new("bf_error *")
    out = ffi.new("bf_select **")
    cspecs = [ffi.new("char[]", m.encode()) for m in specs]
    _check(lib.bf_select_new(len(cspecs), cspecs, data.channels, opts.o, out, err), err)
    s = out[0]
    run = _Run(progress)
    run.hook(opts)
    try:
        rc = run(lambda: lib.bf_select_run(s, data._s, opts.o, ffi.NULL, ffi.NULL, err))
        _check(rc, err)
        path = os.fsencode(data.path) if data.path else ffi.NULL
        text = ffi.new("char **")
        _check(lib.bf_select_json(s, path, text, err), err)
        selection = _take_text(text[0])
        fit = None
        if s.chosen >= 0:  # the chosen fit, as `brdfit select -o` writes it
            r = s.c[s.chosen].result
            _check(lib.bf_fit_result_json(r, path, text, err), err)
            m = Model._from_ptr(r.model)
            x = np.array(ffi.unpack(r.x, lib.bf_model_nvalues(r.model)))
            fit = FitResult(_take_text(text[0]), m, bool(r.ok), False, m._dict(x))
        return SelectResult(selection, fit)
    finally:
        lib.bf_select_free(s)


select.__doc__ = """Chooses the smallest model that serves, as `brdfit select`: fits every candidate
(models: a list of specs or one string as -m takes it; None: the library's default
candidates for the data's channel count) and chooses the one with the fewest free
parameters whose error is within the tolerance of the best. progress(iteration, cost)
sees every solve; returning True stops the selection. The options are brdfit select's, as
keywords:

""" + _doc("select")


# ---- Export -------------------------------------------------------------------------

def export(result: Union[FitResult, str, os.PathLike], to: str, path: Optional[Union[str, os.PathLike]] = None,
           convert: bool = False) -> str:
    """Writes a fit (a FitResult, or a result file) as a renderer's material, as `brdfit
    export`: to one of the library's targets ("gltf", "blender", "mitsuba"); convert=True
    converts any model (else only isotropic one-lobe ones). Writes path (atomically) and
    returns it, or returns the text when path is None."""
    t = lib.bf_export_target_find(_text("to", to).encode())
    if t == ffi.NULL:
        names = [_str(lib.bf_export_target_get(i).name) for i in range(lib.bf_export_target_count())]
        raise UsageError("to: %r is not a target (%s)" % (to, ", ".join(names)))
    err = ffi.new("bf_error *")
    m = ffi.new("bf_model **")
    x = ffi.new("double **")
    if isinstance(result, FitResult):
        _check(lib.bf_params_parse(result.to_json().encode(), b"the fit", m, x, err), err)
    elif isinstance(result, (str, os.PathLike)):
        _check(lib.bf_params_read(os.fsencode(_path_text(result)), m, x, err), err)
    else:
        raise UsageError("result: needs a brdfit.FitResult or a result file, got %s" % type(result).__name__)
    fit_r = ffi.new("bf_fit_result *")
    lib.bf_fit_result_init(fit_r)
    try:
        _check(lib.bf_export_check(t, m[0], int(_flag("convert", convert)), err), err)
        e = ffi.new("bf_export_material *")
        lib.bf_export_material_init(e)
        _check(lib.bf_export_prepare(t, m[0], x[0], e, fit_r, err), err)
        if path is not None:
            out = _path_text(path)
            _check(lib.bf_export_write(t, e, os.fsencode(out), err), err)
            return out
        text = ffi.new("char **")
        _check(lib.bf_export_text(t, e, text, err), err)
        return _take_text(text[0])
    finally:
        lib.bf_fit_result_clear(fit_r)
        lib.bf_model_free(m[0])
        lib.bf_free(x[0])
