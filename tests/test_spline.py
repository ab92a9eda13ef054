"""Smoothing spline (eqs. 2–3; issue 2, item 4)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import make_smoothing_spline

from splinecontact import Profile, fit_spline, weierstrass_mandelbrot
from splinecontact.errors import ParameterError
from splinecontact.spline import smoothing_parameter


def test_lambda_computed_without_cancellation() -> None:
    dx = 1e-4
    p = 1.0 / (1.0 + dx**2 / 10.0)
    naive = (1.0 - p) / p
    exact = smoothing_parameter(dx)
    assert exact == pytest.approx(dx**2 / 10.0, rel=1e-15)
    assert abs(naive - exact) / exact > 1e-9  # the naive form loses digits


@pytest.mark.parametrize("alpha", [1.5, 2.0, 2.5])
def test_matches_scipy_make_smoothing_spline(alpha: float) -> None:
    p = weierstrass_mandelbrot(1.5, n_points=10_000, length=1.0, seed=2)
    fit = fit_spline(p, alpha=alpha)
    reference = make_smoothing_spline(p.x, p.z, lam=fit.lam)
    for order, values in ((0, fit.f), (1, fit.slope), (2, fit.second_derivative)):
        expected = reference.derivative(order)(p.x) if order else reference(p.x)
        assert np.max(np.abs(values - expected)) <= 1e-8 * np.max(np.abs(expected))


def test_natural_ends_and_exact_on_straight_lines() -> None:
    x = np.linspace(0.0, 1.0, 101)
    fit = fit_spline(Profile(x, 0.3 * x - 0.1))
    assert fit.second_derivative[0] == 0.0 and fit.second_derivative[-1] == 0.0
    np.testing.assert_allclose(fit.f, 0.3 * x - 0.1, atol=1e-13)
    np.testing.assert_allclose(fit.slope, 0.3, atol=1e-11)
    np.testing.assert_allclose(fit.second_derivative, 0.0, atol=1e-8)


def test_tighter_alpha_follows_the_data_more_closely() -> None:
    p = weierstrass_mandelbrot(1.6, n_points=20_000, length=2.0, seed=4)
    misfit = [np.sqrt(np.mean((fit_spline(p, alpha=a).f - p.z) ** 2)) for a in (1.5, 2.0, 2.5)]
    assert misfit[0] > misfit[1] > misfit[2]


@pytest.mark.parametrize(("alpha", "x0"), [(0.0, 1.0), (-1.0, 1.0), (2.0, 0.0), (2.0, -1.0)])
def test_bad_parameters(alpha: float, x0: float) -> None:
    p = Profile(np.linspace(0, 1, 10), np.zeros(10))
    with pytest.raises(ParameterError):
        fit_spline(p, alpha=alpha, x0=x0)


def test_smoothing_length_is_where_a_sinusoid_keeps_half_its_amplitude() -> None:
    """(λ·dx)^(1/4) is a length: a sine of wavelength 2π(λ·dx)^(1/4) keeps half its amplitude."""
    dx = 1e-4
    x = np.arange(200_001) * dx
    fit0 = fit_spline(Profile(x, np.zeros_like(x)))
    cutoff = 2 * np.pi * fit0.smoothing_length
    assert cutoff == pytest.approx(3.5e-3, rel=0.02)  # PHYSICS.md: ~3.5 nm at the paper's grid
    fit = fit_spline(Profile(x, np.sin(2 * np.pi * x / cutoff)))
    middle = slice(50_000, 150_000)
    amplitude = np.max(np.abs(fit.f[middle]))
    assert amplitude == pytest.approx(0.5, abs=0.01)


def test_pair_of_fits_on_two_threads_equals_two_calls(monkeypatch: pytest.MonkeyPatch) -> None:
    # above the threshold the two fits run on two threads; each depends only on its profile
    from splinecontact import spline, weierstrass_mandelbrot_pair
    from splinecontact.spline import fit_spline_pair

    n = spline._PAIR_THREAD_MIN_POINTS + 5
    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=3, n_points=n, length=n * 1e-4)
    fit_l, fit_u = fit_spline_pair(lower, upper, alpha=2.0, x0=1.0)
    assert fit_u is not None
    for fit, body in ((fit_l, lower), (fit_u, upper)):
        alone = fit_spline(body)
        for name in ("f", "slope", "second_derivative"):
            assert np.array_equal(getattr(fit, name), getattr(alone, name))
    only, none = fit_spline_pair(lower, None)
    assert none is None and np.array_equal(only.f, fit_l.f)
    with pytest.raises(ParameterError, match="alpha"):
        fit_spline_pair(lower, upper, alpha=-1.0)
