"""Every contact law with interacting contacts on sliding and force-controlled paths: oracles.

The sliding driver (:mod:`splinecontact.contact.interaction_slide`) carries the laws' history
(one row per lower-body grid point) across its steps: trials (force-control iterations,
repeated solves) solve on a copy, the accepted step commits it once. Oracles:

* **Limits.** With w = 0 (adhesive laws) or S_y = 10⁹ GPa (elastic–plastic) every law is eq. 10,
  so a sliding path and a force-controlled segment give interacting Hertz to the tolerance of
  the contact-level solves (both 1e−12, widths converged; compared at 1e−9 of the largest F_N).
* **Force control with adhesion.** A constant-F_N segment with JKR holds F_N to 1e−6 at every
  step (no RuntimeWarning: F_N(δ_N) is continuous there).
* **One contact, periodic.** Two circles sliding past each other with JKR (DMT): the single
  contact obeys δ = δ^eff + e_z² S(a) P with (δ^eff, P) on the law's closed-form curve, δ the
  circles' overlap at the step's (u_T, δ_N) (as ``tests/test_interaction_laws.py`` for the
  normal path, ``tests/test_interaction_slide.py`` for Hertz).
* **Energy.** The driver's work over a closed (u_T, δ_N) cycle is ≥ 0 with every law.
* **Plastic memory.** The history follows the lower body's grid points: sliding away and back
  to the same configuration finds the plastic state it left (the force of the elastic
  unloading line, below the virgin curve's).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from splinecontact import Profile, Segment, simulate
from splinecontact.analysis import driver_work
from splinecontact.contact import DMT, JKR, ElasticPlastic, InteractionSettings, MaugisDugdale
from splinecontact.contact.adhesion import jkr_evaluate
from splinecontact.contact.interaction import self_coefficient
from splinecontact.generate import weierstrass_mandelbrot

from conftest import ANGSTROM, circle_cap, held_force_slide

E_STAR = 10.0
G_STAR = E_STAR / 2.6

#: Converged widths and tight solves at every step and trial.
TIGHT = InteractionSettings(width="hertz", width_iterations=100, tol=1e-12, width_tol=1e-13)

LIMITS = [
    JKR(work_of_adhesion=0.0),
    DMT(work_of_adhesion=0.0, cohesive_stress=1.0),
    MaugisDugdale(work_of_adhesion=0.0, cohesive_stress=1.0),
    ElasticPlastic(yield_strength=1e9),
]

LAWS = [
    JKR(work_of_adhesion=0.05),
    DMT(work_of_adhesion=0.05, cohesive_stress=1.0),
    MaugisDugdale(work_of_adhesion=0.05, cohesive_stress=1.0),
    ElasticPlastic(yield_strength=0.5),
]


@pytest.fixture(scope="module")
def rough() -> tuple[Profile, Profile]:
    lower = weierstrass_mandelbrot(1.5, n_points=1024, length=4.0, seed=3)
    upper = weierstrass_mandelbrot(1.3, n_points=1024, length=4.0, seed=8)
    return lower, upper


def _top(lower: Profile, upper: Profile, fraction: float = 0.12) -> float:
    return fraction * (lower.peak_to_valley + upper.peak_to_valley)


@pytest.mark.parametrize("law", LIMITS, ids=lambda law: type(law).__name__)
def test_each_law_in_its_limit_is_interacting_hertz_sliding_and_in_force(rough, law) -> None:  # type: ignore[no-untyped-def]
    lower, upper = rough
    top = _top(lower, upper)
    kwargs = {"e_star": E_STAR, "g_star": G_STAR, "mu0": 0.3, "interaction": TIGHT,
              "diagnostics": False}  # fmt: skip
    loaded = simulate(lower, upper, path=[Segment(normal=top, steps=3)], **kwargs)
    target = 0.8 * float(loaded.normal_force[-1])
    path = [
        Segment(normal=top, steps=3),
        Segment(tangential=0.03, steps=4),
        Segment(normal_force=target, steps=2),
        Segment(normal_force=target, tangential=-0.02, steps=4),
    ]
    hertz = simulate(lower, upper, path=path, **kwargs)
    result = simulate(lower, upper, path=path, law=law, **kwargs)
    scale = float(hertz.normal_force.max())
    assert scale > 0.0 and hertz.n_contacts.max() >= 2
    assert np.isfinite(result.normal_force_target[8:]).all()
    for name in ("normal_force", "tangential_force"):
        np.testing.assert_allclose(
            getattr(result, name), getattr(hertz, name), rtol=0, atol=1e-9 * scale
        )
    np.testing.assert_allclose(
        result.contact_area, hertz.contact_area, rtol=0, atol=1e-9 * hertz.contact_area.max()
    )
    np.testing.assert_allclose(result.displacement, hertz.displacement, rtol=0, atol=1e-9 * top)
    np.testing.assert_array_equal(result.n_contacts, hertz.n_contacts)
    assert result.to_xarray().attrs["law"] == law.name


@pytest.mark.parametrize("name", ["DMT", "JKR"])
def test_adhesive_constant_force_segment_holds_the_force(rough, name: str) -> None:  # type: ignore[no-untyped-def]
    """DMT's force is continuous in the approach (also at touching), so the coupled F_N(δ_N)
    with the contacts held is continuous and every step holds F_N to 1e−6, no warning. JKR's
    jumps in at touching and out at its fold: every step holds F_N to 1e−6 except those a
    RuntimeWarning counts (the nearer side of the jump)."""
    lower, upper = rough
    top = _top(lower, upper, 0.2)
    if name == "DMT":
        law: DMT | JKR = DMT(work_of_adhesion=0.05, cohesive_stress=1.0)
    else:
        law = JKR(work_of_adhesion=0.05)
    kwargs = {"e_star": E_STAR, "g_star": G_STAR, "mu0": 0.3, "interaction": True,
              "diagnostics": False, "law": law}  # fmt: skip
    result, target, messages = held_force_slide(lower, upper, top, **kwargs)
    held = np.isfinite(result.normal_force_target)
    assert held.sum() == 6
    miss = np.abs(result.normal_force[held] / target - 1.0)
    n_miss = int(np.sum(miss > 1e-6))
    if name == "DMT":
        assert n_miss == 0 and not messages
    elif n_miss:
        assert len(messages) == 1 and f"at {n_miss} of 6 " in messages[0]
    assert np.median(miss) <= 1e-6
    assert result.n_contacts[held].min() >= 2
    assert np.ptp(result.displacement[held]) > 0.0  # δ_N moves to hold F_N while sliding


def _circles(r1: float, r2: float, half_width: float) -> tuple[Profile, Profile]:
    n = round(half_width / ANGSTROM)
    x = np.arange(-n, n + 1) * ANGSTROM
    return Profile(x, circle_cap(x, r1)), Profile(x, circle_cap(x, r2))


@pytest.mark.parametrize("name", ["JKR", "DMT"])
def test_single_adhesive_contact_sliding_keeps_the_closed_form(name: str) -> None:
    """Two circles (R1 = 1, R2 = 2 µm), periodic, the upper one slid across the lower at
    δ_N = 0.003 µm: at every step δ = δ^eff + e_z² S(a) P, δ the circles' overlap, and
    (δ^eff, P) on the law's closed-form curve."""
    r1, r2, d, u0 = 1.0, 2.0, 0.003, 0.02
    lower, upper = _circles(r1, r2, 4 * u0 + 2 * math.sqrt(d * r1 * r2 / (r1 + r2)))
    w, sigma0 = 0.1, 1.0
    law = JKR(work_of_adhesion=w) if name == "JKR" else DMT(work_of_adhesion=w, cohesive_stress=1.0)
    settings = InteractionSettings(
        periodic=True, width="hertz", width_iterations=100, tol=1e-12, width_tol=1e-13
    )
    path = [
        Segment(normal=0.0, tangential=-u0, steps=2),
        Segment(normal=d, steps=6),
        Segment(normal=d, tangential=u0, steps=20),
    ]
    result = simulate(
        lower, upper, mu0=0.0, e_star=E_STAR, path=path, law=law, interaction=settings,
        record_contacts="all", diagnostics=False,
    )  # fmt: skip
    period = lower.n_points * lower.dx
    checked = 0
    points = []
    for rec in result.contacts:
        if rec.step < 8 or rec.point.size == 0:
            continue
        assert rec.point.size == 1
        u = float(result.tangential_displacement[rec.step])
        length = math.hypot(u, r1 + r2 - d)
        overlap, e_z = r1 + r2 - length, (r1 + r2 - d) / length
        p = float(rec.normal_force[0])
        d_eff = float(rec.overlap[0])
        r_eff = float(rec.effective_radius[0])
        assert r_eff == pytest.approx(2.0 * r1 * r2 / (r1 + r2), rel=1e-3)
        assert float(rec.normal_z[0]) == pytest.approx(e_z, abs=1e-6)
        if name == "JKR":
            force, width, branch = jkr_evaluate(d_eff, r_eff, E_STAR, law.w, 2.0)
            assert branch == 2.0
            assert p == pytest.approx(force, rel=1e-9)
            b = width / math.sqrt(2.0)
        else:
            h0 = law.w / sigma0
            if d_eff >= 0.0:
                closed = 0.25 * math.pi * E_STAR * d_eff - 2.0 * sigma0 * math.sqrt(r_eff * h0)
                b = math.sqrt(0.5 * d_eff * r_eff)
            else:
                closed = -2.0 * sigma0 * math.sqrt(r_eff * (h0 + d_eff))
                b = 0.0
            assert p == pytest.approx(closed, rel=1e-9, abs=1e-15)
        a = max(b, math.sqrt(2.0 * abs(p) * r_eff / (math.pi * E_STAR)))
        e_zc = float(rec.normal_z[0])
        expected = d_eff + e_zc**2 * p * self_coefficient(a, period, E_STAR)
        # SAD's overlap of the discretised circles: the analytic one to the spline's accuracy
        assert expected == pytest.approx(overlap, abs=2e-3 * d)
        points.append(int(rec.point[0]))
        checked += 1
    assert checked == 21
    assert max(points) - min(points) > 20  # the contact migrates across many cells


@pytest.mark.parametrize("law", LAWS, ids=lambda law: type(law).__name__)
def test_sliding_cycle_dissipates(rough, law) -> None:  # type: ignore[no-untyped-def]
    """A closed (u_T, δ_N) cycle (apart at both ends): the driver's work is ≥ 0."""
    lower, upper = rough
    top = _top(lower, upper)
    path = [
        Segment(normal=-0.3 * top, steps=2),
        Segment(normal=top, steps=6),
        Segment(tangential=0.04, steps=6),
        Segment(tangential=0.0, steps=6),
        Segment(normal=-0.3 * top, steps=6),
    ]
    result = simulate(
        lower, upper, e_star=E_STAR, g_star=G_STAR, mu0=0.3, law=law, path=path,
        interaction=True, diagnostics=False,
    )  # fmt: skip
    assert result.n_contacts.max() >= 2 and result.normal_force[-1] == 0.0
    scale = float(np.abs(result.normal_force).max()) * top
    assert driver_work(result, 2, result.displacement.size - 1) >= -1e-9 * scale
    assert np.all(np.diff(result.dissipated_work) >= 0.0)


def test_plastic_memory_survives_sliding_back(rough) -> None:  # type: ignore[no-untyped-def]
    """Load plastically, unload to half the approach, slide away and back: the contacts at
    the start configuration find the plastic state they left (the force of the elastic
    unloading line, to the solve's tolerance), well below the virgin loading's at that
    approach (what a lost history would give)."""
    lower, upper = rough
    top = _top(lower, upper, 0.2)
    law = ElasticPlastic(yield_strength=0.1)
    kwargs = {"e_star": E_STAR, "mu0": 0.0, "law": law, "interaction": TIGHT,
              "diagnostics": False}  # fmt: skip
    path = [
        Segment(normal=0.5 * top, steps=3),
        Segment(normal=top, steps=3),
        Segment(normal=0.5 * top, steps=3),
        Segment(tangential=0.01, steps=3),
        Segment(tangential=0.0, steps=3),
    ]
    result = simulate(lower, upper, path=path, **kwargs)
    f = result.normal_force
    virgin, unloaded, back = float(f[3]), float(f[9]), float(f[15])
    assert result.displacement[3] == result.displacement[15] == 0.5 * top
    assert result.tangential_displacement[15] == 0.0 and result.tangential_displacement[12] > 0
    assert unloaded < 0.9 * virgin
    assert back == pytest.approx(unloaded, rel=1e-6)


@pytest.mark.parametrize("law", LAWS, ids=lambda law: type(law).__name__)
def test_driver_on_a_normal_cycle_is_the_normal_path(rough, law) -> None:  # type: ignore[no-untyped-def]
    """The sliding driver on a normal cycle (loading, unloading into tension and apart,
    reloading), with the widths converged at every step, carries each law's history as the
    normal path does: the same contacts and F_N to the tolerance of the contact-level solves
    (JKR's hysteresis, the plastic memory and the releases of dropped contacts included)."""
    from splinecontact.contact.interaction_slide import run_interacting_path
    from splinecontact.contact.laws import bind_law
    from splinecontact.contact.simulation import _reach_radius, spline_fits

    lower, upper = rough
    top = _top(lower, upper)
    segments = [
        Segment(normal=top, steps=6),
        Segment(normal=-0.3 * top, steps=6),
        Segment(normal=top, steps=6),
    ]
    settings = InteractionSettings(tol=1e-11, width="hertz", width_iterations=100, width_tol=1e-12)
    today = simulate(
        lower, upper, e_star=E_STAR, mu0=0.0, law=law, interaction=settings, path=segments,
        diagnostics=False,
    )  # fmt: skip
    fits = spline_fits(lower, upper, alpha=today.parameters["alpha"], x0=today.parameters["x0"])
    bound = bind_law(
        law, E_STAR, _reach_radius(lower, fits) if getattr(law, "needs_radius", False) else 0.0
    )
    curves, _ = run_interacting_path(
        lower, upper, segments, fits, settings, e_star=E_STAR, g_star=today.parameters["g_star"],
        mu0=0.0, law=bound,
    )  # fmt: skip
    scale = float(np.abs(today.normal_force).max())
    assert today.n_contacts.max() >= 2
    np.testing.assert_allclose(curves["displacement"], today.displacement, atol=1e-15 * top)
    np.testing.assert_array_equal(curves["n_contacts"], today.n_contacts)
    np.testing.assert_allclose(curves["normal_force"], today.normal_force, atol=1e-6 * scale)
    np.testing.assert_allclose(
        curves["contact_area"], today.contact_area, atol=1e-6 * today.contact_area.max()
    )
