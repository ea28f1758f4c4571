"""Data in: a file read and prepared, or given samples prepared, with the data options."""
from __future__ import annotations

import os
from typing import Any, Union

from ._args import _path_text
from ._brdfit import ffi, lib
from ._errors import UsageError, _check
from ._options import _doc, _Options
from ._samples import Samples


def _load(path: Union[str, os.PathLike], opts: _Options, report: Any = ffi.NULL) -> "Samples":
    """The samples of path; report (a bf_load_report *) gets what loading left out."""
    p = _path_text(path)
    err = ffi.new("bf_error *")
    out = ffi.new("bf_samples **")
    _check(lib.bf_samples_load(os.fsencode(p), opts.o, out, report, err), err)
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
