"""Data in: a file read and prepared, or given samples prepared, with the data options."""
from __future__ import annotations

import os
from typing import Any, Optional, TYPE_CHECKING, Union

from ._args import _path_text
from ._brdfit import ffi, lib
from ._errors import UsageError, _check
from ._options import _doc, _Options
from ._run import CancelEvent, _Run
from ._samples import Samples

if TYPE_CHECKING:  # the keywords' types, for type checkers only
    from typing import Unpack

    from ._keywords import ReadKeywords


def _load(path: Union[str, "os.PathLike[str]"], opts: _Options, run: _Run, report: Any = ffi.NULL) -> "Samples":
    """The file read and prepared in run's worker (run hooked to opts: its cancel flag
    stops the readers, Ctrl-C too); report (a bf_load_report *) gets what loading left out."""
    p = _path_text(path)
    name = os.fsencode(p)

    def call() -> "Samples":  # in the worker, which owns the samples until they are wrapped
        err = ffi.new("bf_error *")
        out = ffi.new("bf_samples **")
        _check(lib.bf_samples_load(name, opts.o, out, report, err), err)
        return Samples._wrap(out[0], p)

    return run(call)


def read(path: Union[str, "os.PathLike[str]"], cancel: Optional[CancelEvent] = None,
         **data_options: Unpack[ReadKeywords]) -> "Samples":
    if not isinstance(path, (str, os.PathLike)):
        raise UsageError("path: needs a file name, got %r" % (path,))
    opts = _Options("read", data_options, "read")
    run = _Run(None, cancel, "read")
    run.hook(opts)
    return _load(path, opts, run)


read.__doc__ = """Reads a data file (CSV, MERL .binary, Cornell, ALTA, RGL .bsdf, .mbsdf) and prepares
its samples as the command line does (read, preprocess, scene, subsample), with the data
options as keywords. cancel (a threading.Event) once set, or Ctrl-C, stops a long read:
brdfit.Error (code "cancelled"), or KeyboardInterrupt. The options:

""" + _doc("read")


def _prepared(x: Any, opts: _Options, what: str, run: _Run) -> "Samples":
    """Samples for a fit: a file loaded with the options (in run's worker), or a copy of
    given samples prepared with them (the preprocessing, scene and subsample;
    bf_samples_prepare)."""
    if isinstance(x, (str, os.PathLike)):
        return _load(x, opts, run)
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
