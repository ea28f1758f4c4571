"""Running a library call: a worker thread, the progress callback, and interrupts."""
from __future__ import annotations

import threading
from typing import Any, Callable, Dict, Optional

from ._brdfit import ffi, lib
from ._errors import UsageError
from ._options import _Options

# How often the calling thread looks up from waiting (Ctrl-C is seen at once regardless).
_POLL_SECONDS = 0.025


class _Run:
    """One library call in a worker thread, so that the calling thread stays in Python.

    The worker owns the call: fn does the call and makes the result from what it wrote,
    and everything the call uses is held by fn's references (library memory through
    ffi.gc), so it is freed when the worker lets go, never under it. An exception in the
    calling thread (Ctrl-C's KeyboardInterrupt, a signal handler's TimeoutError), wherever
    it lands, sets the library's cancel flag, and the calling thread waits for the worker
    to end before raising it. The progress callback runs in the worker (with the GIL); an
    exception it raises, or True, stops the call."""

    def __init__(self, progress: Optional[Callable[[int, float], Any]]):
        if progress is not None and not callable(progress):
            raise UsageError("progress: needs a callable (iteration, cost) -> bool, got %r" % (progress,))
        self.progress = progress
        self.cancel = ffi.new("bf_cancel_flag *", 0)
        self.error: Optional[BaseException] = None
        self.handle = ffi.new_handle(self)

    def hook(self, opts: _Options) -> None:
        lib.bf_options_set_cancel(opts.o, self.cancel, ffi.NULL)
        if self.progress is not None:
            lib.bf_options_set_progress(opts.o, lib._brdfit_progress, self.handle)

    def __call__(self, fn: Callable[[], Any]) -> Any:
        box: Dict[str, Any] = {}
        began, done = threading.Event(), threading.Event()

        def work() -> None:  # holds self (the cancel flag, the progress handle) and fn
            began.set()
            try:
                box["rc"] = fn()
            except BaseException as e:  # surfaced in the calling thread
                box["exc"] = e
            finally:
                done.set()

        self._pending: Optional[BaseException] = None
        try:
            threading.Thread(target=work, name="brdfit", daemon=True).start()
        except BaseException as e:  # in start(): the worker may or may not have begun
            self.cancel[0] = 1
            self._pending = e
            if not self._wait(began, 1.0):
                raise
        self._wait(done, None)
        if self._pending is not None:
            raise self._pending
        if self.error is not None:
            raise self.error
        if "exc" in box:
            raise box["exc"]
        return box["rc"]

    def _wait(self, event: threading.Event, limit: Optional[float]) -> bool:
        """Waits for event (at most limit seconds); an exception meanwhile sets the cancel
        flag and is kept for the caller (the first one), and the wait goes on."""
        waited = 0.0
        while limit is None or waited < limit:
            try:
                if event.wait(_POLL_SECONDS):
                    return True
                waited += _POLL_SECONDS
            except BaseException as e:
                self.cancel[0] = 1
                if self._pending is None:
                    self._pending = e
        return False

@ffi.def_extern()
def _brdfit_progress(user, iteration, cost):
    run = ffi.from_handle(user)
    if run.error is not None or run.cancel[0]:
        return 1
    try:
        stop = bool(run.progress(int(iteration), float(cost)))
    except BaseException as e:
        run.error = e
        stop = True
    if stop:  # the whole call stops, not only this solve
        run.cancel[0] = 1
        return 1
    return 0
