"""One set of rules: the package restates none of the library's (issue 35).

- A scene-weighted fit and compare give the command line's metrics, whether the data
  reach the call as a file name with its options or as samples read before.
- The keyword options, their defaults, ranges and help come from the library's table
  (brdfit.options), and no option name, default or range is written in python/brdfit/.
"""

import ast
import json
from pathlib import Path

import pytest

import brdfit
from _support import CAYMAN, EXAMPLES, cli, normalize_json_text

TURNTABLE = EXAMPLES / "scenes" / "turntable.json"
FAST = dict(threads=1, starts=2, screen=8)
FAST_CLI = ["--threads", "1", "--starts", "2", "--screen", "8"]
PACKAGE = Path(brdfit.__file__).resolve().parent
# _keywords.py is generated from the library's table (test_types checks that it is up to
# date), so it names options by construction.
SOURCES = sorted(p for p in (Path(__file__).resolve().parents[1] / "brdfit").glob("*.py") if p.name != "_keywords.py")


def _cli_fit(tmp_path, *options):
    out = tmp_path / "fit.json"
    cli("fit", CAYMAN, "-m", "walter", *options, "-q", "-o", out)
    return json.loads(out.read_text())


def test_scene_fit_metrics_equal_the_command_lines(tmp_path):
    want = _cli_fit(tmp_path, "--rgb", "--scene", TURNTABLE, *FAST_CLI)
    by_file = brdfit.fit(CAYMAN, "walter", rgb=True, scene=TURNTABLE, **FAST)
    read_first = brdfit.fit(brdfit.read(CAYMAN, rgb=True, scene=TURNTABLE), "walter", **FAST)
    for got in (by_file, read_first):
        for key in ("rmse", "rmse_log", "rmse_cos", "rmse_rel", "bic", "aic", "n"):
            assert got.metrics[key] == want["metrics"][key], key
        assert got.params == want["params"]
    # Weighted by the scene, not every sample alike: the unweighted error differs.
    plain = _cli_fit(tmp_path, "--rgb", *FAST_CLI)
    assert plain["metrics"]["rmse_log"] != want["metrics"]["rmse_log"]


def test_scene_compare_metrics_equal_the_command_lines(tmp_path):
    out = tmp_path / "c.json"
    cli("compare", CAYMAN, "-m", "lambert,walter", "--rgb", "--scene", TURNTABLE, *FAST_CLI, "-q", "--json", out)
    want = json.loads(out.read_text())
    for data in (CAYMAN, brdfit.read(CAYMAN, rgb=True, scene=TURNTABLE)):
        kw = dict(rgb=True, scene=TURNTABLE) if data is CAYMAN else {}
        got = brdfit.compare([data], "lambert,walter", **kw, **FAST)
        for g, w in zip(got.json["materials"][0]["fits"], want["materials"][0]["fits"]):
            for key in ("rmse_log", "rmse", "bic", "error", "rank"):
                assert g[key] == w[key], (g["model"], key)


def test_keywords_are_the_librarys_table():
    names = {t: {d["name"] for d in brdfit.options(t)} for t in ("read", "fit", "compare", "select", "tradeoff")}
    assert {"max_theta", "scene", "subsample", "seed", "rgb"} <= names["read"]
    assert names["read"] < names["fit"]
    assert "accuracy" in names["fit"] and "accuracy" not in names["compare"]  # as the commands take them
    assert {"tolerance", "error", "rank", "folds", "jobs"} <= names["compare"]
    assert names["read"] < names["tradeoff"] and "accuracy" not in names["tradeoff"]
    assert {"samples", "methods", "residuals", "starts_list", "test_fraction", "cost", "repeats"} <= names["tradeoff"]
    tolerance = {d["name"]: d for d in brdfit.options("compare")}["tolerance"]
    assert tolerance["default"] == "0.05" and tolerance["range"]
    # Help comes from the table too, with keywords for option names.
    assert "max_theta=DEG" in brdfit.read.__doc__
    assert "--" not in brdfit.fit.__doc__.split("keywords:")[1]


def test_messages_name_keywords_and_come_from_the_library():
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.read(CAYMAN, max_theta=95)
    assert str(e.value) == "max_theta needs degrees in (0, 90], got '95'"
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.read(CAYMAN, rgb=True, color="xyz")
    assert str(e.value) == "rgb and color exclude each other"
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.compare([CAYMAN], "walter", accuracy="fast")
    assert "accuracy is not an option of compare" in str(e.value)


def _option_literals():
    """The string constants where a rule about options would live in the package's code
    (compared with, tested for membership, dict keys and subscripts, lists and tuples of
    names), and every number, with where it is."""
    strings, numbers = set(), []
    for path in SOURCES:
        tree = ast.parse(path.read_text(), str(path))
        for n in ast.walk(tree):
            holders = []
            if isinstance(n, ast.Compare):
                holders = [n.left] + list(n.comparators)
            elif isinstance(n, ast.Dict):
                holders = [k for k in n.keys if k is not None]
            elif isinstance(n, ast.Subscript):
                holders = [n.slice]
            elif isinstance(n, (ast.Tuple, ast.List, ast.Set)):
                holders = list(n.elts)
            for h in holders:  # the constants themselves, or in a tuple, list or set there
                for c in ([h] + list(h.elts) if isinstance(h, (ast.Tuple, ast.List, ast.Set)) else [h]):
                    if isinstance(c, ast.Constant) and isinstance(c.value, str):
                        strings.add(c.value)
            if isinstance(n, ast.Constant) and isinstance(n.value, (int, float)) and not isinstance(n.value, bool):
                numbers.append((path.name, n.lineno, n.value))
    return strings, numbers


def test_the_package_holds_no_option_default_or_range():
    strings, numbers = _option_literals()
    table = [d for t in ("read", "fit", "compare", "select", "tradeoff") for d in brdfit.options(t)]
    # No option is named in the code: the library's table names them. "fix" and "bound"
    # are read as dicts (their shape is the package's), so their names are the exception.
    named = sorted(d["name"] for d in table if d["name"] in strings and d["name"] not in ("fix", "bound"))
    assert named == [], "options named in python/brdfit: %s" % named
    # No default and no bound of a range is written as a number (0, 1, 2 and small
    # counts are indices and array shapes, not option values).
    values = {float(d[k]) for d in table for k in ("default",) if d[k] and d[k].replace(".", "").replace("e-", "")
              .isdigit()}
    values |= {float(b) for d in table for b in (d.get("lo"), d.get("hi")) if isinstance(b, (int, float))}
    suspicious = [(f, line, v) for f, line, v in numbers
                  if float(v) in values and float(v) not in (0.0, 1.0, 2.0, 3.0, 4.0)]
    assert suspicious == [], "option values written in python/brdfit: %s" % suspicious
    # The range texts and the defaults' texts are the library's, not the package's.
    for d in table:
        for k in ("range", "default"):
            if d[k] and len(d[k]) > 3:
                assert d[k] not in strings, "%s's %s restated: %r" % (d["name"], k, d[k])


def test_select_equals_the_command_line(tmp_path):
    out, fit = tmp_path / "s.json", tmp_path / "chosen.json"
    cli("select", CAYMAN, "--rgb", "--scene", TURNTABLE, "--models", "lambert,walter,ward_iso", *FAST_CLI, "-q",
        "--json", out, "-o", fit)
    got = brdfit.select(str(CAYMAN), "lambert,walter,ward_iso", rgb=True, scene=TURNTABLE, **FAST)
    assert got.to_json() == out.read_text()
    assert normalize_json_text(got.fit.to_json()) == normalize_json_text(fit.read_text())
    assert got.chosen == json.loads(fit.read_text())["model"] + ":" + ",".join(
        "%s=%s" % kv for kv in json.loads(fit.read_text())["options"].items())
    # The default candidates are the library's, as the command's.
    few = brdfit.read(CAYMAN, luminance=True, subsample=300)
    assert len(brdfit.select(few, threads=1, starts=1).json["candidates"]) > 10


def test_no_temporary_files():
    # Results come back in memory (bf_fit_result_json, bf_compare_json, bf_select_json,
    # bf_export_text, bf_params_parse): the package never writes a file of its own.
    for path in SOURCES:
        assert "tempfile" not in path.read_text(), path.name
