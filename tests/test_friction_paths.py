"""Load paths and friction on analytic geometries: closed forms the engine must meet.

Two circles of radii R1 (lower) and R2 (upper) whose apexes sit at the same grid point: with
the upper body shifted by u and lowered by d, the centre separation is X = (u, R1 + R2 − d), the
overlap δ = R1 + R2 − |X|, and the normal force on the upper body (π/4)E*δ·X/|X|.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from splinecontact import Profile, Segment, simulate
from splinecontact.analysis import dissipated_energy, driver_work, segment_steps

from conftest import ANGSTROM, circle_cap

E_STAR = 10.0
G_STAR = E_STAR / 2.6
QP = 0.25 * math.pi


def _grid(half_width: float) -> np.ndarray:
    n = round(half_width / ANGSTROM)
    return np.arange(-n, n + 1) * ANGSTROM


def _circles(r1: float, r2: float, half_width: float) -> tuple[Profile, Profile]:
    x = _grid(half_width)
    return Profile(x, circle_cap(x, r1)), Profile(x, circle_cap(x, r2))


def _analytic(r1: float, r2: float, u: np.ndarray, d: np.ndarray):  # type: ignore[no-untyped-def]
    """Overlap δ and the unit repulsive direction e = X/|X| of two circles."""
    x_vec = np.stack([u, r1 + r2 - d])
    length = np.hypot(*x_vec)
    return r1 + r2 - length, x_vec[0] / length, x_vec[1] / length


# (R1, R2, overlap d, travel u0) with u0 a sizable fraction of the contact half-width √(d R_eff).
SLIDING_CASES = [(10.0, 5.0, 0.01, 0.1), (1.0, 2.0, 0.004, 0.03), (0.5, 0.5, 0.002, 0.01)]


@pytest.mark.parametrize(("r1", "r2", "d", "u0"), SLIDING_CASES)
def test_frictionless_sliding_of_two_circles(r1: float, r2: float, d: float, u0: float) -> None:
    lower, upper = _circles(r1, r2, 4 * u0 + 2 * math.sqrt(d * r1 * r2 / (r1 + r2)))
    path = [
        Segment(normal=0.0, tangential=-u0, steps=5),
        Segment(normal=d, steps=40),
        Segment(normal=d, tangential=u0, steps=300),
    ]
    result = simulate(lower, upper, mu0=0.0, e_star=E_STAR, path=path, record_contacts="all")
    sliding = slice(45, None)
    u = result.tangential_displacement[sliding]
    dn = result.displacement[sliding]
    np.testing.assert_allclose(u, np.linspace(-u0, u0, 301), rtol=0, atol=1e-15)
    assert np.all(dn == d)
    assert np.all(result.n_contacts[sliding] == 1)
    delta, e_x, e_z = _analytic(r1, r2, u, dn)
    magnitude = QP * E_STAR * delta
    fn_exact = magnitude * e_z
    ft_exact = magnitude * e_x
    np.testing.assert_allclose(result.normal_force[sliding], fn_exact, rtol=1e-6)
    # F_T passes through 0 at u = 0: its error is measured against the force's magnitude.
    assert np.all(np.abs(result.tangential_force[sliding] - ft_exact) <= 1e-6 * magnitude)
    # Resisting before the apexes pass, pushing after.
    assert np.all(result.tangential_force[sliding][u < 0] < 0)
    assert np.all(result.tangential_force[sliding][u > 0] > 0)
    # The contact centre migrates across many cells.
    points = [c.point[0] for c in result.contacts[45:]]
    assert max(points) - min(points) > 50
    # Net tangential work over −u0 → +u0 is zero.
    ft = result.tangential_force[sliding]
    work = np.sum(0.5 * (ft[1:] + ft[:-1]) * np.diff(u))
    assert abs(work) <= 1e-6 * np.sum(0.5 * np.abs(ft[1:] + ft[:-1]) * np.diff(u))
    assert np.all(result.dissipated_work == 0)


@pytest.mark.parametrize(("r1", "r2", "d", "u0"), SLIDING_CASES[:2])
def test_sticking_spring_follows_the_contact(r1: float, r2: float, d: float, u0: float) -> None:
    """μ0 large: F^t = −G* ∫ Δu·t along the path (trapezoidal sum, computed here from X)."""
    lower, upper = _circles(r1, r2, 4 * u0 + 2 * math.sqrt(d * r1 * r2 / (r1 + r2)))
    path = [
        Segment(normal=0.0, tangential=-u0, steps=5),
        Segment(normal=d, steps=40),
        Segment(normal=d, tangential=u0, steps=300),
        Segment(normal=0.5 * d, tangential=0.3 * u0, steps=100),
    ]
    result = simulate(
        lower, upper, mu0=1e6, e_star=E_STAR, g_star=G_STAR, path=path, record_contacts="all"
    )
    u = result.tangential_displacement
    dn = result.displacement
    delta, e_x, e_z = _analytic(r1, r2, u, dn)
    first = int(np.flatnonzero(result.n_contacts[6:])[0]) + 6  # first contact of the lowering
    assert delta[first] > 0 and delta[first - 1] <= 1e-3 * d
    live = slice(first, None)
    assert np.all(result.n_contacts[live] == 1)
    assert np.all(result.n_slipping == 0)
    du = np.diff(u[live])
    dd = np.diff(dn[live])
    increments = 0.5 * (
        du * (e_z[live][1:] + e_z[live][:-1]) + dd * (e_x[live][1:] + e_x[live][:-1])
    )
    spring = -G_STAR * np.concatenate([[0.0], np.cumsum(increments)])
    magnitude = QP * E_STAR * delta[live]
    recorded = np.array([c.tangential_force[0] for c in result.contacts[first:]])
    scale = np.abs(spring).max()
    assert scale > 0.01 * magnitude.max()  # the spring force is a sizable part of the force
    assert np.all(np.abs(recorded - spring) <= 1e-6 * scale)
    fn_exact = magnitude * e_z[live] - spring * e_x[live]
    ft_exact = magnitude * e_x[live] + spring * e_z[live]
    np.testing.assert_allclose(result.normal_force[live], fn_exact, rtol=1e-6)
    assert np.all(np.abs(result.tangential_force[live] - ft_exact) <= 1e-6 * magnitude)
    points = [c.point[0] for c in result.contacts[first:]]
    assert max(points) - min(points) > 50  # many cells crossed, the spring kept


@pytest.mark.parametrize(("radius", "mu0"), [(1.0, 0.3), (0.2, 0.05)])
def test_coulomb_cap_on_a_rigid_flat(radius: float, mu0: float) -> None:
    x = _grid(0.02)
    lower = Profile(x, circle_cap(x, radius))
    delta = 1e-3 * radius
    f_n = QP * E_STAR * delta
    cap = mu0 * f_n
    amplitude = 3.0 * cap / G_STAR
    path = [
        Segment(normal=delta, steps=10),
        Segment(normal=delta, tangential=amplitude, steps=301),
        Segment(tangential=-amplitude, steps=457),
        Segment(tangential=amplitude, steps=457),
        Segment(tangential=-amplitude, steps=457),
        Segment(tangential=amplitude, steps=457),
    ]
    result = simulate(lower, "flat", mu0=mu0, e_star=E_STAR, g_star=G_STAR, path=path)
    assert np.all(result.n_contacts[1:] == 1)
    np.testing.assert_allclose(result.normal_force[10:], f_n, rtol=1e-12)
    u = result.tangential_displacement
    ft = result.tangential_force
    bounds = segment_steps(result)
    a, b = bounds[1]
    expected = -np.minimum(G_STAR * u[a : b + 1], cap)
    np.testing.assert_allclose(ft[a : b + 1], expected, rtol=1e-12, atol=1e-15 * cap)
    # Single spring–slider (Cattaneo-type) loop, written independently of the engine.
    f_prev = ft[b]
    for a, b in bounds[2:]:
        for k in range(a + 1, b + 1):
            trial = f_prev - G_STAR * (u[k] - u[k - 1])
            f_prev = min(max(trial, -cap), cap)
            assert abs(ft[k] - f_prev) <= 1e-12 * cap
    # Slip flags: slipping steps are exactly where |F_T| is at the cap and moving on.
    assert np.all(result.n_slipping[bounds[1][0] + 1 :] <= 1)
    # Dissipation per full cycle (+A → −A → +A): 4 F_c (A − F_c/G*).
    closed = 4.0 * cap * (amplitude - cap / G_STAR)
    for start, stop in ((bounds[1][1], bounds[3][1]), (bounds[3][1], bounds[5][1])):
        assert dissipated_energy(result, start, stop) == pytest.approx(closed, rel=1e-9)
        # The driver's work over the closed loop agrees up to the trapezoidal rule at 4 kinks.
        du = amplitude / 457 * 2
        assert abs(driver_work(result, start, stop) - closed) <= 4 * G_STAR * du * du


def test_unloading_retraces_loading_without_slip() -> None:
    """An elastic Hertz pair off-axis (inclined contact, spring loaded): no hysteresis."""
    r1, r2, d = 2.0, 1.0, 0.004
    lower, upper = _circles(r1, r2, 0.25)
    n = 80
    for mu0, hysteresis in ((1e6, False), (0.002, True)):
        path = [
            Segment(normal=0.0, tangential=0.03, steps=3),
            Segment(normal=d, steps=n),
            Segment(normal=0.0, steps=n),
        ]
        result = simulate(lower, upper, mu0=mu0, e_star=E_STAR, path=path)
        load = slice(3, 3 + n + 1)
        unload = slice(3 + 2 * n, 3 + n - 1, -1)
        np.testing.assert_allclose(
            result.displacement[unload], result.displacement[load], atol=1e-15
        )
        fn_l, fn_u = result.normal_force[load], result.normal_force[unload]
        ft_l, ft_u = result.tangential_force[load], result.tangential_force[unload]
        scale = np.abs(fn_l).max()
        assert np.any(result.n_contacts[load] == 1)
        if not hysteresis:
            assert np.all(result.n_slipping == 0)
            assert np.all(np.abs(fn_u - fn_l) <= 1e-9 * scale)
            assert np.all(np.abs(ft_u - ft_l) <= 1e-9 * scale)
        else:  # the oracle can fail: with slip the curves separate and energy is dissipated
            assert result.n_slipping.max() > 0
            assert np.abs(ft_u - ft_l).max() > 1e-3 * scale
            assert result.dissipated_work[-1] > 0


@pytest.mark.parametrize("mu0", [0.0, 0.3, 1e6])
def test_force_control_holds_the_normal_force(mu0: float) -> None:
    r1, r2 = 2.0, 1.0
    lower, upper = _circles(r1, r2, 0.3)
    target = QP * E_STAR * 0.003
    path = [
        Segment(normal=0.002, steps=20),
        Segment(normal_force=target, tangential=0.05, steps=60),
        Segment(normal_force=0.5 * target, tangential=-0.02, steps=40),
    ]
    result = simulate(lower, upper, mu0=mu0, e_star=E_STAR, path=path)
    held = np.isfinite(result.normal_force_target)
    assert held.sum() == 100
    np.testing.assert_allclose(
        result.normal_force[held], result.normal_force_target[held], rtol=1e-6
    )
    assert np.all(np.isnan(result.normal_force_target[:21]))
    if mu0 == 0.0:  # frictionless: δ_N is the root of F_N(u, δ_N) = target, known exactly
        from scipy.optimize import brentq

        for k in np.flatnonzero(held):
            u, want = result.tangential_displacement[k], result.normal_force_target[k]

            def residual(dn: float, u: float = u, want: float = want) -> float:
                delta, _, e_z = _analytic(r1, r2, np.array([u]), np.array([dn]))
                return float(QP * E_STAR * delta[0] * e_z[0] - want)

            exact = brentq(residual, 0.0, 0.05, xtol=1e-15)
            assert abs(result.displacement[k] - exact) <= 1e-6 * exact
        # The circles are lowered to keep F_N while they slide apart sideways.
        assert np.ptp(result.displacement[21:81]) > 1e-4
