"""brdfit.info: every number `brdfit info --json` reports, and the report as the command
prints it (JSON and text, byte for byte), for the same file and data options (drops,
negatives, a scene, a subsample, spectral data), and its errors in the library's words."""

import json
import math
import sys

import numpy as np
import pytest

import brdfit
from _support import CAYMAN, DATA, EXAMPLES, PTFE, PTFE_CLI, PTFE_KW, cli

TURNTABLE = EXAMPLES / "scenes" / "turntable.json"


def _same(got, want):
    """A number equals the command's (JSON null: NaN, nothing covered). cJSON writes 15
    digits where they read back within its own tolerance (a relative DBL_EPSILON), 17
    otherwise: that tolerance is the comparison's."""
    if want is None:
        return math.isnan(got)
    return abs(got - want) <= max(abs(got), abs(want)) * sys.float_info.epsilon


def _check(got, want, path):
    """got (a brdfit.Info) holds every value of want (brdfit info --json)."""
    r = got.report
    assert got.path == str(path) == want["file"]
    assert r.read == want["samples_read"] and got.n == want["samples"] == r.kept == got.samples.n
    assert got.channel_names == want["channels"]
    if want["wavelengths"] is None:
        assert got.wavelengths is None
    else:
        assert all(_same(g, w) for g, w in zip(got.wavelengths, want["wavelengths"]))
        assert len(got.wavelengths) == len(want["wavelengths"])
    assert got.weighted == want["weighted"]
    prep = want["prep"]
    assert (r.below_horizon, r.nonfinite, r.above_max_theta, r.negative, r.subsampled_out, r.kept) == (
        prep["below_horizon"], prep["nonfinite"], prep["above_max_theta"], prep["negative"], prep["subsampled_out"],
        prep["kept"])
    assert got.options["negative"] == prep["negative_action"]
    if want["scene"] is None:
        assert not r.scene and got.options["scene"] == ""
    else:
        assert r.scene and (r.scene_in, r.scene_kept) == (want["scene"]["samples_in"], want["scene"]["kept"])
        assert got.options["scene"] == want["scene"]["file"]
    for k in ("theta_i", "theta_o", "theta_h", "theta_d"):
        lo, hi = getattr(got, k)
        assert _same(lo, want["coverage_deg"][k]["min"]) and _same(hi, want["coverage_deg"][k]["max"]), k
    c = want["counts"]
    assert (got.below_horizon, got.nonfinite, got.negative, got.zero) == (
        c["below_horizon"], c["nonfinite"], c["negative"], c["zero"])
    assert [v["channel"] for v in want["values"]] == got.channel_names
    for i, v in enumerate(want["values"]):
        for g, w in ((got.value_min[i], v["min"]), (got.value_max[i], v["max"]), (got.value_mean[i], v["mean"])):
            assert _same(g, w), (v, g)


CASES = [
    ("rgb", CAYMAN, ["--rgb"], dict(rgb=True)),
    ("spectral", CAYMAN, [], {}),
    ("drops", PTFE, PTFE_CLI + ["--max-theta", "60", "--negative", "drop", "--subsample", "300", "--seed", "4"],
     dict(PTFE_KW, max_theta=60, negative="drop", subsample=300, seed=4)),
    ("clamp", CAYMAN, ["--luminance", "--negative", "clamp"], dict(luminance=True, negative="clamp")),
    ("scene", CAYMAN, ["--rgb", "--scene", str(TURNTABLE), "--subsample", "50"],
     dict(rgb=True, scene=str(TURNTABLE), subsample=50)),
    ("csv", DATA / "dirs_small.csv", ["--values", "theta_o"], dict(values="theta_o")),
]


@pytest.mark.parametrize("name,path,cli_opts,kw", CASES, ids=[c[0] for c in CASES])
def test_info_equals_the_commands_json(name, path, cli_opts, kw):
    printed = cli("info", path, *cli_opts, "--json").stdout
    want = json.loads(printed)
    got = brdfit.info(path, **kw)
    _check(got, want, path)
    # The reports themselves, byte for byte: the library makes them for both.
    assert got.json == printed
    assert got.text == cli("info", path, *cli_opts).stdout


def test_info_counts_what_was_dropped():
    # The drops add up: read = every drop + kept (a sample counts once).
    got = brdfit.info(PTFE, **PTFE_KW, max_theta=60, negative="drop", subsample=300)
    r = got.report
    assert r.above_max_theta > 0 and r.subsampled_out > 0 and r.kept == 300
    assert r.read == r.below_horizon + r.nonfinite + r.above_max_theta + r.negative + r.subsampled_out + r.kept
    assert got.theta_i[1] <= 60 and got.theta_o[1] <= 60
    # The samples are those a fit sees: brdfit.read's with the same options.
    same = brdfit.read(PTFE, **PTFE_KW, max_theta=60, negative="drop", subsample=300)
    assert np.array_equal(got.samples.values, same.values)


def test_info_errors_are_the_librarys(tmp_path):
    missing = tmp_path / "nope.csv"
    p = cli("info", missing, ok=False)
    assert p.returncode == 1
    with pytest.raises(brdfit.Error) as e:
        brdfit.info(missing)
    assert not isinstance(e.value, brdfit.UsageError)
    assert "brdfit info: " + str(e.value) == p.stderr.strip()
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.info(CAYMAN, max_theta=95)
    assert str(e.value) == "max_theta needs degrees in (0, 90], got '95'"
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.info(CAYMAN, starts=3)  # a fit's option, not a read's
    assert "starts" in str(e.value)
    with pytest.raises(brdfit.UsageError):
        brdfit.info(42)
