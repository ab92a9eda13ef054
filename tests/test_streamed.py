"""Streamed realizations (chunks): the same results as the whole-array pipeline.

Small profiles with a tiny forced chunk (2048 points, the generator's block) so that every run
crosses many seams; the whole-array run is the reference.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from splinecontact import Profile, simulate, weierstrass_mandelbrot, weierstrass_mandelbrot_pair
from splinecontact.contact import DMT, JKR, ElasticPlastic, _chunks, streamed
from splinecontact.contact.laws import Hertz
from splinecontact.contact.streamed import margin_points, simulate_generated
from splinecontact.errors import GridMismatchError, ParameterError
from splinecontact.generate import _BLOCK, _heights_kernel, _terms
from splinecontact.spline import _reinsch_uniform, fit_spline, smoothing_parameter

#: Largest relative deviation accepted between a streamed and a whole run (measured: ≤ 2e−15).
RTOL = 1e-9

GEN = {"n_points": 24_000, "length": 2.4}


def _whole(dimension: float, seed: int, flat: bool, **sim: Any) -> Any:
    lower, upper = weierstrass_mandelbrot_pair(dimension, seed=seed, **GEN)
    return simulate(lower, "flat" if flat else upper, diagnostics=False, **sim)


def _assert_same(streamed_run: Any, whole: Any) -> None:
    assert streamed_run.curves.keys() == whole.curves.keys()
    for name, reference in whole.curves.items():
        values = streamed_run.curves[name]
        if reference.dtype.kind in "iu":  # counts: exactly the same
            np.testing.assert_array_equal(values, reference, err_msg=name)
        else:
            scale = float(np.max(np.abs(reference)))
            np.testing.assert_allclose(
                values, reference, rtol=RTOL, atol=RTOL * scale, err_msg=name
            )
    assert streamed_run.scalars.keys() == whole.scalars.keys()
    for name, reference in whole.scalars.items():
        assert streamed_run.scalars[name] == pytest.approx(reference, rel=RTOL, abs=1e-300), name
    assert streamed_run.parameters == whole.parameters
    assert streamed_run.lower_metadata == whole.lower_metadata
    assert streamed_run.upper_metadata == whole.upper_metadata


@pytest.mark.parametrize("flat", [False, True], ids=["rough-on-rough", "rough-on-flat"])
@pytest.mark.parametrize(("dimension", "seed"), [(1.2, 1), (1.5, 2), (1.8, 3)])
def test_generated_realization_equals_the_whole_run(
    dimension: float, seed: int, flat: bool
) -> None:
    whole = _whole(dimension, seed, flat, steps=60)
    for chunk in (2048, 3 * 2048):
        run = simulate_generated(
            dimension, seed=seed, flat=flat, generator=GEN, steps=60, chunk_points=chunk
        )
        _assert_same(run, whole)
    assert whole.curves["n_contacts"][-1] > 3  # the comparison saw contacts


def test_given_profiles_and_a_law_with_a_reach_equal_the_whole_run() -> None:
    lower, upper = weierstrass_mandelbrot_pair(1.4, seed=5, **GEN)
    law = JKR(work_of_adhesion=0.5)
    whole = simulate(lower, upper, steps=40, record_contacts=[20, 40], diagnostics=False,
                     law=Hertz())  # fmt: skip
    run = streamed.simulate_streamed(
        lower, upper, steps=40, final_displacement=None, final_displacement_factor=0.2,
        e_star=10.0, g_star=10.0 / 2.6, mu0=0.3, alpha=2.0, x0=1.0,
        record_steps=np.array([20, 40]), law=Hertz(), chunk_points=2048,
    )  # fmt: skip
    _assert_same(run, whole)
    for ours, theirs in zip(run.contacts, whole.contacts, strict=True):
        np.testing.assert_array_equal(ours.point, theirs.point)
        np.testing.assert_allclose(ours.normal_force, theirs.normal_force, rtol=RTOL)
    with pytest.raises(ParameterError, match="needs the bodies' radii"):
        simulate_generated(1.5, seed=1, generator=GEN, law=law, chunk_points=2048)


@pytest.mark.parametrize(
    "law",
    [DMT(work_of_adhesion=0.2, cohesive_stress=0.5), ElasticPlastic(yield_strength=0.5)],
    ids=["dmt-with-a-reach", "elastic-plastic"],
)
def test_other_laws_equal_the_whole_run(law: Any) -> None:
    whole = _whole(1.5, 9, False, steps=40, law=law)
    run = simulate_generated(1.5, seed=9, generator=GEN, steps=40, law=law, chunk_points=2048)
    _assert_same(run, whole)


def test_simulate_streams_from_the_threshold(monkeypatch: pytest.MonkeyPatch) -> None:
    lower, upper = weierstrass_mandelbrot_pair(1.6, seed=8, **GEN)
    whole = simulate(lower, upper, steps=30, diagnostics=False)
    calls: list[int] = []
    original = streamed.simulate_streamed

    def spy(*args: Any, **kwargs: Any) -> Any:
        calls.append(1)
        return original(*args, **kwargs, chunk_points=2048)

    monkeypatch.setattr(streamed, "simulate_streamed", spy)
    monkeypatch.setattr("splinecontact.contact.simulation.STREAM_MIN_POINTS", GEN["n_points"])
    run = simulate(lower, upper, steps=30, diagnostics=False)
    assert calls == [1]
    _assert_same(run, whole)
    short = weierstrass_mandelbrot(1.5, n_points=GEN["n_points"] - 1, length=2.0, seed=1)
    with pytest.raises(GridMismatchError):
        simulate(lower, short, steps=5)


def test_study_realization_streams_from_the_threshold(monkeypatch: pytest.MonkeyPatch) -> None:
    from splinecontact.parameters import PARAMETERS
    from splinecontact.study.runner import realization_seed, simulate_realization

    parameters = {name: spec.default for name, spec in PARAMETERS.items()}
    parameters.update(GEN, steps=25, dimension=1.5, contact_type="rough-on-flat")
    seed = realization_seed(3, 1)
    whole = simulate_realization(parameters, seed)
    monkeypatch.setattr(streamed, "STREAM_MIN_POINTS", GEN["n_points"])
    monkeypatch.setattr(streamed, "CHUNK_POINTS", 2048)
    run = simulate_realization(parameters, seed)
    assert run.lower_metadata == whole.lower_metadata
    _assert_same(run, whole)


def test_chunked_heights_are_bit_identical() -> None:
    n, length = 10_000, 1.0
    profile = weierstrass_mandelbrot(1.5, n_points=n, length=length, seed=4)
    source, _, _ = streamed._generated((1.5, n, length, 1.0, 1.5, 20, 20, 0.005, "hurst"), 4, 2048)
    for start, stop in ((0, 2048), (4096, 10_000), (2048, 8192)):
        out = np.empty(stop - start)
        assert np.array_equal(source.fill(out, start), profile.z[start:stop])
    # the first pass's sums continued across chunks are the whole run's
    terms = _terms(1.5, n, length, 1.0, 1.5, 20, 20, "hurst", 4)
    args = (terms.omega, terms.amp_re, terms.amp_im, _BLOCK, terms.prefactor, terms.constant,
            terms.shift)  # fmt: skip
    dx = length / (n - 1)
    whole = _heights_kernel(np.empty(n), dx, *args, 0, 0.0, 0.0)
    assert streamed._first_pass(terms, n, dx, 2048)[:2] == whole


def _window_fit(z: np.ndarray, start: int, stop: int, lam_grid: float, dx: float, margin: int):
    lo, hi = max(0, start - margin), min(z.size, stop + margin)
    window = np.ascontiguousarray(z[lo:hi])
    f, slope, second = (np.empty(window.size) for _ in range(3))
    _reinsch_uniform(window, lam_grid, dx, dx * dx, f, slope, second)
    return f[start - lo : stop - lo], slope[start - lo : stop - lo]


@pytest.mark.parametrize(("alpha", "x0"), [(2.0, 1.0), (1.5, 1.0), (2.5, 0.5), (2.0, 30.0)])
def test_spline_windows_equal_the_global_fit(alpha: float, x0: float) -> None:
    profile = weierstrass_mandelbrot(1.5, n_points=30_000, length=3.0, seed=6)
    dx = profile.dx
    lam_grid = smoothing_parameter(dx, alpha=alpha, x0=x0) / dx**3
    margin = margin_points(lam_grid)  # not rounded up: the derived margin itself
    fit = fit_spline(profile, alpha=alpha, x0=x0)
    rq = profile.rq
    for start, stop in ((0, 5000), (7001, 9003), (12_345, 30_000), (15_000, 15_001)):
        f, slope = _window_fit(profile.z, start, stop, lam_grid, dx, margin)
        assert np.max(np.abs(f - fit.f[start:stop])) <= 1e-12 * rq
        assert np.max(np.abs(slope - fit.slope[start:stop])) <= 1e-9 * np.max(np.abs(fit.slope))


def test_margin_follows_the_measured_decay() -> None:
    """An impulse's effect on the fit decays like ρ^d, ρ the rate the margin is derived from."""
    n, dx = 4001, 1e-4
    lam_grid = smoothing_parameter(dx) / dx**3  # the paper's grid: λ' = 1000
    z = np.zeros(n)
    z[n // 2] = 1.0
    f, slope, second = (np.empty(n) for _ in range(3))
    _reinsch_uniform(z, lam_grid, dx, dx * dx, f, slope, second)
    envelope = [np.max(np.abs(f[n // 2 + d : n // 2 + d + 40])) for d in (100, 200)]
    rho = _chunks._decay_rate(lam_grid)
    assert envelope[1] / envelope[0] == pytest.approx(rho**100, rel=0.5)
    assert 300 < margin_points(lam_grid) < 500


@settings(max_examples=12, deadline=None)
@given(
    chunk_blocks=st.integers(min_value=1, max_value=12),
    seed=st.integers(min_value=0, max_value=10_000),
    flat=st.booleans(),
)
def test_seams_neither_lose_nor_duplicate_contacts(
    chunk_blocks: int, seed: int, flat: bool
) -> None:
    whole = _whole(1.5, seed, flat, steps=30, record_contacts="all")
    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=seed, **GEN)
    run = streamed.simulate_streamed(
        lower, None if flat else upper, steps=30, final_displacement=None,
        final_displacement_factor=0.2, e_star=10.0, g_star=10.0 / 2.6, mu0=0.3, alpha=2.0,
        x0=1.0, record_steps=np.arange(31), law=Hertz(), chunk_points=2048 * chunk_blocks,
    )  # fmt: skip
    np.testing.assert_array_equal(run.curves["n_candidates"], whole.curves["n_candidates"])
    np.testing.assert_array_equal(run.curves["n_contacts"], whole.curves["n_contacts"])
    for ours, theirs in zip(run.contacts, whole.contacts, strict=True):
        assert np.unique(ours.point).size == ours.point.size
        np.testing.assert_array_equal(np.sort(ours.point), np.sort(theirs.point))


def test_bad_chunk_is_refused() -> None:
    with pytest.raises(ParameterError, match="chunk_points"):
        simulate_generated(1.5, seed=1, generator=GEN, chunk_points=100)
    with pytest.raises(ParameterError, match="n_points"):
        simulate_generated(1.5, seed=1, generator={"n_points": 3})


def test_a_profile_too_short_for_a_chunk_is_one_window() -> None:
    x = np.linspace(0.0, 0.2, 900)
    lower = Profile(x, 1e-3 * np.sin(40.0 * x) + 1e-4 * np.cos(300.0 * x))
    whole = simulate(lower, "flat", steps=10, diagnostics=False)
    run = streamed.simulate_streamed(
        lower, None, steps=10, final_displacement=None, final_displacement_factor=0.2,
        e_star=10.0, g_star=10.0 / 2.6, mu0=0.3, alpha=2.0, x0=1.0,
        record_steps=np.zeros(0, dtype=np.int64), law=Hertz(), chunk_points=2048,
    )  # fmt: skip
    _assert_same(run, whole)


@pytest.mark.slow
def test_default_chunks_at_a_few_million_points() -> None:
    """The default chunk (2²⁰ points, three chunks and a partial one) on the paper's grid."""
    generator = {"n_points": 3_500_000, "length": 350.0}
    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=21, **generator)
    whole = simulate(lower, upper, steps=200, diagnostics=False)
    del lower, upper
    run = simulate_generated(1.5, seed=21, generator=generator, steps=200)
    _assert_same(run, whole)
