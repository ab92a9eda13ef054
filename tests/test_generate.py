"""Weierstrass–Mandelbrot generator (eq. 1; issue 2, item 3)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from splinecontact import weierstrass_mandelbrot, weierstrass_mandelbrot_pair
from splinecontact.errors import ParameterError
from splinecontact.spectra import hurst_exponent


def _direct_sum(dimension: float, x: np.ndarray, seed: int, law: str = "hurst") -> np.ndarray:
    """Eq. 1 summed term by term (the obviously-correct reference)."""
    gamma, directions, n_max, wavelength = 1.5, 20, 20, 1.0
    phases = np.random.default_rng(seed).uniform(0, 2 * np.pi, size=(directions, n_max + 1))
    exponent = (dimension - 2) * (1 if law == "hurst" else 2)
    nyquist = 0.5 / (x[1] - x[0])
    z = np.zeros_like(x)
    for m in range(1, directions + 1):
        for n in range(n_max + 1):
            frequency = gamma**n * math.cos(math.pi * m / directions) / wavelength
            if abs(frequency) > nyquist:
                continue
            phi = phases[m - 1, n]
            z += gamma ** (exponent * n) * (math.cos(phi) - np.cos(2 * np.pi * frequency * x + phi))
    z -= z.mean()
    return z * 0.005 / np.mean(np.abs(z))


@pytest.mark.parametrize("law", ["hurst", "as_printed"])
def test_matches_direct_summation_of_eq1(law: str) -> None:
    p = weierstrass_mandelbrot(1.4, n_points=30_001, length=3.0, seed=11, amplitude_law=law)
    reference = _direct_sum(1.4, p.x, 11, law)
    assert np.max(np.abs(p.z - reference)) < 1e-9 * 0.005


def test_same_seed_is_bit_identical_and_different_seeds_differ() -> None:
    a = weierstrass_mandelbrot(1.5, n_points=50_000, length=5.0, seed=3)
    b = weierstrass_mandelbrot(1.5, n_points=50_000, length=5.0, seed=3)
    c = weierstrass_mandelbrot(1.5, n_points=50_000, length=5.0, seed=4)
    assert np.array_equal(a.z, b.z)
    assert not np.array_equal(a.z, c.z)


def test_seed_sequence_and_generator_inputs() -> None:
    ss = np.random.SeedSequence(5)
    a = weierstrass_mandelbrot(1.5, n_points=2_000, length=0.2, seed=ss)
    b = weierstrass_mandelbrot(1.5, n_points=2_000, length=0.2, seed=np.random.SeedSequence(5))
    assert np.array_equal(a.z, b.z)
    g = weierstrass_mandelbrot(1.5, n_points=2_000, length=0.2, seed=np.random.default_rng(5))
    assert np.isfinite(g.z).all()


@pytest.mark.parametrize("dimension", [1.0, 1.3, 1.7, 2.0])
def test_ra_equals_target(dimension: float) -> None:
    p = weierstrass_mandelbrot(dimension, n_points=100_000, length=10.0, ra=0.0123, seed=1)
    assert abs(p.ra - 0.0123) <= 1e-12 * 0.0123
    assert abs(p.z.mean()) < 1e-15


def test_pair_uses_independent_reproducible_phases() -> None:
    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=8, n_points=5_000, length=0.5)
    lower2, upper2 = weierstrass_mandelbrot_pair(1.5, seed=8, n_points=5_000, length=0.5)
    assert np.array_equal(lower.z, lower2.z) and np.array_equal(upper.z, upper2.z)
    assert not np.array_equal(lower.z, upper.z)
    assert lower.metadata["seed_spawn_key"] == [0]
    assert upper.metadata["seed_spawn_key"] == [1]


def test_terms_above_nyquist_are_dropped_and_counted() -> None:
    fine = weierstrass_mandelbrot(1.5, n_points=1_000_001, length=100.0, seed=1)
    coarse = weierstrass_mandelbrot(1.5, n_points=10_001, length=100.0, seed=1)
    assert fine.metadata["n_terms_dropped_above_nyquist"] == 0
    # Nyquist 50/µm: terms with 1.5^n |cos(πm/20)| > 50 are dropped.
    expected = sum(
        1
        for m in range(1, 21)
        for n in range(21)
        if 2 * m != 20 and 1.5**n * abs(math.cos(math.pi * m / 20)) > 50.0
    )
    assert coarse.metadata["n_terms_dropped_above_nyquist"] == expected > 0
    assert fine.metadata["n_terms"] == 20 * 21


@pytest.mark.parametrize("dimension", [1.2, 1.5, 1.8])
def test_psd_slope_gives_hurst_two_minus_d(dimension: float) -> None:
    measured = np.mean(
        [hurst_exponent(weierstrass_mandelbrot(dimension, seed=s)) for s in range(3)]
    )
    assert abs(measured - (2.0 - dimension)) < 0.1


def test_printed_amplitude_law_doubles_the_hurst_exponent() -> None:
    measured = np.mean(
        [
            hurst_exponent(weierstrass_mandelbrot(1.7, seed=s, amplitude_law="as_printed"))
            for s in range(3)
        ]
    )
    assert abs(measured - 2.0 * (2.0 - 1.7)) < 0.1


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"dimension": 2.5}, "outside"),
        ({"dimension": 0.9}, "outside"),
        ({"dimension": float("nan")}, "not finite"),
        ({"dimension": 1.5, "n_points": 4}, "n_points"),
        ({"dimension": 1.5, "length": -1.0}, "length"),
        ({"dimension": 1.5, "gamma": 1.0}, "gamma"),
        ({"dimension": 1.5, "ra": 0.0}, "ra"),
        ({"dimension": 1.5, "directions": 0}, "directions"),
        ({"dimension": 1.5, "n_max": -1}, "n_max"),
        ({"dimension": 1.5, "amplitude_law": "printed"}, "amplitude_law"),
        ({"dimension": 1.5, "wavelength": 0.0}, "wavelength"),
    ],
)
def test_bad_parameters_raise(kwargs: dict, fragment: str) -> None:
    dimension = kwargs.pop("dimension")
    kwargs.setdefault("n_points", 1000)
    with pytest.raises(ParameterError, match=fragment):
        weierstrass_mandelbrot(dimension, **kwargs)


def test_pair_shares_one_read_only_grid_and_matches_single_calls() -> None:
    lower, upper = weierstrass_mandelbrot_pair(1.6, seed=4, n_points=4_001, length=0.4)
    assert lower.x is upper.x and not lower.x.flags.writeable and not upper.z.flags.writeable
    parent = np.random.SeedSequence(4)
    alone = weierstrass_mandelbrot(
        1.6, n_points=4_001, length=0.4, seed=np.random.SeedSequence(4, spawn_key=(1,))
    )
    assert parent.spawn_key == ()
    assert np.array_equal(alone.z, upper.z) and np.array_equal(alone.x, upper.x)


@pytest.mark.parametrize("n_points", [5, 6, 7, 1_001, 4_099])
def test_heights_have_zero_mean_and_target_ra_at_any_length(n_points: int) -> None:
    # the kernel removes the closed-form grid mean of eq. 1; the block tail (n not a multiple
    # of the 4-point register block) must give the same heights as the direct sum
    p = weierstrass_mandelbrot(1.5, n_points=n_points, length=0.002 * n_points, seed=9)
    assert abs(p.z.mean()) < 1e-15
    assert abs(p.ra - 0.005) <= 1e-12 * 0.005
    reference = _direct_sum(1.5, p.x, 9)
    assert np.max(np.abs(p.z - reference)) < 1e-9 * 0.005


def test_pair_on_two_threads_is_bit_identical_to_one_after_the_other(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # above the threshold the two sums run on two threads; each profile depends only on its own
    # child seed, so the result equals the single calls and the sequential pair bit for bit
    from splinecontact import generate

    n = generate._PAIR_THREAD_MIN_POINTS + 3
    lower, upper = weierstrass_mandelbrot_pair(1.4, seed=11, n_points=n, length=3.0)
    assert lower.x is upper.x and not lower.x.flags.writeable
    for index, threaded in enumerate((lower, upper)):
        alone = weierstrass_mandelbrot(
            1.4, n_points=n, length=3.0, seed=np.random.SeedSequence(11, spawn_key=(index,))
        )
        assert np.array_equal(alone.z, threaded.z) and np.array_equal(alone.x, threaded.x)
        assert alone.metadata == threaded.metadata
    monkeypatch.setattr(generate, "_PAIR_THREAD_MIN_POINTS", 10**12)
    seq_lower, seq_upper = weierstrass_mandelbrot_pair(1.4, seed=11, n_points=n, length=3.0)
    assert np.array_equal(seq_lower.z, lower.z) and np.array_equal(seq_upper.z, upper.z)


def test_pair_refuses_unknown_and_bad_arguments_like_single_calls() -> None:
    with pytest.raises(TypeError):
        weierstrass_mandelbrot_pair(1.5, seed=1, n_point=1000)  # type: ignore[call-arg]
    with pytest.raises(ParameterError, match="n_points"):
        weierstrass_mandelbrot_pair(1.5, seed=1, n_points=3)
