"""Long fits behave: the GIL is released during fits and evaluations (two fits in two
threads run at once), progress=callable receives brdfit.Progress and True stops the
fit, an exception raised in the callback is re-raised, and Ctrl-C (SIGINT) stops a
running fit within a second or so with KeyboardInterrupt, not by killing the process."""

import math
import numbers
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import brdfit
from _support import CAYMAN, assert_params_identical, vectors_from_angles

# A fit of about a second on one core (disney on all of cayman, 64 starts).
LONG_FIT = dict(accuracy="best", threads=1)


class Boom(Exception):
    pass


# --- progress ---------------------------------------------------------------------

def test_progress_receives_iteration_and_cost(cayman):
    calls = []

    def progress(p):
        calls.append((p.iteration, p.cost))

    r = brdfit.fit(cayman, "walter", progress=progress, threads=1)
    assert len(calls) >= 3
    for it, cost in calls:
        assert isinstance(it, numbers.Integral) and it >= 0
        assert isinstance(cost, numbers.Real) and math.isfinite(cost) and cost >= 0
    # a callback that returns None changes nothing
    plain = brdfit.fit(cayman, "walter", threads=1)
    assert_params_identical(r.params, plain.params)
    assert r.metrics == plain.metrics


def test_progress_true_stops_the_fit(cayman):
    full = []
    brdfit.fit(cayman, "walter", progress=lambda p: full.append(p.iteration), threads=1)
    assert len(full) > 10

    calls = []

    def stop_at_third(p):
        calls.append(p.iteration)
        return len(calls) >= 3

    r = brdfit.fit(cayman, "walter", progress=stop_at_third, threads=1)
    assert r.cancelled and not r.ok
    # one thread: no solve goes on after the callback asked to stop
    assert len(calls) == 3, f"{len(calls)} calls after the callback returned True at the third"
    # the library is fine afterwards, and a callback returning False stops nothing
    again = []
    brdfit.fit(cayman, "walter", progress=lambda p: again.append(p.iteration) or False, threads=1)
    assert again == full


def test_progress_exception_is_reraised(cayman):
    calls = []

    def progress(p):
        calls.append(p.iteration)
        if len(calls) == 2:
            raise Boom("from the callback")

    with pytest.raises(Boom, match="from the callback"):
        brdfit.fit(cayman, "walter", progress=progress, threads=1)
    assert len(calls) == 2, f"the callback was called {len(calls)} times after raising at the second"
    # the fit after it is a normal one
    a = brdfit.fit(cayman, "ward_iso", starts=1)
    b = brdfit.fit(cayman, "ward_iso", starts=1, progress=lambda p: None)
    assert_params_identical(a.params, b.params)


def test_progress_exception_with_several_threads(cayman):
    """With the solver's own threads the exception still comes back to the caller."""
    def progress(p):
        raise Boom("first call")

    with pytest.raises(Boom):
        brdfit.fit(cayman, "walter", progress=progress, threads=2)


# --- the GIL ------------------------------------------------------------------------

class _Spinner:
    """A Python thread that counts while it holds the GIL: if the main thread's C call
    keeps the GIL, the count cannot grow during it (but for the few milliseconds before
    the call takes it)."""

    def __init__(self):
        self.count = 0
        self.stop = False
        self.thread = threading.Thread(target=self._run, daemon=True)

    def _run(self):
        while not self.stop:
            self.count += 1

    def __enter__(self):
        self.old_interval = sys.getswitchinterval()
        sys.setswitchinterval(0.001)
        self.thread.start()
        while self.count == 0:
            time.sleep(0.001)
        # its rate while the main thread sleeps (sleeping releases the GIL)
        c0, t0 = self.count, time.perf_counter()
        time.sleep(0.2)
        self.rate = (self.count - c0) / (time.perf_counter() - t0)
        return self

    def during(self, fn):
        """Runs fn(); returns (its seconds, the spinner's count during it as a fraction
        of what it counts in that time when free)."""
        before, t0 = self.count, time.perf_counter()
        fn()
        elapsed = time.perf_counter() - t0
        return elapsed, (self.count - before) / (self.rate * elapsed)

    def __exit__(self, *exc):
        self.stop = True
        self.thread.join()
        sys.setswitchinterval(self.old_interval)


def test_fit_releases_the_gil(cayman):
    with _Spinner() as spin:
        assert spin.rate > 1000
        elapsed, share = spin.during(lambda: brdfit.fit(cayman, "disney", **LONG_FIT))
    assert elapsed > 0.2
    # released: the spinner runs most of the time; held: a few milliseconds of a second
    assert share > 0.1, f"the spinner ran {share:.1%} of its free rate during a {elapsed:.2f} s fit"


def test_eval_releases_the_gil():
    n = 1000000
    rng = np.random.default_rng(0)
    ti, to = rng.uniform(0, 80, n), rng.uniform(0, 80, n)
    pi, po = rng.uniform(0, 360, n), rng.uniform(0, 360, n)
    wi, wo = vectors_from_angles(ti, pi), vectors_from_angles(to, po)
    m = brdfit.Model("disney", channels=3)
    p = {"base_color": [0.5, 0.4, 0.3], "metallic": 0.2, "subsurface": 0.3, "specular": 0.5, "roughness": 0.4,
         "specular_tint": 0.1, "anisotropic": 0.2, "sheen": 0.1, "sheen_tint": 0.5, "clearcoat": 0.2,
         "clearcoat_gloss": 0.8}
    with _Spinner() as spin:
        results = [spin.during(lambda: m.eval(wi, wo, p)) for _ in range(3)]
    elapsed, share = max(results, key=lambda r: r[1])
    assert share > 0.1, f"the spinner ran {share:.1%} of its free rate during a {elapsed:.3f} s evaluation"


def test_two_fits_in_two_threads_run_at_once(cayman):
    """Two fits started together in two threads overlap in time. Without a released GIL
    the second could only start when the first ended: their [start, end] intervals would
    overlap by a few milliseconds at most, not by most of a fit."""
    garnet = brdfit.read(str(CAYMAN.parent / "garnet_red.brdf"), rgb=True)
    barrier = threading.Barrier(2)
    spans, results, errors = {}, {}, []

    def work(key, samples):
        try:
            barrier.wait()
            t0 = time.perf_counter()
            results[key] = brdfit.fit(samples, "disney", **LONG_FIT)
            spans[key] = (t0, time.perf_counter())
        except BaseException as e:  # reported below
            errors.append(e)

    threads = [threading.Thread(target=work, args=("a", cayman)), threading.Thread(target=work, args=("b", garnet))]
    for t in threads:
        t.start()
    for t in threads:
        t.join(120)
    assert not errors, errors
    (a0, a1), (b0, b1) = spans["a"], spans["b"]
    overlap = min(a1, b1) - max(a0, b0)
    shorter = min(a1 - a0, b1 - b0)
    assert shorter > 0.05
    assert overlap > 0.5 * shorter, (f"fits ran {a0:.3f}..{a1:.3f} and {b0:.3f}..{b1:.3f}: overlap {overlap:.3f} s "
                                     f"of {shorter:.3f} s")
    # thread-safe: each equals the same fit run alone
    alone = brdfit.fit(cayman, "disney", **LONG_FIT)
    assert_params_identical(results["a"].params, alone.params)


# --- Ctrl-C -------------------------------------------------------------------------

INTERRUPT_SCRIPT = textwrap.dedent("""
    import signal, sys, time
    import brdfit
    # as in a terminal, whatever the test runner left SIGINT as
    signal.signal(signal.SIGINT, signal.default_int_handler)
    s = brdfit.read(sys.argv[1], rgb=True)
    print("ready", flush=True)
    try:
        # several seconds: an evolutionary global search with many evaluations
        brdfit.fit(s, "disney", backend="nlopt", algorithm="GN_ISRES", max_iterations=2000000, starts=1)
        print("finished", flush=True)
    except KeyboardInterrupt:
        print("interrupted", flush=True)
        r = brdfit.fit(s, "lambert", starts=1)
        print("after", r.metrics["n"], flush=True)
        raise
""")


def test_ctrl_c_stops_a_fit_with_keyboard_interrupt(tmp_path):
    script = tmp_path / "interrupt.py"
    script.write_text(INTERRUPT_SCRIPT)
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(Path(brdfit.__file__).parent.parent)] +
                                        ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
    p = subprocess.Popen([sys.executable, str(script), str(CAYMAN)], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, env=env, cwd=str(tmp_path))
    try:
        line = p.stdout.readline()
        assert line.strip() == "ready", f"got {line!r}; stderr: {p.stderr.read() if p.poll() is not None else ''}"
        time.sleep(1.0)  # the fit is running
        assert p.poll() is None, "the fit ended before the interrupt"
        t0 = time.perf_counter()
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=30)
        took = time.perf_counter() - t0
    finally:
        if p.poll() is None:
            p.kill()
            p.wait()
    assert "finished" not in out
    assert "interrupted" in out, f"stdout {out!r} stderr {err!r}"
    assert "after 4317" in out, "the library did not work after the interrupt"
    assert "KeyboardInterrupt" in err
    assert "Segmentation" not in err and "Fatal Python error" not in err
    # re-raised KeyboardInterrupt: Python exits by SIGINT (or status 1 / 130), never a crash
    assert p.returncode in (1, 130, -signal.SIGINT), f"exit status {p.returncode}: {err}"
    # "within a second" on a quiet machine; a loaded test machine gets some slack
    assert took < 5.0, f"{took:.2f} s from SIGINT to exit"
