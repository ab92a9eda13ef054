"""Interacting SAD with every contact law (JKR, DMT, Maugis–Dugdale, elastic–plastic): oracles.

The nonlinear contact-level solve (:mod:`splinecontact.contact.interaction_laws`) finds loads
P_i = f_i(δ_i^eff; state_i) with δ^eff = δ − e_z (C P). Its oracles:

* **Limits.** With w = 0 (adhesive laws) or S_y → ∞ (elastic–plastic) every law is eq. 10's
  Hertz law, so the solve must give interacting Hertz (the linear complementarity solve) to the
  solve's tolerance (both 1e−12; the law solve stops at ``LAW_TOL_FLOOR`` = 1e−9 of the approach
  scale at most, here it meets 1e−12 because the w = 0 laws are Hertz in closed form).
* **One contact, periodic.** A contact without neighbour or image couples only to itself: its
  vertical displacement is e_z P S(a) with S(a) = c (ln(L_p/(π a)) − 3/2), c = 2/(πE*) (the part
  of the periodic Hertz central displacement that the local law leaves out, as for Hertz in
  ``tests/test_interaction_slide.py``), so SAD's rigid overlap δ and the law's own approach
  δ^eff obey δ = δ^eff + e_z² S(a) P, with (δ^eff, P) on the law's closed-form curve
  (JKR: δ^eff = b²/R − 3√(2wb/(πE*)), P = πE*b²/(4R) − √(2πE*wb), R = R_eff/2) and the
  contact's half-width a = max(b, √(2|P|R_eff/(πE*))) (the width rule of the module).
* **Energy.** Over a closed displacement cycle the work of the normal force is ≥ 0 for every law
  and zero for Hertz (elastic: unloading retraces loading).
* **Plastic memory.** After a plastic first loading, unloading and reloading retrace the same
  elastic line (the residual interference is remembered), and the reloading starts later than
  the first loading.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from splinecontact import Profile, Segment, simulate
from splinecontact.contact import (
    DMT,
    JKR,
    ElasticPlastic,
    Hertz,
    InteractionSettings,
    MaugisDugdale,
    make_law,
)
from splinecontact.contact.adhesion import jkr_evaluate
from splinecontact.contact.interaction import self_coefficient
from splinecontact.errors import ParameterError, UnknownContactLawError
from splinecontact.generate import weierstrass_mandelbrot

from conftest import ANGSTROM, circle_cap

E_STAR = 10.0

#: Converged widths at every step (the relations above are then exact to the solve's tolerance).
TIGHT = InteractionSettings(width="hertz", width_iterations=100, tol=1e-12, width_tol=1e-13)


@pytest.fixture(scope="module")
def rough() -> tuple[Profile, Profile]:
    lower = weierstrass_mandelbrot(1.5, n_points=1024, length=4.0, seed=3)
    upper = weierstrass_mandelbrot(1.3, n_points=1024, length=4.0, seed=8)
    return lower, upper


def _reach(lower: Profile, upper: Profile, fraction: float = 0.12) -> float:
    """The largest approach of the paths [µm]: ``fraction`` × the summed peak-to-valley heights.

    At 0.12 eq. 9 accepts the same contacts at every δ_N on the way in and out (2–9 contacts).
    Above it, interacting SAD itself (with Hertz) accepts a lifted summit on one way and not
    the other (the uplift of the previous step decides), so even Hertz's cycle is not closed
    (0.1–1 % of F_max δ_max at 0.15–0.2 on these profiles): the energy oracle needs equal sets.
    """
    return fraction * (lower.peak_to_valley + upper.peak_to_valley)


def _cycle(d_max: float, steps: int = 12) -> list[Segment]:
    """0 → −0.3 d_max, then the closed cycle −0.3 d_max → d_max → −0.3 d_max (apart at both ends,
    the same step sizes on the way in and out)."""
    return [
        Segment(normal=-0.3 * d_max, steps=3),
        Segment(normal=d_max, steps=steps),
        Segment(normal=-0.3 * d_max, steps=steps),
    ]


def _work(result) -> float:  # type: ignore[no-untyped-def]
    """∮ F_N dδ_N over the closed cycle from step 3 on (trapezoids) [mN·µm/µm]."""
    f = result.normal_force[3:]
    return float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(result.displacement[3:])))


LIMITS = [
    JKR(work_of_adhesion=0.0),
    DMT(work_of_adhesion=0.0, cohesive_stress=1.0),
    MaugisDugdale(work_of_adhesion=0.0, cohesive_stress=1.0),
    ElasticPlastic(yield_strength=1e9),
]


@pytest.mark.parametrize("law", LIMITS, ids=lambda law: type(law).__name__)
def test_each_law_in_its_limit_is_interacting_hertz(rough, law) -> None:  # type: ignore[no-untyped-def]
    lower, upper = rough
    path = _cycle(_reach(lower, upper, 0.2))
    hertz = simulate(lower, upper, path=path, interaction=TIGHT, diagnostics=False)
    result = simulate(lower, upper, path=path, law=law, interaction=TIGHT, diagnostics=False)
    scale = float(hertz.normal_force.max())
    assert scale > 0.0 and hertz.n_contacts.max() >= 2
    np.testing.assert_allclose(result.normal_force, hertz.normal_force, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(
        result.contact_area, hertz.contact_area, rtol=0, atol=1e-9 * hertz.contact_area.max()
    )
    np.testing.assert_array_equal(result.n_contacts, hertz.n_contacts)
    assert result.to_xarray().attrs["law"] == law.name


def _single_circle(law: object, path: list[Segment]) -> tuple[int, float, Any]:
    """A unit circle (1 Å spacing, periodic) pressed on the flat along ``path`` with ``law``,
    converged widths: (index of the apex, period [µm], the result with every contact)."""
    n = round(1.0 / ANGSTROM)
    x = np.arange(-n, n + 1) * ANGSTROM
    lower = Profile(x, circle_cap(x, 1.0))
    settings = InteractionSettings(
        periodic=True, width="hertz", width_iterations=100, tol=1e-12, width_tol=1e-13
    )
    result = simulate(
        lower, "flat", path=path, law=law, interaction=settings, e_star=E_STAR,
        record_contacts="all", diagnostics=False,
    )  # fmt: skip
    return n, lower.n_points * lower.dx, result


def test_single_jkr_contact_obeys_closed_form_with_periodic_self_term() -> None:
    """A circle (R = 1 µm) on the rigid flat, periodic, loaded into contact and pulled off:
    every step in contact satisfies δ = δ^eff + e_z² S(a) P with (δ^eff, P) on the 2D JKR curve;
    the contact first touches with tension (jump-in), carries tension on unloading and lets go."""
    law = JKR(work_of_adhesion=0.1)
    w = law.w
    n, period, result = _single_circle(
        law, [Segment(normal=0.004, steps=10), Segment(normal=-0.004, steps=20)]
    )
    checked = 0
    for rec in result.contacts:
        if rec.point.size == 0:
            continue
        assert rec.point.size == 1
        p = float(rec.normal_force[0])
        d_eff = float(rec.overlap[0])
        r_eff = float(rec.effective_radius[0])
        e_z = float(rec.normal_z[0])
        force, width, branch = jkr_evaluate(d_eff, r_eff, E_STAR, w, 2.0)
        assert branch == 2.0
        assert p == pytest.approx(force, rel=1e-9)
        b = width / math.sqrt(2.0)
        r = 0.5 * r_eff
        assert d_eff == pytest.approx(
            b * b / r - 3.0 * math.sqrt(2.0 * w * b / (math.pi * E_STAR)), abs=1e-12
        )
        a = max(b, math.sqrt(2.0 * abs(p) * r_eff / (math.pi * E_STAR)))
        # the contact is the apex, where SAD's overlap of the circle and the flat is δ_N
        assert rec.point[0] == n and e_z == pytest.approx(1.0, abs=1e-12)
        expected = d_eff + e_z**2 * p * self_coefficient(a, period, E_STAR)
        assert expected == pytest.approx(float(result.displacement[rec.step]), abs=1e-9 * 0.004)
        checked += 1
    assert checked >= 20
    f = result.normal_force
    assert f[1] < 0.0  # jump-in at touching: the contact is pulled in (tension)
    assert f.min() < 0.0 and f[-1] == 0.0  # tension on unloading, then pull-off
    assert np.all(np.diff(f[1:11]) > 0.0)


def test_single_dmt_contact_obeys_closed_form_with_periodic_self_term() -> None:
    """The same circle with 2D DMT (w = 0.1 J/m², σ0 = 1 GPa): in contact
    P = (π/4)E*δ^eff − 2σ0√(R_eff h0), at a gap P = −2σ0√(R_eff (h0 + δ^eff)), h0 = w/σ0, and
    δ = δ^eff + e_z² S(a) P at every step that carries a force."""
    law = DMT(work_of_adhesion=0.1, cohesive_stress=1.0)
    sigma0 = 1.0
    h0 = law.w / sigma0
    n, period, result = _single_circle(
        law, [Segment(normal=0.004, steps=10), Segment(normal=-0.002, steps=10)]
    )
    checked = 0
    for rec in result.contacts:
        if rec.point.size == 0:
            continue
        p = float(rec.normal_force[0])
        d_eff = float(rec.overlap[0])
        r_eff = float(rec.effective_radius[0])
        if d_eff >= 0.0:
            closed = 0.25 * math.pi * E_STAR * d_eff - 2.0 * sigma0 * math.sqrt(r_eff * h0)
            b = math.sqrt(0.5 * d_eff * r_eff)
        else:
            closed = -2.0 * sigma0 * math.sqrt(r_eff * (h0 + d_eff))
            b = 0.0
        assert p == pytest.approx(closed, rel=1e-9, abs=1e-15)
        a = max(b, math.sqrt(2.0 * abs(p) * r_eff / (math.pi * E_STAR)))
        assert rec.point[0] == n
        expected = d_eff + float(rec.normal_z[0]) ** 2 * p * self_coefficient(a, period, E_STAR)
        assert expected == pytest.approx(float(result.displacement[rec.step]), abs=1e-9 * 0.004)
        checked += 1
    assert checked >= 15
    assert result.normal_force.min() < 0.0


@pytest.mark.parametrize(
    "law",
    [
        Hertz(),
        JKR(work_of_adhesion=0.05),
        DMT(work_of_adhesion=0.05, cohesive_stress=0.5),
        MaugisDugdale(work_of_adhesion=0.05, cohesive_stress=0.5),
        ElasticPlastic(yield_strength=0.2),
    ],
    ids=lambda law: type(law).__name__,
)
@pytest.mark.parametrize("flat", [True, False], ids=["on-flat", "on-rough"])
def test_load_unload_cycle_dissipates_nothing_negative(rough, law, flat) -> None:  # type: ignore[no-untyped-def]
    lower, upper = rough
    # μ0 = 0: the tangential springs (eqs. 11–13) dissipate by themselves
    result = simulate(
        lower, "flat" if flat else upper, path=_cycle(_reach(lower, upper)), law=law,
        interaction=TIGHT, mu0=0.0, diagnostics=False,
    )  # fmt: skip
    assert result.n_contacts.max() >= 2
    counts = result.n_contacts[3:]
    if isinstance(law, Hertz):  # the oracle's premise: the same contacts in and out
        np.testing.assert_array_equal(counts, counts[::-1])
    f = result.normal_force
    scale = float(np.abs(f).max()) * float(result.displacement.max())
    assert scale > 0.0
    work = _work(result)
    if isinstance(law, Hertz):
        assert abs(work) <= 1e-9 * scale
        assert f.min() >= 0.0
    else:
        assert work >= -1e-9 * scale
    if isinstance(law, ElasticPlastic):
        assert work > 1e-3 * scale  # the first loading flattens the asperities
    if isinstance(law, (JKR, DMT, MaugisDugdale)):
        assert f.min() < 0.0  # adhesive tension on the way out


def test_plastic_residual_is_remembered_on_reloading(rough) -> None:  # type: ignore[no-untyped-def]
    lower, upper = rough
    d_max = _reach(lower, upper)
    path = [
        Segment(normal=d_max, steps=10),
        Segment(normal=0.0, steps=10),
        Segment(normal=d_max, steps=10),
    ]
    law = ElasticPlastic(yield_strength=0.2)
    result = simulate(
        lower, upper, path=path, law=law, interaction=TIGHT, mu0=0.0, diagnostics=False
    )
    f = result.normal_force
    scale = float(f.max())
    first, unload, reload = f[:11], f[10:21][::-1], f[20:31]
    # reloading retraces the unloading line (elastic, the flattened shape remembered) to the
    # law solve's tolerance (LAW_TOL_FLOOR = 1e-9 of the approach scale per step) …
    np.testing.assert_allclose(reload, unload, rtol=0, atol=1e-8 * scale)
    # … which lies below the first loading: the pair touches later (residual interference)
    assert np.all(reload <= first + 1e-8 * scale)
    assert np.any(reload < first - 1e-2 * scale)
    assert f[20] == 0.0 and np.argmax(reload > 0.0) > np.argmax(first > 0.0)


def test_bad_parameters_give_the_same_errors_with_interaction(rough) -> None:  # type: ignore[no-untyped-def]
    lower, _ = rough
    bad = JKR(work_of_adhesion=-1.0)
    with pytest.raises(ParameterError) as plain:
        simulate(lower, "flat", steps=3, law=bad, diagnostics=False)
    with pytest.raises(type(plain.value), match="work_of_adhesion"):
        simulate(lower, "flat", steps=3, law=bad, interaction=True, diagnostics=False)
    with pytest.raises(UnknownContactLawError):
        make_law("no-such-law")
    with pytest.raises(ParameterError, match=r"yield_strength|hardness"):
        simulate(
            lower, "flat", steps=3, law=ElasticPlastic(yield_strength=0.0), interaction=True,
            diagnostics=False,
        )  # fmt: skip


def test_interacting_loading_with_a_law_records_it(rough) -> None:  # type: ignore[no-untyped-def]
    """``simulate(steps=..., interaction=True, law=...)`` (no path) runs the same solve."""
    lower, _ = rough
    law = MaugisDugdale(work_of_adhesion=0.05, cohesive_stress=0.5)
    result = simulate(lower, "flat", steps=8, law=law, interaction=TIGHT, diagnostics=False)
    attrs = result.to_xarray().attrs
    assert attrs["law"] == "maugis-dugdale" and attrs["interaction"] == "elastic half-plane"
    assert result.normal_force[-1] > 0.0
