"""The package's errors and the texts the library hands over: one place that turns a
bf_error into an exception and a library-made string into a str."""
from __future__ import annotations

from typing import Any, Optional

from ._brdfit import ffi, lib


class Error(Exception):
    """A failure the library reports: its one-line message, and .code, the bf_status name."""

    def __init__(self, message: str, code: str = "error"):
        super().__init__(message)
        self.message = message
        self.code = code


class UsageError(Error, ValueError):
    """Bad usage (a bad option, model spec or argument): also a ValueError."""

    def __init__(self, message: str, code: str = "arg"):
        super().__init__(message, code)


def _raise(err: Any, what: str = "", usage: bool = False) -> None:
    msg = ffi.string(err.msg).decode("utf-8", "replace")
    if what:
        msg = "%s: %s" % (what, msg)
    cls = UsageError if usage or err.code == lib.BF_ERR_ARG else Error
    raise cls(msg, ffi.string(lib.bf_status_name(err.code)).decode())


def _check(rc: int, err: Any, what: str = "", usage: bool = False) -> None:
    """Raises the library's error: UsageError (a ValueError) for bad usage, and for any
    error of a check of the caller's arguments (usage: a value out of its range is the
    caller's, as the command's exit status 2 says); Error otherwise."""
    if rc != lib.BF_OK:
        _raise(err, what, usage)


def _take_text(p: Any) -> str:
    """A text the library made (bf_free'd here)."""
    try:
        text: str = ffi.string(p).decode("utf-8", "surrogateescape")
        return text  # a non-UTF-8 file name as Python names it
    finally:
        lib.bf_free(p)



def _str(p: Any) -> Optional[str]:
    return None if p == ffi.NULL else ffi.string(p).decode()
