"""Surface spheres (paper eqs. 4–6) on sampled circles, where the exact spheres are known.

A smoothing spline (eqs. 2–3) of a finely sampled circle of radius R is the circle up to the
spline's smoothing error, which for the default α = 2, x0 = 1 µm scales as (dx/R)²: on these
grids the radius is within 0.6·(dx/R)² of R (measured: 5.8e−9 at dx/R = 1e−4, 6.0e−7 at 1e−3,
2.3e−8 at dx/R = 2e−4), so the tests hold the radius to 2(dx/R)² relative and the centres to
2(dx/R)²·R. The inner 80 % of the grid is checked: at the natural ends the spline has f″ = 0 by
construction (a flat sphere), which is not the circle's.
"""

from __future__ import annotations

import numpy as np
import pytest

from splinecontact import Profile, SurfaceSpheres, fit_spline, surface_spheres
from splinecontact.errors import ParameterError

from conftest import ANGSTROM, circle_cap, circle_cup


def _spheres(radius: float, dx: float, shape=circle_cap) -> tuple[Profile, SurfaceSpheres]:  # type: ignore[no-untyped-def]
    x = np.arange(-0.5 * radius, 0.5 * radius + 0.5 * dx, dx)
    profile = Profile(x, shape(x, radius))
    return profile, surface_spheres(fit_spline(profile))


def _inner(n: int) -> slice:
    return slice(n // 10, n - n // 10)


@pytest.mark.parametrize(("radius", "dx"), [(1.0, ANGSTROM), (1.0, 1e-3), (5.0, 1e-3)])
def test_spheres_of_a_circular_peak_are_the_circle(radius: float, dx: float) -> None:
    profile, spheres = _spheres(radius, dx)
    inner = _inner(profile.n_points)
    tol = 2.0 * (dx / radius) ** 2
    assert spheres.r_min == pytest.approx(0.5 * dx)
    assert not spheres.is_flat[inner].any()
    # eq. 5: κ = 1/R > 0 on a peak (convex toward the other body)
    np.testing.assert_allclose(spheres.radius[inner], radius, rtol=tol, atol=0)
    np.testing.assert_allclose(spheres.curvature[inner], 1.0 / radius, rtol=tol, atol=0)
    # eq. 6: O = a − R n is the circle's centre (0, −R) at every point
    np.testing.assert_allclose(spheres.centre_x[inner], 0.0, rtol=0, atol=tol * radius)
    np.testing.assert_allclose(spheres.centre_z[inner], -radius, rtol=0, atol=tol * radius)
    # eq. 4: the outward normal of the circle, (x, z + R)/R
    x, z = profile.x[inner], profile.z[inner]
    np.testing.assert_allclose(spheres.normal_x[inner], x / radius, rtol=0, atol=tol)
    np.testing.assert_allclose(spheres.normal_z[inner], (z + radius) / radius, rtol=0, atol=tol)
    np.testing.assert_allclose(np.hypot(spheres.normal_x, spheres.normal_z), 1.0, rtol=1e-15)


def test_spheres_of_a_circular_cup_have_negative_radius_and_centre_above() -> None:
    radius, dx = 2.0, 1e-3
    profile, spheres = _spheres(radius, dx, circle_cup)
    inner = _inner(profile.n_points)
    tol = 2.0 * (dx / radius) ** 2
    np.testing.assert_allclose(spheres.radius[inner], -radius, rtol=tol, atol=0)
    np.testing.assert_allclose(spheres.centre_x[inner], 0.0, rtol=0, atol=tol * radius)
    np.testing.assert_allclose(spheres.centre_z[inner], radius, rtol=0, atol=tol * radius)


def test_flat_profile_has_flat_spheres_centred_on_the_points() -> None:
    x = np.linspace(0.0, 1.0, 51)
    spheres = surface_spheres(fit_spline(Profile(x, np.zeros_like(x))))
    assert spheres.is_flat.all()
    assert np.isinf(spheres.radius).all()
    np.testing.assert_array_equal(spheres.centre_x, x)
    np.testing.assert_array_equal(spheres.centre_z, np.zeros_like(x))
    np.testing.assert_array_equal(spheres.normal_z, np.ones_like(x))


def test_radius_is_clamped_to_r_min() -> None:
    # a circle of radius 1 µm with r_min = 2 µm: every sphere is clamped to |R| = 2 µm exactly
    profile, _ = _spheres(1.0, 1e-3)
    clamped = surface_spheres(fit_spline(profile), r_min=2.0)
    inner = _inner(profile.n_points)
    assert clamped.r_min == 2.0
    np.testing.assert_array_equal(clamped.radius[inner], 2.0)
    assert np.all(np.abs(clamped.curvature) <= 0.5)


@pytest.mark.parametrize("r_min", [0.0, -1.0, float("nan")])
def test_bad_r_min_is_refused(r_min: float) -> None:
    x = np.linspace(0.0, 1.0, 11)
    with pytest.raises(ParameterError, match="r_min"):
        surface_spheres(fit_spline(Profile(x, np.zeros_like(x))), r_min=r_min)


def test_non_spline_input_is_refused() -> None:
    with pytest.raises(ParameterError, match="not a SplineFit"):
        surface_spheres(np.zeros(5))  # type: ignore[arg-type]
