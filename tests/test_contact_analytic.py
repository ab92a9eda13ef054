"""SAD on analytic geometries, through the whole pipeline (issue 2 acceptance).

Two sampled circles touching at a grid point overlap by exactly the imposed displacement, so the
2D Hertz line-contact force (π/4) E* δ is known exactly at every step.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from splinecontact import Profile, simulate
from splinecontact.contact import contact_geometry

from conftest import ANGSTROM, circle_cap, circle_cup

# Analytic geometries (single circles, cups, a rigid flat) are one curved form by construction:
# simulate()'s FormWarning/LargeContactWarning on them are true and irrelevant here; the
# diagnostics themselves are tested in tests/test_cli_measured.py.
pytestmark = pytest.mark.filterwarnings("ignore::splinecontact.diagnostics.SimulationWarning")

E_STAR = 10.0


def _grid(half_width: float) -> np.ndarray:
    n = round(half_width / ANGSTROM)
    return np.arange(-n, n + 1) * ANGSTROM


def _check_single_hertz_contact(result, radius_eff: float) -> None:  # type: ignore[no-untyped-def]
    d = result.curves["displacement"][1:]
    force = result.curves["normal_force"][1:]
    assert np.all(result.curves["n_contacts"][1:] == 1)
    np.testing.assert_allclose(force, 0.25 * math.pi * E_STAR * d, rtol=1e-6)
    assert np.all(force > 0)  # the bodies are pushed apart
    for record in result.contacts:
        if record.step == 0:
            continue
        assert record.point.size == 1
        assert record.normal_z[0] > 0.999999
        np.testing.assert_allclose(record.overlap, d[record.step - 1], rtol=1e-6)
        np.testing.assert_allclose(record.effective_radius, radius_eff, rtol=1e-6)
        assert abs(record.x[0]) < 0.5 * ANGSTROM


@pytest.mark.parametrize(("r_lower", "r_upper"), [(1.0, 0.5), (0.1, 10.0), (3.0, 3.0)])
def test_convex_convex_circles(r_lower: float, r_upper: float) -> None:
    x = _grid(0.05)
    lower = Profile(x, circle_cap(x, r_lower))
    upper = Profile(x, circle_cap(x, r_upper))
    final = 1e-3 * min(r_lower, r_upper)
    result = simulate(lower, upper, steps=20, final_displacement=final, record_contacts="all")
    _check_single_hertz_contact(result, 2 * r_lower * r_upper / (r_lower + r_upper))


@pytest.mark.parametrize(("r_ball", "r_cup"), [(0.5, 2.0), (0.1, 0.3), (2.0, 10.0)])
def test_ball_in_lower_cup(r_ball: float, r_cup: float) -> None:
    x = _grid(0.05)
    lower = Profile(x, circle_cup(x, r_cup))  # concave lower body
    upper = Profile(x, circle_cap(x, r_ball))  # convex ball pointing down into it
    result = simulate(
        lower, upper, steps=20, final_displacement=1e-3 * r_ball, record_contacts="all"
    )
    _check_single_hertz_contact(result, 2 * r_ball * r_cup / (r_cup - r_ball))


@pytest.mark.parametrize(("r_peak", "r_cup"), [(0.5, 2.0), (1.0, 10.0)])
def test_peak_in_upper_cup(r_peak: float, r_cup: float) -> None:
    x = _grid(0.05)
    lower = Profile(x, circle_cap(x, r_peak))
    upper = Profile(x, circle_cup(x, r_cup))  # the upper body's surface is a cup over the peak
    result = simulate(
        lower, upper, steps=20, final_displacement=1e-3 * r_peak, record_contacts="all"
    )
    _check_single_hertz_contact(result, 2 * r_peak * r_cup / (r_cup - r_peak))


@pytest.mark.parametrize("radius", [0.1, 1.0, 10.0])
def test_circle_against_rigid_flat(radius: float) -> None:
    x = _grid(0.05)
    lower = Profile(x, circle_cap(x, radius))
    result = simulate(
        lower, "flat", steps=20, final_displacement=1e-3 * radius, record_contacts="all"
    )
    _check_single_hertz_contact(result, 2 * radius)  # sphere on plane: R_eff = 2R (eq. 10)


def test_flat_upper_body_is_rigid_flat_limit() -> None:
    x = _grid(0.02)
    lower = Profile(x, circle_cap(x, 1.0))
    flat_profile = Profile(x, np.zeros_like(x))
    a = simulate(lower, "flat", steps=10, final_displacement=1e-3)
    b = simulate(lower, flat_profile, steps=10, final_displacement=1e-3)
    np.testing.assert_allclose(a.normal_force, b.normal_force, rtol=1e-12)


def test_concave_concave_and_wide_cup_are_rejected() -> None:
    """Table 1: a ball wider than the cup, or two cups, make no contact."""
    x = _grid(0.02)
    ball_wide = Profile(x, circle_cap(x, 3.0))
    cup_narrow = Profile(x, circle_cup(x, 1.0))
    for lower, upper in ((cup_narrow, ball_wide), (cup_narrow, cup_narrow)):
        geometry = contact_geometry(
            lower,
            upper,
            steps=5,
            final_displacement=1e-4,
            final_displacement_factor=0.2,
            alpha=2.0,
            x0=1.0,
        )
        assert geometry.point.size > 0  # gaps do close (at the rims) ...
        # ... but κ^u + κ^l ≤ 0 there (0 only at the spline's natural ends): Table 1 rejects.
        assert np.all(geometry.curvature_lower + geometry.curvature_upper <= 0)
        result = simulate(lower, upper, steps=5, final_displacement=1e-4)
        assert np.all(result.n_contacts == 0)
        assert np.all(result.normal_force == 0)


@pytest.mark.parametrize("radius", [1e6, 1e9, 1e12])
def test_near_flat_contact_overlap_is_exact(radius: float) -> None:
    x = _grid(0.01)
    lower = Profile(x, circle_cap(x, radius))
    final = 1e-3
    for upper in ("flat", Profile(x, circle_cap(x, radius))):
        result = simulate(lower, upper, steps=4, final_displacement=final, record_contacts="all")
        for record in result.contacts[1:]:
            apex = record.point == x.size // 2
            assert apex.sum() == 1
            expected = result.displacement[record.step]
            assert abs(record.overlap[apex][0] - expected) <= 1e-9 * expected
            assert np.isfinite(record.effective_radius).all()


def test_flat_spots_and_spline_ends_give_no_nan() -> None:
    x = np.linspace(0.0, 0.1, 1001)
    z = np.where(np.abs(x - 0.05) < 0.02, 0.0, -((np.abs(x - 0.05) - 0.02) ** 2))
    result = simulate(Profile(x, z), Profile(x, z), steps=10, final_displacement=1e-4)
    for name in ("normal_force", "tangential_force", "contact_area", "mean_separation"):
        assert np.isfinite(result.curves[name]).all()
