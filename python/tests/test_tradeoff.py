"""brdfit.tradeoff is `brdfit tradeoff`: the same JSON byte for byte for the same data and
options, the same recommendation and plot, and bad options refused with the command's
words, naming the keyword."""

import json
import os
import re
import subprocess

import pytest

import brdfit
from _support import CAYMAN, REPO, cli

# A small grid on the bundled car paint: 1439 samples, 288 held out.
FAST = dict(rgb=True, samples=[300, "all"], methods="ceres", starts_list=1, seed=1, threads=1)
FAST_CLI = ["--rgb", "--samples", "300,all", "--methods", "ceres", "--starts-list", "1", "--seed", "1",
            "--threads", "1"]


def _cli_tradeoff(tmp_path, data, model, *options):
    """`brdfit tradeoff`: (its JSON's text, its stdout)."""
    out = tmp_path / "t.json"
    p = cli("tradeoff", data, "-m", model, *options, "-q", "--json", out)
    return out.read_text(), p.stdout


def test_json_equals_the_command_lines(tmp_path):
    text, stdout = _cli_tradeoff(tmp_path, CAYMAN, "walter", *FAST_CLI)
    got = brdfit.tradeoff(str(CAYMAN), "walter", **FAST)
    assert got.to_json() == text
    table = json.loads(text)
    assert got.json == table
    assert [r["samples"] for r in got.rows] == [300, 1151]
    assert got.recommended is got.rows[table["recommended"]] and got.best is got.rows[table["best"]]
    assert got.recommended["within_tolerance"] and got.recommended["status"] == "ok"
    # The recommendation is the command's, as a brdfit fit command line.
    line = [ln for ln in stdout.splitlines() if ln.startswith("recommended: ")][0]
    assert line.endswith("): " + got.command)
    assert got.command.startswith("brdfit fit %s --rgb --seed 1 --threads 1 -m walter " % CAYMAN)
    # The plot is the command's too.
    plot = tmp_path / "cli.svg"
    cli("tradeoff", CAYMAN, "-m", "walter", *FAST_CLI, "-q", "--plot", plot, "--plot-size", "320x200")
    sized = brdfit.tradeoff(str(CAYMAN), "walter", plot_size="320x200", **FAST)
    sized.write_plot(tmp_path / "py.svg")
    assert (tmp_path / "py.svg").read_bytes() == plot.read_bytes()
    assert 'width="320' in plot.read_text()


def test_json_equals_the_command_lines_other_options(tmp_path):
    # Samples read first (their path names the data), more lists, another error, fraction
    # and tolerance, lists as Python lists.
    text, _ = _cli_tradeoff(tmp_path, CAYMAN, "lambert", "--rgb", "--samples", "200,1k", "--residuals", "log,linear",
                            "--starts-list", "auto,2", "--test-fraction", "0.3", "--error", "rmse", "--tolerance",
                            "0.2", "--seed", "4", "--threads", "1", "--max-theta", "80")
    data = brdfit.read(CAYMAN, rgb=True)
    got = brdfit.tradeoff(data, "lambert", samples=["200", "1k"], residuals=["log", "linear"],
                          starts_list=["auto", 2], test_fraction=0.3, error="rmse", tolerance=0.2, seed=4, threads=1,
                          max_theta=80)
    assert got.to_json() == text
    table = json.loads(text)
    assert table["error"] == "rmse" and table["test_fraction"] == 0.3 and len(got.rows) == 16
    assert {r["residual"] for r in got.rows} == {"log", "linear"}
    # The base options are repeated as they were given to this call (rgb went to read).
    assert " --seed 4 --threads 1 --max-theta 80 -m lambert " in got.command


def _cli_message(*options):
    p = cli("tradeoff", CAYMAN, "-m", "walter", *options, ok=False)
    assert p.returncode == 2, p.stderr
    return p.stderr.strip()


@pytest.mark.parametrize("keyword, value, cli_options", [
    ("samples", "500,lots", ["--samples", "500,lots"]),
    ("samples", [0], ["--samples", "0"]),
    ("samples", "500,,all", ["--samples", "500,,all"]),
    ("methods", ["ceres", "LD_NOPE"], ["--methods", "ceres,LD_NOPE"]),
    ("residuals", "log,square", ["--residuals", "log,square"]),
    ("starts_list", [1, "x"], ["--starts-list", "1,x"]),
    ("test_fraction", 1, ["--test-fraction", "1"]),
    ("repeats", 0, ["--repeats", "0"]),
    ("cost", "time", ["--cost", "time"]),
    ("error", "mse", ["--error", "mse"]),
    ("tolerance", -1, ["--tolerance", "-1"]),
    ("plot_size", "10x10", ["--plot-size", "10x10"]),
])
def test_bad_options_refused_with_the_commands_words(keyword, value, cli_options):
    want = _cli_message(*cli_options)
    assert want.startswith("brdfit tradeoff: --")
    # The command's line, the option named as a keyword.
    want = re.sub(r"--([a-z][a-z-]*)", lambda m: m.group(1).replace("-", "_"), want[len("brdfit tradeoff: "):])
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.tradeoff(str(CAYMAN), "walter", rgb=True, **{keyword: value})
    assert str(e.value) == want
    assert str(e.value).startswith(keyword)
    assert isinstance(e.value, ValueError)


def test_other_refusals():
    # Too many settings, before any data is read.
    with pytest.raises(brdfit.UsageError, match=r"^\d+ settings is too many \(at most 100000\): shorten the lists$"):
        brdfit.tradeoff("/nonexistent.csv", "walter", samples=list(range(1, 21)), starts_list=list(range(1, 65)),
                        residuals=["log", "linear"] * 32)
    with pytest.raises(brdfit.UsageError, match="accuracy is not an option of tradeoff"):
        brdfit.tradeoff(str(CAYMAN), "walter", accuracy="fast")
    with pytest.raises(brdfit.UsageError, match="unknown model 'nosuch'"):
        brdfit.tradeoff(str(CAYMAN), "nosuch")
    # Too few samples to hold any out: the data named.
    one = brdfit.Samples.from_angles([30], [0], [30], [180], [[0.5]])
    with pytest.raises(brdfit.Error, match="^1 sample: too few to hold any out for testing$"):
        brdfit.tradeoff(one, "lambert")


def test_options_are_the_tables():
    table = {d["name"]: d for d in brdfit.options("tradeoff")}
    assert {"samples", "methods", "residuals", "starts_list", "test_fraction", "cost", "timing", "repeats", "error",
            "tolerance", "plot_size", "max_theta", "starts", "backend"} <= set(table)
    assert "accuracy" not in table and "rank" not in table
    help_text = cli("tradeoff", "--help").stdout
    for d in table.values():
        if d["group"] == "tradeoff":
            assert d["help"].split("\n")[0] in help_text, d["name"]
    assert table["samples"]["default"] == "1000,4000,16000,64000,all"
    assert table["test_fraction"]["range"] == "a number between 0 and 1 (exclusive)"
    assert "samples=N,...|all" in brdfit.tradeoff.__doc__


def test_progress_stops_and_samples_without_a_file():
    # progress returning True stops the run: the fit in progress ends cancelled, the rest
    # do not run, and nothing is recommended.
    calls = []
    got = brdfit.tradeoff(str(CAYMAN), "lambert", lambda p: calls.append(p) or True, rgb=True,
                          samples=[300, "all"], threads=1)
    assert calls and calls[0].model == "lambert" and [r["status"] for r in got.rows] == ["failed", "not_run", "not_run", "not_run"]
    assert got.recommended is None and got.command is None and got.best is None
    # Samples made in memory: no data name.
    data = brdfit.read(CAYMAN, luminance=True)
    mem = brdfit.Samples.from_angles(*data.angles(), data.values)
    got = brdfit.tradeoff(mem, "lambert", samples="all", methods="ceres", threads=1)
    assert got.json["data"] == "" and got.json["samples"] == data.n and len(got.rows) == 1
    assert got.command.startswith("brdfit fit  --threads 1 -m lambert ")


def test_docs_example_runs_as_written(tmp_path):
    text = (REPO / "docs" / "python.md").read_text()
    section = text.split("## Cost against accuracy", 1)[1].split("\n## ", 1)[0]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    (tmp_path / "examples").symlink_to(REPO / "examples")
    (tmp_path / "t.py").write_text("import brdfit\n" + code)
    env = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(brdfit.__file__)))
    p = subprocess.run(["/usr/bin/python3", "t.py"], cwd=tmp_path, env=env, capture_output=True, text=True,
                       timeout=300)
    assert p.returncode == 0, p.stderr
    assert "brdfit fit examples/cornell/cayman.brdf --rgb -m walter " in p.stdout
    assert (tmp_path / "tradeoff.svg").read_text().startswith("<?xml")
