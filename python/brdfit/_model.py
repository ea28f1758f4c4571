"""Models: the library's model registry and a configured model to evaluate."""
from __future__ import annotations

import json
from typing import Any, Dict, List, Mapping, Optional

import numpy as np

from ._args import _array, _directions, _flag
from ._brdfit import ffi, lib
from ._errors import UsageError, _check, _take_text


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
