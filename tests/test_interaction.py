"""Interacting SAD: contacts coupled through the elastic half-plane, against closed forms and the BEM."""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.fft as sfft

from splinecontact import Profile, bem
from splinecontact.contact import contact_geometry, run_loading
from splinecontact.contact.halfplane import _near_pairs, _quadrature
from splinecontact.contact.interaction import (
    InteractionSettings,
    extended_geometry,
    interacting_loading,
    pair_coefficient,
    periodic_green,
    self_coefficient,
)
from splinecontact.contact.interaction_operator import _apply, _level, mesh_cache
from splinecontact.errors import ParameterError
from splinecontact.spline import fit_spline

E_STAR = 10.0
C0 = 2.0 / (math.pi * E_STAR)


def spectral_displacement(pressure: np.ndarray, dx: float) -> np.ndarray:
    """Zero-mean periodic displacement of nodal pressures by the BEM's response 2/(E*|q|)."""
    problem = bem.contact_problem(np.zeros(pressure.size), e_star=E_STAR, dx=dx)
    return np.asarray(sfft.irfft(problem.response * sfft.rfft(pressure), pressure.size))


def test_green_function_is_the_bem_kernel_summed() -> None:
    n, dx = 4096, 0.01
    load = np.zeros(n)
    load[0] = 1.0 / dx  # unit line load on one node
    u = spectral_displacement(load, dx)
    r = np.arange(n) * dx
    far = (np.arange(n) >= 20) & (np.arange(n) <= n - 20)
    green = periodic_green(r[far], n * dx, E_STAR)
    np.testing.assert_allclose(u[far], green, rtol=1e-4, atol=1e-6 * np.abs(green).max())


@pytest.mark.parametrize("a", [0.05, 0.2])
def test_hertz_central_displacement_closed_form(a: float) -> None:
    # c (ln(L/(πa)) + 1/2) = SAD's 2c + self_coefficient, checked on a fine periodic grid
    n, length = 2**15, 20.0
    dx = length / n
    x = (np.arange(n) - n // 2) * dx
    p = (2.0 / (math.pi * a * a)) * np.sqrt(np.clip(a * a - x * x, 0.0, None))
    p *= 1.0 / (p.sum() * dx)  # unit load on the grid
    u = spectral_displacement(np.roll(p, -n // 2), dx)
    expected = 2.0 * C0 + self_coefficient(a, length, E_STAR)
    assert u[0] == pytest.approx(expected, rel=2e-3)
    assert expected == pytest.approx(C0 * (math.log(length / (math.pi * a)) + 0.5), rel=1e-12)


def test_pair_coefficient_limits() -> None:
    period = 100.0
    # far apart: the line-load Green function
    for r in (5.0, 20.0, 50.0):
        assert pair_coefficient(r, 0.05, 0.08, period, E_STAR) == pytest.approx(
            float(periodic_green(r, period, E_STAR)), rel=1e-4
        )
    # symmetric in the two widths and in the sign of r
    assert pair_coefficient(0.3, 0.1, 0.2, period, E_STAR) == pytest.approx(
        pair_coefficient(-0.3, 0.2, 0.1, period, E_STAR), rel=1e-12
    )


def test_punch_average_of_a_line_load_closed_form() -> None:
    # a line load (a_source = 0) averaged over a punch of half-width a: ln((ρ + √(ρ² − a²))/2);
    # the symmetrised coefficient also averages the target's Hertz field over the source
    from scipy.integrate import quad

    period, a, r = 1000.0, 0.3, 0.5
    punch = math.log(0.5 * (r + math.sqrt(r * r - a * a)))

    def hertz(s: float) -> float:
        return (2 / (math.pi * a * a)) * math.sqrt(a * a - s * s) * math.log(abs(r - s))

    hertz_mean = quad(hertz, -a, a)[0]
    smooth = math.log(2 * math.pi / period) + math.log(
        math.sin(math.pi * r / period) / (math.pi * r / period)
    )
    expected = -C0 * (0.5 * (punch + hertz_mean) + smooth)
    assert pair_coefficient(r, a, 0.0, period, E_STAR) == pytest.approx(expected, rel=2e-3)


def mesh_displacement(
    x: np.ndarray, a: np.ndarray, load: np.ndarray, period: float, mirror_axis: float, cells: int
) -> np.ndarray:
    """w_i of the compiled particle–mesh operator (contacts and their mirror images, e_z = 1)."""
    n = x.size
    pos = np.mod(np.concatenate([x, mirror_axis - x]), period)
    owner = np.concatenate([np.arange(n), np.arange(n)]).astype(np.int64)
    cache = mesh_cache(cells)
    base = _level(cache, cells, period, E_STAR)
    h = period / cells
    near = min(max(4 * h, 6.0 * a.max()), 0.25 * period)
    nodes, weights = _quadrature()
    start, src, coef = _near_pairs(
        pos, np.concatenate([a, a]), n, owner, period, cells, near, cache[base], C0, nodes, weights
    )
    ones = np.ones(2 * n)
    u, _ = _apply(cache, base, load, 0.0, ones[:n], (pos, owner, ones, h, start, src, coef))
    return u


@pytest.mark.parametrize("seed", [1, 2])
def test_mesh_far_field_matches_the_direct_sum(seed: int) -> None:
    rng = np.random.default_rng(seed)
    n_nodes, dx, n = 8192, 0.01, 60
    period = 2 * n_nodes * dx
    mirror_axis = (2 * n_nodes - 1) * dx
    x = np.sort(rng.uniform(0.0, n_nodes * dx, n))
    a = rng.uniform(0.005, 0.05, n)
    load = rng.uniform(0.0, 1e-2, n)
    mesh = mesh_displacement(x, a, load, period, mirror_axis, 256)
    images = mirror_axis - x
    direct = np.empty(n)
    for i in range(n):
        total = self_coefficient(a[i], period, E_STAR) * load[i]
        for j in range(n):
            if j != i:
                total += pair_coefficient(x[i] - x[j], a[i], a[j], period, E_STAR) * load[j]
            total += pair_coefficient(x[i] - images[j], a[i], a[j], period, E_STAR) * load[j]
        direct[i] = total
    np.testing.assert_allclose(mesh, direct, rtol=0, atol=2e-3 * np.abs(direct).max())


def circle_profile(n: int, dx: float, radius: float, centres: list[float]) -> Profile:
    x = np.arange(n) * dx
    z = np.full(n, -np.inf)
    for c in centres:
        s = np.clip(x - c, -radius, radius)
        z = np.maximum(z, -(s * s) / (radius + np.sqrt(radius * radius - s * s)))
    return Profile(x, z)


def bem_at(
    profile: Profile, forces: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Exact approach [µm], mean gap [µm] and (segment) contact length [µm] and patches."""
    n = profile.n_points
    f = fit_spline(profile, alpha=2.0, x0=1.0).f
    problem = bem.contact_problem(bem.mirror_extend(Profile(profile.x, f)), e_star=E_STAR)
    rows = []
    previous = None
    for force in forces:
        step = bem.solve_pressure(
            problem, force / profile.length, initial_pressure=previous, fields=True
        )
        previous = step.pressure
        assert step.pressure is not None
        stats = bem.contact_statistics(step.pressure[:n], profile.dx, periodic=False)
        rows.append((step.approach, step.mean_gap, stats.contact_length_subgrid, stats.n_patches))
    approach, gap, length, patches = (np.array(column) for column in zip(*rows, strict=True))
    return approach, gap, length, patches


def test_single_asperity_interacting_independent_and_exact_agree() -> None:
    n, dx, radius = 4096, 0.01, 200.0
    profile = circle_profile(n, dx, radius, [n // 2 * dx])
    kwargs = dict(
        steps=200, final_displacement=6e-3, final_displacement_factor=0.2, alpha=2.0, x0=1.0
    )
    plain = contact_geometry(profile, "flat", **kwargs)  # type: ignore[arg-type]
    independent = run_loading(plain, e_star=E_STAR, g_star=E_STAR / 2.6, mu0=0.3).curves
    geometry = extended_geometry(profile, "flat", **kwargs)  # type: ignore[arg-type]
    inter, _ = interacting_loading(
        geometry, e_star=E_STAR, g_star=E_STAR / 2.6, mu0=0.3, n_points=n
    )
    steps = np.array([40, 80, 120, 160, 200])
    # Hertz: a² = 4PR/(πE*), both variants, each at its own force
    for curves, width in (
        (independent, np.sqrt(2) * independent["contact_area"]),
        (inter, inter["coalesced_contact_length"]),
    ):
        force = curves["normal_force"][steps]
        hertz = 2.0 * np.sqrt(4.0 * force * radius / (math.pi * E_STAR))
        np.testing.assert_allclose(width[steps], hertz, rtol=2e-3)
        assert np.all(curves["n_contacts"][steps] == 1)
    np.testing.assert_allclose(
        np.sqrt(2) * inter["contact_area"][steps],
        inter["coalesced_contact_length"][steps],
        rtol=2e-3,
    )
    # and the interacting variant's approach and mean gap are the exact (BEM) ones
    approach, gap, length, patches = bem_at(profile, inter["normal_force"][steps])
    assert np.all(patches == 1)
    np.testing.assert_allclose(inter["displacement"][steps], approach, rtol=2e-3)
    np.testing.assert_allclose(inter["mean_separation"][steps], gap, rtol=1e-5)
    np.testing.assert_allclose(inter["coalesced_contact_length"][steps], length, rtol=0.01)
    # the independent variant is much stiffer in plane strain (log of the body size)
    assert np.all(independent["normal_force"][steps] > 1.4 * inter["normal_force"][steps])


def two_asperity_errors(
    n: int, dx: float, spacing: float, final: float
) -> tuple[float, float, float]:
    """Largest relative error of approach and contact length at equal force, and s / a_max."""
    radius = 200.0
    mid = n // 2 * dx
    profile = circle_profile(n, dx, radius, [mid - spacing / 2, mid + spacing / 2])
    geometry = extended_geometry(
        profile,
        "flat",
        steps=100,
        final_displacement=final,
        final_displacement_factor=0.2,
        alpha=2.0,
        x0=1.0,
    )
    inter, _ = interacting_loading(
        geometry, e_star=E_STAR, g_star=E_STAR / 2.6, mu0=0.3, n_points=n
    )
    steps = np.array([20, 40, 60, 80, 100])
    approach, _, length, patches = bem_at(profile, inter["normal_force"][steps])
    assert np.all(patches == 2)
    assert np.all(inter["n_contact_patches"][steps] == 2)
    err_approach = float(np.max(np.abs(inter["displacement"][steps] / approach - 1.0)))
    err_length = float(np.max(np.abs(inter["coalesced_contact_length"][steps] / length - 1.0)))
    return err_approach, err_length, spacing / (length[-1] / 4)


@pytest.mark.parametrize("spacing", [0.9, 36.0])
def test_two_asperities_force_approach_matches_bem(spacing: float) -> None:
    err_approach, err_length, ratio = two_asperity_errors(4096, 0.02, spacing, 4e-3)
    assert 1.8 <= ratio <= 2.1 or ratio >= 48.0
    assert err_approach <= 0.02
    assert err_length <= 0.02


@pytest.mark.slow
@pytest.mark.parametrize("spacing", [1.0, 1.5, 2.5, 5.0, 10.0, 20.0, 36.0])
def test_two_asperities_force_approach_matches_bem_fine(spacing: float) -> None:
    err_approach, err_length, ratio = two_asperity_errors(8192, 0.01, spacing, 4e-3)
    assert ratio >= 1.9
    assert err_approach <= 0.02
    assert err_length <= 0.02


def test_bad_settings_are_refused() -> None:
    profile = circle_profile(256, 0.01, 50.0, [1.28])
    geometry = extended_geometry(
        profile,
        "flat",
        steps=5,
        final_displacement=1e-3,
        final_displacement_factor=0.2,
        alpha=2.0,
        x0=1.0,
    )
    for settings, message in (
        (InteractionSettings(tol=0.0), "tol"),
        (InteractionSettings(mesh_cells=100), "mesh_cells"),
        (InteractionSettings(width="wide"), "width"),
    ):
        with pytest.raises(ParameterError, match=message):
            interacting_loading(
                geometry, e_star=E_STAR, g_star=1.0, mu0=0.3, n_points=256, settings=settings
            )
    with pytest.raises(ParameterError, match="reach_fraction"):
        extended_geometry(
            profile,
            "flat",
            steps=5,
            final_displacement=1e-3,
            final_displacement_factor=0.2,
            alpha=2.0,
            x0=1.0,
            reach_fraction=-1.0,
        )


def test_simulate_with_interaction() -> None:
    from splinecontact import simulate
    from splinecontact.generate import weierstrass_mandelbrot

    profile = weierstrass_mandelbrot(1.5, n_points=4096, length=10.0, seed=3)
    plain = simulate(profile, "flat", steps=50, diagnostics=False)
    again = simulate(profile, "flat", steps=50, diagnostics=False, interaction=False)
    for name in plain.curves:  # the default stays the paper's independent contacts
        np.testing.assert_array_equal(plain.curves[name], again.curves[name])
    coupled = simulate(
        profile, "flat", steps=50, diagnostics=False, interaction=True, record_contacts="last"
    )
    assert coupled.coalesced_contact_length is not None
    assert coupled.parameters["interaction"] == "elastic half-plane"
    np.testing.assert_array_equal(coupled.displacement, plain.displacement)
    np.testing.assert_array_equal(coupled.mean_separation, plain.mean_separation)
    # coupled contacts carry less at the same rigid approach, and never more than SAD's law
    assert coupled.normal_force[-1] < plain.normal_force[-1]
    last = coupled.contacts[-1]
    assert np.all(last.normal_force > 0)
    np.testing.assert_allclose(last.normal_force, 0.25 * math.pi * E_STAR * last.overlap)
    assert last.normal_force.sum() * 0.999 <= coupled.normal_force_normal_part[-1] * 1.001
    ds = coupled.to_xarray()
    assert ds["coalesced_contact_length"].attrs["units"] == "µm"


def test_simulate_interaction_refuses_what_it_does_not_support() -> None:
    from splinecontact import simulate

    profile = circle_profile(256, 0.01, 50.0, [1.28])
    with pytest.raises(ParameterError, match="interaction"):
        simulate(profile, "flat", steps=5, interaction="yes")  # type: ignore[arg-type]
    # (sliding and force-controlled paths run since: tests/test_interaction_slide.py)


@pytest.mark.filterwarnings("ignore::splinecontact.diagnostics.SimulationWarning")
def test_compare_reports_the_interacting_variant() -> None:
    from splinecontact.compare import compare_profiles

    profile = circle_profile(4096, 0.01, 200.0, [20.48])
    comparison = compare_profiles(
        profile, "flat", steps=100, final_displacement=6e-3, n_forces=4, interaction=True
    )
    c = comparison.columns
    assert np.all(np.isfinite(c["ratio_length_int"]))
    np.testing.assert_allclose(c["ratio_length_int"], 1.0, rtol=0.02)
    np.testing.assert_allclose(c["mean_gap_error_int"], 0.0, atol=1e-4)
    np.testing.assert_allclose(c["ratio_approach_int"], 1.0, rtol=0.01)
    assert np.all(c["ratio_patches_int"] == 1.0)
    # the independent variant on the same forces: its approach is too small (plane strain)
    assert np.all(c["ratio_approach"] > 1.3)
