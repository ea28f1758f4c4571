"""Many materials at once: the data files of a folder, or of a glob pattern, each read as
brdfit.read reads it."""
from __future__ import annotations

import glob
import os
from typing import Any, List, Optional, Union

from ._args import _path_text
from ._brdfit import lib
from ._data import _load
from ._errors import UsageError
from ._options import _doc, _Options
from ._run import CancelEvent, _Run
from ._samples import Samples


def _known(path: str) -> bool:
    """Whether the name's extension is a format the library reads (bf_format_by_extension)."""
    return bool(lib.bf_format_by_extension(os.fsencode(path)) != lib.BF_FORMAT_AUTO)


def _files(where: str) -> List[str]:
    if os.path.isdir(where):
        names = [os.path.join(where, n) for n in os.listdir(where)]
        return sorted(p for p in names if os.path.isfile(p) and _known(p))
    return sorted(glob.glob(where))


def read_all(folder_or_glob: Union[str, "os.PathLike[str]"], cancel: Optional[CancelEvent] = None,
             **data_options: Any) -> List[Samples]:
    if not isinstance(folder_or_glob, (str, os.PathLike)):
        raise UsageError("folder_or_glob: needs a folder or a glob pattern, got %r" % (folder_or_glob,))
    where = _path_text(folder_or_glob)
    opts = _Options("read", data_options, "read")  # the options are checked once, before any file
    paths = _files(where)
    if not paths:
        raise UsageError("folder_or_glob: %s: %s" % (
            where, "no data file in the folder (by extension: brdfit.read's formats)" if os.path.isdir(where)
            else "matches no file"))
    run = _Run(None, cancel, "read_all")
    run.hook(opts)
    return [_load(p, opts, run) for p in paths]


read_all.__doc__ = """The data files of a folder (those whose extension names a format the library reads,
as bf_format_by_extension tells), or the files a glob pattern matches, in the order of their sorted names, each read and prepared as brdfit.read does
(Samples with .path). No file is a UsageError. cancel (a threading.Event) once set, or
Ctrl-C, stops the reading (brdfit.Error, code "cancelled"; KeyboardInterrupt). The data
options as keywords:

""" + _doc("read")
