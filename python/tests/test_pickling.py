"""Models and Samples pickle: equal after a round trip, and through the processes of a
ProcessPoolExecutor (which pickles what it sends) a fit gives the same numbers."""

import pickle
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

import brdfit
from _support import CAYMAN, PAPER_WHITE, WALTER_RGB, vectors_from_angles

FAST = dict(threads=1, starts=1)


def _dirs(n, seed):
    rng = np.random.default_rng(seed)
    return (vectors_from_angles(rng.uniform(0, 80, n), rng.uniform(0, 360, n)),
            vectors_from_angles(rng.uniform(0, 80, n), rng.uniform(0, 360, n)))


def _fit(job):
    """In a worker: a fit of the samples with the model (its parameters as the start)."""
    samples, model = job
    r = brdfit.fit(samples, model, **FAST)
    return r.params, r.metrics["rmse_log"], r.model


def _eval(job):
    model, wi, wo = job
    return model.eval(wi, wo, gradient=True)


def test_model_round_trip():
    wi, wo = _dirs(6, 1)
    for m in (brdfit.Model("walter", channels=3), brdfit.Model.from_file(WALTER_RGB),
              brdfit.Model("microfacet:D=ggx,lobes=2,mono=specular", channels=2,
                           params={"rho_d": [0.1, 0.2], "alpha_2": 0.3})):
        back = pickle.loads(pickle.dumps(m))
        assert back == m and back is not m
        assert back.spec == m.spec and back.channels == m.channels and back.params == m.params
        assert repr(back) == repr(m)
        for a, b in zip(back.eval(wi, wo, gradient=True), m.eval(wi, wo, gradient=True)):
            np.testing.assert_array_equal(a, b)


def test_samples_round_trip(cayman):
    rng = np.random.default_rng(2)
    wi, wo = _dirs(30, 3)
    own = brdfit.Samples(wi, wo, rng.uniform(0.1, 1.0, (30, 2)), weights=rng.uniform(0.5, 2.0, 30))
    merl = brdfit.read(PAPER_WHITE, grid="merl", subsample=500)
    for s in (own, cayman, merl):
        back = pickle.loads(pickle.dumps(s))
        assert back.path == s.path and back.channel_names == s.channel_names and len(back) == len(s)
        np.testing.assert_array_equal(back.values, s.values)
        for a, b in zip(back.angles(), s.angles()):
            np.testing.assert_array_equal(a, b)
        assert (back.weights is None) == (s.weights is None)
        if s.weights is not None:
            np.testing.assert_array_equal(back.weights, s.weights)
        with pytest.raises(ValueError):
            back.values[0, 0] = -1.0  # read-only, as the original's
    # MERL cells stay cells: solid-angle weights need them, and the fits agree.
    back = pickle.loads(pickle.dumps(merl))
    assert brdfit.fit(back, "lambert", solid_angle=True, **FAST).params == \
        brdfit.fit(merl, "lambert", solid_angle=True, **FAST).params


def test_what_new_samples_cannot_carry_is_refused():
    with pytest.raises(brdfit.UsageError) as e:
        pickle.dumps(brdfit.read(CAYMAN))  # spectral: wavelengths
    assert "wavelengths" in str(e.value)


def test_fits_in_two_worker_processes_equal_fits_here(cayman):
    wi, wo = _dirs(8, 4)
    data = [cayman[::3], cayman[1::3], brdfit.Samples(wi, wo, np.full((8, 3), 0.2))]
    jobs = [(data[0], "walter"), (data[1], brdfit.Model("lambert", channels=3)),
            (data[2], brdfit.Model.from_file(WALTER_RGB))]
    here = [_fit(j) for j in jobs]
    with ProcessPoolExecutor(max_workers=2) as pool:
        there = list(pool.map(_fit, jobs))
        evals = list(pool.map(_eval, [(r[2], wi, wo) for r in here]))
    for (p, e, m), (q, f, n) in zip(here, there):
        assert p == q and e == f and m == n
    for (v, g), (_, _, m) in zip(evals, here):
        v0, g0 = m.eval(wi, wo, gradient=True)
        np.testing.assert_array_equal(v, v0)
        np.testing.assert_array_equal(g, g0)
