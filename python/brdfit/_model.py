"""Models: the library's model registry and a configured model to evaluate."""
from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Literal, Mapping, Optional, Sequence, Tuple, Union, overload

import numpy as np

from ._args import Array, _array, _path_text
from ._brdfit import ffi, lib
from ._errors import UsageError, _check, _take_text
from ._eval import Result, evaluate


def version() -> str:
    """The library's version, as `brdfit --version` says it."""
    return str(ffi.string(lib.bf_version()).decode())


def models() -> List[Dict[str, Any]]:
    """Every model family with its parameters, options and sizes: the "models" list of
    `brdfit models --json`."""
    p = lib.bf_models_json()
    if p == ffi.NULL:
        raise MemoryError("brdfit: out of memory")
    families: List[Dict[str, Any]] = json.loads(_take_text(p))["models"]
    return families


def _restore(spec: str, channels: int, params: Optional[Sequence[float]]) -> "Model":
    """A pickled Model made again (Model.__reduce__)."""
    m = Model(spec, channels)
    if params is not None:
        m._params = m._checked(params, "params")
    return m


class Model:
    """A configured model: `Model("walter", channels=3)`, or any spec `brdfit fit -m` takes
    ("microfacet:D=ggx,lobes=2"); params (name -> value) gives it parameters of its own,
    which eval uses where it is given none. `Model.from_file(path)` reads a result or
    parameter file. Models pickle (spec, channels and parameters), so they pass to the
    processes of a ProcessPoolExecutor; two are equal when their canonical specs,
    channels and parameters (bit for bit, or both none) are."""

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
    def _from_ptr(cls, m: Any) -> "Model":
        return cls(ffi.string(lib.bf_model_spec(m)).decode(), lib.bf_model_channels(m))

    @classmethod
    def from_file(cls, path: Union[str, bytes, "os.PathLike[Any]"]) -> "Model":
        """The model of a result file (`brdfit fit -o`) or a parameter file, holding its
        parameters (the library's reader: every parameter given, inside its bounds)."""
        if not isinstance(path, (str, bytes, os.PathLike)):
            raise UsageError("path: needs a file name, got %r" % (path,))
        p = _path_text(path)
        err = ffi.new("bf_error *")
        out = ffi.new("bf_model **")
        x = ffi.new("double **")
        _check(lib.bf_params_read(os.fsencode(p), out, x, err), err)
        m = cls.__new__(cls)
        m._m = ffi.gc(out[0], lib.bf_model_free)
        try:
            m._params = np.array(ffi.unpack(x[0], lib.bf_model_nvalues(out[0])), dtype=np.float64)
        finally:
            lib.bf_free(x[0])
        return m

    def __reduce__(self) -> Tuple[Any, Tuple[Any, ...]]:
        return _restore, (self.spec, self.channels, None if self._params is None else self._params.tolist())

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Model):
            return NotImplemented
        a, b = self._params, other._params
        same = (a is None and b is None) or (a is not None and b is not None and bool(np.array_equal(a, b)))
        return same and self.channels == other.channels and self.spec == other.spec

    def __hash__(self) -> int:
        return hash((self.spec, self.channels, None if self._params is None else tuple(self._params.tolist())))

    @property
    def spec(self) -> str:
        """The canonical spec, every option written out."""
        return str(ffi.string(lib.bf_model_spec(self._m)).decode())

    @property
    def name(self) -> str:
        """The family's name ("walter")."""
        return str(ffi.string(lib.bf_model_name(self._m)).decode())

    @property
    def channels(self) -> int:
        return int(lib.bf_model_channels(self._m))

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

    def _color(self, i: int) -> bool:
        return bool(lib.bf_model_param(self._m, i).color)

    def _find(self, key: Any) -> int:
        """The index of parameter key; a UsageError naming the model's parameters if none."""
        i = lib.bf_model_find_param(self._m, key.encode()) if isinstance(key, str) and "\0" not in key else -1
        if i < 0:
            raise UsageError("params: %s has no parameter %r (it has %s)" % (self.spec, key,
                                                                              ", ".join(self.param_names)))
        return int(i)

    @property
    def defaults(self) -> Dict[str, Any]:
        """Each parameter's default value (a list of channels values for a colour)."""
        x = np.empty(lib.bf_model_nvalues(self._m))
        lib.bf_model_defaults(self._m, ffi.from_buffer("double[]", x))
        return self._dict(x)

    @property
    def bounds(self) -> Dict[str, Tuple[float, float]]:
        """Each parameter's bounds (lo, hi), the library's (brdfit.models() also says which
        of them are open, that is excluded)."""
        out: Dict[str, Tuple[float, float]] = {}
        for i in range(lib.bf_model_nparams(self._m)):
            p = lib.bf_model_param(self._m, i)
            out[ffi.string(p.name).decode()] = (float(p.lo), float(p.hi))
        return out

    def vector(self, params: Optional[Mapping[str, Any]] = None) -> Array:
        """The model vector (nvalues,) in the order of value_names: params (name -> value,
        as eval takes one set) over the model's own parameters (else the defaults),
        checked against the bounds."""
        return self._vector(params, self._params)

    def params_from(self, vector: Any) -> Dict[str, Any]:
        """The parameters (name -> float, or a list of channels floats for a colour) of a
        model vector (nvalues,), checked against the bounds: vector's inverse."""
        return self._dict(self._checked(vector, "vector"))

    def _checked(self, vector: Any, what: str) -> Array:
        x = _array(what, vector, [(lib.bf_model_nvalues(self._m),)])
        err = ffi.new("bf_error *")
        _check(lib.bf_model_check(self._m, ffi.from_buffer("double[]", x), err), err, what, usage=True)
        return x

    @property
    def params(self) -> Optional[Dict[str, Any]]:
        """The parameters this model was given (a fit's result: the fitted ones), or None."""
        return None if self._params is None else self._dict(self._params)

    def _dict(self, x: Array) -> Dict[str, Any]:
        out: Dict[str, Any] = {}
        C = self.channels
        for i in range(lib.bf_model_nparams(self._m)):
            o = lib.bf_model_param_offset(self._m, i)
            name = ffi.string(lib.bf_model_param(self._m, i).name).decode()
            out[name] = [float(v) for v in x[o:o + C]] if self._color(i) else float(x[o])
        return out

    def _vector(self, params: Optional[Mapping[str, Any]], base: Optional[Array] = None) -> Array:
        """The model vector: base (else the defaults) with params over them, checked
        against the bounds."""
        x = np.empty(lib.bf_model_nvalues(self._m))
        if base is not None:
            x[:] = base
        else:
            lib.bf_model_defaults(self._m, ffi.from_buffer("double[]", x))
        if params is None:
            return x
        if not isinstance(params, Mapping):
            raise UsageError("params: needs a dict of parameter name -> value, got %s" % type(params).__name__)
        C = self.channels
        for key, value in params.items():
            i = self._find(key)
            o = lib.bf_model_param_offset(self._m, i)
            n = C if self._color(i) else 1
            v = _array("params[%r]" % key, value, [(), (n,)]).reshape(-1)
            x[o:o + n] = v if v.size == n else np.repeat(v, n)
        err = ffi.new("bf_error *")
        _check(lib.bf_model_check(self._m, ffi.from_buffer("double[]", x), err), err, "params", usage=True)
        return x

    @overload
    def eval(self, wi: Any, wo: Any, params: Optional[Mapping[str, Any]] = None,
             gradient: Literal[False] = False) -> Array: ...

    @overload
    def eval(self, wi: Any, wo: Any, params: Optional[Mapping[str, Any]] = None, *,
             gradient: Literal[True, "channel"]) -> Tuple[Array, Array]: ...

    @overload
    def eval(self, wi: Any, wo: Any, params: Optional[Mapping[str, Any]],
             gradient: Literal[True, "channel"]) -> Tuple[Array, Array]: ...

    def eval(self, wi: Any, wo: Any, params: Optional[Mapping[str, Any]] = None,
             gradient: Union[bool, str] = False) -> Result:
        """The BRDF (1/sr) at direction pairs: wi, wo unit vectors (towards the light and the
        viewer, z the normal), each (n, 3) or one (3,); one direction goes with all n of the
        other. Returns (n, channels) values, (channels,) for one (3,) pair.

        params: name -> value (a sequence of channels values for a colour parameter);
        missing ones take the model's own (a fit's result: the fitted values; else the
        defaults). K parameter sets in one call: a scalar parameter as shape (K,), a colour
        one as (K, channels) (or (K, 1): one value for every channel); the result gains a
        first axis K.

        gradient=True also returns the analytic Jacobian, (n, channels, len(value_names)):
        d value[c] / d each entry of the model vector. gradient="channel" returns instead
        (n, channels, len(param_names)): d value[c] / d each parameter, a colour
        parameter's entry for channel c (what a channel's own fit needs), with no
        (n, channels, nvalues) block, for many channels."""
        return evaluate(self, wi, wo, params, gradient)

    def __repr__(self) -> str:
        held = "" if self._params is None else ", params=..."
        return "brdfit.Model(%r, channels=%d%s)" % (self.spec, self.channels, held)
