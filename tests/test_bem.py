"""Tests of the boundary element reference (splinecontact.bem) against closed forms.

Oracles: Westergaard's sinusoid and Hertz's cylinder (splinecontact.reference), exact discrete
identities (full-contact pressure, composite gap, mirror symmetry), and properties that any
correct solution has (complementarity, force balance, monotone mean gap, translation invariance).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from splinecontact import Profile, _fft, bem
from splinecontact import reference as ref
from splinecontact.errors import BEMError, NoConvergenceError, ParameterError

E_STAR = 10.0  # GPa


def sinusoid(n: int, length: float, amplitude: float) -> tuple[np.ndarray, float]:
    dx = length / n
    x = np.arange(n) * dx
    return amplitude * np.cos(2 * np.pi * x / length), dx


def random_periodic(n: int, seed: int, hurst: float = 0.7) -> np.ndarray:
    rng = np.random.default_rng(seed)
    k = np.arange(n // 2 + 1, dtype=float)
    amp = np.zeros_like(k)
    amp[1:] = k[1:] ** (-(1 + 2 * hurst) / 2)
    spec = amp * np.exp(2j * np.pi * rng.random(k.size))
    z = np.fft.irfft(spec, n)
    return z / np.std(z) * 0.01


# --- Westergaard ----------------------------------------------------------------------------


@pytest.fixture(scope="module")
def westergaard_path() -> tuple[bem.BEMPath, np.ndarray, float, float, float]:
    n, length, h = 2**14, 10.0, 0.01
    z, dx = sinusoid(n, length, h)
    problem = bem.contact_problem(z, e_star=E_STAR, dx=dx)
    p_star = ref.westergaard_full_contact_pressure(h, length, E_STAR)
    psi = np.array([0.01, 0.03, 0.1, 0.3, 0.5, 0.7, 0.9, 0.95])
    path = bem.load_path(problem, psi * p_star)
    return path, psi, p_star, h, length


def test_westergaard_contact_width_subgrid(westergaard_path):
    path, psi, p_star, h, length = westergaard_path
    exact = 2 * ref.westergaard_contact_half_width(psi * p_star, h, length, E_STAR)
    got = path.column("contact_length_subgrid")
    assert np.all(np.abs(got / exact - 1) < 1e-3)


def test_westergaard_contact_width_node_count(westergaard_path):
    path, psi, p_star, h, length = westergaard_path
    exact = 2 * ref.westergaard_contact_half_width(psi * p_star, h, length, E_STAR)
    # node count: within one node per edge
    assert np.all(np.abs(path.column("contact_length") - exact) <= 2 * path.dx + 1e-12)
    assert np.all(path.column("n_patches") == 1)


def test_westergaard_mean_gap(westergaard_path):
    path, psi, p_star, h, length = westergaard_path
    exact = ref.westergaard_mean_gap(psi * p_star, h, length, E_STAR)
    got = path.column("mean_gap")
    assert np.all(np.abs(got / exact - 1) < 1e-5)


def test_westergaard_force_and_approach(westergaard_path):
    path, psi, p_star, h, length = westergaard_path
    np.testing.assert_allclose(path.column("force"), psi * p_star * length, rtol=1e-12)
    # first touch at mean gap h (the crest), so approach = h − ḡ
    np.testing.assert_allclose(path.column("approach"), h - path.column("mean_gap"), atol=1e-15)


def test_westergaard_pressure_field():
    n, length, h = 2**12, 10.0, 0.01
    z, dx = sinusoid(n, length, h)
    problem = bem.contact_problem(z, e_star=E_STAR, dx=dx)
    p_mean = 0.4 * ref.westergaard_full_contact_pressure(h, length, E_STAR)
    step = bem.solve_pressure(problem, p_mean, fields=True)
    x = np.arange(n) * dx
    x = np.where(x > length / 2, x - length, x)
    exact = ref.westergaard_pressure(x, p_mean, h, length, E_STAR)
    assert step.pressure is not None and step.gap is not None
    # away from the edges (square-root singularity of the derivative) pointwise to 1e-3 of peak
    a = float(ref.westergaard_contact_half_width(p_mean, h, length, E_STAR))
    interior = np.abs(x) < a - 20 * dx
    assert np.max(np.abs(step.pressure - exact)[interior]) < 1e-3 * exact.max()
    assert np.all(step.gap >= 0) and np.all(step.gap[step.pressure > 0] == 0)


def test_full_contact_pressure_is_westergaard_p_star():
    z, dx = sinusoid(256, 3.0, 0.02)
    problem = bem.contact_problem(z, e_star=E_STAR, dx=dx)
    p_star = ref.westergaard_full_contact_pressure(0.02, 3.0, E_STAR)
    assert problem.full_contact_pressure == pytest.approx(p_star, rel=1e-10)


def test_displacement_control_inverts_load_control():
    n, length, h = 2**12, 10.0, 0.01
    z, dx = sinusoid(n, length, h)
    problem = bem.contact_problem(z, e_star=E_STAR, dx=dx)
    p_star = ref.westergaard_full_contact_pressure(h, length, E_STAR)
    psi = np.array([0.05, 0.3, 0.8])
    gaps = ref.westergaard_mean_gap(psi * p_star, h, length, E_STAR)
    path = bem.gap_path(problem, gaps)
    np.testing.assert_allclose(path.column("mean_pressure"), psi * p_star, rtol=1e-4)
    np.testing.assert_allclose(path.column("mean_gap"), gaps, rtol=1e-14)


# --- Hertz ----------------------------------------------------------------------------------


@pytest.mark.parametrize("target_nodes", [100, 300, 1000])
def test_hertz_cylinder_half_width(target_nodes):
    n, dx, radius = 2**14, 0.01, 1000.0
    x = (np.arange(n) - n // 2) * dx
    z = -(x**2) / (2 * radius)
    problem = bem.contact_problem(z, e_star=E_STAR, dx=dx, check_periodic=False)
    a_target = target_nodes * dx / 2
    force = np.pi * E_STAR * a_target**2 / (4 * radius)
    step = bem.solve_pressure(problem, force / problem.length)
    assert step.contact_nodes >= target_nodes - 2
    a_exact = float(ref.hertz_cylinder_half_width(force, radius, E_STAR))
    assert step.contact_length_subgrid / 2 == pytest.approx(a_exact, rel=1e-2)
    assert step.n_patches == 1


def test_hertz_pressure_field_peak():
    n, dx, radius = 2**13, 0.01, 1000.0
    x = (np.arange(n) - n // 2) * dx
    z = -(x**2) / (2 * radius)
    problem = bem.contact_problem(z, e_star=E_STAR, dx=dx, check_periodic=False)
    force = np.pi * E_STAR * 2.0**2 / (4 * radius)  # a = 2 µm = 200 nodes
    step = bem.solve_pressure(problem, force / problem.length, fields=True)
    exact = ref.hertz_cylinder_pressure(x, force, radius, E_STAR)
    assert step.pressure is not None
    assert step.pressure.max() == pytest.approx(exact.max(), rel=1e-2)


# --- composite gap, mirror, statistics ------------------------------------------------------


def test_rough_on_rough_is_composite_gap():
    n = 512
    lower = random_periodic(n, 1)
    upper = random_periodic(n, 2)
    x = np.arange(n) * 0.1
    both = bem.contact_problem(Profile(x, lower), Profile(x, upper), e_star=E_STAR)
    summed = bem.contact_problem(lower + upper, e_star=E_STAR, dx=0.1)
    p = 0.2 * both.full_contact_pressure
    a = bem.solve_pressure(both, p)
    b = bem.solve_pressure(summed, p)
    assert a.contact_nodes == b.contact_nodes
    assert a.mean_gap == pytest.approx(b.mean_gap, rel=1e-12)


def test_mirror_extend_is_periodic_and_symmetric():
    n = 200
    x = np.arange(n) * 0.05
    z = 0.01 * x + 0.002 * np.sin(7 * x)  # tilted: not periodic
    profile = Profile(x, z)
    with pytest.raises(bem.NonPeriodicProfileError, match="wrap around"):
        bem.contact_problem(profile, e_star=E_STAR)
    mirrored = bem.mirror_extend(profile)
    assert mirrored.n_points == 2 * n and mirrored.dx == pytest.approx(profile.dx)
    problem = bem.contact_problem(mirrored, e_star=E_STAR)
    step = bem.solve_pressure(problem, 0.05 * problem.full_contact_pressure, fields=True)
    assert step.pressure is not None
    np.testing.assert_allclose(step.pressure, step.pressure[::-1], atol=1e-9 * step.pressure.max())


def test_contact_statistics_periodic_wrap():
    p = np.array([1.0, 0.5, 0, 0, 0.3, 0, 0, 0.2])
    s = bem.contact_statistics(p, 1.0)
    assert s.n_patches == 2  # node 7 joins nodes 0-1 across the wrap
    assert s.contact_nodes == 4 and s.contact_length == 4.0
    s_wall = bem.contact_statistics(p, 1.0, periodic=False)
    assert s_wall.n_patches == 3
    assert bem.contact_statistics(np.zeros(8), 1.0).n_patches == 0
    full = bem.contact_statistics(np.ones(8), 0.5)
    assert (full.n_patches, full.contact_length, full.contact_length_subgrid) == (1, 4.0, 4.0)


def test_contact_statistics_square_root_edge_is_exact():
    # p = sqrt(a² − x²) sampled on nodes: the sub-grid length recovers 2a to O(dx²/a)
    dx, a = 1.0, 50.3
    x = np.arange(-128, 128) * dx
    p = np.sqrt(np.clip(a**2 - x**2, 0, None))
    s = bem.contact_statistics(p, dx)
    assert s.contact_length_subgrid == pytest.approx(2 * a, abs=0.05)


def test_zero_load_and_no_contact_gap():
    z, dx = sinusoid(64, 1.0, 0.01)
    problem = bem.contact_problem(z, e_star=E_STAR, dx=dx)
    step = bem.solve_pressure(problem, 0.0, fields=True)
    assert step.force == 0.0 and step.contact_nodes == 0
    assert step.mean_gap == pytest.approx(0.01)
    far = bem.solve_gap(problem, 0.05)
    assert far.force == 0.0 and far.mean_gap == 0.05 and far.approach == pytest.approx(-0.04)


# --- properties -----------------------------------------------------------------------------


@settings(max_examples=15, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    fraction=st.floats(0.02, 0.9),
    shift=st.integers(1, 127),
)
def test_solution_properties(seed, fraction, shift):
    n = 128
    z = random_periodic(n, seed)
    problem = bem.contact_problem(z, e_star=E_STAR, dx=0.05)
    p_mean = fraction * problem.full_contact_pressure
    step = bem.solve_pressure(problem, p_mean, fields=True)
    assert step.pressure is not None and step.gap is not None
    assert np.all(step.pressure >= 0)
    assert step.pressure.mean() == pytest.approx(p_mean, rel=1e-12)
    assert step.force == pytest.approx(p_mean * problem.length, rel=1e-12)
    assert step.residual <= bem.DEFAULT_TOLERANCE
    # the raw gap recomputed from the pressure vanishes on the contact and is ≥ 0 elsewhere
    u = problem.displacement(step.pressure)
    gap = step.mean_gap + problem.mean_height + u - z
    scale = problem.rms_height
    assert np.max(np.abs(gap[step.pressure > 0])) <= 1e-9 * scale
    assert np.min(gap) >= -1e-9 * scale
    # translation invariance
    shifted = bem.contact_problem(np.roll(z, shift), e_star=E_STAR, dx=0.05)
    other = bem.solve_pressure(shifted, p_mean)
    assert other.contact_nodes == step.contact_nodes
    assert other.n_patches == step.n_patches
    assert other.mean_gap == pytest.approx(step.mean_gap, rel=1e-8, abs=1e-9 * scale)


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 10_000))
def test_mean_gap_decreases_with_load(seed):
    z = random_periodic(256, seed)
    problem = bem.contact_problem(z, e_star=E_STAR, dx=0.05)
    loads = np.linspace(0.01, 0.9, 8) * problem.full_contact_pressure
    path = bem.load_path(problem, loads)
    assert np.all(np.diff(path.column("mean_gap")) < 0)
    assert np.all(np.diff(path.column("approach")) > 0)


def test_warm_start_matches_cold_start():
    z = random_periodic(1024, 5)
    problem = bem.contact_problem(z, e_star=E_STAR, dx=0.05)
    loads = np.array([0.05, 0.1, 0.2]) * problem.full_contact_pressure
    path = bem.load_path(problem, loads)
    cold = bem.solve_pressure(problem, loads[-1])
    assert path.steps[-1].contact_nodes == cold.contact_nodes
    assert path.steps[-1].mean_gap == pytest.approx(cold.mean_gap, rel=1e-8)


# --- errors ---------------------------------------------------------------------------------


@pytest.fixture
def small_problem() -> bem.ContactProblem:
    z, dx = sinusoid(64, 1.0, 0.01)
    return bem.contact_problem(z, e_star=E_STAR, dx=dx)


def test_negative_load(small_problem):
    with pytest.raises(bem.NegativeLoadError, match=r"-0\.1"):
        bem.solve_pressure(small_problem, -0.1)
    with pytest.raises(bem.NegativeLoadError):
        bem.load_path(small_problem, [0.01, -0.01])
    with pytest.raises(bem.NegativeLoadError):
        bem.solve_pressure(small_problem, float("nan"))


def test_load_beyond_full_contact(small_problem):
    p_full = small_problem.full_contact_pressure
    with pytest.raises(bem.FullContactError, match="full contact"):
        bem.solve_pressure(small_problem, 1.01 * p_full)
    with pytest.raises(bem.FullContactError):
        bem.solve_pressure(small_problem, p_full)
    with pytest.raises(bem.FullContactError, match="mean gap"):
        bem.solve_gap(small_problem, 0.0)
    with pytest.raises(bem.FullContactError):
        bem.gap_path(small_problem, [0.005, -0.001])


def test_flat_against_flat_is_full_contact_at_any_load():
    problem = bem.contact_problem(np.zeros(16), e_star=E_STAR, dx=1.0)
    with pytest.raises(bem.FullContactError):
        bem.solve_pressure(problem, 1e-6)


def test_no_convergence_raises():
    z = random_periodic(2048, 3)
    problem = bem.contact_problem(z, e_star=E_STAR, dx=0.05)
    with pytest.raises(NoConvergenceError, match="did not converge in 2 iterations"):
        bem.solve_pressure(problem, 0.1 * problem.full_contact_pressure, max_iterations=2)
    with pytest.raises(NoConvergenceError):
        bem.solve_gap(problem, 0.5 * problem.first_contact_gap, max_iterations=2)
    assert issubclass(NoConvergenceError, BEMError)


@pytest.mark.parametrize(
    ("kwargs", "error", "match"),
    [
        ({"lower": np.zeros(4), "dx": 1.0}, bem.BEMGridError, "at least 8"),
        ({"lower": np.zeros(16)}, bem.BEMGridError, "pass the grid spacing"),
        ({"lower": np.zeros(16), "dx": -1.0}, bem.BEMGridError, "positive"),
        ({"lower": np.zeros((4, 4)), "dx": 1.0}, bem.BEMGridError, "one-dimensional"),
        ({"lower": np.r_[np.zeros(15), np.nan], "dx": 1.0}, bem.BEMGridError, "height 15"),
        ({"lower": np.zeros(16), "upper": np.zeros(17), "dx": 1.0}, bem.BEMGridError, "17"),
        ({"lower": np.zeros(16), "upper": "round", "dx": 1.0}, bem.BEMGridError, "round"),
        ({"lower": np.zeros(16), "dx": 1.0, "e_star": 0.0}, bem.BEMParameterError, "e_star"),
        ({"lower": np.arange(16.0), "dx": 1.0}, bem.NonPeriodicProfileError, "z\\[15\\]"),
    ],
)
def test_bad_input(kwargs, error, match):
    kwargs = {"e_star": E_STAR, **kwargs}
    lower = kwargs.pop("lower")
    with pytest.raises(error, match=match):
        bem.contact_problem(lower, **kwargs)


def test_grid_spacing_mismatch():
    x = np.arange(16) * 0.1
    with pytest.raises(bem.BEMGridError, match="spacings differ"):
        bem.contact_problem(Profile(x, np.zeros(16)), Profile(2 * x, np.zeros(16)), e_star=1.0)
    with pytest.raises(bem.BEMGridError, match="spacings differ"):
        bem.contact_problem(Profile(x, np.zeros(16)), e_star=1.0, dx=0.2)


def test_bad_solver_parameters(small_problem):
    with pytest.raises(bem.BEMParameterError, match="tol"):
        bem.solve_pressure(small_problem, 0.01, tol=0.0)
    with pytest.raises(bem.BEMParameterError, match="max_iterations"):
        bem.solve_pressure(small_problem, 0.01, max_iterations=0)


def test_errors_are_bem_errors():
    for cls in (
        bem.BEMGridError,
        bem.NonPeriodicProfileError,
        bem.NegativeLoadError,
        bem.FullContactError,
        bem.BEMParameterError,
    ):
        assert issubclass(cls, BEMError)


def test_path_column_unknown(small_problem):
    path = bem.load_path(small_problem, [0.001])
    with pytest.raises(KeyError, match="unknown"):
        path.column("area")
    assert set(bem.STEP_UNITS) >= {"force", "mean_gap", "contact_length_subgrid", "n_patches"}


# --- reference solutions --------------------------------------------------------------------


def test_reference_limits():
    h, lam = 0.01, 5.0
    p_star = ref.westergaard_full_contact_pressure(h, lam, E_STAR)
    assert p_star == pytest.approx(np.pi * E_STAR * h / lam)
    assert ref.westergaard_mean_gap(0.0, h, lam, E_STAR) == pytest.approx(h)
    assert ref.westergaard_mean_gap(p_star, h, lam, E_STAR) == pytest.approx(0.0, abs=1e-18)
    assert ref.westergaard_contact_half_width(p_star, h, lam, E_STAR) == pytest.approx(lam / 2)
    # the Westergaard pressure integrates to p̄ λ
    x = np.linspace(-lam / 2, lam / 2, 200_001)
    p = ref.westergaard_pressure(x, 0.3 * p_star, h, lam, E_STAR)
    assert np.trapezoid(p, x) == pytest.approx(0.3 * p_star * lam, rel=1e-4)
    # Hertz: pressure integrates to P
    force, radius = 0.02, 100.0
    a = float(ref.hertz_cylinder_half_width(force, radius, E_STAR))
    x = np.linspace(-a, a, 200_001)
    assert np.trapezoid(ref.hertz_cylinder_pressure(x, force, radius, E_STAR), x) == (
        pytest.approx(force, rel=1e-4)
    )
    # small loads: the Westergaard half-width tends to Hertz with R = λ²/(4π² h)
    small = 1e-6 * p_star
    a_w = float(ref.westergaard_contact_half_width(small, h, lam, E_STAR))
    a_h = float(ref.hertz_cylinder_half_width(small * lam, lam**2 / (4 * np.pi**2 * h), E_STAR))
    assert a_w == pytest.approx(a_h, rel=1e-5)


def test_reference_errors():
    with pytest.raises(ParameterError, match="amplitude"):
        ref.westergaard_full_contact_pressure(-1.0, 1.0, 1.0)
    with pytest.raises(ParameterError, match="outside"):
        ref.westergaard_mean_gap(2.0, 0.01, 1.0, 1.0)
    with pytest.raises(ParameterError, match="force"):
        ref.hertz_cylinder_half_width(-1.0, 1.0, 1.0)
    with pytest.raises(ParameterError, match="radius"):
        ref.hertz_cylinder_half_width(1.0, 0.0, 1.0)


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 10_000), fraction=st.floats(0.03, 0.8))
def test_displacement_and_load_control_agree(seed, fraction):
    z = random_periodic(256, seed)
    problem = bem.contact_problem(z, e_star=E_STAR, dx=0.05)
    by_load = bem.solve_pressure(problem, fraction * problem.full_contact_pressure)
    by_gap = bem.solve_gap(problem, by_load.mean_gap)
    assert by_gap.mean_pressure == pytest.approx(by_load.mean_pressure, rel=1e-6)
    assert by_gap.contact_nodes == by_load.contact_nodes


def test_rough_load_path_to_ten_percent_contact():
    # the benchmark case at a quarter of its size: every step converges, contact grows
    z = random_periodic(2**14, 1, hurst=0.8)
    dx = 100.0 / z.size
    slope = np.sqrt(np.mean((np.roll(z, -1) - z) ** 2)) / dx
    problem = bem.contact_problem(z * 0.1 / slope, e_star=E_STAR, dx=dx)
    loads = 0.048 * E_STAR * 0.1 * np.arange(1, 26) / 25
    path = bem.load_path(problem, loads)
    fraction = path.column("contact_nodes") / problem.n_points
    assert 0.05 < fraction[-1] < 0.2
    assert np.all(np.diff(path.column("mean_gap")) < 0)
    assert np.all(path.column("residual") <= bem.DEFAULT_TOLERANCE)


# --- the fused solver against the legacy loop ------------------------------------------------


def _rough_problem(n: int) -> bem.ContactProblem:
    z = random_periodic(n, 1, hurst=0.8)
    dx = 100.0 / z.size
    slope = np.sqrt(np.mean((np.roll(z, -1) - z) ** 2)) / dx
    return bem.contact_problem(z * 0.1 / slope, e_star=E_STAR, dx=dx)


@pytest.mark.parametrize("sparse_updates", [True, False])
def test_fused_solver_matches_legacy_loop(monkeypatch, sparse_updates):
    # 20 steps to ~10 % contact, tol 1e-10: same contact set at every step, mean gaps to 1e-9,
    # pressures to the tolerance's scale, and the iteration count of the plain-numpy loop
    from bem_legacy import legacy_load_path

    if not sparse_updates:  # every iteration re-applies the operator with an FFT pair,
        monkeypatch.setattr(bem._solver, "_sparse_limit", lambda n: -1)
        # through the embedding in a transform of 2n points (not the direct transform)
        monkeypatch.setattr(_fft, "transform_size", lambda n: 2 * n)
    problem = _rough_problem(2**12)
    loads = 0.048 * E_STAR * 0.1 * np.arange(1, 21) / 20
    path = bem.load_path(problem, loads, fields=True)
    legacy = legacy_load_path(problem, loads, bem.DEFAULT_TOLERANCE)
    assert path.column("contact_nodes")[-1] / problem.n_points > 0.05
    for step, old in zip(path.steps, legacy, strict=True):
        assert step.pressure is not None
        np.testing.assert_array_equal(step.pressure > 0.0, old.pressure > 0.0)
        old_gap = old.separation - problem.mean_height
        assert step.mean_gap == pytest.approx(old_gap, rel=1e-9, abs=0.0)
        np.testing.assert_allclose(step.pressure, old.pressure, rtol=0, atol=1e-6 * loads[-1])
    new_total = int(path.column("iterations").sum())
    old_total = sum(s.iterations for s in legacy)
    # rounding-level differences (summation order, FFT library) can move a conjugate-gradient
    # restart by an iteration or two; the work must not grow
    assert abs(new_total - old_total) <= 0.02 * old_total


def test_compiled_loop_matches_the_embedded_transform(monkeypatch):
    # the one compiled loop with the direct transform and with the same grid embedded in a
    # transform of twice its length (the path of odd grids and other prime factors) moves only
    # rounding: same contact sets, mean gaps to 1e-9; and each is reproducible to the bit
    problem = _rough_problem(2**12)
    loads = 0.048 * E_STAR * 0.1 * np.arange(1, 11) / 10
    compiled = bem.load_path(problem, loads, fields=True)
    again = bem.load_path(problem, loads, fields=True)
    monkeypatch.setattr(_fft, "transform_size", lambda n: 2 * n)
    embedded = bem.load_path(problem, loads, fields=True)
    for a, b, c in zip(compiled.steps, again.steps, embedded.steps, strict=True):
        assert a.pressure is not None and b.pressure is not None and c.pressure is not None
        np.testing.assert_array_equal(a.pressure, b.pressure)
        assert a.iterations == b.iterations and a.mean_gap == b.mean_gap
        np.testing.assert_array_equal(a.pressure > 0.0, c.pressure > 0.0)
        assert a.mean_gap == pytest.approx(c.mean_gap, rel=1e-9, abs=0.0)


@pytest.mark.parametrize("n", [3 * 2**10, 1999])
def test_compiled_loop_matches_legacy_loop_on_other_grid_sizes(n):
    # grids that are not a power of two run the same compiled loop (3·2^10 transformed
    # directly with radix-3 stages, a prime through the embedding): same contact set at every
    # step, mean gaps to 1e-9 and the legacy iteration count
    from bem_legacy import legacy_load_path

    problem = _rough_problem(n)
    loads = 0.048 * E_STAR * 0.1 * np.arange(1, 11) / 10
    path = bem.load_path(problem, loads, fields=True)
    legacy = legacy_load_path(problem, loads, bem.DEFAULT_TOLERANCE)
    for step, old in zip(path.steps, legacy, strict=True):
        assert step.pressure is not None
        np.testing.assert_array_equal(step.pressure > 0.0, old.pressure > 0.0)
        old_gap = old.separation - problem.mean_height
        assert step.mean_gap == pytest.approx(old_gap, rel=1e-9, abs=0.0)
        np.testing.assert_allclose(step.pressure, old.pressure, rtol=0, atol=1e-6 * loads[-1])
    old_total = sum(s.iterations for s in legacy)
    assert abs(int(path.column("iterations").sum()) - old_total) <= 0.02 * old_total


def test_returned_gap_is_that_of_the_returned_pressure():
    # the displacement is updated incrementally inside the loop; what is returned must be the
    # gap of the returned pressure recomputed from scratch
    problem = _rough_problem(2**11)
    step = bem.solve_pressure(problem, 0.02 * problem.full_contact_pressure, fields=True)
    assert step.pressure is not None and step.gap is not None
    u = problem.displacement(step.pressure)
    separation = step.mean_gap + problem.mean_height
    exact = np.clip(separation + u - problem.heights, 0.0, None)
    exact[step.pressure > 0.0] = 0.0
    scale = problem.rms_height
    assert np.max(np.abs(exact - step.gap)) <= 2 * bem.DEFAULT_TOLERANCE * scale


@given(seed=st.integers(0, 1000), k=st.integers(1, 12))
@settings(max_examples=25, deadline=None)
def test_point_load_columns_equal_the_operator(seed, k):
    # the sparse update (response to a few point loads, added column by column) is A δ
    rng = np.random.default_rng(seed)
    n = 128
    problem = bem.contact_problem(random_periodic(n, seed), e_star=E_STAR, dx=0.1)
    nodes = rng.choice(n, size=k, replace=False).astype(np.int64)
    weights = rng.normal(size=k)
    delta = np.zeros(n)
    delta[nodes] = weights
    column = problem.displacement(np.eye(1, n, 0)[0])
    u = np.zeros(n)
    bem._k_add_columns(u, np.concatenate([column, column]), nodes, weights, k)
    np.testing.assert_allclose(u, problem.displacement(delta), rtol=0, atol=1e-12)
