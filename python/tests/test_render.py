"""brdfit.render: the sphere and the half/difference image of a model, a fit's result or a
MERL table, equal to what `brdfit render` writes to an EXR for the same options (read back
with oiiotool), the library's defaults (those of the command), and errors in the
library's words."""

import json

import numpy as np
import pytest

import brdfit
from _images import assert_image_equal, read_image
from _support import CAYMAN, DIRS_SMALL, LAMBERT_RGB, WALTER_RGB, cli, synth


def _cli_render(tmp_path, *args, name="r.exr"):
    out = tmp_path / name
    cli("render", *args, "-q", "-o", out)
    return read_image(out)


def test_sphere_equals_the_commands_exr(tmp_path):
    want = _cli_render(tmp_path, "--params", LAMBERT_RGB, "--light", "0,0", "--light", "60,90", "--view", "10,0",
                       "--size", "33")
    got = brdfit.render(str(LAMBERT_RGB), lights=[(0, 0), (60, 90)], view=(10, 0), resolution=33)
    assert got.dtype == np.float32 and got.shape == (33, 33, 3)
    assert_image_equal(got, want, "lambert sphere, two lights")
    # A lit Lambert sphere: rho/pi at the centre lit along the view (tests/cli_render.sh).
    centre = brdfit.render(str(LAMBERT_RGB), lights=[(0, 0)], resolution=33)[16, 16]
    rho = json.loads(LAMBERT_RGB.read_text())["params"]["rho_d"]
    assert np.allclose(centre, np.array(rho) / np.pi, rtol=1e-6)


def test_sphere_defaults_are_the_commands(tmp_path):
    # No size, light or view: the library's defaults (bf_sphere_options_init), the command's.
    want = _cli_render(tmp_path, "--params", WALTER_RGB)
    got = brdfit.render(str(WALTER_RGB))
    assert got.shape == want.shape
    assert_image_equal(got, want, "walter sphere, defaults")
    # The same from a Model given the file's parameters, and from a fit's result.
    spec = json.loads(WALTER_RGB.read_text())
    m = brdfit.Model("walter:fresnel=schlick", 3, params=spec["params"])
    assert np.array_equal(brdfit.render(m), got)
    assert np.array_equal(brdfit.render(brdfit.Model("walter", 3), params=spec["params"]), got)
    # Outside the disc, exactly 0.
    n = got.shape[0]
    j, i = np.mgrid[0:n, 0:n]
    outside = ((2 * (i + 0.5) / n - 1) ** 2 + (1 - 2 * (j + 0.5) / n) ** 2) >= 1
    assert outside.any() and np.all(got[outside] == 0) and got[~outside].max() > 0


def test_a_fits_result_renders_as_its_file(tmp_path):
    fitted = brdfit.fit(brdfit.read(CAYMAN, rgb=True, subsample=200), "walter", starts=1, threads=1)
    path = tmp_path / "fit.json"
    path.write_text(fitted.to_json())
    want = _cli_render(tmp_path, "--params", path, "--light", "30,45", "--size", "40")
    got = brdfit.render(fitted, lights=[(30, 45)], resolution=40)
    assert_image_equal(got, want, "a fit's sphere")
    assert np.array_equal(got, brdfit.render(path, lights=[(30, 45)], resolution=40))


def test_halfdiff_of_a_model_equals_the_commands_exr(tmp_path):
    want = _cli_render(tmp_path, "--params", WALTER_RGB, "--half-diff", "--phi-d", "45", "--size", "90x45")
    got = brdfit.render(str(WALTER_RGB), kind="halfdiff", phi_d=45, size=(90, 45))
    assert got.shape == (45, 90, 3)
    assert_image_equal(got, want, "walter half/difference")
    # Size N is N x N, and the default size is the sphere's, as the command's.
    want = _cli_render(tmp_path, "--params", LAMBERT_RGB, "--half-diff", "--phi-d", "90")
    got = brdfit.render(str(LAMBERT_RGB), kind="halfdiff", phi_d=90)
    assert got.shape == want.shape
    assert_image_equal(got, want, "lambert half/difference, default size")


@pytest.fixture(scope="module")
def merl_table(tmp_path_factory):
    path = tmp_path_factory.mktemp("merl") / "walter.binary"
    synth("--params", WALTER_RGB, "--pattern", "merl", "-q", "-o", path)
    return path


def test_merl_table_halfdiff_equals_the_commands_exr(tmp_path, merl_table):
    want = _cli_render(tmp_path, "--data", merl_table, "--half-diff", "--phi-d", "90", "--size", "64x48")
    table = brdfit.read(merl_table)
    got = brdfit.render(table, kind="halfdiff", phi_d=90, size=(64, 48))
    assert_image_equal(got, want, "MERL half/difference")
    assert got.max() > 0


def test_merl_table_sphere_is_the_models(merl_table):
    # The table holds the model at cell centres: its sphere is the model's but for the
    # cells' quantisation (and the cells MERL leaves out near the horizon).
    table = brdfit.render(brdfit.read(merl_table), resolution=64)
    model = brdfit.render(str(WALTER_RGB), resolution=64)
    lit = (table > 0.01) & (model > 0.01)
    assert lit.sum() > 0.9 * (model > 0.01).sum()
    assert np.median(np.abs(table[lit] - model[lit]) / model[lit]) < 1e-3
    assert np.all(table[model == 0] == 0)


def test_render_errors_are_the_librarys(tmp_path, monkeypatch):
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.render(str(LAMBERT_RGB), resolution=0)
    assert str(e.value) == "sphere render: need a size >= 1 and at least one light"
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.render(str(LAMBERT_RGB), lights=[])
    assert str(e.value) == "sphere render: need a size >= 1 and at least one light"
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.render(str(LAMBERT_RGB), kind="halfdiff", phi_d=90, size=(0, 5))
    assert str(e.value) == "half/difference image: bad size 0x5 (each side 1 to 16384)"
    # The library's limits, in its words: the sides and the lights of the command.
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.render(str(LAMBERT_RGB), resolution=16385)
    assert str(e.value) == "sphere render: size 16385 is above 16384 pixels"
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.render(str(LAMBERT_RGB), lights=[(10, k) for k in range(17)])
    assert str(e.value) == "at most 16 lights"
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.render(str(LAMBERT_RGB), lights=[(10, 0), (20, float("nan"))])
    assert str(e.value) == "sphere render: light 2 (20, nan) is not a finite direction"
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.render(str(LAMBERT_RGB), kind="halfdiff", phi_d=float("inf"))
    assert str(e.value) == "half/difference image: phi_d is not finite"
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.render(str(LAMBERT_RGB), tonemap="Log")
    assert str(e.value) == "tonemap: unknown tone map 'Log' (clamp, reinhard or log)"
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.render(str(LAMBERT_RGB), tonemap=True, exposure=0)
    assert str(e.value) == "tone map: exposure must be a finite number above 0, got 0"
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.render(str(LAMBERT_RGB), tonemap="log", decades=-1)
    assert str(e.value) == "tone map: decades must be a finite number above 0, got -1"
    # A picture this machine cannot hold is refused before it is drawn, as by the command.
    with monkeypatch.context() as env:
        env.setenv("BRDFIT_MEMORY", "1M")
        p = cli("render", "--params", LAMBERT_RGB, "--size", "300", "-o", tmp_path / "big.png", ok=False)
        with pytest.raises(brdfit.Error) as e:
            brdfit.render(str(LAMBERT_RGB), resolution=300)
    assert p.returncode == 1 and e.value.code == "nomem" and "brdfit render: " + str(e.value) == p.stderr.strip()
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.render(brdfit.read(DIRS_SMALL, values="theta_o"))
    assert str(e.value) == "sphere render: the data is not a MERL table as read"
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.render(brdfit.read(DIRS_SMALL, values="theta_o"), kind="halfdiff", phi_d=90)
    assert str(e.value) == "half/difference image: the data is not a MERL table as read"
    missing = tmp_path / "nope.json"
    p = cli("render", "--params", missing, "-o", tmp_path / "e.exr", ok=False)
    with pytest.raises(brdfit.Error) as e:
        brdfit.render(missing)
    assert p.returncode == 1 and "brdfit render: " + str(e.value) == p.stderr.strip()
    for bad in (dict(kind="slice"), dict(exposure=2), dict(tonemap=3), dict(lights=[(45,)]), dict(view="0,0"),
                dict(resolution=2.5), dict(kind="halfdiff", phi_d=90, resolution=8), dict(size=8),
                dict(params={"rho_d": 0.5})):
        with pytest.raises(brdfit.UsageError):
            brdfit.render(str(LAMBERT_RGB), **bad)
    with pytest.raises(brdfit.UsageError):
        brdfit.render(brdfit.Model("lambert", 3), params={"nope": 1})
    with pytest.raises(brdfit.UsageError):
        brdfit.render(42)


def test_halfdiff_defaults_are_the_librarys(tmp_path):
    # No phi_d and no size: bf_halfdiff_options_init's, the command's --half-diff defaults.
    want = _cli_render(tmp_path, "--params", WALTER_RGB, "--half-diff")
    got = brdfit.render(str(WALTER_RGB), kind="halfdiff")
    assert got.shape == want.shape
    assert_image_equal(got, want, "walter half/difference, defaults")
    assert np.array_equal(got, brdfit.render(str(WALTER_RGB), kind="halfdiff", phi_d=90))
    assert not np.array_equal(got, brdfit.render(str(WALTER_RGB), kind="halfdiff", phi_d=45))


def _srgb_codes(v):
    """8-bit codes of display values as the PNG writer encodes them (clamped, sRGB)."""
    v = np.clip(v.astype(np.float64), 0, 1)
    return 255 * np.where(v <= 0.0031308, 12.92 * v, 1.055 * v ** (1 / 2.4) - 0.055)


@pytest.mark.parametrize("kind, options, kw", [
    ("sphere", [], dict(tonemap=True)),
    ("sphere", ["--tonemap", "reinhard", "--exposure", "3"], dict(tonemap="reinhard", exposure=3)),
    ("halfdiff", ["--half-diff", "--size", "40x30"], dict(kind="halfdiff", size=(40, 30), tonemap=True)),
    ("halfdiff", ["--half-diff", "--size", "40", "--tonemap", "log", "--decades", "2"],
     dict(kind="halfdiff", size=40, tonemap="log", decades=2)),
])
def test_tonemap_is_the_commands_png(tmp_path, kind, options, kw):
    got = brdfit.render(str(WALTER_RGB), **kw)
    linear = brdfit.render(str(WALTER_RGB), **{k: v for k, v in kw.items() if k not in ("tonemap", "exposure",
                                                                                    "decades")})
    # The mappings by hand (render.h): the defaults are clamp for a sphere, log for the
    # half/difference image, exposure 1, 4 decades.
    mode = kw["tonemap"] if kw["tonemap"] is not True else "clamp" if kind == "sphere" else "log"
    e = linear.astype(np.float64) * kw.get("exposure", 1)
    if mode == "clamp":
        want = e
    elif mode == "reinhard":
        want = np.where(e > 0, e / (1 + e), 0)
    else:
        top, dec = np.log10(e.max()), kw.get("decades", 4)
        want = np.where(e > 0, np.maximum(0, (np.log10(np.where(e > 0, e, 1)) - (top - dec)) / dec), 0)
    assert np.allclose(got, want, rtol=1e-5, atol=1e-6)
    # And the command's PNG holds them (8-bit codes: within one).
    out = tmp_path / "r.png"
    cli("render", "--params", WALTER_RGB, *options, "-q", "-o", out)
    codes = read_image(out)
    assert codes.shape == got.shape
    assert np.abs(codes - _srgb_codes(got)).max() <= 1
