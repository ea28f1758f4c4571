"""brdfit.compare (.rows, .to_json() equal to `brdfit compare --json`) and
brdfit.export (files equal to `brdfit export` of the same result file)."""

import json

import numpy as np
import pytest

import brdfit
from _support import CAYMAN, GARNET, PTFE, PTFE_CLI, PTFE_KW, cli, cli_fit, normalize_json_text


def _get(row, key):
    if isinstance(row, dict):
        return row[key]
    return getattr(row, key)


def _has(row, key):
    return key in row if isinstance(row, dict) else hasattr(row, key)


def _cli_compare(tmp_path, data, models, *options):
    out = tmp_path / "compare.json"
    cli("compare", *data, "-m", ",".join(models), *options, "-q", "--json", out)
    text = out.read_text()
    return text, json.loads(text)


def _check_rows(rows, want):
    rows = list(rows)
    fits = [(m["data"], f) for m in want["materials"] for f in m["fits"]]
    assert len(rows) == len(fits)
    assert sorted(str(_get(r, "model")) for r in rows) == sorted(f["model"] for _, f in fits)
    for row in rows:
        model = _get(row, "model")
        cands = [f for _, f in fits if f["model"] == model]
        for key in ("error", "rmse_log", "bic", "rank"):
            if _has(row, key):
                assert any(_get(row, key) == f[key] for f in cands), f"{model}: {key} = {_get(row, key)}"


def test_compare_equals_cli(tmp_path):
    models = ["lambert", "walter"]
    text, want = _cli_compare(tmp_path, [CAYMAN, GARNET], models, "--rgb", "--starts", "1")
    samples = [brdfit.read(str(CAYMAN), rgb=True), brdfit.read(str(GARNET), rgb=True)]
    c = brdfit.compare(samples, models, starts=1)
    assert normalize_json_text(c.to_json()) == normalize_json_text(text)
    _check_rows(c.rows, want)
    assert len(list(c.rows)) == 4


def test_compare_ranking_options_equal_cli(tmp_path):
    models = ["lambert", "oren_nayar", "ward_iso"]
    text, want = _cli_compare(tmp_path, [PTFE], models, *PTFE_CLI, "--starts", "1", "--rank", "aic",
                              "--error", "rmse", "--tolerance", "0.2")
    c = brdfit.compare([brdfit.read(str(PTFE), **PTFE_KW)], models, starts=1, rank="aic", error="rmse",
                       tolerance=0.2)
    assert normalize_json_text(c.to_json()) == normalize_json_text(text)
    assert want["rank_by"] == "aic" and want["error"] == "rmse"
    _check_rows(c.rows, want)


def test_compare_takes_a_model_list_as_m_does(tmp_path):
    models = ["lambert", "microfacet:D=ggx,G=smith_ggx", "walter"]
    text, _ = _cli_compare(tmp_path, [CAYMAN], models, "--rgb", "--starts", "1")
    s = brdfit.read(str(CAYMAN), rgb=True)
    c = brdfit.compare([s], ",".join(models), starts=1)
    assert normalize_json_text(c.to_json()) == normalize_json_text(text)
    assert [r["spec"].split(":")[0] for r in c.rows] == ["lambert", "microfacet", "walter"]


def test_compare_rows_hold_the_fits(tmp_path):
    c = brdfit.compare([brdfit.read(str(CAYMAN), rgb=True, subsample=400)], ["lambert", "ward_iso"], starts=1)
    j = json.loads(c.to_json())
    rows = list(c.rows)
    assert len(rows) == 2
    assert {str(_get(r, "model")) for r in rows} == {"lambert", "ward_iso"}
    fits = j["materials"][0]["fits"]
    assert [f["model"] for f in fits] == ["lambert", "ward_iso"]
    assert all(f["ok"] for f in fits)
    assert all(m["samples"] == 400 for m in j["materials"])
    assert sorted(f["rank"] for f in fits) == [1, 2]


# --- export ---------------------------------------------------------------------------

@pytest.fixture(scope="module")
def walter_result_files(tmp_path_factory):
    """One fit result from the command line and the same fit from Python."""
    tmp = tmp_path_factory.mktemp("export")
    text, want, path = cli_fit(tmp, CAYMAN, "walter", "--rgb", "--starts", "1")
    r = brdfit.fit(brdfit.read(str(CAYMAN), rgb=True), "walter", starts=1)
    return tmp, path, r


@pytest.mark.parametrize("to", ["gltf", "blender", "mitsuba"])
def test_export_equals_cli(walter_result_files, to):
    tmp, cli_result, r = walter_result_files
    want = tmp / f"cli.{to}"
    cli("export", cli_result, "--to", to, "-o", want)
    got = tmp / f"py.{to}"
    brdfit.export(r, to=to, path=str(got))
    assert got.read_bytes() == want.read_bytes()


def test_export_own_model_exactly(tmp_path):
    """A gltf fit exports as itself (no conversion), equal to the command line's file."""
    text, want, path = cli_fit(tmp_path, CAYMAN, "gltf", "--rgb", "--starts", "1")
    r = brdfit.fit(brdfit.read(str(CAYMAN), rgb=True), "gltf", starts=1)
    cli("export", path, "--to", "gltf", "-o", tmp_path / "cli.gltf")
    brdfit.export(r, to="gltf", path=str(tmp_path / "py.gltf"))
    got = (tmp_path / "py.gltf").read_bytes()
    assert got == (tmp_path / "cli.gltf").read_bytes()
    doc = json.loads(got)
    assert doc["asset"]["version"] == "2.0"
    bc = doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"]
    np.testing.assert_allclose(bc[:3], want["params"]["base_color"], rtol=1e-12)


def test_export_bad_target(walter_result_files, tmp_path):
    _, _, r = walter_result_files
    with pytest.raises(ValueError) as e:
        brdfit.export(r, to="povray", path=str(tmp_path / "x.pov"))
    assert isinstance(e.value, brdfit.Error)
    assert "povray" in str(e.value)
    assert not (tmp_path / "x.pov").exists()


def test_compare_references_equal_the_command_lines(tmp_path):
    """reference= is compare's --reference (the library's option): brdfit's own result,
    named for the material, is judged as the fit judges itself, in the command's JSON."""
    fast = ["--rgb", "--threads", "1", "--starts", "2", "--screen", "8"]
    fitted = tmp_path / "refs" / "cayman.json"
    fitted.parent.mkdir()
    cli("fit", CAYMAN, "-m", "walter", *fast, "-q", "-o", fitted)
    _, want = _cli_compare(tmp_path, [CAYMAN], ["walter", "lambert"], *fast, "--reference", fitted.parent)
    for ref in (fitted.parent, [fitted], str(fitted)):
        got = brdfit.compare([CAYMAN], "walter,lambert", rgb=True, threads=1, starts=2, screen=8, reference=ref)
        refs = got.json["materials"][0]["fits"][0]["references"]
        assert refs == want["materials"][0]["fits"][0]["references"]
        assert len(refs) == 1 and refs[0]["brdfit_worse"] is False and refs[0]["cost"] == refs[0]["brdfit_cost"]
        assert refs[0]["rmse_log"] == got.json["materials"][0]["fits"][0]["rmse_log"]
        assert got.json["materials"][0]["fits"][1]["references"] == []
    with pytest.raises(brdfit.Error, match="nosuch.json: cannot open"):
        brdfit.compare([CAYMAN], "walter", rgb=True, threads=1, reference=tmp_path / "nosuch.json")
