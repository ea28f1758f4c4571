"""Pictures as arrays: a lit sphere and the half/difference image of a model or a MERL
table (brdfit/render.h), the linear values `brdfit render` writes to an EXR."""
from __future__ import annotations

import os
from typing import Any, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import NDArray

from ._args import _path_text
from ._brdfit import ffi, lib
from ._errors import UsageError, _check
from ._fit import FitResult
from ._model import Model
from ._samples import Samples

Source = Union[Model, FitResult, Samples, str, "os.PathLike[str]"]


def _int(name: str, v: Any, ctype: str = "int") -> int:
    """An integer that a C ctype holds (the library says which of those values it takes)."""
    if isinstance(v, bool) or not isinstance(v, (int, np.integer)):
        raise UsageError("%s: needs an integer, got %r" % (name, v))
    try:
        ffi.new(ctype + " *", int(v))
    except OverflowError:
        raise UsageError("%s: %d is out of range" % (name, int(v))) from None
    return int(v)


def _number(name: str, v: Any) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
        raise UsageError("%s: needs a number, got %r" % (name, v))
    return float(v)


def _dir(name: str, v: Any) -> Tuple[float, float]:
    """(theta, phi) in degrees, as --light and --view take them (the library checks that
    they are finite directions)."""
    if isinstance(v, (str, bytes)) or not isinstance(v, (tuple, list, np.ndarray)) or len(v) != 2:
        raise UsageError("%s: needs (theta, phi) in degrees, got %r" % (name, v))
    return _number(name, v[0]), _number(name, v[1])


def _model_of(source: Source, params: Any) -> Tuple[Any, NDArray[np.float64]]:
    """The library model (owned by the source or freed with the returned cdata) and its
    vector, of a Model (its own parameters, params over them), a FitResult (its fitted
    model) or a parameter file (as --params reads it)."""
    if isinstance(source, FitResult):
        source = source.model
    if isinstance(source, Model):
        base = source.params or {}
        base.update(params or {})
        return source._m, source._vector(base)
    if params is not None:
        raise UsageError("params: only with a brdfit.Model (a parameter file holds its own)")
    err = ffi.new("bf_error *")
    m = ffi.new("bf_model **")
    x = ffi.new("double **")
    _check(lib.bf_params_read(os.fsencode(_path_text(source)), m, x, err), err)
    model = ffi.gc(m[0], lib.bf_model_free)
    try:
        vec = np.array(ffi.unpack(x[0], lib.bf_model_nvalues(model)))
    finally:
        lib.bf_free(x[0])
    return model, vec


def _sphere_options(resolution: Optional[int], view: Any, lights: Any) -> Tuple[Any, Any]:
    """bf_sphere_options at the library's defaults (bf_sphere_options_init), with what was
    given over them, checked by the library (bf_sphere_options_check: the size, the number
    of lights, finite directions); and the lights' array, which must outlive the options."""
    o = ffi.new("bf_sphere_options *")
    lib.bf_sphere_options_init(o)
    if resolution is not None:
        o.resolution = _int("resolution", resolution)
    if view is not None:
        o.view.theta, o.view.phi = _dir("view", view)
    keep = None
    if lights is not None:
        if isinstance(lights, (str, bytes)) or not isinstance(lights, (tuple, list, np.ndarray)):
            raise UsageError("lights: needs a list of (theta, phi) in degrees, got %r" % (lights,))
        dirs = [_dir("lights[%d]" % i, d) for i, d in enumerate(lights)]
        keep = ffi.new("bf_dir[]", max(len(dirs), 1))
        for i, (t, p) in enumerate(dirs):
            keep[i].theta, keep[i].phi = t, p
        o.lights = keep
        o.nlights = len(dirs)
    err = ffi.new("bf_error *")
    _check(lib.bf_sphere_options_check(o, err), err)
    return o, keep


def _halfdiff_options(size: Any, phi_d: Any) -> Any:
    """bf_halfdiff_options at the library's defaults (bf_halfdiff_options_init: the size,
    phi_d), with what was given over them, checked by the library."""
    o = ffi.new("bf_halfdiff_options *")
    lib.bf_halfdiff_options_init(o)
    if isinstance(size, (tuple, list)) and len(size) == 2:
        o.width, o.height = _int("size", size[0]), _int("size", size[1])
    elif size is not None:
        o.width = o.height = _int("size", size)
    if phi_d is not None:
        o.phi_d = _number("phi_d", phi_d)
    err = ffi.new("bf_error *")
    _check(lib.bf_halfdiff_options_check(o, err), err)
    return o


def _tonemap_options(tonemap: Any, default: Optional[int], exposure: Any, decades: Any) -> Any:
    """bf_tonemap_options for tonemap (True: the kind's default mapping, default, or the
    options' own when None; a name as --tonemap takes it), exposure and decades over the
    library's defaults (bf_tonemap_options_init), checked by the library; None for tonemap
    None or False."""
    if tonemap is None or tonemap is False:
        if exposure is not None or decades is not None:
            raise UsageError("%s: only with tonemap" % ("exposure" if exposure is not None else "decades"))
        return None
    o = ffi.new("bf_tonemap_options *")
    lib.bf_tonemap_options_init(o)
    err = ffi.new("bf_error *")
    if tonemap is True:
        if default is not None:
            o.mode = default
    elif isinstance(tonemap, str):
        mode = ffi.new("bf_tonemap_mode *")
        _check(lib.bf_tonemap_parse(tonemap.encode(), mode, err), err, "tonemap")
        o.mode = mode[0]
    else:
        raise UsageError("tonemap: needs True or a mapping's name, got %r" % (tonemap,))
    if exposure is not None:
        o.exposure = _number("exposure", exposure)
    if decades is not None:
        o.decades = _number("decades", decades)
    _check(lib.bf_tonemap_options_check(o, err), err)
    return o


def _image(width: int, height: int) -> Tuple[NDArray[np.float32], Any]:
    """An (height, width, 3) float32 image and its pointer, once the library says that
    this machine can hold it (bf_render_memory_check: as the command refuses a size)."""
    err = ffi.new("bf_error *")
    _check(lib.bf_render_memory_check(width, height, err), err)
    img = np.zeros((height, width, 3), dtype=np.float32)
    return img, ffi.from_buffer("float[]", img)


def render(source: Source, kind: str = "sphere", params: Optional[Any] = None, resolution: Optional[int] = None,
           view: Optional[Sequence[float]] = None, lights: Optional[Sequence[Sequence[float]]] = None,
           size: Optional[Union[int, Tuple[int, int]]] = None, phi_d: Optional[float] = None,
           tonemap: Union[None, bool, str] = None, exposure: Optional[float] = None,
           decades: Optional[float] = None) -> NDArray[np.float32]:
    """A picture as a float32 array (height, width, 3) of linear values, what `brdfit render`
    writes to an EXR: every channel count shown as RGB (one channel as grey, three as they
    are, others as the mean of the channels).

    source: a brdfit.Model (its parameters, or its defaults; params= over them), a
    FitResult (its fitted model), a parameter file (a fit's result, as --params takes it),
    or brdfit.Samples of a MERL table (brdfit.read of a .binary file).

    kind="sphere": the unit sphere lit by directional lights, seen orthographically
    (render.h gives the frames); resolution (pixels a side), view and lights ((theta, phi)
    in degrees: towards the camera, and towards each light) default to the library's
    (bf_sphere_options_init), as the command's --size, --view and --light do.

    kind="halfdiff": theta_h (columns, even in sqrt(theta_h)) by theta_d (rows, from the
    top) at a fixed phi_d (degrees), as `brdfit render --half-diff`; size is N or (width,
    height); both default to the library's (bf_halfdiff_options_init), as the command's.

    tonemap: the display mapping of the command's PNG instead of linear values (before
    the 8-bit encoding, which clamps to [0, 1]): True for the kind's own (the command's
    default), or "clamp", "reinhard" or "log"; exposure and decades as --exposure and
    --decades, defaulting to the library's (bf_tonemap_options_init).

    The sizes, angles and the mapping are checked by the library, with its messages
    (brdfit.UsageError); a picture this machine cannot hold is refused before it is
    drawn (brdfit.Error, code "nomem")."""
    if not isinstance(kind, str) or kind not in ("sphere", "halfdiff"):
        raise UsageError("kind: 'sphere' or 'halfdiff', got %r" % (kind,))
    merl = isinstance(source, Samples)
    if not merl and not isinstance(source, (Model, FitResult, str, os.PathLike)):
        raise UsageError("source: needs a brdfit.Model, a FitResult, a parameter file or MERL brdfit.Samples, got %s"
                         % type(source).__name__)
    if merl and params is not None:
        raise UsageError("params: not for measured samples")
    err = ffi.new("bf_error *")
    if kind == "sphere":
        if size is not None or phi_d is not None:
            raise UsageError("%s: for kind='halfdiff'; the sphere takes resolution" % (
                "size" if size is not None else "phi_d"))
        o, keep = _sphere_options(resolution, view, lights)
        tm = _tonemap_options(tonemap, None, exposure, decades)
        img, rgb = _image(o.resolution, o.resolution)
        if merl:
            assert isinstance(source, Samples)
            _check(lib.bf_render_sphere_merl(source._s, o, rgb, err), err)
        else:
            m, x = _model_of(source, params)
            _check(lib.bf_render_sphere(m, ffi.from_buffer("double[]", x), o, rgb, err), err)
        del keep  # the lights lived until here
    else:
        if resolution is not None or view is not None or lights is not None:
            raise UsageError("%s: for kind='sphere'; the half/difference image takes size and phi_d" % (
                "resolution" if resolution is not None else "view" if view is not None else "lights"))
        hd = _halfdiff_options(size, phi_d)
        tm = _tonemap_options(tonemap, hd.tonemap, exposure, decades)
        img, rgb = _image(hd.width, hd.height)
        if merl:
            assert isinstance(source, Samples)
            _check(lib.bf_render_halfdiff_merl(source._s, hd.width, hd.height, hd.phi_d, rgb, err), err)
        else:
            m, x = _model_of(source, params)
            _check(lib.bf_render_halfdiff_model(m, ffi.from_buffer("double[]", x), hd.width, hd.height, hd.phi_d, rgb,
                                                err), err)
    if tm is not None:
        _check(lib.bf_tonemap_apply(rgb, img.size, tm, err), err)
    return img
