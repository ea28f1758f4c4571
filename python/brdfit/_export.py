"""Export: a fit as a renderer's material."""
from __future__ import annotations

import os
from typing import Optional, Union

from ._args import _flag, _path_text, _text
from ._brdfit import ffi, lib
from ._errors import UsageError, _check, _str, _take_text
from ._fit import FitResult


def export(result: Union[FitResult, str, "os.PathLike[str]"], to: str, path: Optional[Union[str, "os.PathLike[str]"]] = None,
           convert: bool = False) -> str:
    """Writes a fit (a FitResult, or a result file) as a renderer's material, as `brdfit
    export`: to one of the library's targets ("gltf", "blender", "mitsuba"); convert=True
    converts any model (else only isotropic one-lobe ones). Writes path (atomically) and
    returns it, or returns the text when path is None."""
    t = lib.bf_export_target_find(_text("to", to).encode())
    if t == ffi.NULL:
        names = [ffi.string(lib.bf_export_target_get(i).name).decode() for i in range(lib.bf_export_target_count())]
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
