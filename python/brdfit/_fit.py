"""Fitting: brdfit.fit and its result."""
from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Mapping, Optional, Union

import numpy as np

from ._brdfit import ffi, lib
from ._data import _prepared
from ._errors import Error, UsageError, _check, _take_text
from ._model import Model
from ._options import _doc, _Options
from ._run import CancelEvent, ProgressFn, _Run


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


def fit(samples: Any, model: Union[str, Model], progress: Optional[ProgressFn] = None,
        start: Optional[Mapping[str, Any]] = None, cancel: Optional[CancelEvent] = None, **options: Any) -> FitResult:
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
    if start is not None:
        x0 = Model(spec, data.channels)._vector(start)
        _check(lib.bf_options_set_start(opts.o, ffi.from_buffer("double[]", x0), x0.size, err), err, "start")
    data._ready()

    def call() -> FitResult:  # in the worker, which owns r (freed with it)
        r = ffi.gc(ffi.new("bf_fit_result *"), lib.bf_fit_result_clear)
        lib.bf_fit_result_init(r)
        _check(lib.bf_fit(data._s, spec.encode(), opts.o, r, err), err, spec)
        return _result(r, data.path)

    return run(call)


def _result(r, path: Optional[str]) -> FitResult:
    """A FitResult of the library's result r (a cancelled fit has no result text)."""
    m = Model._from_ptr(r.model)
    cancelled = r.solution.stop == lib.BF_STOP_CANCELLED
    x = np.array(ffi.unpack(r.x, lib.bf_model_nvalues(r.model)))
    text = None
    if not cancelled:
        err = ffi.new("bf_error *")
        out = ffi.new("char **")
        _check(lib.bf_fit_result_json(r, os.fsencode(path) if path else ffi.NULL, out, err), err)
        text = _take_text(out[0])
    return FitResult(text, m, bool(r.ok), cancelled, m._dict(x))


fit.__doc__ = """Fits model (a spec or a Model) to samples (brdfit.Samples, or a data file name), as
`brdfit fit` does. start (name -> value, as Model params take them) replaces the
data-driven start; a Model given parameters (a fit's .model) starts from them. The search
still adds its own starts unless starts=1. progress(brdfit.Progress) is called as the
fit goes (its phase, start of starts, iteration, cost, samples); returning True stops the
fit, and so does cancel (a threading.Event) once set: the result then says .cancelled
(stopped while still reading a data file: brdfit.Error, code "cancelled"). Ctrl-C stops
it and raises KeyboardInterrupt. The options are brdfit fit's, as keywords:

""" + _doc("fit") + """

With brdfit.Samples, the data options other than the reading ones apply to a copy of them
(preprocessing, scene, subsample)."""
