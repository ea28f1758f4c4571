"""Materials from photographs: `brdfit fit-images` (brdfit/photo.h) with its maps as
NumPy arrays."""
from __future__ import annotations

import os
from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple, Union, cast

import numpy as np
from numpy.typing import NDArray

from ._args import _path_text
from ._brdfit import ffi, lib
from ._errors import UsageError, _check, _take_text
from ._fit import _spec_of
from ._model import Model
from ._render import _int, _number
from ._run import CancelEvent, ProgressFn, _Run


def _copy(ptr: Any, dtype: Any, shape: Tuple[int, ...]) -> NDArray[Any]:
    """A copy of library memory: ptr to prod(shape) values of dtype (the C type's)."""
    dt = np.dtype(dtype)
    n = int(np.prod(shape))
    if n == 0 or ptr == ffi.NULL:
        return np.zeros(shape, dtype=dt)
    return np.frombuffer(ffi.buffer(ptr, n * dt.itemsize), dtype=dt).reshape(shape).copy()


class FitImagesResult:
    """A per-pixel fit of a stack (bf_photo_result), as arrays of (height, width, ...) rows
    from the top, camera frame (x right, y up, z towards the camera):

    .model (a Model: the spec and channels fitted), .mask (bool: the fitted pixels),
    .normals (3), .params (name -> map: (h, w) for a scalar, (h, w, channels) for a
    colour), .values (the model vector of each pixel, model.value_names), .error (the RMS
    relit error of each pixel's used samples), .lambert_normals, .lambert_albedo (the
    Lambertian baseline), .clusters (int, -1 outside; None without clusters), .shared (one
    dict per cluster: entry name -> value of the shared parameters), .counts (name ->
    count of bf_photo_counts: pixels, masked, failed, samples, shadowed, dark, saturated,
    invalid), .relit_rms and .lambert_rms (the relit error of the model and of the
    baseline), .image_rms, .image_lambert_rms, .image_samples (per image), .relit (a list
    of (image index, measured, relit by the model) images), .scale (as used), .rows (the
    rows fitted: a tile's band), .iterations, .restarted, .threads, .seconds and
    .cancelled (a run stopped by progress or Ctrl-C: the maps are incomplete); .json, the
    text fit-images writes to fit.json (bf_photo_result_json; no "command"; None for a
    cancelled run).
    The maps are floats (float32) as the library holds them; fit-images writes the same
    values to normals.exr, NAME.exr, error.exr and the others."""

    def __init__(self, r: Any, summary: Optional[str] = None):
        self.json = summary
        H, W, C, P = int(r.height), int(r.width), int(r.channels), int(r.nvalues)
        self.model = Model._from_ptr(r.model)
        self.width, self.height, self.channels = W, H, C
        self.rows = (int(r.y0), int(r.y1))
        self.scale = float(r.scale)
        self.mask = _copy(r.mask, np.uint8, (H, W)) != 0
        self.normals = _copy(r.normals, np.float32, (H, W, 3))
        self.values = _copy(r.params, np.float32, (H, W, P))
        self.error = _copy(r.error, np.float32, (H, W))
        self.lambert_normals = _copy(r.lambert_normals, np.float32, (H, W, 3))
        self.lambert_albedo = _copy(r.lambert_albedo, np.float32, (H, W, C))
        self.clusters: Optional[NDArray[np.intc]] = None if r.cluster == ffi.NULL else _copy(r.cluster, np.intc, (H, W))
        m = self.model._m
        self.params: Dict[str, NDArray[np.float32]] = {}
        for i in range(lib.bf_model_nparams(m)):
            info = lib.bf_model_param(m, i)
            o = lib.bf_model_param_offset(m, i)
            name = ffi.string(info.name).decode()
            self.params[name] = self.values[:, :, o:o + C] if info.color else self.values[:, :, o]
        names = self.model.value_names
        nshared = int(r.nshared)
        shared = _copy(r.shared, np.float64, (int(r.nclusters), nshared)) if nshared else None
        self.shared: List[Dict[str, float]] = [] if shared is None else [
            {names[r.shared_entry[i]]: float(row[i]) for i in range(nshared)} for row in shared]
        self.counts: Dict[str, int] = {f: int(getattr(r.counts, f)) for f, _ in ffi.typeof("bf_photo_counts").fields}
        K = int(r.nimages)
        self.relit_rms, self.lambert_rms = float(r.relit_rms), float(r.lambert_rms)
        self.image_rms = _copy(r.image_rms, np.float64, (K,))
        self.image_lambert_rms = _copy(r.image_lambert_rms, np.float64, (K,))
        self.image_samples = _copy(r.image_samples, np.uintp, (K,))
        self.relit: List[Tuple[int, NDArray[np.float32], NDArray[np.float32]]] = [
            (int(r.relit_index[i]), _copy(r.relit_measured[i], np.float32, (H, W, C)),
             _copy(r.relit_model[i], np.float32, (H, W, C))) for i in range(int(r.nrelit))]
        self.iterations, self.restarted = int(r.iterations), int(r.restarted)
        self.threads, self.seconds = int(r.threads), float(r.seconds)
        self.cancelled = bool(r.cancelled)

    def __repr__(self) -> str:
        return "brdfit.FitImagesResult(%r, %dx%d, %d pixels, relit error %.4g%s)" % (
            self.model.spec, self.width, self.height, self.counts["pixels"], self.relit_rms,
            ", cancelled" if self.cancelled else "")




def fit_images(stack: Union[str, "os.PathLike[str]"], model: Union[str, Model, None] = None,
               normals: Union[str, "os.PathLike[str]", None] = None, share: Union[str, Sequence[str], None] = None,
               clusters: Optional[int] = None, scale: Union[float, str, None] = None,
               tile: Union[str, Tuple[int, int], None] = None, relit: Optional[int] = None,
               seed: Optional[int] = None, threads: Optional[int] = None,
               progress: Optional[Callable[[float], Any]] = None,
               cancel: Optional[CancelEvent] = None) -> FitImagesResult:
    """Fits a normal and a model's parameters to every pixel of a stack of photographs under
    known lights, as `brdfit fit-images STACK` does (docs/images.md), with the maps as
    arrays instead of files: a FitImagesResult.

    stack: a DiLiGenT folder or a JSON stack file. model: a spec or Model (the library's
    default when None). normals: "fit", "flat" (the sample's plane) or an image file of
    unit normals in the camera frame. share: parameter names fitted once per material
    cluster (a list, or "a,b"), clusters: how many clusters. scale: a number, or "auto"
    (default: the stack's). tile: (I, N) or "I/N", band I of N bands of rows. relit: how
    many relit comparisons to keep. seed: the clusters' seed. threads: 0 or None for every
    core (the results do not depend on it). None leaves the library's default
    (bf_photo_options_init). progress(done) is called with the fraction of pixels done;
    returning True, or cancel (a threading.Event) once set, stops the fit (the result says
    .cancelled). Ctrl-C stops it and raises
    KeyboardInterrupt."""
    path = _path_text(stack) if isinstance(stack, (str, os.PathLike)) else None
    if path is None:
        raise UsageError("stack: needs a folder or a JSON stack file, got %r" % (stack,))
    run = _Run(cast(Optional[ProgressFn], progress), cancel, "fit_images", partial=True)  # progress(done) here
    o = ffi.new("bf_photo_options *")
    lib.bf_photo_options_init(o)
    keep: List[Any] = []  # the texts the options point to live as long as the call

    def text(name: str, v: str) -> Any:
        if "\0" in v:
            raise UsageError("%s: %r: a NUL character cannot be in it" % (name, v))
        c = ffi.new("char[]", os.fsencode(v))
        keep.append(c)
        return c

    err = ffi.new("bf_error *")
    # Texts are parsed by the library (bf_photo_options_set_*), and every range is its
    # check's (bf_photo_options_check), its messages naming the keywords.
    o.spelling = lib.BF_SPELL_KEYWORD
    if model is not None:
        o.model = text("model", _spec_of(model, "model"))
    if normals is not None:
        if not isinstance(normals, (str, os.PathLike)):
            raise UsageError("normals: needs 'fit', 'flat' or an image file, got %r" % (normals,))
        _check(lib.bf_photo_options_set_normals(o, text("normals", _path_text(normals)), err), err)
    if share is not None:
        if isinstance(share, str):
            names = share
        elif isinstance(share, (list, tuple)) and all(isinstance(s, str) for s in share):
            names = ",".join(share)
        else:
            raise UsageError("share: needs parameter names (a list, or 'a,b'), got %r" % (share,))
        o.share = text("share", names)
    if clusters is not None:
        o.clusters = _int("clusters", clusters)
    if isinstance(scale, str):
        _check(lib.bf_photo_options_set_scale(o, text("scale", scale), err), err)
    elif scale is not None:
        o.scale_given, o.scale = 1, _number("scale", scale)
    if isinstance(tile, str):
        _check(lib.bf_photo_options_set_tile(o, text("tile", tile), err), err)
    elif tile is not None:
        if not isinstance(tile, (tuple, list)) or len(tile) != 2:
            raise UsageError("tile: needs (I, N) or 'I/N' (band I of N, from 1), got %r" % (tile,))
        i, n = _int("tile", tile[0]), _int("tile", tile[1])
        o.tile_index, o.tile_count = _int("tile", i - 1), n
    if relit is not None:
        o.relit_images = _int("relit", relit)
    if seed is not None:
        o.seed = _int("seed", seed, "uint64_t")
    if threads is not None:
        o.threads = _int("threads", threads)
    _check(lib.bf_photo_options_check(o, err), err)  # before the stack is read
    o.cancel = run.cancel
    if progress is not None:
        o.progress = lib._brdfit_photo_progress
        o.progress_user = run.handle

    held = (o, keep)  # the options and the texts they point to, for the call

    def call() -> FitImagesResult:  # in the worker, which owns them, the stack and the result
        opts, _texts = held
        s = ffi.new("bf_stack **")
        _check(lib.bf_stack_read(os.fsencode(path), s, err), err)
        st = ffi.gc(s[0], lib.bf_stack_free)
        out = ffi.new("bf_photo_result **")
        rc = lib.bf_photo_fit(st, opts, out, err)
        r = ffi.gc(out[0], lib.bf_photo_result_free) if out[0] != ffi.NULL else None
        _check(rc, err)
        assert r is not None
        summary = None  # a cancelled fit has none
        if not r.cancelled:
            made = ffi.new("char **")
            _check(lib.bf_photo_result_json(r, st, opts, ffi.NULL, made, err), err)
            summary = _take_text(made[0])
        return FitImagesResult(r, summary)

    result: FitImagesResult = run(call)
    return result


@ffi.def_extern()
def _brdfit_photo_progress(user: Any, done: float) -> None:
    """bf_photo_options.progress: calls the run's progress(done) (in the worker, with the
    GIL); True or an exception stops the fit through the cancel flag."""
    run = ffi.from_handle(user)
    if run.error is not None or run.cancel[0]:
        return
    try:
        stop = bool(run.progress(float(done)))
    except BaseException as e:
        run.error = e
        stop = True
    if stop:
        run.cancel[0] = 1
