"""Cost against accuracy: brdfit.tradeoff and its result."""
from __future__ import annotations

import json
import os
from typing import Any, Dict, List, Optional, TYPE_CHECKING, Union

from ._args import _path_text
from ._brdfit import ffi, lib
from ._data import _prepared
from ._errors import _check, _take_text
from ._fit import _spec_of
from ._model import Model
from ._options import _doc, _Options
from ._run import CancelEvent, ProgressFn, _Run

if TYPE_CHECKING:  # the keywords' types, for type checkers only
    from typing import Unpack

    from ._keywords import TradeoffKeywords


class TradeoffResult:
    """A tradeoff: .rows (one dict per setting, in the table's order, as `brdfit tradeoff
    --json` writes them), .recommended (the cheapest setting within the tolerance of the
    best, one of .rows; None when no setting fitted), .best (the lowest test error), .command
    (the recommended setting as a `brdfit fit` command line, or None), .json (all of it) and
    .to_json() (its text); .write_plot(path) draws test error against cost as `--plot`."""

    def __init__(self, text: str, command: Optional[str], table: Any):
        self._text = text
        self._table = table  # the library's table (ffi.gc), for the plot
        self.json: Dict[str, Any] = json.loads(text)
        self.rows: List[Dict[str, Any]] = list(self.json["rows"])
        self.recommended: Optional[Dict[str, Any]] = self.rows[table.recommended] if table.recommended >= 0 else None
        self.best: Optional[Dict[str, Any]] = self.rows[table.best] if table.best >= 0 else None
        self.command = command

    def to_json(self) -> str:
        """The table's text, as `brdfit tradeoff DATA -m MODEL --json FILE` writes it."""
        return self._text

    def write_plot(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Test error against fitting cost with the Pareto front, as `brdfit tradeoff --plot`
        draws it: PNG, SVG or PDF by the name's extension, plot_size= as its size."""
        p = _path_text(path)
        err = ffi.new("bf_error *")
        t = self._table
        _check(lib.bf_tradeoff_write_plot(t, os.fsencode(p), lib.BF_PLOT_BY_NAME, t.plot_width, t.plot_height,
                                          ffi.NULL, err), err)

    def __repr__(self) -> str:
        return "brdfit.TradeoffResult(%d settings, recommended=%r)" % (
            len(self.rows), None if self.recommended is None else self.command)


def tradeoff(samples: Any, model: Union[str, Model], /, progress: Optional[ProgressFn] = None,
             cancel: Optional[CancelEvent] = None, **options: Unpack[TradeoffKeywords]) -> TradeoffResult:
    spec = _spec_of(model, "model")
    opts = _Options("tradeoff", options, "tradeoff")
    opts.check([spec])
    run = _Run(progress, cancel, "tradeoff", partial=True)
    run.hook(opts)  # reading the data file too
    data = _prepared(samples, opts, "samples", run)
    data._ready()

    def call() -> TradeoffResult:  # in the worker, which owns the table
        err = ffi.new("bf_error *")
        out = ffi.new("bf_tradeoff **")
        name = os.fsencode(data.path) if data.path else ffi.NULL
        _check(lib.bf_tradeoff_run(data._s, name, spec.encode(), opts.o, ffi.NULL, ffi.NULL, out, err), err)
        t = ffi.gc(out[0], lib.bf_tradeoff_free)
        text = ffi.new("char **")
        _check(lib.bf_tradeoff_json(t, text, err), err)
        table = _take_text(text[0])
        command = None
        if t.recommended >= 0:
            _check(lib.bf_tradeoff_fit_command(t, t.recommended, text, err), err)
            command = _take_text(text[0])
        return TradeoffResult(table, command, t)

    result: TradeoffResult = run(call)
    return result


tradeoff.__doc__ = """Measures fitting cost against accuracy, as `brdfit tradeoff` does: holds out a seeded
test share of samples (brdfit.Samples, or a data file name), fits model (a spec or a
Model) to the rest under every combination of sample count, method, residual form and
start count, judges each on the held-out samples, and recommends the cheapest setting
within the tolerance of the best. samples and model are positional (samples= is the
option). progress(brdfit.Progress) sees every solve; returning True, or cancel (a
threading.Event) once set, stops the run: the fit then running says "failed", the rest
"not_run", and nothing is recommended. The
options are brdfit tradeoff's, as keywords (a list may be given as a Python list:
samples=[1000, "all"]):

""" + _doc("tradeoff")
