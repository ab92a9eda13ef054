"""The roughness parameters (R_A, R_q, R_Sq) agree wherever the package reports them.

Their one definition is :mod:`splinecontact.profile`; a simulation's scalars (monotone loading
and load path), its xarray export and the profile's own properties must give the same numbers,
bit for bit, and those numbers must match the textbook formulas (eq. 15 for R_Sq).
"""

from __future__ import annotations

import numpy as np
import pytest

from splinecontact import Profile, Segment, fit_spline, simulate, weierstrass_mandelbrot_pair
from splinecontact.profile import (
    rms_slope,
    roughness_average,
    roughness_rms,
    slope_rms,
    surface_statistics,
)


@pytest.fixture(scope="module")
def pair() -> tuple[Profile, Profile]:
    return weierstrass_mandelbrot_pair(1.5, seed=7, n_points=512, length=1.0)


def test_definitions_match_the_formulas() -> None:
    z = np.array([0.0, 1.0, -1.0, 2.0, 0.5])
    dx = 0.25
    mean = z.mean()
    assert roughness_average(z) == pytest.approx(np.abs(z - mean).sum() / z.size, rel=1e-15)
    assert roughness_rms(z) == pytest.approx(np.sqrt(((z - mean) ** 2).sum() / z.size), rel=1e-15)
    slopes = np.array([(z[i] - z[i - 1]) / dx for i in range(1, z.size)])
    assert rms_slope(z, dx) == pytest.approx(np.sqrt((slopes**2).sum() / (z.size - 1)), rel=1e-15)
    assert slope_rms(slopes) == pytest.approx(rms_slope(z, dx), rel=1e-15)


def test_profile_properties_are_the_definitions(pair: tuple[Profile, Profile]) -> None:
    lower, _ = pair
    assert lower.ra == roughness_average(lower.z)
    assert lower.rq == roughness_rms(lower.z)
    assert lower.rsq == rms_slope(lower.z, lower.dx)


@pytest.mark.parametrize("kind", ["flat", "rough"])
def test_simulation_scalars_agree_with_the_profiles(
    pair: tuple[Profile, Profile], kind: str
) -> None:
    lower, upper_profile = pair
    upper = "flat" if kind == "flat" else upper_profile
    fit_l = fit_spline(lower)
    runs = [
        simulate(lower, upper, steps=5, diagnostics=False),
        simulate(lower, upper, path=[Segment(normal=1e-3, steps=3)]),
    ]
    for result in runs:
        s = result.scalars
        assert s["ra_lower"] == lower.ra
        assert s["rq_lower"] == lower.rq
        assert s["rsq_lower"] == lower.rsq
        assert s["peak_to_valley_lower"] == lower.peak_to_valley
        assert s["rsq_lower_spline"] == slope_rms(fit_l.slope)
        ds = result.to_xarray()
        for name in ("ra_lower", "rq_lower", "rsq_lower", "ra_upper", "rq_upper", "rsq_gap"):
            assert float(ds[name]) == s[name]
        if kind == "flat":
            assert s["ra_upper"] == s["rq_upper"] == s["rsq_upper"] == 0.0
            assert s["rsq_gap"] == lower.rsq
            assert s["rsq_gap_spline"] == s["rsq_lower_spline"]
        else:
            fit_u = fit_spline(upper_profile)
            assert s["ra_upper"] == upper_profile.ra
            assert s["rq_upper"] == upper_profile.rq
            assert s["rsq_upper"] == upper_profile.rsq
            assert s["rsq_upper_spline"] == slope_rms(fit_u.slope)
            # the gap z^u − z^l of the turned-over upper body has the slope of z^l + z^u
            assert s["rsq_gap"] == Profile(lower.x, lower.z + upper_profile.z).rsq
            assert s["rsq_gap_spline"] == slope_rms(fit_l.slope + fit_u.slope)
        expected = surface_statistics(
            lower,
            None if kind == "flat" else upper_profile,
            fit_l.slope,
            None if kind == "flat" else fit_spline(upper_profile).slope,
        )
        assert {k: s[k] for k in expected} == expected
