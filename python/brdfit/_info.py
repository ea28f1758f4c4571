"""What a data file holds once read and prepared: `brdfit info`, from the library's load
report (bf_load_report) and description (bf_samples_describe)."""
from __future__ import annotations

import os
from typing import Any, Dict, List, Optional, Tuple, Union

import numpy as np
from numpy.typing import NDArray

from ._brdfit import ffi, lib
from ._data import _load
from ._errors import UsageError, _check, _take_text
from ._options import _doc, _Options, options
from ._run import CancelEvent, _Run
from ._samples import Samples

# bf_options_get's buffer: a scene's file name is the longest value a read option holds.
_VALUE_CHARS = 8192


class LoadReport:
    """What loading left out, and why (bf_load_report, field for field): read (samples in
    the file), channels_read, below_horizon, nonfinite, above_max_theta (dropped),
    negative (with a negative value: dropped, clamped or kept, as the option negative
    says), scene (a scene was applied), scene_in and scene_kept (the samples the scene
    was given and kept), subsampled_out, kept (samples loaded). A sample dropped for
    several reasons counts once, under the first of non-finite, below the horizon, above
    max_theta, negative."""

    def __init__(self, r: Any):
        self.read = int(r.read)
        self.channels_read = int(r.channels_read)
        self.below_horizon = int(r.below_horizon)
        self.nonfinite = int(r.nonfinite)
        self.negative = int(r.negative)
        self.above_max_theta = int(r.above_max_theta)
        self.scene = bool(r.scene)
        self.scene_in = int(r.scene_in)
        self.scene_kept = int(r.scene_kept)
        self.subsampled_out = int(r.subsampled_out)
        self.kept = int(r.kept)

    def __repr__(self) -> str:
        return "brdfit.LoadReport(read=%d, kept=%d)" % (self.read, self.kept)


def _range(r: Any) -> Tuple[float, float]:
    return float(r.lo), float(r.hi)  # NaN, NaN: nothing covered


class Info:
    """What `brdfit info` reports for a data file.

    .path, .samples (the brdfit.Samples a fit would see), .report (a LoadReport: what the
    reading and preprocessing dropped and why), .options (the read options' values as the
    library holds them, name -> text, defaults included: which negative action, which
    scene), and of the samples used (bf_samples_describe): .n, .channel_names,
    .wavelengths (nm, or None), .weighted, .theta_i, .theta_o, .theta_h, .theta_d
    (min, max in degrees over the samples above the horizon), .below_horizon, .nonfinite,
    .negative, .zero (counts), .value_min, .value_max, .value_mean (per channel, over the
    finite values); .json and .text, what `brdfit info --json` and `brdfit info` print for
    the file, byte for byte (bf_samples_info_json, bf_samples_info_text)."""

    def __init__(self, path: str, samples: Samples, report: LoadReport, info: Any, options: Dict[str, str],
                 texts: Tuple[str, str]):
        C = int(info.channels)
        self.path = path
        self.json, self.text = texts
        self.samples = samples
        self.report = report
        self.options = options
        self.n = int(info.n)
        self.channel_names: List[str] = samples.channel_names
        w = samples._s.wavelength
        self.wavelengths: Optional[NDArray[np.float64]] = None if w == ffi.NULL else np.array(ffi.unpack(w, C))
        self.weighted = bool(info.weighted)
        self.theta_i = _range(info.theta_i)
        self.theta_o = _range(info.theta_o)
        self.theta_h = _range(info.theta_h)
        self.theta_d = _range(info.theta_d)
        self.below_horizon = int(info.below_horizon)
        self.nonfinite = int(info.nonfinite)
        self.negative = int(info.negative)
        self.zero = int(info.zero)
        self.value_min = np.array([info.value[c].lo for c in range(C)])
        self.value_max = np.array([info.value[c].hi for c in range(C)])
        self.value_mean = np.array(ffi.unpack(info.mean, C)) if C else np.zeros(0)

    def __repr__(self) -> str:
        return "brdfit.Info(%r: %d samples read, %d used x %d channels)" % (self.path, self.report.read, self.n,
                                                                           len(self.channel_names))


def _values(opts: _Options) -> Dict[str, str]:
    """Every read option's value as the library will use it (bf_options_get)."""
    err = ffi.new("bf_error *")
    buf = ffi.new("char[]", _VALUE_CHARS)
    out: Dict[str, str] = {}
    for d in options("read"):
        _check(lib.bf_options_get(opts.o, d["name"].encode(), buf, _VALUE_CHARS, err), err)
        out[d["name"]] = ffi.string(buf).decode("utf-8", "surrogateescape")
    return out


def info(path: Union[str, "os.PathLike[str]"], cancel: Optional[CancelEvent] = None, **data_options: Any) -> Info:
    if not isinstance(path, (str, os.PathLike)):
        raise UsageError("path: needs a file name, got %r" % (path,))
    opts = _Options("read", data_options, "read")
    report = ffi.new("bf_load_report *")
    lib.bf_load_report_init(report)
    run = _Run(None, cancel, "info")
    run.hook(opts)
    samples = _load(path, opts, run, report)
    d = ffi.gc(ffi.new("bf_samples_info *"), lib.bf_samples_info_clear)
    lib.bf_samples_info_init(d)
    err = ffi.new("bf_error *")
    _check(lib.bf_samples_describe(samples._s, d, err), err, samples.path or "samples")
    # The command's report, made by the library from the same samples, load report and
    # options (the file named as it was given).
    name = os.fsencode(samples.path or "")
    texts = []
    for report_fn in (lib.bf_samples_info_json, lib.bf_samples_info_text):
        out = ffi.new("char **")
        _check(report_fn(samples._s, report, opts.o, name, out, err), err)
        texts.append(_take_text(out[0]))
    return Info(samples.path or "", samples, LoadReport(report), d, _values(opts), (texts[0], texts[1]))


info.__doc__ = """What a data file holds once read and prepared as a fit would see it, as `brdfit info`
reports it: a brdfit.Info (samples read and used, channels, what the preprocessing
dropped and why, angle coverage, value ranges). cancel (a threading.Event) once set, or
Ctrl-C, stops a long read (brdfit.Error, code "cancelled"; KeyboardInterrupt). The data
options as keywords:

""" + _doc("read")
