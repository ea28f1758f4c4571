"""brdfit.fit_images: the per-pixel fit of a stack of photographs, with maps equal to what
`brdfit fit-images` writes for the same stack and options (normals.exr, a map per
parameter, error.exr, the Lambertian baseline, clusters.exr, the relit comparisons, read
back with oiiotool; and fit.json's counts, relit errors, shared values and tile), on
synthetic stacks whose truth is known; progress, Ctrl-C, and errors in the library's words."""

import json
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import brdfit
from _images import assert_image_equal, make_stack, read_image, read_images
from _support import INTERRUPT_SECONDS, cli

WALTER = {"rho_d": [0.5, 0.35, 0.2], "rho_s": 0.3, "alpha": 0.15}


@pytest.fixture(scope="module")
def sphere(tmp_path_factory):
    return make_stack(tmp_path_factory.mktemp("stack") / "sphere", size=16, lights=20, params=WALTER)


@pytest.fixture(scope="module")
def checker(tmp_path_factory):
    return make_stack(tmp_path_factory.mktemp("stack") / "checker", size=20, lights=16, params=WALTER, checker=True)


def _cli_fit_images(tmp_path, stack, *options):
    out = tmp_path / "out"
    cli("fit-images", stack, *options, "-q", "-o", out, timeout=300)
    return out, json.loads((out / "fit.json").read_text())


def _check_against_outputs(got, out, want):
    """Every map of got against the files fit-images wrote to out, and the summary want."""
    W, mask = got.width, got.mask
    maps = {"normals.exr": got.normals, "error.exr": got.error, "lambert_normals.exr": got.lambert_normals,
            "lambert_albedo.exr": got.lambert_albedo}
    maps.update(("%s.exr" % name, m) for name, m in got.params.items())
    # Relit comparisons: measured | relit by the model, inside the mask.
    assert [k for k, _, _ in got.relit] == sorted(int(f[6:9]) for f in os.listdir(out)
                                                 if f.startswith("relit_") and f.endswith(".exr"))
    maps.update(("relit_%03d.exr" % k, np.concatenate([measured, model], axis=1) * np.tile(mask, 2)[:, :, None])
                for k, measured, model in got.relit)
    names = ["mask.png"] + sorted(maps)
    files = dict(zip(names, read_images(*[out / n for n in names])))
    assert np.array_equal(files["mask.png"][:, :, 0] > 0, mask)
    for name in sorted(maps):
        assert_image_equal(maps[name], files[name], name)
    c = want["counts"]
    assert got.counts == {"pixels": c["pixels"], "masked": c["masked_pixels"], "failed": c["failed_pixels"],
                          "samples": c["samples_used"], "shadowed": c["shadowed"], "dark": c["dark_outliers"],
                          "saturated": c["saturated"], "invalid": c["invalid"]}
    assert got.restarted == c["restarted_pixels"]
    assert (got.relit_rms, got.lambert_rms) == (want["relit_error"]["model"], want["relit_error"]["lambert"])
    per = want["relit_error"]["per_image"]
    assert got.image_rms.tolist() == [e["model"] for e in per]
    assert got.image_lambert_rms.tolist() == [e["lambert"] for e in per]
    assert got.image_samples.tolist() == [e["samples"] for e in per]
    assert got.scale == want["options"]["scale"]
    assert got.model.spec == want["spec"] and got.channels == want["channels"]
    assert (got.width, got.height) == (want["stack"]["width"], want["stack"]["height"])
    assert got.shared == [e["values"] for e in want.get("shared", [])]
    assert not got.cancelled


def test_fit_images_equals_the_commands_outputs(tmp_path, sphere):
    out, want = _cli_fit_images(tmp_path, sphere, "-m", "walter")
    got = brdfit.fit_images(sphere, "walter")
    _check_against_outputs(got, out, want)
    # .json is fit.json's text (bf_photo_result_json) but for the command line, the wall
    # time and the build's git description (the command and the module may be built from
    # different commits).
    summary = json.loads(got.json)
    assert "command" not in summary or summary["command"] is None
    for d in (summary, want):
        d.pop("command", None)
        d["timing"].pop("seconds")
        d["brdfit_version"] = d["brdfit_version"].split()[0]
    assert summary == want
    # The truth: the sphere's normals and roughness are recovered.
    j, i = np.mgrid[0:16, 0:16]
    sx, sy = 2 * (i + 0.5) / 16 - 1, 1 - 2 * (j + 0.5) / 16
    truth = np.stack([sx, sy, np.sqrt(np.clip(1 - sx ** 2 - sy ** 2, 0, 1))], -1)
    cos = np.sum(got.normals[got.mask] * truth[got.mask], axis=1)
    assert got.counts["pixels"] == got.mask.sum() > 100 and np.degrees(np.arccos(np.clip(cos, -1, 1))).max() < 0.5
    assert abs(np.median(got.params["alpha"][got.mask]) - WALTER["alpha"]) < 0.01
    assert got.params["rho_d"].shape == (16, 16, 3) and got.params["alpha"].shape == (16, 16)
    assert got.values.shape == (16, 16, len(got.model.value_names))
    assert got.relit_rms < 0.01 * got.lambert_rms
    assert got.clusters is None and got.rows == (0, 16)


def test_shared_parameters_clusters_and_options(tmp_path, checker):
    out, want = _cli_fit_images(tmp_path, checker, "-m", "walter", "--share", "alpha,f0", "--clusters", "2",
                                "--relit", "2", "--scale", "2", "--seed", "3", "--threads", "1")
    got = brdfit.fit_images(checker, brdfit.Model("walter", 3), share=["alpha", "f0"], clusters=2, relit=2, scale=2,
                            seed=3)
    _check_against_outputs(got, out, want)
    clusters = read_image(out / "clusters.exr")[:, :, 0]
    assert np.array_equal(got.clusters, clusters) and set(np.unique(got.clusters)) == {-1, 0, 1}
    assert len(got.shared) == 2 and all(set(s) == {"alpha", "f0"} for s in got.shared)
    assert len(got.relit) == 2 and got.scale == 2


def test_tiles_flat_normals_and_auto_scale(tmp_path, sphere):
    out, want = _cli_fit_images(tmp_path, sphere, "--tile", "2/3", "--normals", "flat", "--scale", "auto")
    got = brdfit.fit_images(str(sphere), tile="2/3", normals="flat", scale="auto")
    _check_against_outputs(got, out, want)
    assert got.rows == (want["options"]["tile"]["rows_from"], want["options"]["tile"]["rows_to"])
    assert not got.mask[:got.rows[0]].any() and not got.mask[got.rows[1]:].any()
    assert np.all(got.normals[got.mask] == [0, 0, 1])
    same = brdfit.fit_images(sphere, tile=(2, 3), normals="flat", scale="auto", threads=1)
    assert np.array_equal(same.values, got.values)  # the threads change nothing


def test_normals_from_a_file(tmp_path, sphere):
    first, _ = _cli_fit_images(tmp_path, sphere)
    given = first / "normals.exr"
    (tmp_path / "again").mkdir()
    out, want = _cli_fit_images(tmp_path / "again", sphere, "--normals", given)
    got = brdfit.fit_images(sphere, normals=given)
    _check_against_outputs(got, out, want)


def test_progress_stops_and_raises(sphere):
    seen = []
    got = brdfit.fit_images(sphere, progress=lambda done: seen.append(done) or True)
    assert got.cancelled and seen and 0 <= seen[0] <= 1
    seen.clear()
    done = brdfit.fit_images(sphere, progress=lambda d: seen.append(d))
    assert not done.cancelled and seen == sorted(seen) and seen[-1] <= 1

    def boom(done):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        brdfit.fit_images(sphere, progress=boom)


CHILD = textwrap.dedent(r"""
    import os, random, signal, sys, threading, time
    import brdfit

    stack, kind = sys.argv[1], sys.argv[2]
    whole = brdfit.fit_images(stack, threads=1)
    signal.signal(signal.SIGALRM, lambda *_: (_ for _ in ()).throw(TimeoutError("alarm")))
    random.seed(3)
    worst, stopped = 0.0, 0
    for k in range(8):
        delay = random.uniform(0.0, 0.4)
        at = [time.monotonic() + delay]
        if kind == "int":
            threading.Timer(delay, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
        else:
            signal.setitimer(signal.ITIMER_REAL, delay)
        try:
            while True:
                brdfit.fit_images(stack, threads=1)
        except (KeyboardInterrupt, TimeoutError):
            stopped += 1
            worst = max(worst, time.monotonic() - at[0])
        signal.setitimer(signal.ITIMER_REAL, 0)
    again = brdfit.fit_images(stack, threads=1)
    assert (again.values == whole.values).all(), "a fit after the interrupts differs"
    print("stopped %d worst %.3f" % (stopped, worst))
""")


@pytest.mark.parametrize("kind", ["int", "alarm"])
def test_interrupts(tmp_path, kind):
    stack = make_stack(tmp_path / "big", size=40, lights=24, params=WALTER)
    script = tmp_path / "child.py"
    script.write_text(CHILD)
    p = subprocess.run([sys.executable, str(script), str(stack), kind], capture_output=True, text=True, timeout=300,
                       env=dict(os.environ))
    assert p.returncode == 0, "exit %d (a signal is negative): %s" % (p.returncode, p.stderr[-2000:])
    words = p.stdout.split()
    assert words[1] == "8" and float(words[3]) < INTERRUPT_SECONDS, p.stdout


def test_fit_images_errors_are_the_librarys(tmp_path, sphere):
    missing = tmp_path / "nope.json"
    p = cli("fit-images", missing, "-o", tmp_path / "o", ok=False)
    with pytest.raises(brdfit.Error) as e:
        brdfit.fit_images(missing)
    assert p.returncode == 1 and "brdfit fit-images: " + str(e.value) == p.stderr.strip()
    # The library's checks and messages, the command's but for the option's name (a keyword
    # here, bf_photo_options.spelling).
    for options, kw, msg in (
            (["-m", "nope"], dict(model="nope"), "model: unknown model 'nope' (see brdfit models)"),
            (["--share", "zz"], dict(share="zz"), "share: walter has no parameter 'zz' (brdfit models)"),
            (["--tile", "3/2"], dict(tile="3/2"), "bad value '3/2' for tile (I/N with 1 <= I <= N)"),
            (["--tile", "1/"], dict(tile="1/"), "bad value '1/' for tile (I/N with 1 <= I <= N)"),
            (["--scale", "big"], dict(scale="big"), "bad value 'big' for scale (auto or a positive number)"),
            (["--scale", "-1"], dict(scale=-1), "bad value '-1' for scale (auto or a positive number)"),
            (["--clusters", "65"], dict(clusters=65), "clusters needs an integer from 1 to 64, got '65'"),
            (["--relit", "9"], dict(relit=9), "relit needs an integer from 0 to 8, got '9'")):
        p = cli("fit-images", sphere, *options, "-o", tmp_path / "o", ok=False)
        with pytest.raises(brdfit.UsageError) as e:
            brdfit.fit_images(sphere, **kw)
        assert str(e.value) == msg
        keyword = next(iter(kw))
        assert p.returncode == 2 and p.stderr.strip() == "brdfit fit-images: " + msg.replace(keyword, options[0], 1)
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.fit_images(sphere, tile=(0, 4))
    assert str(e.value) == "bad value '0/4' for tile (I/N with 1 <= I <= N)"
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.fit_images(sphere, scale=float("nan"))
    assert str(e.value) == "bad value 'nan' for scale (auto or a positive number)"
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.fit_images(sphere, threads=1025)
    assert str(e.value) == "threads needs an integer from 1 to 1024 (0: every core), got '1025'"
    p = cli("fit-images", sphere, "--tile", "3/40", "-o", tmp_path / "o", ok=False)
    with pytest.raises(brdfit.UsageError) as e:
        brdfit.fit_images(sphere, tile=(3, 40))
    assert str(e.value) == "tile 3/40: out of range (the image has 16 rows)"
    assert p.returncode == 1 and "brdfit fit-images: --" + str(e.value) == p.stderr.strip()
    for bad in (dict(tile="1/"), dict(tile=(1, 2, 3)), dict(clusters="2"), dict(scale="big"), dict(scale=float("nan")), dict(relit=1.5),
                dict(seed=-1), dict(threads=2 ** 40), dict(share=[1]), dict(normals=3), dict(model=3)):
        with pytest.raises(brdfit.UsageError):
            brdfit.fit_images(sphere, **bad)
    with pytest.raises(brdfit.UsageError):
        brdfit.fit_images(None)
    with pytest.raises(brdfit.UsageError):
        brdfit.fit_images(sphere, progress=5)
