"""Comparing: brdfit.compare and its result."""
from __future__ import annotations

import json
import os
from typing import Any, Dict, Iterable, List, Optional, Sequence, TYPE_CHECKING, Tuple, Union

from ._brdfit import ffi, lib
from ._data import _prepared
from ._errors import UsageError, _check, _take_text
from ._fit import _spec_of
from ._frames import frame
from ._model import Model
from ._options import _doc, _Options
from ._run import CancelEvent, ProgressFn, _Run
from ._samples import Samples

if TYPE_CHECKING:  # the keywords' types, for type checkers only
    from typing import Unpack

    from ._keywords import CompareKeywords


class CompareResult:
    """A comparison: .rows (one dict per material x model: "data" and the fit's fields of
    `brdfit compare --json`, as it writes them), .to_dataframe() (the rows as a pandas
    DataFrame), .json (all of it) and .to_json() (its text). It pickles (as its text)."""

    def __init__(self, text: str):
        self._text = text
        self.json: Dict[str, Any] = json.loads(text)
        self.rows: List[Dict[str, Any]] = [dict(f, data=mat["data"]) for mat in self.json["materials"]
                                           for f in mat["fits"]]

    def to_json(self) -> str:
        return self._text

    def to_dataframe(self) -> Any:
        """The rows as a pandas DataFrame, one row per material x model in .rows' order:
        "data" (the data's name) first, then the fit's fields ("model", "spec", "status",
        "rank", the criteria and metrics ...). Numbers are float64 columns with NaN where
        the JSON has null (a criterion a robust loss leaves undefined, a fit that did not
        run; a column with no value at all is NaN throughout); "params" and "stderr" are
        columns of dicts (name -> float, a list per channel for a colour; None for a fit
        that did not run: `pandas.json_normalize(df["params"].tolist())` spreads them
        into columns); "warnings" a column of lists. ImportError without pandas."""
        return frame([dict({"data": r["data"]}, **r) for r in self.rows], nested=("params", "stderr"))

    def __reduce__(self) -> Tuple[Any, ...]:
        return (CompareResult, (self._text,))

    def __repr__(self) -> str:
        mats = self.json["materials"]
        return "brdfit.CompareResult(materials=%d, models=%r, best=%r)" % (
            len(mats), self.json["models"], [m.get("best") for m in mats])


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


def compare(samples_list: Sequence[Any], models: Union[str, Sequence[Any]], progress: Optional[ProgressFn] = None,
            cancel: Optional[CancelEvent] = None, **options: Unpack[CompareKeywords]) -> CompareResult:
    if isinstance(samples_list, (Samples, str, os.PathLike)) or not isinstance(samples_list, Iterable):
        raise UsageError("samples_list: needs a list of brdfit.Samples (or data file names)")
    samples_list = list(samples_list)
    if not samples_list:
        raise UsageError("samples_list: needs at least one sample set")
    specs = _model_list(models)
    opts = _Options("compare", options, "compare")
    opts.check(specs)
    run = _Run(progress, cancel, "compare")
    run.hook(opts)  # reading the data files too
    data = [_prepared(x, opts, "samples_list[%d]" % i, run) for i, x in enumerate(samples_list)]
    for d in data:
        d._ready()
    names = [os.fsencode(d.path or "samples %d" % i) for i, d in enumerate(data)]

    def call() -> CompareResult:  # in the worker, which owns the comparison
        err = ffi.new("bf_error *")
        out = ffi.new("bf_compare **")
        keep = [ffi.new("char[]", n) for n in names]
        cspecs = [ffi.new("char[]", m.encode()) for m in specs]
        _check(lib.bf_compare_new(len(data), keep, len(cspecs), cspecs, out, err), err)
        c = ffi.gc(out[0], lib.bf_compare_free)
        ptrs = ffi.new("bf_samples *[]", [d._s for d in data])
        _check(lib.bf_compare_run(c, ptrs, opts.o, ffi.NULL, ffi.NULL, err), err)
        lib.bf_compare_rank(c)
        text = ffi.new("char **")
        _check(lib.bf_compare_json(c, text, err), err)
        return CompareResult(_take_text(text[0]))

    result: CompareResult = run(call)
    return result


compare.__doc__ = """Fits every model to every sample set and ranks them, as `brdfit compare`: models is a
list of specs, or one string as -m takes it ("lambert,walter", "all"); samples_list holds
brdfit.Samples or data file names. progress(brdfit.Progress) sees every fit's progress
(.material: the index in samples_list, .model: the spec; with jobs > 1 from several
threads); returning True, or cancel (a threading.Event) once set, stops the comparison,
which then raises brdfit.Error (code "cancelled"). The options are brdfit compare's, as
keywords:

""" + _doc("compare")
