"""Fitting: brdfit.fit and its result."""
from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, TYPE_CHECKING, Tuple, Union

import numpy as np
import numpy.typing as npt

from ._args import Array, _path_text
from ._brdfit import ffi, lib
from ._data import _prepared
from ._errors import Error, UsageError, _check, _take_text
from ._frames import NAN, floats
from ._model import Model
from ._options import _doc, _Options
from ._run import CancelEvent, ProgressFn, _Run
from ._samples import Samples

if TYPE_CHECKING:  # the keywords' types, for type checkers only
    from typing import Unpack

    from ._keywords import FitKeywords

# Residuals computed per call of the objective: a short call each, so that Ctrl-C is
# seen between them on a large data set (the objective has no cancel flag).
_RESIDUAL_CHUNK = 1 << 16


class FitResult:
    """A fit: .params and .stderr (name -> float, a list per channel for a colour; a
    standard error the data do not determine is NaN), .metrics (name -> float, NaN where
    undefined), .warnings, .ok, .cancelled, .model (a Model holding the fitted
    parameters, to evaluate), .covariance, .residuals(), .json (the result as the library
    wrote it) and .to_json() (the text `brdfit fit -o` writes). FitResult.from_json reads
    a saved result back; a FitResult pickles (as its JSON text and covariance)."""

    def __init__(self, text: Optional[str], model: Model, x: npt.NDArray[np.float64], ok: bool, cancelled: bool,
                 samples: Optional[Samples] = None, covariance: Optional[Array] = None):
        self._text = text
        self.json: Dict[str, Any] = json.loads(text) if text else {}
        self.ok = ok
        self.cancelled = cancelled
        self.model = model
        self.model._params = x
        # The model vector as names: floats, exactly the numbers the result file holds.
        self.params: Dict[str, Any] = model._dict(x)
        if text:
            self.stderr: Dict[str, Any] = floats(self.json.get("stderr", {}))
            self.metrics: Dict[str, Any] = floats(self.json.get("metrics", {}))
        else:  # cancelled: no standard errors, and the library computed no metrics
            self.stderr = {k: [NAN] * len(v) if isinstance(v, list) else NAN for k, v in self.params.items()}
            self.metrics = {}
        self.warnings: List[str] = self.json.get("warnings", ["the fit was cancelled"] if cancelled else [])
        self._samples = samples
        # (nvalues, nvalues) in value_names order, the library's (bf_fit_result.covariance):
        # NaN in an undetermined entry's row and column, 0 in a fixed one's; None when the
        # library gave none (cancelled, or read from JSON, which does not hold it).
        self.covariance = covariance
        if covariance is not None:
            covariance.flags.writeable = False

    @classmethod
    def from_json(cls, text_or_path: Union[str, "os.PathLike[str]"]) -> "FitResult":
        """A result saved by `.to_json()` or `brdfit fit -o`: its text (a str starting
        with "{") or its file name. The model and its parameters are the library's reading
        of it (bf_params_parse, bf_params_read, as `brdfit eval` reads it), so the result
        evaluates, exports and writes (.to_json(): the same text) as the saved one. It has
        no samples: .residuals() then needs them."""
        err = ffi.new("bf_error *")
        m = ffi.new("bf_model **")
        xp = ffi.new("double **")
        if isinstance(text_or_path, str) and text_or_path.lstrip().startswith("{"):
            text = text_or_path
            if "\0" in text:
                raise UsageError("text_or_path: a NUL character cannot be in a result's text")
            # A text the library made holds a non-UTF-8 file name as Python decodes it
            # (surrogateescape, _take_text): its bytes again here.
            rc = lib.bf_params_parse(text.encode("utf-8", "surrogateescape"), b"the result", m, xp, err)
        elif isinstance(text_or_path, (str, os.PathLike)):
            path = _path_text(text_or_path)
            rc = lib.bf_params_read(os.fsencode(path), m, xp, err)
            text = None
        else:
            raise UsageError("text_or_path: needs a result's JSON text or its file name, got %r" % (text_or_path,))
        try:
            _check(rc, err, "" if text is not None else path)
            model = Model._from_ptr(m[0])
            x = np.array(ffi.unpack(xp[0], lib.bf_model_nvalues(m[0])))
        finally:
            lib.bf_model_free(m[0])
            lib.bf_free(xp[0])
        if text is None:  # the library read it; the text is kept as it is, byte for byte
            with open(os.fsencode(path), encoding="utf-8", errors="surrogateescape", newline="") as f:
                text = f.read()
        try:
            data = json.loads(text)
        except ValueError as e:  # what the library's reader takes and JSON does not
            raise Error("the result: not JSON (%s)" % e, "parse") from None
        if not isinstance(data.get("metrics"), dict) or "ok" not in data:
            raise UsageError("text_or_path: a parameter file, not a fit's result (no metrics): "
                             "brdfit.Model(spec, channels, params) takes its parameters")
        return cls(text, model, x, bool(data["ok"]), False)

    @property
    def spec(self) -> str:
        return self.model.spec

    def to_json(self) -> str:
        """The result file's text, as `brdfit fit DATA -m MODEL -o FILE` writes it."""
        if self._text is None:
            raise Error("the fit was cancelled: no result to write", "arg")
        return self._text

    def residuals(self, samples: Optional[Samples] = None) -> npt.NDArray[np.float64]:
        """The fit's residuals, (n, channels), in the form it was fitted in (.json
        ["residual"]: linear f - m, log ln(1 + f c) - ln(1 + m c), ...; objective.h), at
        the fitted parameters, computed by the library's objective: for the samples the
        fit was fitted to (as prepared for it), or for the given brdfit.Samples. Without
        the data's own weights or solid-angle weights (as .metrics: a log fit's
        sqrt(mean(r**2)) is .metrics["rmse_log"]); a scene's weights, which the library
        always applies, multiply them by sqrt(weight). Samples below the horizon have 0.
        A robust loss is not applied (the residuals it was applied to)."""
        if samples is None:
            if self._samples is None:
                raise UsageError("samples: this result has no samples (it was read from JSON or unpickled, or "
                                 "cancelled): give the brdfit.Samples to compute its residuals at")
            s = self._samples
        elif isinstance(samples, Samples):
            s = samples
        else:
            raise UsageError("samples: needs brdfit.Samples or None, got %s" % type(samples).__name__)
        if self._text is None:
            raise Error("the fit was cancelled: it has no fitted parameters", "arg")
        err = ffi.new("bf_error *")
        oo = ffi.new("bf_objective_options *")
        lib.bf_objective_options_init(oo)
        form = self.json.get("residual")
        if not isinstance(form, str):
            raise Error("the result names no residual form (its \"residual\")", "parse")
        _check(lib.bf_residual_parse(form.encode(), ffi.addressof(oo, "residual"), err), err, "residual")
        oo.use_weights = 0
        oo.solid_angle = 0
        s._ready()
        out = ffi.new("bf_objective **")
        _check(lib.bf_objective_new(self.model._m, s._s, oo, out, err), err, "samples")
        obj = ffi.gc(out[0], lib.bf_objective_free)
        p = lib.bf_objective_problem(obj)
        z = np.empty(lib.bf_objective_nz(obj) + 1)  # internal vector: all entries free here
        x = ffi.from_buffer("double[]", self.model._params)
        lib.bf_objective_to_internal(obj, x, ffi.from_buffer("double[]", z))
        nres = int(p.nres)
        res = np.empty(nres)
        zp, rp = ffi.from_buffer("double[]", z), ffi.from_buffer("double[]", res)
        for r0 in range(0, nres, _RESIDUAL_CHUNK):
            r1 = min(r0 + _RESIDUAL_CHUNK, nres)
            if p.eval(p.user, zp, r0, r1, rp + r0, ffi.NULL) != 0:
                raise MemoryError("brdfit: out of memory computing residuals")
        return res.reshape(s.n, s.channels)

    def __reduce__(self) -> Tuple[Any, ...]:
        """Pickled as its JSON text (a cancelled fit: its spec and start)."""
        if self._text is not None:
            return (_unpickled, (self._text, self.covariance))
        return (_cancelled, (self.spec, self.model.channels, self.params))

    def __repr__(self) -> str:
        return "brdfit.FitResult(%r, ok=%s, rmse_log=%s)" % (self.spec, self.ok, self.metrics.get("rmse_log", NAN))


def _unpickled(text: str, covariance: Optional[Array]) -> FitResult:
    r = FitResult.from_json(text)
    if covariance is not None:
        r.covariance = np.array(covariance)
        r.covariance.flags.writeable = False
    return r


def _cancelled(spec: str, channels: int, params: Dict[str, Any]) -> FitResult:
    m = Model(spec, channels)
    return FitResult(None, m, m._vector(params), False, True)


def _spec_of(model: Any, what: str) -> str:
    spec = model.spec if isinstance(model, Model) else model
    if not isinstance(spec, str) or "\0" in spec:
        raise UsageError("%s: needs a model spec or brdfit.Model, got %r" % (what, model))
    return spec


def fit(samples: Any, model: Union[str, Model], progress: Optional[ProgressFn] = None,
        start: Union[None, Mapping[str, Any], Model, Sequence[float], Array] = None,
        cancel: Optional[CancelEvent] = None, **options: Unpack[FitKeywords]) -> FitResult:
    spec = _spec_of(model, "model")
    opts = _Options("fit", options, "fit")
    opts.check([spec])
    run = _Run(progress, cancel, "fit", partial=True)
    run.hook(opts)  # reading the data file too
    data = _prepared(samples, opts, "samples", run)
    # The start: start= (name -> value), else the parameters a Model was given (a fit's
    # result), for the data's channels.
    if isinstance(model, Model) and model.channels != data.channels:
        raise UsageError("model: %s has %d channels, the data %d" % (spec, model.channels, data.channels))
    if start is None and isinstance(model, Model) and model._params is not None:
        start = model.params
    err = ffi.new("bf_error *")
    if start is not None:  # names -> values, a Model holding parameters, or the model vector
        m0 = Model(spec, data.channels)
        if isinstance(start, Model):
            if start._params is None:
                raise UsageError("start: %r holds no parameters" % (start,))
            start = start.params
        x0 = m0._vector(start) if isinstance(start, Mapping) else m0._checked(start, "start")
        _check(lib.bf_options_set_start(opts.o, ffi.from_buffer("double[]", x0), x0.size, err), err, "start")
    data._ready()

    def call() -> FitResult:  # in the worker, which owns r (freed with it)
        r = ffi.gc(ffi.new("bf_fit_result *"), lib.bf_fit_result_clear)
        lib.bf_fit_result_init(r)
        _check(lib.bf_fit(data._s, spec.encode(), opts.o, r, err), err, spec)
        return _result(r, data)

    result: FitResult = run(call)
    return result


def _result(r: Any, data: Samples) -> FitResult:
    """A FitResult of the library's result r, fitted to data (a cancelled fit has no
    result text)."""
    m = Model._from_ptr(r.model)
    cancelled = r.solution.stop == lib.BF_STOP_CANCELLED
    x = np.array(ffi.unpack(r.x, lib.bf_model_nvalues(r.model)))
    text = None
    if not cancelled:
        err = ffi.new("bf_error *")
        out = ffi.new("char **")
        _check(lib.bf_fit_result_json(r, os.fsencode(data.path) if data.path else ffi.NULL, out, err), err)
        text = _take_text(out[0])
    cov = None
    if r.covariance != ffi.NULL:
        P = x.size
        cov = np.array(ffi.unpack(r.covariance, P * P)).reshape(P, P)
    return FitResult(text, m, x, bool(r.ok), cancelled, None if cancelled else data, cov)


fit.__doc__ = """Fits model (a spec or a Model) to samples (brdfit.Samples, or a data file name), as
`brdfit fit` does. start (name -> value, as Model params take them; a Model holding
parameters; or the model vector in value_names order) replaces the data-driven start; a
Model given as model with parameters (a fit's .model) starts from them. The search
still adds its own starts unless starts=1. progress(brdfit.Progress) is called as the
fit goes (its phase, start of starts, iteration, cost, samples); returning True stops the
fit, and so does cancel (a threading.Event) once set: the result then says .cancelled
(stopped while still reading a data file: brdfit.Error, code "cancelled"). Ctrl-C stops
it and raises KeyboardInterrupt. The options are brdfit fit's, as keywords:

""" + _doc("fit") + """

With brdfit.Samples, the data options other than the reading ones apply to a copy of them
(preprocessing, scene, subsample)."""
