"""Interacting SAD with tangential sliding and force control: oracles that can fail.

One contact has no neighbour: its coupled load P differs from SAD's independent (π/4)E*δ only
by the part of its own periodic Hertz displacement that eq. 10 leaves out (the self term of
:func:`splinecontact.contact.interaction.self_coefficient`), taken along its normal:
δ = P/((π/4)E*) + e_z² P S(a), a² = 2PR_eff/(πE*), S = c(ln(L_p/(πa)) − 3/2), c = 2/(πE*).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from splinecontact import Profile, Segment, simulate
from splinecontact.analysis import driver_work
from splinecontact.contact import InteractionSettings
from splinecontact.contact.interaction import self_coefficient
from splinecontact.errors import LoadPathError
from splinecontact.generate import weierstrass_mandelbrot

from conftest import ANGSTROM, circle_cap

E_STAR = 10.0
G_STAR = E_STAR / 2.6
QP = 0.25 * math.pi

#: Periodic, Hertz widths converged at every step: the single-contact relation is exact.
EXACT = InteractionSettings(
    periodic=True, width="hertz", width_iterations=100, tol=1e-12, width_tol=1e-13
)


def _circles(r1: float, r2: float, half_width: float) -> tuple[Profile, Profile]:
    n = round(half_width / ANGSTROM)
    x = np.arange(-n, n + 1) * ANGSTROM
    return Profile(x, circle_cap(x, r1)), Profile(x, circle_cap(x, r2))


def _analytic(r1: float, r2: float, u: np.ndarray, d: np.ndarray):  # type: ignore[no-untyped-def]
    """Overlap δ and the unit repulsive direction e = X/|X| of two circles."""
    x_vec = np.stack([u, r1 + r2 - d])
    length = np.hypot(*x_vec)
    return r1 + r2 - length, x_vec[0] / length, x_vec[1] / length


@pytest.fixture(scope="module")
def rough() -> tuple[Profile, Profile]:
    lower = weierstrass_mandelbrot(1.5, n_points=1024, length=4.0, seed=3)
    upper = weierstrass_mandelbrot(1.3, n_points=1024, length=4.0, seed=8)
    return lower, upper


def test_frictionless_sliding_of_two_circles_single_contact() -> None:
    """F_T/F_N = u/(R1 + R2 − d) (the force is along X whatever its size), and the coupled
    load obeys the single-contact relation of the module docstring at every step, while the
    contact centre migrates across many cells."""
    r1, r2, d, u0 = 1.0, 2.0, 0.004, 0.03
    lower, upper = _circles(r1, r2, 4 * u0 + 2 * math.sqrt(d * r1 * r2 / (r1 + r2)))
    path = [
        Segment(normal=0.0, tangential=-u0, steps=3),
        Segment(normal=d, steps=10),
        Segment(normal=d, tangential=u0, steps=60),
    ]
    result = simulate(
        lower, upper, mu0=0.0, e_star=E_STAR, path=path, interaction=EXACT,
        record_contacts="all", diagnostics=False,
    )  # fmt: skip
    independent = simulate(
        lower, upper, mu0=0.0, e_star=E_STAR, path=path, record_contacts="all",
        diagnostics=False,
    )  # fmt: skip
    sliding = slice(13, None)
    u = result.tangential_displacement[sliding]
    assert np.all(result.n_contacts[sliding] == 1)
    delta, e_x, e_z = _analytic(r1, r2, u, result.displacement[sliding])
    f_n = result.normal_force[sliding]
    f_t = result.tangential_force[sliding]
    magnitude = np.hypot(f_n, f_t)
    np.testing.assert_allclose(f_t / f_n, u / (r1 + r2 - d), rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(f_t / magnitude, e_x, rtol=0, atol=1e-9)
    assert np.all(f_t[u < 0] < 0) and np.all(f_t[u > 0] > 0)
    # the exact relation between the coupled load and the independent variant's overlap
    period = lower.n_points * lower.dx
    records = [c for c in result.contacts if c.step >= 13]
    assert [c.step for c in records] == list(range(13, result.displacement.size))
    by_step = {c.step: c for c in independent.contacts}
    for rec in records:
        k = rec.step - 13
        p = rec.normal_force[0]
        a = math.sqrt(2.0 * p * rec.effective_radius[0] / (math.pi * E_STAR))
        expected = p / (QP * E_STAR) + e_z[k] ** 2 * p * self_coefficient(a, period, E_STAR)
        assert expected == pytest.approx(delta[k], rel=1e-9)
        assert p == pytest.approx(magnitude[k], rel=1e-12)
        # the independent variant at the same step: SAD's overlap, same contact cell
        assert by_step[rec.step].overlap[0] == pytest.approx(delta[k], rel=1e-6)
        assert by_step[rec.step].point[0] == rec.point[0]
    # the independent load differs by the self term alone (here negative: L_p < πa e^{3/2})
    assert np.all(np.abs(magnitude - independent.normal_force[sliding] / e_z) > 1e-3 * magnitude)
    points = [c.point[0] for c in records]
    assert max(points) - min(points) > 50
    assert np.all(result.dissipated_work == 0)


@pytest.mark.parametrize("mu0", [0.05, 0.5])
def test_coulomb_cap_of_a_circle_on_the_flat(mu0: float) -> None:
    """Rigid flat: sliding changes no geometry; F_N stays the coupled load of the loading and
    F_T = −min(G* u_T, μ0 F_N) (the single spring–slider with the coupled cap)."""
    x = np.arange(-1000, 1001) * ANGSTROM  # period ≫ the contact width
    lower = Profile(x, circle_cap(x, 0.5))
    delta = 5e-4
    loaded = simulate(
        lower, "flat", e_star=E_STAR, g_star=G_STAR, mu0=mu0, interaction=EXACT,
        path=[Segment(normal=delta, steps=4)], diagnostics=False,
    )  # fmt: skip
    f_n = float(loaded.normal_force[-1])
    cap = mu0 * f_n
    amplitude = 3.0 * cap / G_STAR
    result = simulate(
        lower, "flat", e_star=E_STAR, g_star=G_STAR, mu0=mu0, interaction=EXACT,
        path=[Segment(normal=delta, steps=4), Segment(tangential=amplitude, steps=30)],
        diagnostics=False,
    )  # fmt: skip
    assert np.all(result.n_contacts[1:] == 1)
    np.testing.assert_allclose(result.normal_force[4:], f_n, rtol=1e-9)
    u = result.tangential_displacement[4:]
    np.testing.assert_allclose(
        result.tangential_force[4:], -np.minimum(G_STAR * u, cap), rtol=1e-9, atol=1e-12 * cap
    )
    assert result.n_slipping[-1] == 1 and result.dissipated_work[-1] > 0


def _rough_path(amplitude: float, top: float) -> list[Segment]:
    return [
        Segment(normal=top, steps=4),
        Segment(tangential=amplitude, steps=8),
        Segment(tangential=-amplitude, steps=8),
        Segment(tangential=0.0, steps=4),
    ]


def test_rough_pair_mirror_symmetry_cap_and_dissipation(rough) -> None:  # type: ignore[no-untyped-def]
    """u_T → −u_T on the mirrored bodies flips F_T and keeps F_N; every contact's |F^t| ≤
    μ0 P; a closed cycle dissipates ≥ 0 (and the driver's work over it is ≥ 0)."""
    lower, upper = rough
    top = 0.2 * (lower.peak_to_valley + upper.peak_to_valley)
    amplitude = 0.05
    mu0 = 0.3
    # periodic with a fixed mesh: the coupled problem of the mirrored bodies is the mirror
    # image of this one (symmetry walls at 0 and L are not the mirror of the grid points
    # 0 … (n − 1)dx, and a mesh chosen per step does not sit symmetrically)
    # (and the widths converged to rounding: stopped at width_tol, their last update depends on
    # the order of the contacts)
    settings = InteractionSettings(
        periodic=True, mesh_cells=4096, width="hertz", width_iterations=100, width_tol=1e-13
    )
    kwargs = {"e_star": E_STAR, "g_star": G_STAR, "mu0": mu0, "diagnostics": False,
              "interaction": settings}  # fmt: skip
    result = simulate(
        lower, upper, path=_rough_path(amplitude, top), record_contacts="all", **kwargs
    )
    assert result.n_contacts[4:].min() >= 2  # several coupled contacts
    assert result.n_slipping.max() > 0
    for rec in result.contacts:
        assert np.all(np.abs(rec.tangential_force) <= mu0 * rec.normal_force * (1 + 1e-12))
        assert np.all(rec.normal_force > 0)
    work = result.dissipated_work
    assert work[-1] > 0 and np.all(np.diff(work) >= 0)
    assert driver_work(result, 4, 24) >= -1e-9 * float(np.abs(result.tangential_force).max())

    def mirrored(p: Profile) -> Profile:
        return Profile(p.x, p.z[::-1].copy())

    mirror = simulate(mirrored(lower), mirrored(upper), path=_rough_path(-amplitude, top), **kwargs)
    scale = float(np.abs(result.normal_force).max())
    np.testing.assert_allclose(mirror.normal_force, result.normal_force, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(
        mirror.tangential_force, -result.tangential_force, rtol=0, atol=1e-9 * scale
    )
    np.testing.assert_array_equal(mirror.n_contacts, result.n_contacts)


def _held(result):  # type: ignore[no-untyped-def]
    held = np.isfinite(result.normal_force_target)
    return held, np.abs(result.normal_force[held] / result.normal_force_target[held] - 1)


@pytest.mark.parametrize("bodies", ["two bumps on the flat", "two circles"])
def test_force_control_holds_the_coupled_normal_force(bodies: str) -> None:
    """Constant-F_N segments (loading, sliding, unloading and reloading in force) hold the
    coupled F_N to 1e−6 relative at every step where F_N(δ_N) is continuous: two coupled
    contacts (two bumps 0.1 µm apart on a flat), one contact sliding along its normal."""
    x = np.arange(-1000, 1001) * ANGSTROM
    if bodies == "two circles":
        lower: Profile = Profile(x, circle_cap(x, 1.0))
        upper: Profile | str = Profile(x, circle_cap(x, 2.0))
    else:
        lower = Profile(x, np.maximum(circle_cap(x, 1.0, -0.05), circle_cap(x, 1.0, 0.05)))
        upper = "flat"
    target = QP * E_STAR * 0.002
    path = [
        Segment(normal=0.001, steps=3),
        Segment(normal_force=target, steps=3),
        Segment(normal_force=target, tangential=0.02, steps=6),
        Segment(normal_force=0.3 * target, steps=2),
        Segment(normal_force=target, tangential=-0.01, steps=4),
    ]
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        result = simulate(
            lower, upper, e_star=E_STAR, mu0=0.3, interaction=True, path=path,
            diagnostics=False,
        )  # fmt: skip
    held, miss = _held(result)
    assert held.sum() == 15 and not held[:4].any()
    assert miss.max() <= 1e-6
    d = result.displacement
    assert d[14] < d[12] and d[18] > d[14]  # unloading and reloading in force
    assert result.n_contacts[held].min() == (1 if bodies == "two circles" else 2)
    if bodies == "two circles":  # the upper circle is lowered to keep F_N while it slides
        assert np.ptp(d[6:13]) > 1e-5


def test_force_control_on_a_rough_pair_holds_or_says_where(rough) -> None:  # type: ignore[no-untyped-def]
    """On a rough pair F_N(δ_N) jumps where eq. 9 accepts or drops a contact: every step holds
    F_N to 1e−6 except those a RuntimeWarning counts (the nearer side of a jump)."""
    lower, upper = rough
    top = 0.2 * (lower.peak_to_valley + upper.peak_to_valley)
    loaded = simulate(
        lower, upper, e_star=E_STAR, mu0=0.3, interaction=True, diagnostics=False,
        path=[Segment(normal=top, steps=4)],
    )  # fmt: skip
    target = float(loaded.normal_force[-1])
    path = [
        Segment(normal_force=target, steps=3),
        Segment(normal_force=target, tangential=0.04, steps=6),
    ]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", RuntimeWarning)
        result = simulate(
            lower, upper, e_star=E_STAR, mu0=0.3, interaction=True, path=path, diagnostics=False
        )
    held, miss = _held(result)
    assert held.sum() == 9
    n_miss = int(np.sum(miss > 1e-6))
    messages = [str(w.message) for w in caught if "could not be held" in str(w.message)]
    if n_miss:
        assert len(messages) == 1 and f"at {n_miss} of 9 " in messages[0]
    else:
        assert not messages
    assert np.median(miss) <= 1e-6


def test_normal_only_path_is_the_interacting_normal_path(rough) -> None:  # type: ignore[no-untyped-def]
    """A path without sliding or force control runs the interacting normal path (bit-identical
    to the monotone interacting loading); the sliding driver on the same path, with the widths
    converged at every step (no lag of the widths behind the loads), agrees with it to the
    tolerance of the contact-level solve."""
    from splinecontact.contact.interaction_slide import run_interacting_path
    from splinecontact.contact.simulation import spline_fits

    lower, _ = rough
    top = 0.2 * lower.peak_to_valley
    settings = InteractionSettings(tol=1e-10, width="hertz", width_iterations=100, width_tol=1e-12)
    segments = [Segment(normal=top, steps=6), Segment(normal=0.3 * top, steps=3)]
    today = simulate(lower, "flat", mu0=0.0, interaction=settings, path=segments,
                     diagnostics=False)  # fmt: skip
    fits = spline_fits(lower, "flat", alpha=today.parameters["alpha"], x0=today.parameters["x0"])
    curves, _ = run_interacting_path(
        lower, "flat", segments, fits, settings, e_star=today.parameters["e_star"],
        g_star=today.parameters["g_star"], mu0=0.0,
    )  # fmt: skip
    scale = float(today.normal_force.max())
    # (the steps of the non-interacting path's formula: equal to rounding)
    np.testing.assert_allclose(curves["displacement"], today.displacement, atol=1e-15 * top)
    np.testing.assert_array_equal(curves["n_contacts"], today.n_contacts)
    np.testing.assert_allclose(curves["normal_force"], today.normal_force, atol=1e-6 * scale)


def test_stop_force_is_refused_with_sliding(rough) -> None:  # type: ignore[no-untyped-def]
    lower, upper = rough
    with pytest.raises(LoadPathError, match="stop_force"):
        simulate(
            lower, upper, interaction=InteractionSettings(stop_force=1e-3), diagnostics=False,
            path=[Segment(normal=1e-3, tangential=1e-3, steps=2)],
        )  # fmt: skip


@pytest.mark.parametrize(
    "segment",
    [Segment(normal=1e-3, tangential=1e-3, steps=2), Segment(normal_force=1e-3, steps=2)],
)
def test_sliding_and_force_segments_run_with_interaction(rough, segment) -> None:  # type: ignore[no-untyped-def]
    """Once refused with interaction=True; now followed by the sliding driver."""
    lower, _ = rough
    result = simulate(lower, "flat", interaction=True, path=[segment], diagnostics=False)
    assert result.normal_force.size == 3
    assert result.parameters["interaction"] == "elastic half-plane"
    assert "n_slipping" in result.curves and "coalesced_contact_length" in result.curves


@pytest.mark.parametrize(
    "segment", [Segment(tangential=1e-3, steps=2), Segment(normal_force=1e-3, steps=2)]
)
def test_normal_path_displacements_refuses_sliding_and_force(segment) -> None:  # type: ignore[no-untyped-def]
    from splinecontact.contact.interaction_path import normal_path_displacements

    with pytest.raises(LoadPathError, match="slides or holds a normal force"):
        normal_path_displacements([Segment(normal=1e-3, steps=2), segment])
