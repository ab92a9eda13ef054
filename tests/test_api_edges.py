"""Edge cases of the generator, the spline and ``simulate``: each gave a traceback, a memory
blow-up or a silently wrong result before, and is now refused with a specific
:class:`~splinecontact.SplineContactError` before anything large is allocated."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, event, example, given, settings
from hypothesis import strategies as st

from splinecontact import (
    ParameterError,
    Profile,
    ProfileRangeError,
    ProfileTypeError,
    SplineContactError,
    fit_spline,
    simulate,
    weierstrass_mandelbrot,
    weierstrass_mandelbrot_pair,
)
from splinecontact.diagnostics import SimulationWarning
from splinecontact.generate import MAX_POINTS, MAX_WORK, as_seed_sequence

wm = weierstrass_mandelbrot


@pytest.fixture(scope="module")
def pair() -> tuple[Profile, Profile]:
    return weierstrass_mandelbrot_pair(1.5, seed=11, n_points=2000, length=1.0)


# --- allocations: a stated ceiling, checked first ---------------------------------------------


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"n_points": 10**10}, "n_points = 10000000000 is above the ceiling 20 000 000"),
        ({"n_points": 3 * 10**8}, "max_points="),
        ({"n_points": 100, "n_max": 10**9}, "terms is above the ceiling"),
        ({"n_points": 100, "directions": 10**9}, "terms is above the ceiling"),
        ({"directions": 10**5}, "max_work="),
        ({"n_points": 10**7, "directions": 2000}, "multiply-adds"),
    ],
)
def test_generator_refuses_huge_sizes_before_allocating(kwargs: dict, fragment: str) -> None:
    with pytest.raises(ParameterError, match=fragment):
        wm(1.5, seed=1, **kwargs)


def test_generator_ceilings_can_be_raised() -> None:
    with pytest.raises(ParameterError, match="n_points = 1000 is above the ceiling 999"):
        wm(1.5, n_points=1000, seed=1, max_points=999)
    work = 1000 * 20 * 21
    with pytest.raises(ParameterError, match="max_work"):
        wm(1.5, n_points=1000, seed=1, max_work=work - 1)
    default = wm(1.5, n_points=1000, seed=1)
    raised = wm(1.5, n_points=1000, seed=1, max_work=work, max_points=10**9)
    assert np.array_equal(default.z, raised.z)
    assert MAX_POINTS == 20_000_000 and MAX_WORK == 10**10


@pytest.mark.parametrize("steps", [10**8, 10**9])
def test_simulate_refuses_huge_step_counts(pair: tuple[Profile, Profile], steps: int) -> None:
    with pytest.raises(ParameterError, match=r"above the ceiling 1 000 000.*max_steps="):
        simulate(*pair, steps=steps)


def test_step_ceiling_can_be_raised(pair: tuple[Profile, Profile]) -> None:
    with pytest.raises(ParameterError, match="max_steps"):
        simulate(*pair, steps=6, max_steps=5)
    assert simulate(*pair, steps=6, max_steps=6).n_steps == 6


def test_recording_too_many_contacts_is_refused(
    pair: tuple[Profile, Profile], monkeypatch: pytest.MonkeyPatch
) -> None:
    import splinecontact.contact.simulation as contact

    monkeypatch.setattr(contact, "MAX_RECORDED_CONTACTS", 10)
    with pytest.raises(ParameterError, match="record fewer steps"):
        simulate(*pair, steps=20, record_contacts="all")


# --- overflow in the generator's parameters ---------------------------------------------------


@pytest.mark.parametrize(
    ("dimension", "kwargs", "fragment"),
    [
        (1.0, {"wavelength": 1e200}, "wavelength L = 1e\\+200 µm must be ≤ 1e\\+50 µm"),
        (1.0, {"wavelength": 1e-120}, "wavelength L = 1e-120 µm must be ≥ 1e-50 µm"),
        (1.5, {"wavelength": 1e-200}, "wavelength L = 1e-200 µm must be ≥ 1e-50 µm"),
        (1.5, {"ra": 1e-320}, "ra = 1e-320 µm must be ≥ 1e-50 µm"),
        (1.0, {"n_points": 5, "wavelength": 1e-50, "gamma": 6.4e9, "n_max": 40}, "n_max ≤ 0"),
        (1.5, {"n_points": 5, "length": 1e6, "wavelength": 1e6, "ra": 1e50}, "heights up to"),
        (1.5, {"n_max": 2000}, "gamma\\^n_max = 1.5\\^2000 overflows.*n_max ≤ 6 for this grid"),
        (1.5, {"gamma": 1e300, "n_max": 2}, "overflows"),
        (1.5, {"ra": 1e308}, "ra = 1e\\+308 µm must be ≤ 1e\\+50 µm"),
        (1.5, {"length": 1e300}, "length"),
        (1.5, {"length": 1e-300}, "length = 1e-300 µm must be ≥ 1e-50 µm"),
        (1.5, {"length": 1e-40}, "grid step"),
        (1.5, {"n_points": float("1e400")}, "n_points = inf"),
    ],
)
def test_generator_overflow_is_a_parameter_error(
    dimension: float, kwargs: dict, fragment: str
) -> None:
    kwargs.setdefault("n_points", 2000)
    with pytest.raises(ParameterError, match=fragment):
        wm(dimension, seed=1, **kwargs)


def test_profile_below_the_rounding_of_the_sum_is_refused() -> None:
    # Every kept wavelength is ~1e40 times the profile: the sum is constant up to rounding, and
    # rescaling that noise to R_A used to return a profile of pure rounding error.
    with pytest.raises(ParameterError, match="rounding error"):
        wm(1.5, n_points=2000, seed=1, wavelength=1e40)


@pytest.mark.parametrize("seed", [-1, "abc", 1.5, True, [1, 2], np.float64(3.0)], ids=repr)
def test_bad_seeds_are_parameter_errors(seed: object) -> None:
    with pytest.raises(ParameterError, match="seed"):
        wm(1.5, n_points=100, seed=seed)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="seed"):
        weierstrass_mandelbrot_pair(1.5, n_points=100, seed=seed)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="seed"):
        as_seed_sequence(seed)  # type: ignore[arg-type]


def test_numpy_integer_seeds_still_work() -> None:
    assert np.array_equal(
        wm(1.5, n_points=100, seed=np.int64(5)).z, wm(1.5, n_points=100, seed=5).z
    )


def test_a_pair_needs_a_seed_sequence_not_a_generator() -> None:
    with pytest.raises(ParameterError, match="Generator"):
        weierstrass_mandelbrot_pair(1.5, n_points=100, seed=np.random.default_rng(1))  # type: ignore[arg-type]


# --- the spline's parameters and grids -----------------------------------------------------------


@pytest.mark.parametrize("x0", [1e-300, 1e300])
def test_overflowing_spline_unit_length_is_a_parameter_error(
    pair: tuple[Profile, Profile], x0: float
) -> None:
    with pytest.raises(ParameterError, match="x0"):
        simulate(*pair, steps=5, x0=x0)
    with pytest.raises(ParameterError, match="smoothing weight"):
        fit_spline(pair[0], x0=x0)


def test_smoothing_weight_too_large_for_the_solve_is_refused(pair: tuple[Profile, Profile]) -> None:
    # λ/dx³ = (dx/x0)^α x0³ / (10 dx³) with dx ≈ 5e-4 µm, α = 0.5, x0 = 1e100 µm: about 1e257.
    with pytest.raises(ParameterError, match="straight"):
        fit_spline(pair[0], alpha=0.5, x0=1e100)


@pytest.mark.parametrize("scale", [1e-300, 1e-310, 1e-31])
def test_subnormal_or_tiny_grid_steps_are_refused(scale: float) -> None:
    with pytest.raises(ProfileRangeError, match="grid step"):
        simulate(Profile(np.arange(100) * scale, np.sin(np.arange(100.0))), "flat")


@pytest.mark.parametrize("scale", [1e300, 1e51])
def test_huge_grids_are_refused(scale: float) -> None:
    with pytest.raises(ProfileRangeError, match="beyond"):
        Profile(np.arange(100) * scale, np.sin(np.arange(100.0)))


# --- simulate: types and silent wrong results ------------------------------------------------------


@pytest.mark.parametrize("steps", [float("inf"), float("nan"), None, 2.5, True, "10"], ids=repr)
def test_bad_step_counts_are_parameter_errors(pair: tuple[Profile, Profile], steps: object) -> None:
    with pytest.raises(ParameterError, match="steps"):
        simulate(*pair, steps=steps)  # type: ignore[arg-type]


def test_simulate_with_no_upper_body_is_a_parameter_error(pair: tuple[Profile, Profile]) -> None:
    with pytest.raises(ParameterError, match="upper is a NoneType"):
        simulate(pair[0], None)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    "kwargs",
    [
        {"final_displacement": 1e308},
        {"final_displacement_factor": 1e308},
        {"final_displacement": 1e51},
    ],
)
def test_overflowing_final_displacement_is_refused(
    pair: tuple[Profile, Profile], kwargs: dict
) -> None:
    with pytest.raises(ParameterError, match=r"final.displacement.*1e\+50"):
        simulate(*pair, steps=10, **kwargs)


@pytest.mark.parametrize("height", [1e300, -1e308, 1e51])
def test_heights_near_the_float_limit_are_refused(height: float) -> None:
    x = np.linspace(0.0, 1.0, 100)
    z = np.sin(40 * x) * height
    with pytest.raises(ProfileRangeError, match="beyond ±1e\\+50 µm"):
        Profile(x, z)


def test_complex_heights_are_refused() -> None:
    x = np.linspace(0.0, 1.0, 100)
    with pytest.raises(ProfileTypeError, match="complex"):
        Profile(x, np.sin(x) + 1j * np.cos(x))
    with pytest.raises(ProfileTypeError, match="complex"):
        Profile(x + 0j, np.sin(x))
    with pytest.raises(ProfileTypeError, match="not an array of real numbers"):
        Profile(x, ["a"] * 100)
    with pytest.raises(ProfileTypeError, match="metadata"):
        Profile(x, np.sin(x), metadata=5)  # type: ignore[arg-type]


@pytest.mark.parametrize("record", [[1.5], [True], [np.nan], 5, [[1, 2]], ["1"]], ids=repr)
def test_non_integer_record_contacts_are_refused(
    pair: tuple[Profile, Profile], record: object
) -> None:
    with pytest.raises(ParameterError, match="record_contacts"):
        simulate(*pair, steps=10, record_contacts=record)  # type: ignore[arg-type]


def test_integral_record_contacts_still_work(pair: tuple[Profile, Profile]) -> None:
    result = simulate(*pair, steps=10, record_contacts=np.array([10, 3]))
    assert [c.step for c in result.contacts] == [3, 10]
    assert [c.step for c in simulate(*pair, steps=10, record_contacts=[2.0]).contacts] == [2]


# --- the whole accepted range is computed without overflow ---------------------------------------


@pytest.mark.parametrize("scale", [1e-26, 1e-12, 1e12, 1e45])
def test_scaling_every_length_scales_the_curves(
    pair: tuple[Profile, Profile], scale: float
) -> None:
    """Geometric similarity: x, z and x0 times s give F_N and A_S times s, the same counts.

    λ = (dx/x0)^α/10 · x0³ scales as s³, so the spline in grid units is unchanged; forces per
    unit thickness scale like lengths. Holds across the whole accepted range of lengths.
    """
    lower, upper = pair
    reference = simulate(lower, upper, steps=20)
    scaled = simulate(
        Profile(lower.x * scale, lower.z * scale),
        Profile(upper.x * scale, upper.z * scale),
        steps=20,
        x0=scale,
    )
    np.testing.assert_array_equal(scaled.n_contacts, reference.n_contacts)
    for name in ("normal_force", "tangential_force", "contact_area", "displacement"):
        want = reference.curves[name]
        np.testing.assert_allclose(
            scaled.curves[name] / scale, want, rtol=1e-9, atol=1e-9 * np.abs(want).max()
        )


def test_every_refusal_here_is_a_splinecontact_error() -> None:
    assert issubclass(ParameterError, SplineContactError)
    assert issubclass(ProfileRangeError, SplineContactError)
    assert issubclass(ProfileTypeError, SplineContactError)


# --- property: any numbers give a valid result or a ParameterError, nothing else ---------------

ANY_FLOAT = st.floats(allow_nan=True, allow_infinity=True) | st.sampled_from(
    [1e-320, 1e-300, 1e-50, 1e-30, 1e-10, 1e10, 1e30, 1e50, 1e100, 1e300, 1.7e308]
)


def _mostly(valid: st.SearchStrategy[float]) -> st.SearchStrategy[float]:
    """Mostly values in a valid range, sometimes any float (NaN, inf, huge, tiny, negative)."""
    return st.one_of(valid, valid, valid, ANY_FLOAT)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    dimension=_mostly(st.floats(1.0, 2.0)),
    length=_mostly(st.floats(1e-3, 1e4)),
    wavelength=_mostly(st.floats(1e-3, 1e4)),
    gamma=_mostly(st.floats(1.01, 10.0)),
    ra=_mostly(st.floats(1e-6, 1e3)),
    n_points=st.integers(5, 300) | st.integers(5, 300) | st.integers(-3, 4),
    directions=st.integers(1, 30) | st.integers(1, 30) | st.integers(-2, 0),
    n_max=st.integers(0, 40) | st.integers(0, 40) | st.integers(-2, 3000),
)
def test_generator_gives_a_valid_profile_or_a_parameter_error(
    dimension: float,
    length: float,
    wavelength: float,
    gamma: float,
    ra: float,
    n_points: int,
    directions: int,
    n_max: int,
) -> None:
    try:
        profile = wm(
            dimension,
            n_points=n_points,
            length=length,
            wavelength=wavelength,
            gamma=gamma,
            ra=ra,
            directions=directions,
            n_max=n_max,
            seed=3,
        )
    except ParameterError:
        event("refused")
        return
    event("generated")
    assert np.isfinite(profile.z).all()
    assert profile.ra == pytest.approx(ra, rel=1e-6)


@settings(max_examples=100, deadline=None)
@example(  # every term far longer than the profile: the residual mean is not negligible
    dimension=1.0, length=0.01, wavelength=387.0, gamma=3.5, ra=1.0, n_points=27,
    directions=4, n_max=6, seed=0,
)  # fmt: skip
@given(
    dimension=st.floats(1.0, 2.0),
    length=st.floats(1e-2, 1e3),
    wavelength=st.floats(1e-2, 1e3),
    gamma=st.floats(1.05, 5.0),
    ra=st.floats(1e-6, 1e3),
    n_points=st.integers(5, 300),
    directions=st.integers(1, 30),
    n_max=st.integers(0, 40),
    seed=st.integers(0, 2**64),
)
def test_generator_in_range_gives_profiles_with_the_target_ra(
    dimension: float,
    length: float,
    wavelength: float,
    gamma: float,
    ra: float,
    n_points: int,
    directions: int,
    n_max: int,
    seed: int,
) -> None:
    kwargs = {"n_points": n_points, "length": length, "wavelength": wavelength, "gamma": gamma}
    kwargs |= {"ra": ra, "directions": directions, "n_max": n_max, "seed": seed}
    try:
        profile = wm(dimension, **kwargs)  # type: ignore[arg-type]
    except ParameterError as exc:
        # In range, only a grid too coarse for every term, or terms all far longer than the
        # profile, may be refused.
        assert "Nyquist" in str(exc) or "rounding error" in str(exc)
        event("refused (Nyquist or rounding)")
        return
    event("generated")
    assert np.isfinite(profile.z).all()
    assert profile.ra == pytest.approx(ra, rel=1e-9)
    assert abs(profile.z.mean()) <= 1e-9 * ra


# the sample scans and random parameters can legitimately trigger simulate()'s diagnostics
@pytest.mark.filterwarnings("ignore::splinecontact.diagnostics.SimulationWarning")
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    e_star=_mostly(st.floats(1e-3, 1e3)),
    g_star=_mostly(st.floats(0.0, 1e3)),
    mu0=_mostly(st.floats(0.0, 10.0)),
    alpha=_mostly(st.floats(0.5, 3.0)),
    x0=_mostly(st.floats(1e-2, 1e2)),
    final=st.none() | _mostly(st.floats(1e-4, 1e-1)),
)
def test_simulate_gives_finite_curves_or_a_parameter_error(
    small_pair: tuple[Profile, Profile],
    e_star: float,
    g_star: float,
    mu0: float,
    alpha: float,
    x0: float,
    final: float | None,
) -> None:
    try:
        result = simulate(
            *small_pair,
            steps=5,
            e_star=e_star,
            g_star=g_star,
            mu0=mu0,
            alpha=alpha,
            x0=x0,
            final_displacement=final,
        )
    except ParameterError:
        event("refused")
        return
    event("simulated")
    for name, values in result.curves.items():
        assert np.isfinite(values).all(), name


@pytest.fixture(scope="module")
def small_pair() -> tuple[Profile, Profile]:
    return weierstrass_mandelbrot_pair(1.5, seed=12, n_points=200, length=0.1)


def test_spline_resolution_near_alpha_three_does_not_overflow() -> None:
    """Found by hypothesis on the dependency floors: α just below 3 made the x0 that would
    reach the curvature limit overflow (OverflowError from simulate's diagnostics)."""
    from splinecontact.preprocess import spline_resolution

    resolution = spline_resolution(0.0005025, alpha=2.99609375, x0=1e-30)
    assert resolution.coarse and resolution.x0_for_limit is None
    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=3, n_points=200, length=0.1)
    with pytest.warns(SimulationWarning):
        result = simulate(lower, upper, alpha=2.99609375, x0=1e-30, mu0=1e-320, g_star=0.0)
    assert np.all(np.isfinite(result.normal_force))
