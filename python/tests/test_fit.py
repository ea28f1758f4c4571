"""brdfit.fit: parameters bit-identical to `brdfit fit -o` for the same inputs and
options; .stderr, .metrics, .warnings; .model evaluates as `brdfit eval` does on the
result file; .to_json() is the file `brdfit fit -o` writes, but for wall times."""

import inspect
import json
import math
from pathlib import Path

import numpy as np
import pytest

import brdfit
from _support import (CAYMAN, DIRS_IN_PLANE, PTFE, PTFE_CLI, PTFE_KW, WALTER_RGB, assert_params_identical, cli,
                      cli_fit, flat, normalize_json_text, read_csv_table, synth, vectors_from_angles)


def _check_metrics(got, want):
    """A result's .metrics against the file's: the same names, floats equal to its
    numbers (booleans as they are), NaN where it has null."""
    assert list(got) == list(want)
    for k, w in want.items():
        g = got[k]
        if isinstance(w, bool):
            assert g is w, k
        elif w is None:
            assert isinstance(g, float) and math.isnan(g), f"{k}: {g!r} for null"
        else:
            assert isinstance(g, float) and g == w, f"{k}: {g!r} != {w!r}"


def _check_result(r, text, want):
    """Everything of a Python result against the command line's result file."""
    assert_params_identical(r.params, want["params"])
    assert_params_identical(r.stderr, want["stderr"], what="stderr")
    _check_metrics(r.metrics, want["metrics"])
    assert list(r.warnings) == want["warnings"]
    assert normalize_json_text(r.to_json()) == normalize_json_text(text)


# (model spec, command-line options, the same as keyword arguments)
CAYMAN_CASES = [
    ("walter", [], {}),
    ("lambert", [], {}),
    ("ward_iso", ["--starts", "1"], {"starts": 1}),
    ("cook_torrance", ["--residual", "cbrt", "--loss", "huber"], {"residual": "cbrt", "loss": "huber"}),
    ("microfacet:D=beckmann,G=smith_beckmann", ["--starts", "2", "--screen", "0"], {"starts": 2, "screen": 0}),
    ("walter", ["--accuracy", "fast"], {"accuracy": "fast"}),
    ("blinn_phong", ["--backend", "nlopt", "--starts", "1", "--max-iterations", "300"],
     {"backend": "nlopt", "starts": 1, "max_iterations": 300}),
    ("oren_nayar", ["--seed", "3", "--starts", "4", "--threads", "1"], {"seed": 3, "starts": 4, "threads": 1}),
]


@pytest.mark.parametrize("spec,cli_opts,kw", CAYMAN_CASES, ids=[f"{c[0]}{''.join(c[1])}" for c in CAYMAN_CASES])
def test_fit_cayman_equals_cli(tmp_path, spec, cli_opts, kw):
    text, want, _ = cli_fit(tmp_path, CAYMAN, spec, "--rgb", *cli_opts)
    s = brdfit.read(str(CAYMAN), rgb=True)
    r = brdfit.fit(s, spec, **kw)
    _check_result(r, text, want)


def test_fit_csv_with_column_options_equals_cli(tmp_path):
    text, want, _ = cli_fit(tmp_path, PTFE, "walter", *PTFE_CLI)
    r = brdfit.fit(brdfit.read(str(PTFE), **PTFE_KW), "walter")
    _check_result(r, text, want)
    assert want["channels"] == 1


def test_fit_csv_with_data_and_fit_options_equals_cli(tmp_path):
    text, want, _ = cli_fit(tmp_path, PTFE, "lambert", *PTFE_CLI, "--max-theta", "60", "--residual", "linear")
    r = brdfit.fit(brdfit.read(str(PTFE), max_theta=60, **PTFE_KW), "lambert", residual="linear")
    _check_result(r, text, want)
    assert want["samples"] < 1760


def test_fit_synthetic_recovers_and_equals_cli(tmp_path):
    data = tmp_path / "synthetic.csv"
    synth("--params", WALTER_RGB, "--pattern", "uniform", "--count", "2000", "--noise", "0.01", "--seed", "1",
          "-o", data)
    text, want, _ = cli_fit(tmp_path, data, "walter")
    r = brdfit.fit(brdfit.read(str(data)), "walter")
    _check_result(r, text, want)
    truth = json.loads(WALTER_RGB.read_text())["params"]
    np.testing.assert_allclose(flat(r.params["rho_d"]), truth["rho_d"], rtol=0.02)
    np.testing.assert_allclose(flat(r.params["alpha"]), truth["alpha"], rtol=0.02)


def _fit_fixed(s, spec, fixes):
    """fix= as the command line's NAME=VALUE list or as a dict: whichever the package takes."""
    try:
        return brdfit.fit(s, spec, fix=dict(fixes), starts=1)
    except (TypeError, ValueError):
        return brdfit.fit(s, spec, fix=[f"{k}={v}" for k, v in fixes], starts=1)


def test_fit_fix_equals_cli(tmp_path):
    text, want, _ = cli_fit(tmp_path, CAYMAN, "walter", "--rgb", "--fix", "rho_d[0]=0.1", "--fix", "f0=0.04",
                            "--starts", "1")
    r = _fit_fixed(brdfit.read(str(CAYMAN), rgb=True), "walter", [("rho_d[0]", 0.1), ("f0", 0.04)])
    assert flat(r.params["rho_d"])[0] == 0.1 and flat(r.params["f0"])[0] == 0.04
    _check_result(r, text, want)


def test_fit_on_samples_from_arrays_equals_fit_on_file(tmp_path):
    """Samples made from the file's angles and values fit as the file does (but for the
    data path, which arrays lack)."""
    s_file = brdfit.read(str(PTFE), **PTFE_KW)
    header, t = read_csv_table(PTFE)
    col = header.index
    s_arr = brdfit.Samples.from_angles(t[:, col("thetai")], t[:, col("phi")], t[:, col("thetar")],
                                       t[:, col("phir")], t[:, col("f_r11")])
    a = brdfit.fit(s_file, "ward_iso", starts=1)
    b = brdfit.fit(s_arr, "ward_iso", starts=1)
    assert_params_identical(b.params, a.params)
    assert dict(b.metrics) == dict(a.metrics)


# --- the result's parts ---------------------------------------------------------------

def test_result_fields(tmp_path, cayman):
    r = brdfit.fit(cayman, "walter")
    assert list(r.params) == ["rho_d", "rho_s", "alpha", "f0"]
    assert len(flat(r.params["rho_d"])) == 3 and len(flat(r.params["alpha"])) == 1
    assert isinstance(r.metrics, dict)
    for k in ("rmse", "rmse_log", "aic", "bic", "n", "k"):
        assert k in r.metrics
    assert r.metrics["n"] == 3 * 1439
    assert math.isfinite(r.metrics["rmse_log"]) and r.metrics["rmse_log"] > 0
    assert all(isinstance(w, str) and w for w in r.warnings)
    assert list(r.stderr) == list(r.params)
    # the result file text is JSON and holds the same parameters
    j = json.loads(r.to_json())
    assert j["model"] == "walter" and j["channels"] == 3 and j["data"] == str(CAYMAN)
    assert_params_identical(r.params, j["params"])


def test_result_model_evaluates_as_cli(tmp_path, cayman):
    r = brdfit.fit(cayman, "walter", starts=1)
    pfile = tmp_path / "r.json"
    pfile.write_text(r.to_json())
    out = cli("eval", "--params", pfile, "--dirs", DIRS_IN_PLANE).stdout
    lines = [ln for ln in out.splitlines() if ln and not ln.startswith("#")]
    ref = np.array([[float(x) for x in ln.split(",")] for ln in lines[1:]])
    header, t = read_csv_table(DIRS_IN_PLANE)
    wi, wo = vectors_from_angles(t[:, 0], t[:, 1]), vectors_from_angles(t[:, 2], t[:, 3])
    m = r.model
    assert isinstance(m, brdfit.Model)
    assert list(m.param_names) == list(r.params)
    got = np.asarray(m.eval(wi, wo, r.params))
    assert got.shape == (len(t), 3)
    np.testing.assert_allclose(got, ref[:, 4:], rtol=1e-10, atol=1e-300)


def test_result_model_reproduces_fitted_values(cayman):
    """The fitted model at the samples' own directions gives the metrics' rmse."""
    r = brdfit.fit(cayman, "lambert", starts=1)
    pred = np.asarray(r.model.eval(cayman.wi, cayman.wo, r.params))
    err = pred - np.asarray(cayman.values).reshape(pred.shape)
    rmse = math.sqrt(float(np.mean(err ** 2)))
    assert rmse == pytest.approx(r.metrics["rmse"], rel=1e-9)


def test_fit_does_not_change_the_samples(cayman):
    before = (np.array(cayman.values, copy=True), np.array(cayman.wi, copy=True))
    a = brdfit.fit(cayman, "ward_iso", starts=1)
    np.testing.assert_array_equal(np.asarray(cayman.values), before[0])
    np.testing.assert_array_equal(np.asarray(cayman.wi), before[1])
    b = brdfit.fit(cayman, "ward_iso", starts=1)
    assert_params_identical(a.params, b.params)


def test_fit_to_json_is_a_parameter_file(tmp_path, cayman):
    """What to_json writes, brdfit eval and brdfit export take."""
    r = brdfit.fit(cayman, "lambert", starts=1)
    p = tmp_path / "lambert.json"
    p.write_text(r.to_json())
    cli("export", p, "--to", "gltf", "-o", tmp_path / "x.gltf")
    assert json.loads((tmp_path / "x.gltf").read_text())["asset"]["version"] == "2.0"


# --- Python habits ----------------------------------------------------------------

def test_fit_docstring_lists_the_options():
    doc = brdfit.fit.__doc__ or ""
    for opt in ("residual", "loss", "starts", "backend", "max_iterations", "progress"):
        assert opt in doc, f"help(brdfit.fit) does not mention {opt}"
    assert brdfit.read.__doc__ and "rgb" in brdfit.read.__doc__
    assert brdfit.Model.__doc__ and brdfit.Samples.__doc__


def test_typed():
    pkg = Path(brdfit.__file__).parent
    assert (pkg / "py.typed").is_file()
    sig = inspect.signature(brdfit.fit)
    assert sig.return_annotation is not inspect.Signature.empty or any(
        p.annotation is not inspect.Parameter.empty for p in sig.parameters.values())
