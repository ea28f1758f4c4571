"""Results as NumPy and pandas users take them: FitResult's numbers as floats with NaN for
the library's null, .residuals() from the library's objective, FitResult.from_json,
pickling (also through a process pool), and CompareResult / SelectResult as DataFrames."""

import functools
import json
import math
import multiprocessing
import os
import pickle
import shutil
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pandas as pd
import pytest

import brdfit
from _support import CAYMAN, DIRS_IN_PLANE, GARNET, PTFE, PTFE_KW, WALTER_RGB, cli_fit, normalize_json_text, \
    read_csv_table, vectors_from_angles


def _same(got, want):
    """got (a result's float, list or dict) equals want (the same, or the JSON's value
    with null for NaN), NaN matching NaN or null, value for value."""
    if isinstance(want, dict):
        assert isinstance(got, dict) and list(got) == list(want), (got, want)
        for k in want:
            _same(got[k], want[k])
    elif isinstance(want, list):
        assert isinstance(got, list) and len(got) == len(want), (got, want)
        for g, w in zip(got, want):
            _same(g, w)
    elif want is None or (isinstance(want, float) and math.isnan(want)):
        assert isinstance(got, float) and math.isnan(got), (got, want)
    elif isinstance(want, bool):
        assert got is want
    elif isinstance(want, (int, float)):
        assert isinstance(got, float) and got == want, (got, want)
    else:
        assert got == want, (got, want)


@pytest.fixture(scope="module")
def samples():
    return brdfit.read(str(CAYMAN), rgb=True)


@pytest.fixture(scope="module")
def lambert(samples):
    return brdfit.fit(samples, "lambert", starts=1)


# --- numbers: floats, NaN for null ----------------------------------------------------

def test_numbers_are_floats_with_nan_where_the_json_has_null(lambert):
    j = json.loads(lambert.to_json())
    # rho_d[0] sits on its bound 0: the JSON has 0 (an integer) and a null standard error
    assert j["params"]["rho_d"][0] == 0 and j["stderr"]["rho_d"][0] is None
    assert lambert.params["rho_d"][0] == 0.0 and isinstance(lambert.params["rho_d"][0], float)
    assert math.isnan(lambert.stderr["rho_d"][0])
    assert all(math.isfinite(v) and v > 0 for v in lambert.stderr["rho_d"][1:])
    _same(lambert.params, j["params"])
    _same(lambert.stderr, j["stderr"])
    _same(lambert.metrics, j["metrics"])
    assert lambert.metrics["n"] == 3.0 * 1439 and lambert.metrics["weighted"] is False


def test_criteria_a_robust_loss_leaves_undefined_are_nan(samples):
    r = brdfit.fit(samples, "lambert", starts=1, loss="huber")
    j = json.loads(r.to_json())
    for k in ("loglik", "aic", "aicc", "bic"):
        assert j["metrics"][k] is None
        assert isinstance(r.metrics[k], float) and math.isnan(r.metrics[k])
    assert math.isfinite(r.metrics["rmse_log"]) and r.metrics["rmse_log"] == j["metrics"]["rmse_log"]
    assert repr(r) == "brdfit.FitResult('lambert', ok=True, rmse_log=%r)" % r.metrics["rmse_log"]


def test_a_cancelled_fit_has_nan_standard_errors_and_no_residuals(samples):
    r = brdfit.fit(samples, "walter", starts=1, progress=lambda p: True)
    assert r.cancelled and not r.ok
    assert list(r.stderr) == list(r.params)
    assert all(math.isnan(v) for v in np.ravel([r.stderr[k] for k in ("alpha", "f0")]))
    assert len(r.stderr["rho_d"]) == 3 and all(math.isnan(v) for v in r.stderr["rho_d"])
    assert r.metrics == {}
    with pytest.raises(brdfit.UsageError, match="samples"):
        r.residuals()
    with pytest.raises(brdfit.Error, match="cancelled"):
        r.residuals(samples)
    back = pickle.loads(pickle.dumps(r))
    assert back.cancelled and not back.ok and back.params == r.params and back.spec == r.spec
    with pytest.raises(brdfit.Error, match="cancelled"):
        back.to_json()


# --- residuals --------------------------------------------------------------------------

@pytest.mark.parametrize("form,metric", [("log", "rmse_log"), ("linear", "rmse"), ("cosine", "rmse_cos")])
def test_residuals_rms_is_the_metric_of_their_form(samples, form, metric):
    r = brdfit.fit(samples, "walter", starts=1, residual=form)
    e = r.residuals()
    assert e.shape == (1439, 3) and e.dtype == np.float64
    assert r.json["residual"] == form
    assert math.sqrt(float(np.mean(e ** 2))) == pytest.approx(r.metrics[metric], rel=1e-12)


def test_residuals_are_the_form_of_model_and_measurement(samples):
    """The library's residuals against the form written out in NumPy: log is
    ln(1 + f c) - ln(1 + m c), linear f - m (f the fitted model, m the measurement)."""
    for form in ("linear", "log"):
        r = brdfit.fit(samples, "ward_iso", starts=1, residual=form)
        wi, wo = samples.wi, samples.wo
        f = r.model.eval(wi, wo)
        m = np.asarray(samples.values)
        c = wi[:, 2:3]
        want = f - m if form == "linear" else np.log1p(f * c) - np.log1p(m * c)
        np.testing.assert_allclose(r.residuals(), want, rtol=1e-9, atol=1e-12)


def test_residuals_for_given_samples(samples):
    r = brdfit.fit(samples, "lambert", starts=1)
    own = r.residuals()
    np.testing.assert_array_equal(r.residuals(samples), own)
    # fewer samples: the residuals of those (the relative form aside, each residual is
    # its sample's own)
    sub = brdfit.read(str(CAYMAN), rgb=True, subsample=300, seed=1)
    e = r.residuals(sub)
    assert e.shape == (300, 3)
    np.testing.assert_allclose(e, np.log1p(r.model.eval(sub.wi, sub.wo) * sub.wi[:, 2:3])
                               - np.log1p(np.asarray(sub.values) * sub.wi[:, 2:3]), rtol=1e-9, atol=1e-12)
    with pytest.raises(brdfit.UsageError, match="samples"):
        r.residuals("cayman.brdf")
    one = brdfit.read(str(PTFE), **PTFE_KW)
    with pytest.raises(brdfit.UsageError, match="channels"):
        r.residuals(one)  # one channel for a three-channel fit


# --- from_json --------------------------------------------------------------------------

def _equal_results(a, b):
    assert a.spec == b.spec and a.ok == b.ok and a.warnings == b.warnings
    _same(a.params, b.params)
    _same(a.stderr, b.stderr)
    _same(a.metrics, b.metrics)
    assert a.to_json() == b.to_json()
    assert a.json == b.json


def test_from_json_text_and_file_give_the_fit_back(tmp_path, samples):
    r = brdfit.fit(samples, "walter", starts=1)
    path = tmp_path / "walter.json"
    path.write_text(r.to_json())
    header, t = read_csv_table(DIRS_IN_PLANE)
    wi, wo = vectors_from_angles(t[:, 0], t[:, 1]), vectors_from_angles(t[:, 2], t[:, 3])
    for back in (brdfit.FitResult.from_json(r.to_json()), brdfit.FitResult.from_json(path),
                 brdfit.FitResult.from_json(str(path))):
        _equal_results(back, r)
        assert not back.cancelled
        np.testing.assert_array_equal(back.model.eval(wi, wo), r.model.eval(wi, wo))
        for to in ("gltf", "mitsuba"):
            assert brdfit.export(back, to) == brdfit.export(r, to)
        # no samples of its own; given them, the fit's residuals
        with pytest.raises(brdfit.UsageError, match="samples"):
            back.residuals()
        np.testing.assert_array_equal(back.residuals(samples), r.residuals())


def test_from_json_reads_the_command_lines_file(tmp_path):
    text, want, path = cli_fit(tmp_path, CAYMAN, "lambert", "--rgb", "--starts", "1")
    r = brdfit.FitResult.from_json(path)
    assert r.to_json() == text
    _same(r.params, want["params"])
    _same(r.stderr, want["stderr"])
    _same(r.metrics, want["metrics"])
    assert r.ok is True and r.warnings == want["warnings"] and r.spec == "lambert"
    mine = brdfit.fit(brdfit.read(str(CAYMAN), rgb=True), "lambert", starts=1)
    assert normalize_json_text(mine.to_json()) == normalize_json_text(r.to_json())


def test_from_json_refuses_what_is_not_a_result(tmp_path):
    with pytest.raises(brdfit.UsageError, match="parameter file"):
        brdfit.FitResult.from_json(WALTER_RGB)
    with pytest.raises(brdfit.Error):
        brdfit.FitResult.from_json("{ not json")
    with pytest.raises(brdfit.Error):
        brdfit.FitResult.from_json(tmp_path / "missing.json")
    with pytest.raises(brdfit.UsageError, match="text_or_path"):
        brdfit.FitResult.from_json(42)


# --- pickling ---------------------------------------------------------------------------

def test_results_pickle_through_their_json(samples):
    f = brdfit.fit(samples, "lambert", starts=1, loss="huber")  # NaN criteria
    back = pickle.loads(pickle.dumps(f))
    _equal_results(back, f)
    assert back.params == f.params and back.metrics == f.metrics
    assert repr(back) == repr(f)

    c = brdfit.compare([samples], ["lambert", "ward_iso"], starts=1)
    cb = pickle.loads(pickle.dumps(c))
    assert cb.to_json() == c.to_json() and cb.rows == c.rows and cb.json == c.json
    assert repr(cb) == repr(c) == "brdfit.CompareResult(materials=1, models=['lambert', 'ward_iso'], best=['%s'])" \
        % c.json["materials"][0]["best"]

    s = brdfit.select(samples, ["lambert", "ward_iso"], starts=1)
    sb = pickle.loads(pickle.dumps(s))
    assert sb.to_json() == s.to_json() and sb.chosen == s.chosen and sb.candidates == s.candidates
    _equal_results(sb.fit, s.fit)
    assert repr(sb) == repr(s)


def test_a_result_of_a_file_name_that_is_not_utf8_pickles(tmp_path):
    raw = os.fsencode(str(tmp_path)) + b"/caym\xe9n.brdf"
    shutil.copy(CAYMAN, raw)
    (name,) = os.listdir(tmp_path)  # with a surrogate for the byte
    path = os.path.join(tmp_path, name)
    r = brdfit.fit(path, "lambert", rgb=True, threads=1, starts=1)
    assert r.json["data"] == path
    back = pickle.loads(pickle.dumps(r))
    _equal_results(back, r)
    saved = tmp_path / "r.json"
    saved.write_bytes(r.to_json().encode("utf-8", "surrogateescape"))
    _equal_results(brdfit.FitResult.from_json(saved), r)


def test_fit_in_a_process_pool(samples):
    """ProcessPoolExecutor.map(brdfit.fit, ...): the results come back pickled, equal to
    the same fits here."""
    fit = functools.partial(brdfit.fit, rgb=True, starts=1, threads=1)
    specs = ["lambert", "ward_iso", "walter"]
    with ProcessPoolExecutor(max_workers=2, mp_context=multiprocessing.get_context("spawn")) as pool:
        got = list(pool.map(fit, [str(CAYMAN)] * len(specs), specs))
    for spec, g in zip(specs, got):
        want = fit(str(CAYMAN), spec)
        assert isinstance(g, brdfit.FitResult) and g.spec == want.spec
        assert g.params == want.params
        _same(g.metrics, want.metrics)
        _same(g.stderr, want.stderr)
        assert normalize_json_text(g.to_json()) == normalize_json_text(want.to_json())


# --- data frames ------------------------------------------------------------------------

def _frame_equals_records(df, records, nested=("params", "stderr")):
    assert len(df) == len(records)
    for i, rec in enumerate(records):
        for k, v in rec.items():
            got = df[k].iloc[i]
            if k in nested:
                if v is None:
                    assert got is None
                else:
                    _same(got, v)
            elif v is None:
                assert (isinstance(got, float) and math.isnan(got)) or got is None, (k, got)
            elif isinstance(v, bool):
                assert bool(got) is v, (k, got)
            elif isinstance(v, (int, float)):
                assert isinstance(got, float) and got == v, (k, got, v)
            else:
                assert got == v, (k, got, v)


def test_compare_to_dataframe_equals_rows(samples):
    c = brdfit.compare([samples, brdfit.read(str(GARNET), rgb=True)], ["lambert", "ward_iso"], starts=1)
    df = c.to_dataframe()
    assert isinstance(df, pd.DataFrame)
    assert list(df.columns)[0] == "data" and set(df.columns) == set(c.rows[0])
    _frame_equals_records(df, c.rows)
    for col in ("rank", "k", "n", "error", "rmse", "rmse_log", "aic", "aicc", "bic", "cv", "rank_cv"):
        assert df[col].dtype == np.float64, col
    assert df["cv"].isna().all()  # not ranked by cross-validation: null, NaN
    assert sorted(df["rank"][:2]) == [1.0, 2.0]
    assert isinstance(df["params"][0], dict) and isinstance(df["warnings"][0], list)
    assert math.isnan(df["stderr"][0]["rho_d"][0])


def test_compare_to_dataframe_robust_loss_nan_criteria(samples):
    c = brdfit.compare([samples], ["lambert", "ward_iso"], starts=1, loss="huber", rank="error")
    df = c.to_dataframe()
    _frame_equals_records(df, c.rows)
    assert df["bic"].isna().all() and df["rank_bic"].isna().all() and df["rmse_log"].notna().all()


def test_select_candidates_and_dataframe(samples):
    s = brdfit.select(samples, ["lambert", "ward_iso", "walter"], starts=1)
    assert [c["model"] for c in s.candidates] == ["lambert", "ward_iso", "walter"]
    assert [c["spec"] for c in s.candidates if c["chosen"]] == [s.chosen]
    assert s.candidates == s.json["candidates"]
    for c in s.candidates:
        values = sum(len(v) if isinstance(v, list) else 1 for v in c["params"].values())
        assert isinstance(c["k"], int) and c["k"] == values  # every value free
        assert c["error"] == c["metrics"]["rmse_log"]
    df = s.to_dataframe()
    assert list(df["chosen"]) == [c["chosen"] for c in s.candidates]
    flat = []
    for c in s.candidates:
        rec = {"data": s.json["data"]}
        for k, v in c.items():
            if k != "metrics":
                rec[k] = v
        for k, v in c["metrics"].items():
            rec["metrics_" + k if k in c else k] = v
        flat.append(rec)
    assert set(df.columns) == set(flat[0])
    _frame_equals_records(df, flat)
    for col in ("k", "error", "rank", "rmse_log", "bic", "metrics_k"):
        assert df[col].dtype == np.float64, col


def test_to_dataframe_without_pandas_says_so(samples, monkeypatch):
    import sys
    c = brdfit.compare([samples], ["lambert"], starts=1)
    monkeypatch.setitem(sys.modules, "pandas", None)  # import pandas raises ImportError
    with pytest.raises(ImportError, match="to_dataframe\\(\\) needs pandas"):
        c.to_dataframe()


def test_covariance_is_s2_inverse_jtj_and_travels_with_the_result():
    # Noisy Phong samples, a linear fit: the covariance is s^2 (J^T J)^-1 with J the
    # model's gradient at the fitted parameters (NumPy's own inverse), the diagonal the
    # standard errors squared; a fixed parameter has a row and column of 0.
    rng = np.random.default_rng(3)
    n = 2000
    ti, to, po = rng.uniform(0, 80, n), rng.uniform(0, 80, n), rng.uniform(0, 360, n)
    truth = brdfit.Model("phong", 1, {"rho_d": 0.3, "rho_s": 0.6, "n": 40})
    ones = brdfit.Samples.from_angles(ti, 0 * ti, to, po, np.ones((n, 1)))
    v = truth.eval(ones.wi, ones.wo) * (1 + 0.05 * rng.standard_normal((n, 1)))
    s = brdfit.Samples.from_angles(ti, 0 * ti, to, po, v)
    for fix, free in ((None, [0, 1, 2]), ({"rho_d": 0.3}, [1, 2])):
        r = brdfit.fit(s, "phong", residual="linear", starts=1, fix=fix)
        val, g = r.model.eval(s.wi, s.wo, gradient=True)
        J = g[:, 0, free]
        s2 = ((val[:, 0] - s.values[:, 0]) ** 2).sum() / (n - len(free))
        want = np.zeros((3, 3))
        want[np.ix_(free, free)] = s2 * np.linalg.inv(J.T @ J)
        assert r.covariance.shape == (3, 3)
        np.testing.assert_allclose(r.covariance, want, rtol=1e-5, atol=0)
        se = np.array([r.stderr[k][0] if isinstance(r.stderr[k], list) else r.stderr[k] for k in ("rho_d", "rho_s", "n")])
        np.testing.assert_allclose(np.diag(r.covariance), se ** 2, rtol=1e-12)
        assert not r.covariance.flags.writeable
    back = pickle.loads(pickle.dumps(r))
    assert np.array_equal(back.covariance, r.covariance) and back.to_json() == r.to_json()
    assert brdfit.FitResult.from_json(r.to_json()).covariance is None
    assert brdfit.fit(s, "phong", starts=1, progress=lambda p: True).covariance is None
