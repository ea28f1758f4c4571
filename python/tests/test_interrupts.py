"""Every long call is safe to interrupt: Ctrl-C (SIGINT) and a signal handler that raises
(SIGALRM raising TimeoutError, as signal-based timeouts do) at random times into fit,
compare, select, read, eval of a large array, export, tradeoff and fit_images, 50 times
each, in a child
process: no crash, the exception within a second of the signal, and the next call works.
"""

import os
import subprocess
import sys
import textwrap

import pytest

from _images import make_stack
from _support import CAYMAN, INTERRUPT_SECONDS

# The sanitizer build's suite runs fewer, with more time for the slower library
# (python/CMakeLists.txt).
TIMES = int(os.environ.get("BRDFIT_INTERRUPT_TIMES", "50"))

CHILD = textwrap.dedent(r"""
    import os, random, signal, sys, threading, time
    import numpy as np
    import brdfit

    kind, what, times = sys.argv[1], sys.argv[2], int(sys.argv[3])
    data, stack = sys.argv[4], sys.argv[5]
    samples = brdfit.read(data, rgb=True)
    fitted = brdfit.fit(samples, "walter", threads=2, starts=1)
    n = 400000
    rng = np.random.default_rng(1)
    wi = rng.normal(size=(n, 3)); wi[:, 2] = np.abs(wi[:, 2]) + 0.1
    wo = rng.normal(size=(n, 3)); wo[:, 2] = np.abs(wo[:, 2]) + 0.1
    calls = {
        "fit": lambda: brdfit.fit(samples, "disney", threads=2),
        "compare": lambda: brdfit.compare([samples], "lambert,walter,cook_torrance,disney", jobs=2, threads=2),
        "select": lambda: brdfit.select(samples, "lambert,walter,ward_iso,disney", threads=2),
        "read": lambda: brdfit.read(data, rgb=True, subsample=500),
        "eval": lambda: fitted.model.eval(wi, wo, gradient=True),
        "export": lambda: brdfit.export(fitted, "gltf", convert=True),
        "tradeoff": lambda: brdfit.tradeoff(samples, "walter", samples=[300, "all"], threads=2),
        "fit_images": lambda: brdfit.fit_images(stack, "walter", threads=2),
    }
    call = calls[what]
    signalled = [0.0]

    def timeout(*_):
        raise TimeoutError("alarm")

    signal.signal(signal.SIGALRM, timeout)
    random.seed(7)
    worst = 0.0
    for k in range(times):
        delay = random.uniform(0.0, 0.15)
        try:
            # Armed inside the try: on a loaded machine a short delay can end while the
            # timer's thread is still being started.
            if kind == "int":
                threading.Timer(delay, lambda: (signalled.__setitem__(0, time.monotonic()),
                                                os.kill(os.getpid(), signal.SIGINT))).start()
            else:
                signalled[0] = time.monotonic() + delay
                signal.setitimer(signal.ITIMER_REAL, delay)
            while True:
                call()
        except (KeyboardInterrupt, TimeoutError):
            worst = max(worst, time.monotonic() - signalled[0])
        signal.setitimer(signal.ITIMER_REAL, 0)
        call()  # the next call works
    r = brdfit.fit(samples, "walter", threads=2, starts=1)
    assert r.ok and r.params == fitted.params, "a fit after the interrupts differs"
    print("worst %.3f s" % worst)
""")


@pytest.fixture(scope="module")
def stack(tmp_path_factory):
    # about a second to fit with two threads: signals land in every part of it
    return make_stack(tmp_path_factory.mktemp("stack") / "sphere", size=48, lights=12,
                      params={"rho_d": [0.5, 0.35, 0.2], "rho_s": 0.3, "alpha": 0.15})


@pytest.mark.parametrize("what", ["fit", "compare", "select", "read", "eval", "export", "tradeoff", "fit_images"])
@pytest.mark.parametrize("kind", ["int", "alarm"])
def test_interrupts(tmp_path, stack, kind, what):
    script = tmp_path / "child.py"
    script.write_text(CHILD)
    p = subprocess.run([sys.executable, str(script), kind, what, str(TIMES), str(CAYMAN), str(stack)], capture_output=True, text=True,
                       timeout=300, env=dict(os.environ))
    assert p.returncode == 0, "%s %s: exit %d (a signal is negative): %s" % (kind, what, p.returncode,
                                                                          p.stderr[-2000:])
    worst = float(p.stdout.split()[-2])
    assert worst < INTERRUPT_SECONDS, "%s %s: the exception came %.3f s after the signal" % (kind, what, worst)
