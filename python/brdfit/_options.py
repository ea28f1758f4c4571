"""Run options: the library's table, and a set of its values made from keyword arguments."""
from __future__ import annotations

import os
import re
from typing import Any, Dict, List, Mapping, Optional, Sequence

import numpy as np

from ._args import _path_text
from ._brdfit import ffi, lib
from ._errors import UsageError, _check, _str

_TASKS = {"read": lib.BF_TASK_READ, "fit": lib.BF_TASK_FIT, "compare": lib.BF_TASK_COMPARE,
          "select": lib.BF_TASK_SELECT, "tradeoff": lib.BF_TASK_TRADEOFF}



def _table() -> List[Dict[str, Any]]:
    """The library's option table (brdfit/options.h), as dicts."""
    out = []
    for i in range(lib.bf_option_count()):
        d = lib.bf_option_get(i)
        out.append({"name": _str(d.name), "group": _str(d.group), "tasks": d.tasks, "type": int(d.type),
                    "arg": _str(d.arg), "help": _str(d.help), "default": _str(getattr(d, "def")),
                    "range": _str(d.range), "complete": _str(d.complete),
                    "choices": ffi.string(d.choices).decode().split("|") if d.choices != ffi.NULL else None})
    return out


def options(task: str) -> List[Dict[str, Any]]:
    """The keyword options a function takes ("read", "fit", "compare", "select" or
    "tradeoff"), as the library declares them: name, group, type, arg, help, default (text,
    or None for none or automatic) and range (in words, or None)."""
    if task not in _TASKS:
        raise UsageError("task: one of %s, got %r" % (", ".join(_TASKS), task))
    seen = set()
    out = []
    for d in _table():
        if d["tasks"] & _TASKS[task] and d["name"] not in seen:
            seen.add(d["name"])
            out.append(d)
    return out


def _keyword_help(text: str) -> str:
    """Help text with the command line's option names as keywords ("--max-theta" ->
    max_theta)."""
    return re.sub(r"--([a-z][a-z-]*)", lambda m: m.group(1).replace("-", "_"), text)


def _doc(task: str, groups: Optional[Sequence[str]] = None) -> str:
    lines = []
    for d in options(task):
        if groups is not None and d["group"] not in groups:
            continue
        head = "  %s=%s" % (d["name"], d["arg"] or "True")
        body = _keyword_help(d["help"] or "").replace("\n", " ")
        lines.append("%-28s %s" % (head, body))
    return "\n".join(lines)


def _value_texts(d: Any, name: str, v: Any) -> List[Optional[str]]:
    """A keyword's value as the texts the library takes (Python types to text only: the
    library checks and refuses)."""
    if int(d.type) == lib.BF_OPTION_LIST:
        if isinstance(v, (str, os.PathLike)):
            return [_one_text(v)]
        if isinstance(v, Mapping):
            out: List[Optional[str]] = []
            for k, x in v.items():
                if name == "bound" and isinstance(x, (tuple, list)) and len(x) == 2:
                    out.append("%s=%s:%s" % (k, _one_text(x[0]), _one_text(x[1])))
                elif isinstance(x, (tuple, list, np.ndarray)):  # one value per channel
                    out.extend("%s[%d]=%s" % (k, c, _one_text(xc)) for c, xc in enumerate(x))
                else:
                    out.append("%s=%s" % (k, _one_text(x)))
            return out
        if isinstance(v, (list, tuple)) and all(isinstance(t, (str, os.PathLike)) for t in v):
            return [_one_text(t) for t in v]
        raise UsageError("%s: needs a dict (name -> value) or a list of strings, got %r" % (name, v))
    if isinstance(v, (list, tuple)):
        return [",".join(_one_text(x) for x in v)]
    return [_one_text(v)]


def _one_text(v: Any) -> str:
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        return repr(float(v))
    if isinstance(v, str):
        if "\0" in v:
            raise UsageError("%r: a NUL character cannot be in a value" % (v,))
        return v
    if isinstance(v, os.PathLike):
        return _path_text(v)
    raise UsageError("needs a string, a number or True/False, got %r" % (v,))


class _Options:
    """A set of the library's run options for a task, from keyword arguments: each
    keyword is set by the library (bf_options_set), which checks it and says what is
    wrong, naming the keyword."""

    def __init__(self, task: str, keywords: Mapping[str, Any], what: str):
        err = ffi.new("bf_error *")
        out = ffi.new("bf_options **")
        _check(lib.bf_options_new(_TASKS[task], out, err), err)
        self.o = ffi.gc(out[0], lib.bf_options_free)
        lib.bf_options_set_spelling(self.o, lib.BF_SPELL_KEYWORD)
        self.given = []
        for name, v in keywords.items():
            if v is None:
                continue
            d = lib.bf_option_find(name.encode(), _TASKS[task])
            if d == ffi.NULL:  # the library's message: unknown, or another task's
                _check(lib.bf_options_set(self.o, name.encode(), ffi.NULL, err), err)
            try:
                texts = _value_texts(d, name, v)
            except UsageError as e:
                raise UsageError("%s: %s" % (name, e.message)) from None
            for t in texts:
                _check(lib.bf_options_set(self.o, name.encode(), os.fsencode(t) if t is not None else ffi.NULL, err), err)
            self.given.append((name, _str(d.group)))

    def check(self, specs: Sequence[str] = ()) -> None:
        err = ffi.new("bf_error *")
        keep = [ffi.new("char[]", s.encode()) for s in specs]
        arr = ffi.new("const char *[]", keep) if keep else ffi.NULL
        _check(lib.bf_options_check_models(self.o, arr, len(keep), err), err, usage=True)
        _check(lib.bf_options_check(self.o, err), err, usage=True)

    def reading_given(self) -> List[str]:
        return [n for n, g in self.given if g == "reading"]
