"""Progress reports and cancelling: progress=callable receives brdfit.Progress (the fit's
phase, start of starts, iteration, cost, samples; in compare the material, in select the
candidate), a progress bar drawn from them reaches its end, cancel=threading.Event set
from another thread stops fit (cancelled result), compare and select (brdfit.Error
"cancelled") and a long read, and Ctrl-C stops a long read within a second."""

import dataclasses
import math
import os
import re
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import pytest

import brdfit
from _support import CAYMAN, CAYMAN_SAMPLES, GARNET, INTERRUPT_SECONDS, REPO

PHASES = ["candidates", "screen", "presolve", "data", "done"]
# A fit of a second or more on one core (disney on all of cayman, 64 starts).
LONG_FIT = dict(accuracy="best", threads=1)
LONG_SEARCH = dict(starts=64, screen=512, threads=1)
BIG_CSV_ROWS = 2_000_000


def _phases(reports):
    """The phases in the order they came, each once."""
    out = []
    for p in reports:
        if not out or out[-1] != p.phase:
            out.append(p.phase)
    return out


def _check_fit_reports(reports, spec, samples):
    """What the reports of one fit say, whatever its options: phases in the library's
    order, each phase with one count of starts and one set size, starts within the count
    and never going back, a last report "done" on all samples."""
    assert reports
    phases = _phases(reports)
    assert phases == sorted(phases, key=PHASES.index), phases
    assert phases[-1] == "done" and [p.phase for p in reports].count("done") == 1
    for prev, p in zip(reports, reports[1:]):
        if prev.phase == p.phase:
            assert (prev.starts, prev.samples) == (p.starts, p.samples)
            assert prev.start <= p.start
    for p in reports:
        assert isinstance(p, brdfit.Progress)
        assert p.model == spec and p.material is None and p.fold == 0
        assert 0 <= p.start < p.starts
        assert isinstance(p.iteration, int) and p.iteration >= 0
        assert isinstance(p.cost, float)
        if p.phase != "candidates":
            assert math.isfinite(p.cost) and p.cost >= 0
    assert reports[-1].samples == samples


# --- the reports of a fit ---------------------------------------------------------

def test_reports_of_a_presolved_fit(cayman):
    reports = []
    r = brdfit.fit(cayman, "walter", progress=reports.append, starts=4, screen=16, presolve=1200, threads=1)
    assert r.ok
    _check_fit_reports(reports, "walter", CAYMAN_SAMPLES)
    assert _phases(reports) == PHASES
    opt = r.json["optimizer"]
    by_phase = {ph: [p for p in reports if p.phase == ph] for ph in PHASES}
    # every candidate the search scored, in order, on the screening set
    assert [p.start for p in by_phase["candidates"]] == list(range(opt["candidates"]))
    assert {p.starts for p in by_phase["candidates"]} == {opt["candidates"]} == {16}
    assert {p.samples for p in by_phase["candidates"]} == {opt["screen"]["samples"]}
    # every start it counts, solved there
    assert {p.samples for p in by_phase["screen"]} == {opt["screen"]["samples"]}
    assert len({p.start for p in by_phase["screen"]}) >= opt["starts"] == 4
    # the presolve's subsample (presolve=1200), then all samples once
    assert {p.samples for p in by_phase["presolve"]} == {opt["presolve"]["samples"]} == {1200}
    assert {(p.start, p.starts, p.samples) for p in by_phase["data"]} == {(0, 1, CAYMAN_SAMPLES)}
    # the end: the fit's iterations and final cost
    done = by_phase["done"][0]
    assert done.iteration == opt["iterations"]
    assert done.cost == pytest.approx(opt["final_cost"], rel=1e-12)


def test_reports_of_small_data_and_plain_multistart(cayman):
    small = brdfit.read(CAYMAN, rgb=True, subsample=600)
    screened, plain = [], []
    brdfit.fit(small, "ward_iso", progress=screened.append, starts=3, screen=12, threads=1)
    _check_fit_reports(screened, "ward_iso", 600)
    # small data is its own screening set: the search ends there
    assert _phases(screened) == ["candidates", "screen", "done"]
    assert {p.samples for p in screened} == {600}
    brdfit.fit(small, "ward_iso", progress=plain.append, starts=3, screen=0, threads=1)
    _check_fit_reports(plain, "ward_iso", 600)
    assert _phases(plain) == ["data", "done"]
    assert sorted({p.start for p in plain if p.phase == "data"}) == [0, 1, 2]
    assert {p.starts for p in plain if p.phase == "data"} == {3}


def test_progress_is_a_frozen_value(cayman):
    reports = []
    brdfit.fit(cayman, "lambert", progress=reports.append, starts=1)
    p = reports[-1]
    with pytest.raises(dataclasses.FrozenInstanceError):
        p.cost = 0.0
    assert p == dataclasses.replace(p)
    assert {f.name for f in dataclasses.fields(brdfit.Progress)} == {
        "phase", "start", "starts", "iteration", "cost", "samples", "model", "material", "fold"}


class TextBar:
    """A progress bar of WIDTH cells drawn from the reports alone: the phases share the
    bar equally, the starts share their phase's part, "done" fills it."""

    WIDTH = 40

    def __init__(self):
        self.fractions, self.drawn = [], []

    def __call__(self, p):
        if p.phase == "done":
            f = 1.0
        else:
            f = (PHASES.index(p.phase) + p.start / p.starts) / (len(PHASES) - 1)
        self.fractions.append(f)
        cells = int(f * self.WIDTH)
        self.drawn.append("[" + "#" * cells + " " * (self.WIDTH - cells) + "]")


@pytest.mark.parametrize("options", [dict(starts=4, screen=16, presolve=1200), dict(starts=3, screen=0),
                                     dict(subsample=500)])
def test_a_progress_bar_reaches_its_end(options):
    bar = TextBar()
    r = brdfit.fit(CAYMAN, "walter", rgb=True, progress=bar, threads=1, **options)
    assert r.ok
    assert bar.fractions == sorted(bar.fractions), "the bar went back"
    assert bar.fractions[-1] == 1.0 and bar.drawn[-1] == "[" + "#" * TextBar.WIDTH + "]"
    assert bar.fractions[0] < 1.0 and len(set(bar.drawn)) > 2  # it moved on the way


def test_compare_reports_material_model_and_fold():
    reports, lock = [], threading.Lock()

    def progress(p):
        with lock:
            reports.append(p)

    data = [brdfit.read(CAYMAN, rgb=True, subsample=400), brdfit.read(GARNET, rgb=True, subsample=400)]
    models = ["lambert", "ward_iso"]
    brdfit.compare(data, models, progress=progress, starts=2, screen=8, threads=2, jobs=2, rank="cv", folds=2)
    seen = {(p.material, p.model, p.fold) for p in reports}
    assert seen == {(m, s, f) for m in (0, 1) for s in models for f in (0, 1, 2)}
    # each fit says once that it is done: a bar over the comparison's fits
    done = [(p.material, p.model) for p in reports if p.phase == "done" and p.fold == 0]
    assert sorted(done) == sorted((m, s) for m in (0, 1) for s in models)
    assert all(p.samples <= 400 for p in reports)


def test_select_reports_the_candidate(cayman):
    reports = []
    candidates = ["lambert", "ward_iso", "walter"]
    r = brdfit.select(cayman, candidates, progress=reports.append, starts=2, screen=8, threads=1)
    assert r.chosen.split(":")[0] in candidates  # the spec as the library writes it
    assert {p.model for p in reports} == set(candidates)
    assert all(p.material is None for p in reports)
    assert sorted(p.model for p in reports if p.phase == "done") == sorted(candidates)


def test_progress_and_cancel_are_checked():
    with pytest.raises(brdfit.UsageError, match="progress"):
        brdfit.fit(CAYMAN, "lambert", rgb=True, progress=3)
    with pytest.raises(brdfit.UsageError, match="cancel"):
        brdfit.fit(CAYMAN, "lambert", rgb=True, cancel=True)
    with pytest.raises(brdfit.UsageError, match="cancel"):
        brdfit.read(CAYMAN, cancel="yes")
    with pytest.raises(brdfit.UsageError, match="cancel"):
        brdfit.compare([CAYMAN], "lambert", cancel=object())


# --- cancel= ------------------------------------------------------------------------

def _set_after(event, seconds):
    """Sets event from another thread after seconds; returns a list that gets the time."""
    when = []

    def fire():
        when.append(time.monotonic())
        event.set()

    threading.Timer(seconds, fire).start()
    return when


def test_cancel_stops_a_fit(cayman):
    event = threading.Event()
    when = _set_after(event, 0.2)
    t0 = time.monotonic()
    r = brdfit.fit(cayman, "disney", cancel=event, **LONG_FIT)
    took = time.monotonic() - when[0]
    assert r.cancelled and not r.ok
    assert any("cancelled" in w for w in r.warnings)
    assert time.monotonic() - t0 >= 0.2
    assert took < INTERRUPT_SECONDS, f"{took:.2f} s from the event to the end of the fit"
    # a set event stops the next call at once; an unset one changes nothing
    assert brdfit.fit(cayman, "disney", cancel=event, **LONG_FIT).cancelled
    a = brdfit.fit(cayman, "walter", starts=2, threads=1)
    b = brdfit.fit(cayman, "walter", starts=2, threads=1, cancel=threading.Event())
    assert b.ok and a.params == b.params


@pytest.mark.parametrize("call", ["compare", "select"])
def test_cancel_stops_compare_and_select(cayman, call):
    models = ["lambert", "walter", "cook_torrance", "disney"]
    event = threading.Event()
    when = _set_after(event, 0.2)
    with pytest.raises(brdfit.Error, match="cancelled") as e:
        if call == "compare":
            brdfit.compare([cayman, brdfit.read(GARNET, rgb=True)], models, cancel=event, **LONG_SEARCH)
        else:
            brdfit.select(cayman, models, cancel=event, **LONG_SEARCH)
    took = time.monotonic() - when[0]
    assert e.value.code == "cancelled" and not isinstance(e.value, brdfit.UsageError)
    assert took < INTERRUPT_SECONDS, f"{took:.2f} s from the event to the exception"


def test_progress_true_stops_compare(cayman):
    calls = []

    def stop_at_tenth(p):
        calls.append(p)
        return len(calls) >= 10

    with pytest.raises(brdfit.Error, match="cancelled"):
        brdfit.compare([cayman], ["walter", "disney"], progress=stop_at_tenth, jobs=1, threads=1)
    assert len(calls) == 10


@pytest.fixture(scope="module")
def big_csv(tmp_path_factory):
    """A CSV of BIG_CSV_ROWS samples (about 2 s to read here), written quickly: one block
    of lines repeated."""
    path = tmp_path_factory.mktemp("big") / "big.csv"
    block = "".join("%d,%d,%d,%d,0.%04d,0.%04d,0.%04d\n" % (i % 80, (i * 7) % 360, (i * 3) % 80, (i * 11) % 360,
                                                          i % 9973, (i * 3) % 9973, (i * 5) % 9973)
                    for i in range(10000))
    with open(path, "w") as f:
        f.write("theta_i,phi_i,theta_o,phi_o,r,g,b\n")
        for _ in range(BIG_CSV_ROWS // 10000):
            f.write(block)
    yield path
    path.unlink()


def test_cancel_stops_a_read(big_csv):
    event = threading.Event()
    event.set()
    t0 = time.monotonic()
    with pytest.raises(brdfit.Error, match="cancelled") as e:
        brdfit.read(big_csv, cancel=event)
    assert e.value.code == "cancelled" and time.monotonic() - t0 < 0.5
    # set while it reads: it stops there
    event = threading.Event()
    when = _set_after(event, 0.2)
    with pytest.raises(brdfit.Error, match="reading cancelled") as e:
        brdfit.read(big_csv, cancel=event)
    took = time.monotonic() - when[0]
    assert str(big_csv) in str(e.value)
    assert took < INTERRUPT_SECONDS, f"{took:.2f} s from the event to the exception"
    # a fit given the file name stops in its reading just the same
    event = threading.Event()
    when = _set_after(event, 0.2)
    with pytest.raises(brdfit.Error, match="reading cancelled"):
        brdfit.fit(big_csv, "lambert", cancel=event)
    assert time.monotonic() - when[0] < INTERRUPT_SECONDS



def test_cancel_stops_info_read_all_and_tradeoff(big_csv, cayman):
    # The other calls that read take the same event.
    for call in (lambda e: brdfit.info(big_csv, cancel=e), lambda e: brdfit.read_all(big_csv.parent, cancel=e)):
        event = threading.Event()
        when = _set_after(event, 0.2)
        with pytest.raises(brdfit.Error, match="reading cancelled") as e:
            call(event)
        assert e.value.code == "cancelled" and time.monotonic() - when[0] < INTERRUPT_SECONDS
    # tradeoff stopped before its first fit: a table with nothing run, nothing recommended
    event = threading.Event()
    event.set()
    t = brdfit.tradeoff(cayman, "lambert", cancel=event, samples=[300, "all"], methods="ceres", threads=1)
    assert {r["status"] for r in t.rows} <= {"failed", "not_run"} and t.recommended is None

READ_SCRIPT = textwrap.dedent("""
    import signal, sys, time
    import brdfit
    signalled = []

    def handler(*_):  # Python's own, with the moment it ran
        signalled.append(time.monotonic())
        raise KeyboardInterrupt

    signal.signal(signal.SIGINT, handler)
    print("ready", flush=True)
    try:
        brdfit.read(sys.argv[1])
        print("finished", flush=True)
    except KeyboardInterrupt:
        print("interrupted %.3f" % (time.monotonic() - signalled[0]), flush=True)
        print("after", len(brdfit.read(sys.argv[2], rgb=True)), flush=True)
""")


def test_ctrl_c_stops_a_read(tmp_path, big_csv):
    script = tmp_path / "read.py"
    script.write_text(READ_SCRIPT)
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(Path(brdfit.__file__).parent.parent)] +
                                        ([env["PYTHONPATH"]] if env.get("PYTHONPATH") else []))
    p = subprocess.Popen([sys.executable, str(script), str(big_csv), str(CAYMAN)], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, env=env)
    try:
        assert p.stdout.readline().strip() == "ready"
        time.sleep(0.3)  # the read is under way (it takes seconds)
        assert p.poll() is None
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=60)
    finally:
        if p.poll() is None:
            p.kill()
            p.wait()
    assert p.returncode == 0, err
    assert "finished" not in out, "the read ended before the interrupt"
    took = float(out.split("interrupted ")[1].split()[0])
    assert took < INTERRUPT_SECONDS, f"{took:.2f} s from SIGINT to KeyboardInterrupt"
    assert f"after {CAYMAN_SAMPLES}" in out, "the library did not work after the interrupt"


def test_the_docs_progress_bar_runs(tmp_path):
    """docs/python.md's progress bar ("Long fits"), run as written."""
    text = (REPO / "docs" / "python.md").read_text()
    section = text.split("## Long fits", 1)[1].split("\n## ", 1)[0]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    (tmp_path / "examples").symlink_to(REPO / "examples")
    (tmp_path / "bar.py").write_text("import brdfit\n" + code)
    env = dict(os.environ, PYTHONPATH=str(Path(brdfit.__file__).parent.parent))
    p = subprocess.run([sys.executable, "bar.py"], cwd=tmp_path, env=env, capture_output=True, text=True,
                       timeout=120)
    assert p.returncode == 0, p.stderr
    assert p.stdout.splitlines()[-1] == "[" + "#" * 40 + "] walter done"  # text mode reads "\r" as a line end
