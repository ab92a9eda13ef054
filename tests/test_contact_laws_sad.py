"""Contact laws inside SAD: a circle on the rigid flat (JKR path), the Hertz limits on the analytic
oracles, and the energy of a rough pair's load–unload cycle for every law.

Control mode: displacement (the upper body's δ_N is prescribed by the load path).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from splinecontact import Profile, Segment, simulate, weierstrass_mandelbrot_pair
from splinecontact.contact import DMT, JKR, ElasticPlastic, Hertz, MaugisDugdale, make_law
from splinecontact.contact import adhesion as ad

from conftest import ANGSTROM, circle_cap

E_STAR = 10.0


def _grid(half_width: float) -> np.ndarray:
    n = round(half_width / ANGSTROM)
    return np.arange(-n, n + 1) * ANGSTROM


def test_jkr_circle_on_flat_path_force_width_pairs_and_pull_off() -> None:
    radius = 1.0
    x = _grid(0.1)
    lower = Profile(x, circle_cap(x, radius))
    law = JKR(work_of_adhesion=0.1)
    w = law.w
    # First pass: the relation between δ_N and the apex overlap, and the apex R_eff.
    probe = simulate(
        lower, "flat", e_star=E_STAR, mu0=0.0, law=law, record_contacts="all",
        path=[Segment(normal=0.001, steps=4)],
    )  # fmt: skip
    last = probe.contacts[-1]
    assert last.point.size == 1
    r_eff = float(last.effective_radius[0])
    assert r_eff == pytest.approx(2 * radius, rel=1e-3)
    offset = float(last.overlap[0]) - 0.001
    b_c = ad.jkr_pull_off_half_width(r_eff, E_STAR, w)
    b_m = ad.jkr_jump_out_half_width(r_eff, E_STAR, w)
    d_c = ad.jkr_approach(b_c, r_eff, E_STAR, w) - offset  # δ_N at the load-control pull-off
    d_m = ad.jkr_approach(b_m, r_eff, E_STAR, w) - offset
    path = [
        Segment(normal=-0.001, steps=1),
        Segment(normal=0.002, steps=60),
        Segment(normal=d_c, steps=60),
        Segment(normal=d_m - 0.0002, steps=40),
    ]
    result = simulate(
        lower, "flat", e_star=E_STAR, mu0=0.0, law=law, path=path, record_contacts="all"
    )
    in_contact = result.n_contacts > 0
    assert np.all(result.n_contacts <= 1)
    assert in_contact.any() and not in_contact[-1]
    # Force–width pairs: the closed-form line-contact JKR relation (width = A_S = √2·b).
    b = result.contact_area[in_contact] / math.sqrt(2.0)
    expected = np.array([ad.jkr_force(v, r_eff, E_STAR, w) for v in b])
    np.testing.assert_allclose(result.normal_force[in_contact], expected, rtol=1e-6, atol=0)
    overlap = {c.step: float(c.overlap[0]) for c in result.contacts if c.point.size}
    steps = np.flatnonzero(in_contact)
    np.testing.assert_allclose(
        [overlap[k] for k in steps], [ad.jkr_approach(v, r_eff, E_STAR, w) for v in b],
        rtol=1e-6, atol=1e-12,
    )  # fmt: skip
    # Jump-in where the surfaces touch, hold below δ = 0 on unloading, jump-out at δ(b_m).
    first = int(np.argmax(in_contact))
    assert result.displacement[first] + offset >= 0.0
    assert result.displacement[first - 1] + offset < 0.0
    assert result.normal_force[first] < 0.0
    unloading = np.arange(result.displacement.size) > 61
    held = unloading & (result.displacement + offset < 0.0) & (result.displacement > d_m)
    assert held.any() and np.all(in_contact[held])
    # Minimum force under displacement control = the closed-form (load-control) pull-off.
    assert result.normal_force.min() == pytest.approx(
        ad.jkr_pull_off_force(r_eff, E_STAR, w), rel=1e-4
    )


def _two_circles() -> tuple[Profile, Profile]:
    x = _grid(0.1)
    return Profile(x, circle_cap(x, 2.0)), Profile(x, circle_cap(x, 1.0))


@pytest.mark.parametrize("upper_kind", ["circle", "flat"])
@pytest.mark.parametrize(
    "law",
    [
        JKR(work_of_adhesion=1e-30),
        DMT(work_of_adhesion=1e-30, cohesive_stress=1.0),
        MaugisDugdale(work_of_adhesion=1e-30, cohesive_stress=1.0),
        ElasticPlastic(yield_strength=1e50),
    ],
    ids=lambda law: law.name,
)
def test_every_law_tends_to_hertz_on_the_analytic_oracles(upper_kind: str, law: object) -> None:
    lower, upper_circle = _two_circles()
    upper = upper_circle if upper_kind == "circle" else "flat"
    path = [Segment(normal=0.004, steps=20), Segment(normal=0.001, steps=10)]
    hertz = simulate(lower, upper, e_star=E_STAR, mu0=0.0, path=path)
    other = simulate(lower, upper, e_star=E_STAR, mu0=0.0, path=path, law=law)
    scale = np.abs(hertz.normal_force).max()
    assert scale > 0
    np.testing.assert_allclose(other.normal_force, hertz.normal_force, rtol=1e-9, atol=1e-9 * scale)
    np.testing.assert_allclose(
        other.contact_area, hertz.contact_area, rtol=1e-9, atol=1e-9 * hertz.contact_area.max()
    )
    np.testing.assert_array_equal(other.n_contacts, hertz.n_contacts)


def test_zero_adhesion_is_hertz_bit_for_bit() -> None:
    lower, upper = _two_circles()
    hertz = simulate(lower, upper, e_star=E_STAR, steps=30, diagnostics=False)
    for law in (JKR(work_of_adhesion=0.0), make_law("elastic-plastic", hardness=1e50)):
        other = simulate(lower, upper, e_star=E_STAR, steps=30, law=law, diagnostics=False)
        np.testing.assert_array_equal(other.normal_force, hertz.normal_force)
        np.testing.assert_array_equal(other.contact_area, hertz.contact_area)


LAWS = [
    Hertz(),
    JKR(work_of_adhesion=0.5),
    DMT(work_of_adhesion=0.5, cohesive_stress=0.5),
    MaugisDugdale(work_of_adhesion=0.5, cohesive_stress=2.0),
    ElasticPlastic(hardness=1.0),
]


@pytest.fixture(scope="module")
def rough_pair() -> tuple[Profile, Profile]:
    return weierstrass_mandelbrot_pair(1.5, seed=3, n_points=1500, length=1.0, wavelength=0.1)


@pytest.mark.parametrize("law", LAWS, ids=lambda law: law.name)
def test_rough_pair_cycle_dissipates_nothing_negative(
    rough_pair: tuple[Profile, Profile], law: object
) -> None:
    lower, upper = rough_pair
    depth = 0.004
    path = [
        Segment(normal=-0.01, steps=1),
        Segment(normal=depth, steps=50),
        Segment(normal=-0.01, steps=50),
        Segment(normal=depth, steps=50),
        Segment(normal=-0.01, steps=50),
    ]
    result = simulate(lower, upper, e_star=E_STAR, mu0=0.0, path=path, law=law)
    f = result.normal_force
    d = result.displacement
    increments = 0.5 * (f[1:] + f[:-1]) * np.diff(d)
    scale = np.sum(np.abs(increments))
    assert scale > 0
    # Two closed cycles, each from δ_N = −0.01 µm (no contact) to depth and back.
    for a, b in ((1, 101), (101, 201)):
        assert d[a] == d[b] == -0.01
        work = float(np.sum(increments[a:b]))
        if law.name == "hertz":
            assert abs(work) <= 1e-9 * scale
        else:
            assert work >= -1e-9 * scale
    if law.name != "hertz":
        assert f.min() < 0.0 or law.name == "elastic-plastic"
