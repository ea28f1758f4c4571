"""brdfit.__version__, brdfit.models(), brdfit.Model: parameter names, values equal to
`brdfit eval`, analytic gradients against finite differences, shapes."""

import json
import math

import numpy as np
import pytest

import brdfit
from _support import (DIRS_IN_PLANE, DIRS_SMALL, LAMBERT_RGB, WALTER_RGB, cli, cli_models, default_params,
                      interior_params, models_list, param_vector_names, read_csv_table, vectors_from_angles,
                      write_dirs_csv)


@pytest.fixture(scope="module")
def registry():
    return cli_models()


def _entry(registry, name):
    for m in registry["models"]:
        if m["name"] == name:
            return m
    raise KeyError(name)


def _random_dirs(n, seed, max_theta=85.0):
    rng = np.random.default_rng(seed)
    ti = rng.uniform(0.0, max_theta, n)
    to = rng.uniform(0.0, max_theta, n)
    pi = rng.uniform(0.0, 360.0, n)
    po = rng.uniform(0.0, 360.0, n)
    # a few special pairs: normal incidence, the mirror direction, retro-reflection
    ti = np.concatenate([[0.0, 30.0, 45.0, 60.0], ti])
    pi = np.concatenate([[0.0, 0.0, 10.0, 90.0], pi])
    to = np.concatenate([[0.0, 30.0, 45.0, 20.0], to])
    po = np.concatenate([[0.0, 180.0, 10.0, 270.0], po])
    return ti, pi, to, po


def read_csv_table_from_text(text):
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.startswith("#")]
    header = lines[0].split(",")
    rows = np.array([[float(x) for x in ln.split(",")] for ln in lines[1:]], dtype=np.float64)
    return header, rows.reshape(len(lines) - 1, len(header))


# --- version and registry -------------------------------------------------------------

def test_version_is_the_librarys():
    out = cli("--version").stdout.split()
    # "brdfit 0.1.0 (git ...)": the number is the library's version
    assert isinstance(brdfit.__version__, str)
    assert brdfit.__version__.split()[0] == out[1]


def test_models_equal_the_command_lines_json(registry):
    got = brdfit.models()
    if isinstance(got, dict):
        assert got == registry
    else:
        assert models_list(got) == registry["models"]


def test_models_lists_every_family(registry):
    names = [m["name"] for m in models_list(brdfit.models())]
    assert "lambert" in names and "walter" in names and "disney" in names
    assert names == [m["name"] for m in registry["models"]]


# --- Model: construction and parameter names ------------------------------------------

def test_param_names_walter():
    assert list(brdfit.Model("walter").param_names) == ["rho_d", "rho_s", "alpha", "f0"]
    assert list(brdfit.Model("walter", channels=3).param_names) == ["rho_d", "rho_s", "alpha", "f0"]


def test_param_names_follow_options():
    assert list(brdfit.Model("walter:fresnel=dielectric").param_names) == ["rho_d", "rho_s", "alpha", "ior"]
    assert list(brdfit.Model("microfacet:D=beckmann").param_names) == ["rho_d", "rho_s", "m", "f0"]
    assert list(brdfit.Model("walter:fresnel=none", channels=3).param_names) == ["rho_d", "rho_s", "alpha"]


def test_param_names_of_every_family(registry):
    for entry in registry["models"]:
        for channels in (1, 3):
            m = brdfit.Model(entry["name"], channels=channels)
            assert list(m.param_names) == [p["name"] for p in entry["params"]], entry["name"]


# --- eval against brdfit eval ---------------------------------------------------------

def _eval_file_case(params_file, dirs_file, channels):
    pf = json.loads(params_file.read_text())
    spec = pf["model"]
    if pf.get("options"):
        spec += ":" + ",".join(f"{k}={v}" for k, v in pf["options"].items())
    model = brdfit.Model(spec, channels=channels)
    header, table = read_csv_table(dirs_file)
    col = {h: i for i, h in enumerate(header)}
    wi = vectors_from_angles(table[:, col["theta_i"]], table[:, col["phi_i"]])
    wo = vectors_from_angles(table[:, col["theta_o"]], table[:, col["phi_o"]])
    got = model.eval(wi, wo, pf["params"])
    _, ref = read_csv_table_from_text(cli("eval", "--params", params_file, "--dirs", dirs_file).stdout)
    return np.asarray(got), ref[:, 4:]


def test_eval_equals_cli_walter_in_plane():
    got, want = _eval_file_case(WALTER_RGB, DIRS_IN_PLANE, 3)
    assert got.shape == want.shape == (30, 3)
    assert got.dtype == np.float64
    np.testing.assert_allclose(got, want, rtol=1e-10, atol=1e-300)


def test_eval_equals_cli_lambert_small():
    got, want = _eval_file_case(LAMBERT_RGB, DIRS_SMALL, 3)
    assert got.shape == want.shape
    np.testing.assert_allclose(got, want, rtol=1e-12, atol=0)
    # theta_i = 90 degrees lies on the horizon: exactly zero, as the command line says
    assert (got[2] == 0).all() and (want[2] == 0).all()
    np.testing.assert_allclose(got[0], np.array([0.8, 0.5, 0.2]) / math.pi, rtol=1e-14)


def test_eval_every_family_equals_cli(tmp_path, registry):
    """Every registered model, at its default parameters, equals brdfit eval."""
    channels = 3
    ti, pi, to, po = _random_dirs(40, seed=1, max_theta=80.0)
    dfile = tmp_path / "d.csv"
    write_dirs_csv(dfile, ti, pi, to, po)
    wi, wo = vectors_from_angles(ti, pi), vectors_from_angles(to, po)
    for entry in registry["models"]:
        name = entry["name"]
        params = default_params(entry, channels)
        pfile = tmp_path / f"{name}.json"
        pfile.write_text(json.dumps({"model": name, "channels": channels, "params": params}))
        _, ref = read_csv_table_from_text(cli("eval", "--params", pfile, "--dirs", dfile).stdout)
        want = ref[:, 4:]
        got = np.asarray(brdfit.Model(name, channels=channels).eval(wi, wo, params))
        assert got.shape == want.shape == (len(ti), channels), name
        np.testing.assert_allclose(got, want, rtol=1e-8, atol=1e-12 * max(1.0, np.abs(want).max()),
                                   err_msg=name)


# --- eval: values and shapes on their own ---------------------------------------------

def test_lambert_is_rho_over_pi():
    wi = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, 0.6, 0.8], [0.0, 0.0, -1.0]])
    wo = np.array([[0.0, 0.0, 1.0], [0.0, 0.8, 0.6], [0.8, 0.0, 0.6], [0.0, 0.0, 1.0]])
    m = brdfit.Model("lambert")
    for rho in (0.5, [0.5]):
        v = np.asarray(m.eval(wi, wo, {"rho_d": rho}))
        assert v.shape == (4, 1)
        np.testing.assert_allclose(v[:3, 0], 0.5 / math.pi, rtol=1e-15)
        assert v[3, 0] == 0.0  # below the horizon
    m3 = brdfit.Model("lambert", channels=3)
    v3 = np.asarray(m3.eval(wi, wo, {"rho_d": [0.1, 0.2, 0.3]}))
    assert v3.shape == (4, 3)
    np.testing.assert_allclose(v3[:3], np.tile([0.1, 0.2, 0.3], (3, 1)) / math.pi, rtol=1e-15)


def test_eval_normalises_directions():
    m = brdfit.Model("walter", channels=3)
    p = {"rho_d": [0.8, 0.5, 0.2], "rho_s": [0.9, 0.9, 0.9], "alpha": 0.1, "f0": 0.04}
    ti, pi, to, po = _random_dirs(10, seed=3)
    wi, wo = vectors_from_angles(ti, pi), vectors_from_angles(to, po)
    a = np.asarray(m.eval(wi, wo, p))
    b = np.asarray(m.eval(wi * 2.5, wo * 0.25, p))
    np.testing.assert_allclose(a, b, rtol=1e-12)


def test_eval_shapes_and_single_sample():
    m = brdfit.Model("ward_iso", channels=2)
    p = {"rho_d": [0.3, 0.4], "rho_s": [0.1, 0.2], "alpha": 0.2}
    for n in (1, 2, 17):
        ti, pi, to, po = _random_dirs(n, seed=n)
        ti, pi, to, po = ti[:n], pi[:n], to[:n], po[:n]
        v = np.asarray(m.eval(vectors_from_angles(ti, pi), vectors_from_angles(to, po), p))
        assert v.shape == (n, 2)
        assert np.isfinite(v).all() and (v >= 0).all()


def test_eval_does_not_depend_on_batch():
    """Each sample's value is the same whether evaluated alone or with others."""
    m = brdfit.Model("cook_torrance", channels=3)
    p = {"rho_d": [0.2, 0.3, 0.4], "rho_s": [0.5, 0.5, 0.5], "m": 0.3, "f0": 0.05}
    ti, pi, to, po = _random_dirs(30, seed=11)
    wi, wo = vectors_from_angles(ti, pi), vectors_from_angles(to, po)
    all_at_once = np.asarray(m.eval(wi, wo, p))
    for i in (0, 7, 29):
        one = np.asarray(m.eval(wi[i:i + 1], wo[i:i + 1], p))
        np.testing.assert_array_equal(one[0], all_at_once[i])


def test_eval_is_reciprocal_for_reciprocal_models(registry):
    ti, pi, to, po = _random_dirs(25, seed=5, max_theta=80.0)
    wi, wo = vectors_from_angles(ti, pi), vectors_from_angles(to, po)
    for name in ("lambert", "walter", "cook_torrance", "ward_iso"):
        entry = _entry(registry, name)
        assert entry["reciprocal"]
        m = brdfit.Model(name, channels=3)
        p = interior_params(entry, 3)
        np.testing.assert_allclose(np.asarray(m.eval(wi, wo, p)), np.asarray(m.eval(wo, wi, p)), rtol=1e-9)


# --- gradient ------------------------------------------------------------------------

def _jacobian_array(jac, n, C, names):
    P = len(names)
    if isinstance(jac, dict):
        cols = []
        for pname in dict.fromkeys(nm for nm, _ in names):
            a = np.asarray(jac[pname], dtype=np.float64).reshape(n, C, -1)
            cols.append(a)
        return np.concatenate(cols, axis=2)
    a = np.asarray(jac, dtype=np.float64)
    assert a.size == n * C * P, f"Jacobian of shape {a.shape}, expected n*C*P = {n}*{C}*{P} entries"
    return a.reshape(n, C, P)


def _with_entry(params, name, c, value):
    q = {k: (list(v) if isinstance(v, list) else v) for k, v in params.items()}
    if c is None:
        q[name] = value
    else:
        q[name][c] = value
    return q


@pytest.mark.parametrize("name,channels", [("lambert", 1), ("oren_nayar", 3), ("walter", 3), ("walter", 1),
                                           ("cook_torrance", 3), ("ward", 2), ("blinn_phong", 3),
                                           ("disney", 3), ("ashikhmin_shirley", 1)])
def test_gradient_matches_finite_differences(registry, name, channels):
    entry = _entry(registry, name)
    m = brdfit.Model(name, channels=channels)
    params = interior_params(entry, channels)
    ti, pi, to, po = _random_dirs(12, seed=7, max_theta=75.0)
    wi, wo = vectors_from_angles(ti, pi), vectors_from_angles(to, po)
    n = len(ti)
    out = m.eval(wi, wo, params, gradient=True)
    assert isinstance(out, tuple) and len(out) == 2
    values, jac = out
    values = np.asarray(values)
    np.testing.assert_array_equal(values, np.asarray(m.eval(wi, wo, params)))
    names = param_vector_names(entry, channels)
    J = _jacobian_array(jac, n, channels, names)
    assert np.isfinite(J).all()
    for k, (pname, c) in enumerate(names):
        x = params[pname][c] if c is not None else params[pname]
        h = 1e-6 * max(1.0, abs(x))
        up = np.asarray(m.eval(wi, wo, _with_entry(params, pname, c, x + h)))
        dn = np.asarray(m.eval(wi, wo, _with_entry(params, pname, c, x - h)))
        fd = (up - dn) / (2 * h)
        scale = max(1.0, np.abs(values).max())
        np.testing.assert_allclose(J[:, :, k], fd, rtol=2e-4, atol=2e-6 * scale,
                                   err_msg=f"{name}: d/d {pname}{'' if c is None else f'[{c}]'}")
