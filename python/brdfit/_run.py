"""Running a library call: a worker thread, progress reports, cancelling and interrupts."""
from __future__ import annotations

import _thread
import threading
import time
from typing import Any, Callable, Dict, Optional, Protocol, TypeVar

from ._brdfit import ffi, lib
from ._errors import Error, UsageError
from ._options import _Options
from ._progress import Progress, _progress_of

# How often the calling thread looks up from waiting (Ctrl-C is seen at once regardless,
# a cancel event within this).
_POLL_SECONDS = 0.025
_FIRST_NAP_SECONDS = 0.0005
# How long a worker may take to begin when an exception hid whether it was started; one
# that begins later finds the cancel flag set, or the call abandoned.
_BEGIN_SECONDS = 0.25


class CancelEvent(Protocol):
    """What cancel= takes: a threading.Event, or anything with is_set()."""

    def is_set(self) -> bool: ...


ProgressFn = Callable[[Progress], Any]
T = TypeVar("T")


class _Run:
    """One library call in a worker thread, so that the calling thread stays in Python.

    The worker owns the call: fn does the call and makes the result from what it wrote,
    and everything the call uses is held by fn's references (library memory through
    ffi.gc), so it is freed when the worker lets go, never under it. An exception in the
    calling thread (Ctrl-C's KeyboardInterrupt, a signal handler's TimeoutError), wherever
    it lands, sets the library's cancel flag, and the calling thread waits for the worker
    to end before raising it. The calling thread also polls the cancel event and sets the
    flag once it is set. The progress callback runs in the worker (with the GIL); an
    exception it raises, or True, stops the call.

    what names the call in the error of a stopped call; partial says whether the call's
    result tells that it was stopped (fit: .cancelled), else a call the caller stopped
    (the event, or progress returning True) raises brdfit.Error (code "cancelled")."""

    def __init__(self, progress: Optional[ProgressFn], cancel: Optional[CancelEvent] = None, what: str = "",
                 partial: bool = False):
        if progress is not None and not callable(progress):
            raise UsageError("progress: needs a callable (brdfit.Progress) -> bool, got %r" % (progress,))
        if cancel is not None and not callable(getattr(cancel, "is_set", None)):
            raise UsageError("cancel: needs a threading.Event (anything with is_set()), got %r" % (cancel,))
        self.progress = progress
        self.event = cancel
        self.what = what
        self.partial = partial
        self.cancel = ffi.new("bf_cancel_flag *", 0)
        self.stopped = False  # by the caller: the event, or progress returning True
        self.error: Optional[BaseException] = None
        self.handle = ffi.new_handle(self)

    def hook(self, opts: _Options) -> None:
        lib.bf_options_set_cancel(opts.o, self.cancel, ffi.NULL)
        if self.progress is not None:
            lib.bf_options_set_progress_report(opts.o, lib._brdfit_report, self.handle)

    def __call__(self, fn: Callable[[], T]) -> T:
        box: Dict[str, Any] = {}
        ended = threading.Lock()  # held until the worker ends: it wakes the waiting thread
        ended.acquire()

        def work() -> None:  # holds self (the cancel flag, the progress handle) and fn
            box["began"] = True
            try:
                if "abandoned" not in box:
                    box["rc"] = fn()
            except BaseException as e:  # surfaced in the calling thread
                box["exc"] = e
            finally:
                box["done"] = True
                ended.release()

        self._pending: Optional[BaseException] = None
        self._poll_event()  # an event set already: the call stops at its first check
        try:
            # The low-level call: one C function, so an exception lands before it (no
            # worker) or after it (a worker), never inside a Condition's wait as in
            # threading.Thread.start.
            _thread.start_new_thread(work, ())
        except BaseException as e:  # the worker may or may not have begun
            self.cancel[0] = 1
            self._pending = e
            if not self._wait(box, "began", _BEGIN_SECONDS):
                box["abandoned"] = True  # one that begins later does nothing
                raise
        self._wait(box, "done", None, ended)
        if self._pending is not None:
            raise self._pending
        if self.error is not None:
            raise self.error
        if "exc" in box:
            raise box["exc"]
        if self.stopped and not self.partial:
            raise Error("%s: cancelled" % self.what if self.what else "cancelled", "cancelled")
        rc: T = box["rc"]
        return rc

    def _poll_event(self) -> None:
        if self.event is not None and not self.cancel[0] and self.event.is_set():
            self.stopped = True
            self.cancel[0] = 1

    def _wait(self, box: Dict[str, Any], key: str, limit: Optional[float],
              ended: Optional["threading.Lock"] = None) -> bool:
        """Waits until the worker puts key in box (at most limit seconds), looking at the
        cancel event in between; an exception meanwhile sets the cancel flag and is kept for
        the caller (the first one), and the wait goes on.

        The flag decides, not threading.Event.wait: an exception a signal handler raises
        inside a Condition's wait can leave its lock released twice ("release unlocked
        lock"), and the waiting must survive any number of them. In between it blocks on
        ended, a plain lock the worker releases as it ends (an interrupted acquire leaves
        it as it was, and the flag covers an acquire whose success an exception hid), so
        a short call returns at once; without one it sleeps, from 0.5 ms up."""
        end = None if limit is None else time.monotonic() + limit
        nap = _FIRST_NAP_SECONDS
        while key not in box:
            if end is not None and time.monotonic() >= end:
                return False
            try:
                if ended is not None:
                    ended.acquire(timeout=_POLL_SECONDS)
                else:
                    time.sleep(nap)
                    nap = min(2 * nap, _POLL_SECONDS)
                self._poll_event()
            except BaseException as e:
                self.cancel[0] = 1
                if self._pending is None:
                    self._pending = e
        return True


@ffi.def_extern()
def _brdfit_report(user: Any, report: Any) -> int:
    run = ffi.from_handle(user)
    if run.error is not None or run.cancel[0]:
        return 1
    try:
        stop = bool(run.progress(_progress_of(report)))
    except BaseException as e:
        run.error = e
        stop = True
    if stop:  # the whole call stops, not only this solve
        if run.error is None:
            run.stopped = True
        run.cancel[0] = 1
        return 1
    return 0
