"""Selecting: brdfit.select and its result."""
from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Optional, Sequence, TYPE_CHECKING, Tuple, Union

from ._brdfit import ffi, lib
from ._compare import _model_list
from ._data import _prepared
from ._errors import _check, _take_text
from ._fit import FitResult, _result
from ._frames import frame
from ._options import _doc, _Options
from ._run import CancelEvent, ProgressFn, _Run

if TYPE_CHECKING:  # the keywords' types, for type checkers only
    from typing import Unpack

    from ._keywords import SelectKeywords


class SelectResult:
    """A selection: .chosen (the chosen spec, or None when nothing could be fitted), .fit
    (its FitResult), .candidates (one dict per candidate model, as `brdfit select --json`
    writes it: "spec", "k" the free parameters, "error", "chosen", its "metrics",
    "params", ...), .to_dataframe() (the candidates as a pandas DataFrame), .json (every
    candidate and the choice) and .to_json() (that text). It pickles (as its JSON text
    and its fit's)."""

    def __init__(self, text: str, fit: Optional[FitResult]):
        self._text = text
        self.json: Dict[str, Any] = json.loads(text)
        self.fit = fit
        self.chosen: Optional[str] = fit.spec if fit is not None else None
        self.candidates: List[Dict[str, Any]] = list(self.json["candidates"])

    def to_json(self) -> str:
        return self._text

    def to_dataframe(self) -> Any:
        """The candidates as a pandas DataFrame, one row each in .candidates' order:
        "data" (the data's name), then the candidate's fields with its "metrics" spread
        into columns of their own ("rmse_log", "bic", ...; one a candidate field already
        names is "metrics_" + its name: "metrics_k", the k of the criteria). Numbers are
        float64 columns with NaN where the JSON has null; "params" and "stderr" are
        columns of dicts (name -> float, a list per channel for a colour; None for a
        candidate that did not run). ImportError without pandas."""
        records = []
        for c in self.candidates:
            rec: Dict[str, Any] = {"data": self.json.get("data")}
            for k, v in c.items():
                if k == "metrics":
                    for mk, mv in (v or {}).items():
                        rec["metrics_" + mk if mk in c else mk] = mv
                else:
                    rec[k] = v
            records.append(rec)
        return frame(records, nested=("params", "stderr"))

    def __reduce__(self) -> Tuple[Any, ...]:
        return (SelectResult, (self._text, self.fit))

    def __repr__(self) -> str:
        return "brdfit.SelectResult(chosen=%r)" % (self.chosen,)


def select(samples: Any, models: Optional[Union[str, Sequence[Any]]] = None, progress: Optional[ProgressFn] = None,
           cancel: Optional[CancelEvent] = None, **options: Unpack[SelectKeywords]) -> SelectResult:
    opts = _Options("select", options, "select")
    run = _Run(progress, cancel, "select")
    run.hook(opts)  # reading the data file too
    data = _prepared(samples, opts, "samples", run)
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

    def call() -> SelectResult:  # in the worker, which owns the selection
        err = ffi.new("bf_error *")
        out = ffi.new("bf_select **")
        cspecs = [ffi.new("char[]", m.encode()) for m in specs]
        _check(lib.bf_select_new(len(cspecs), cspecs, data.channels, opts.o, out, err), err)
        s = ffi.gc(out[0], lib.bf_select_free)
        _check(lib.bf_select_run(s, data._s, opts.o, ffi.NULL, ffi.NULL, err), err)
        text = ffi.new("char **")
        _check(lib.bf_select_json(s, os.fsencode(data.path) if data.path else ffi.NULL, text, err), err)
        selection = _take_text(text[0])
        # The chosen fit, as `brdfit select -o` writes it.
        fit = _result(s.c[s.chosen].result, data) if s.chosen >= 0 else None
        return SelectResult(selection, fit)

    result: SelectResult = run(call)
    return result


select.__doc__ = """Chooses the smallest model that serves, as `brdfit select`: fits every candidate
(models: a list of specs or one string as -m takes it; None: the library's default
candidates for the data's channel count) and chooses the one with the fewest free
parameters whose error is within the tolerance of the best. progress(brdfit.Progress)
sees every fit's progress (.model: the candidate's spec); returning True, or cancel (a
threading.Event) once set, stops the selection, which then raises brdfit.Error (code
"cancelled"). The options are brdfit select's, as keywords:

""" + _doc("select")
