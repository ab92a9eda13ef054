"""Load paths on rough pairs: symmetry, bounds and energy (hypothesis property tests)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from splinecontact import Profile, Segment, simulate, weierstrass_mandelbrot_pair
from splinecontact.analysis import (
    dilatancy,
    dissipated_energy,
    driver_work,
    mindlin_stiffness_ratio,
    normal_stiffness,
    segment_steps,
    spring_slider_stiffness_ratio,
    static_friction,
    tangential_stiffness,
)

from conftest import ANGSTROM, circle_cap


def _mirror(profile: Profile) -> Profile:
    return Profile(profile.x, profile.z[::-1].copy())


def _pair(dimension: float, seed: int) -> tuple[Profile, Profile]:
    return weierstrass_mandelbrot_pair(dimension, seed=seed, n_points=3000, length=0.3)


@settings(max_examples=40, deadline=None)
@given(
    dimension=st.floats(1.1, 1.9),
    seed=st.integers(0, 10_000),
    travel=st.floats(0.0005, 0.01),
    depth=st.floats(0.02, 0.2),
    flat=st.booleans(),
)
def test_mirror_symmetry_flips_the_tangential_force(
    dimension: float, seed: int, travel: float, depth: float, flat: bool
) -> None:
    """Mirroring both bodies (x → −x) and the path (u_T → −u_T) flips F_T and keeps F_N."""
    lower, upper = _pair(dimension, seed)
    d = depth * lower.peak_to_valley

    def path(sign: float) -> list[Segment]:
        return [
            Segment(normal=d, steps=15),
            Segment(tangential=sign * travel, steps=40),
            Segment(tangential=-0.5 * sign * travel, steps=30),
        ]

    a = simulate(lower, "flat" if flat else upper, path=path(1.0))
    b = simulate(_mirror(lower), "flat" if flat else _mirror(upper), path=path(-1.0))
    np.testing.assert_array_equal(a.n_contacts, b.n_contacts)
    scale = max(np.abs(a.normal_force).max(), 1e-300)
    assert np.abs(a.normal_force - b.normal_force).max() <= 1e-9 * scale
    assert np.abs(a.tangential_force + b.tangential_force).max() <= 1e-9 * scale
    np.testing.assert_array_equal(a.n_slipping, b.n_slipping)


def test_mirror_symmetry_of_a_symmetric_pair_is_exact_in_u() -> None:
    """Two aligned circles: u_T → −u_T alone flips F_T (the geometry is its own mirror)."""
    n = 1500
    x = np.arange(-n, n + 1) * ANGSTROM
    lower, upper = Profile(x, circle_cap(x, 1.0)), Profile(x, circle_cap(x, 0.7))
    runs = [
        simulate(
            lower, upper, path=[Segment(normal=0.002, steps=10), Segment(tangential=s, steps=50)]
        )
        for s in (0.02, -0.02)
    ]
    a, b = runs
    scale = a.normal_force.max()
    assert np.abs(a.normal_force - b.normal_force).max() <= 1e-9 * scale
    assert np.abs(a.tangential_force + b.tangential_force).max() <= 1e-9 * scale
    assert np.abs(a.tangential_force).max() > 1e-3 * scale


@settings(max_examples=40, deadline=None)
@given(
    dimension=st.floats(1.1, 1.9),
    seed=st.integers(0, 10_000),
    mu0=st.floats(0.0, 1.0),
    travel=st.floats(0.0005, 0.01),
    flat=st.booleans(),
)
def test_static_friction_is_bounded_by_mu0_and_contact_slopes(
    dimension: float, seed: int, mu0: float, travel: float, flat: bool
) -> None:
    """μ_s ≤ (μ0 + T)/(1 − μ0 T), T = max |e_x|/e_z over the accepted contacts (docs/friction.md).

    Against a rigid flat every contact pushes straight up (T = 0), so μ_s ≤ μ0.
    """
    lower, upper = _pair(dimension, seed)
    d = 0.1 * lower.peak_to_valley
    path = [Segment(normal=d, steps=15), Segment(tangential=travel, steps=40)]
    result = simulate(
        lower, "flat" if flat else upper, mu0=mu0, path=path, record_contacts=range(16, 56)
    )
    if not np.any(result.normal_force[16:] > 0):
        return
    ex = np.concatenate([c.normal_x for c in result.contacts])
    ez = np.concatenate([c.normal_z for c in result.contacts])
    if flat:
        assert np.all(ex == 0.0) and np.all(ez == 1.0)
    if ez.size == 0 or np.any(ez <= 0):
        return  # a contact pushing sideways or down: the bound does not apply
    slope = float(np.max(np.abs(ex) / ez))
    if mu0 * slope >= 1:
        return
    bound = (mu0 + slope) / (1 - mu0 * slope)
    mu_s = static_friction(result).mu_s
    assert mu_s <= bound * (1 + 1e-12) + 1e-15
    if flat:
        assert mu_s <= mu0 * (1 + 1e-12) + 1e-15


def test_rough_cycle_dissipates_non_negative_energy() -> None:
    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=3, n_points=20_000, length=2.0)
    d = 0.1 * lower.peak_to_valley
    amplitude = 0.02
    path = [
        Segment(normal=d, steps=100),
        Segment(tangential=amplitude, steps=200),
        Segment(tangential=-amplitude, steps=400),
        Segment(tangential=amplitude, steps=400),
        Segment(normal=0.0, steps=100),
    ]
    result = simulate(lower, upper, mu0=0.3, path=path)
    work = result.dissipated_work
    assert np.all(np.diff(work) >= 0)
    bounds = segment_steps(result)
    cycle = dissipated_energy(result, bounds[1][1], bounds[3][1])
    assert cycle > 0  # contacts do slip on this pair
    assert result.n_slipping.max() > 0
    assert np.isfinite(driver_work(result, bounds[1][1], bounds[3][1]))
    # Frictionless: nothing is ever dissipated.
    frictionless = simulate(lower, upper, mu0=0.0, path=path)
    assert np.all(frictionless.dissipated_work == 0)


def test_single_normal_segment_matches_the_normal_loading() -> None:
    """path=[Segment(normal=d, steps=N)] accepts the same contacts as the plain loading.

    The normal part of F_N and A_S agree to rounding; F_T differs because a path carries the
    tangential spring of a contact whose centre migrates to a neighbouring cell (and integrates
    eq. 11 with the trapezoidal rule), where the plain loading restarts it at zero.
    """
    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=3, n_points=20_000, length=2.0)
    d = 0.1 * lower.peak_to_valley
    for up in (upper, "flat"):
        plain = simulate(lower, up, steps=100, final_displacement=d)
        path = simulate(lower, up, path=[Segment(normal=d, steps=100)])
        np.testing.assert_array_equal(plain.n_contacts, path.n_contacts)
        np.testing.assert_allclose(path.displacement, plain.displacement, rtol=1e-15)
        scale = plain.normal_force.max()
        for name in ("normal_force_normal_part", "contact_area"):
            diff = np.abs(path.curves[name] - plain.curves[name]).max()
            assert diff <= 1e-12 * np.abs(plain.curves[name]).max(), name
        assert np.all(plain.tangential_displacement == 0)
        if up == "flat":  # no tilt: identical forces
            assert np.abs(path.normal_force - plain.normal_force).max() <= 1e-12 * scale


def test_derived_quantities_on_a_circle_on_a_flat() -> None:
    n = 400
    x = np.arange(-n, n + 1) * ANGSTROM
    lower = Profile(x, circle_cap(x, 1.0))
    e_star, g_star, mu0 = 10.0, 4.0, 0.3
    delta = 1e-3
    f_n = 0.25 * np.pi * e_star * delta
    path = [
        Segment(normal=delta, steps=10),
        Segment(tangential=2 * mu0 * f_n / g_star, steps=100),
        Segment(normal_force=0.5 * f_n, tangential=0.0, steps=20),
    ]
    result = simulate(lower, "flat", e_star=e_star, g_star=g_star, mu0=mu0, path=path)
    friction = static_friction(result)
    assert friction.mu_s == pytest.approx(mu0, rel=1e-12)
    assert friction.onset_step == 10 + 51  # slip starts where G* u_T reaches μ0 F_N
    assert tangential_stiffness(result) == pytest.approx(g_star, rel=1e-9)
    assert normal_stiffness(result) == pytest.approx(0.25 * np.pi * e_star, rel=1e-9)
    ratio = tangential_stiffness(result) / normal_stiffness(result)
    assert ratio == pytest.approx(spring_slider_stiffness_ratio(e_star, g_star), rel=1e-9)
    assert mindlin_stiffness_ratio(0.3) == pytest.approx(2 * 0.7 / 1.7)
    assert dilatancy(result, 2) == pytest.approx(0.5 * delta, rel=1e-6)  # the flat rises


def test_force_control_on_a_rough_pair_records_its_misses() -> None:
    """Rough-on-rough F_N(δ_N) jumps where contacts appear (eq. 9): a miss is warned about."""
    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=3, n_points=20_000, length=2.0)
    d = 0.1 * lower.peak_to_valley
    plain = simulate(lower, upper, steps=50, final_displacement=d)
    target = 0.5 * plain.normal_force[-1]
    path = [Segment(normal=d, steps=50), Segment(normal_force=target, tangential=0.02, steps=100)]
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = simulate(lower, upper, path=path)
    held = np.isfinite(result.normal_force_target)
    miss = np.abs(result.normal_force[held] / target - 1)
    n_miss = int(np.sum(miss > 1e-6))
    assert np.median(miss) <= 1e-6  # most steps hold the force
    messages = [str(w.message) for w in caught if issubclass(w.category, RuntimeWarning)]
    if n_miss:
        assert any(f"at {n_miss} of {held.sum()}" in m for m in messages)
    else:
        assert not messages


def test_friction_study_ensemble_on_a_flat_gives_mu0_and_the_spring_ratio() -> None:
    from splinecontact.analysis import friction_study

    ds = friction_study([1.4, 1.6], [1, 2], flat=True, n_points=4000, length=0.4, travel=0.01)
    assert ds["mu_s"].dims == ("dimension", "realization")
    for name in ds.data_vars:
        assert "units" in ds[name].attrs, name
    np.testing.assert_allclose(ds["mu_s"].values, 0.3, rtol=1e-12)
    np.testing.assert_allclose(ds["mu_s_ci"].values, 0.0, atol=1e-12)
    assert np.all(ds["dilatancy"].values == 0.0)
    assert np.all(ds["force_held"].values == 1.0)
    # On a flat every contact is a vertical G* spring: k_T (first increment, all stuck) is G*
    # times the number of contacts. k_N is a fit over the last 20 normal increments, during which
    # contacts only close, so it is at most (π/4)E* times that number: k_T/k_N ≥ G*/((π/4)E*).
    g_star = 10.0 / 2.6
    count = ds["k_t"].values / g_star
    np.testing.assert_allclose(count, np.round(count), rtol=1e-9)
    assert np.all(count >= 1)
    ratio = spring_slider_stiffness_ratio(10.0, g_star)
    assert np.all(ds["stiffness_ratio"].values >= ratio * (1 - 1e-12))
    assert np.all(ds["dissipation"].values > 0)
