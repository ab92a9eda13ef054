"""The public surface of the package: top-level names, ``dir()``, reprs, wrong argument types."""

from __future__ import annotations

import math

import numpy as np
import pytest

import splinecontact
from splinecontact import (
    ParameterError,
    Profile,
    SplineContactError,
    fit_spline,
    simulate,
    surface_spheres,
    weierstrass_mandelbrot,
    weierstrass_mandelbrot_pair,
)

#: What ``dir(splinecontact)`` may show besides ``__all__``: the documented modules only.
DOCUMENTED_MODULES = {
    "analysis",
    "bem",
    "compare",
    "contact",
    "diagnostics",
    "generate",
    "io",
    "outputs",
    "parameters",
    "plotting",
    "preprocess",
    "reference",
    "reproduce",
    "results",
    "schema",
    "spectra",
    "study",
}


@pytest.fixture(scope="module")
def pair() -> tuple[Profile, Profile]:
    # wavelength 0.1 µm on a 1 µm profile: roughness, not one curved form (no FormWarning)
    return weierstrass_mandelbrot_pair(1.5, seed=7, n_points=2000, length=1.0, wavelength=0.1)


def test_read_profile_and_compare_profiles_at_the_top_level() -> None:
    import splinecontact.compare
    import splinecontact.io

    assert splinecontact.read_profile is splinecontact.io.read_profile
    assert splinecontact.compare_profiles is splinecontact.compare.compare_profiles
    assert {"read_profile", "compare_profiles"} <= set(splinecontact.__all__)


def test_dir_shows_the_public_names_and_documented_modules_only() -> None:
    import splinecontact.study

    names = set(dir(splinecontact))
    assert names - set(splinecontact.__all__) == DOCUMENTED_MODULES
    assert set(splinecontact.__all__) <= names
    for stray in ("annotations", "version", "PackageNotFoundError", "loadpath", "spline"):
        assert stray not in names


@pytest.mark.parametrize("name", sorted(DOCUMENTED_MODULES))
def test_every_name_in_dir_resolves(name: str) -> None:
    module = getattr(splinecontact, name)
    assert module.__name__ == f"splinecontact.{name}"


def test_unknown_attribute_is_an_attribute_error() -> None:
    with pytest.raises(AttributeError, match="no attribute 'nothing'"):
        splinecontact.nothing  # noqa: B018
    assert not hasattr(splinecontact, "version")


def test_every_exported_error_is_a_splinecontact_error() -> None:
    for name in splinecontact.errors.__all__:
        assert issubclass(getattr(splinecontact, name), SplineContactError)


def test_reprs_are_short_and_informative(pair: tuple[Profile, Profile]) -> None:
    lower, upper = pair
    result = simulate(lower, upper, steps=20, record_contacts="last")
    text = repr(result)
    assert text.startswith("SimulationResult(rough-on-rough, steps=20, n_points=2000")
    assert "normal_force[-1]=" in text and "mN/µm" in text
    assert "recorded_steps=1" in text
    fit = fit_spline(lower)
    for obj in (result, result.contacts[0], fit, surface_spheres(fit), lower):
        assert len(repr(obj)) < 250
        assert "array(" not in repr(obj)
        assert "\n" not in repr(obj)


BAD_VALUES = [None, "1", True, 1 + 0j, math.nan, math.inf, -math.inf, [1.0]]


@pytest.mark.parametrize(
    "keyword",
    ["steps", "final_displacement", "final_displacement_factor", "e_star", "g_star", "mu0",
     "alpha", "x0", "max_steps"],
)  # fmt: skip
@pytest.mark.parametrize("value", BAD_VALUES, ids=repr)
def test_simulate_refuses_every_wrong_type_with_a_parameter_error(
    pair: tuple[Profile, Profile], keyword: str, value: object
) -> None:
    lower, upper = pair
    if value is None and keyword in ("final_displacement", "g_star"):
        return  # None means "use the default" for these two
    with pytest.raises(ParameterError, match=keyword.replace("_star", "")):
        simulate(lower, upper, **{"steps": 10, keyword: value})  # type: ignore[arg-type]


@pytest.mark.parametrize("body", [None, "Flat", "flat ", 3, np.zeros(10), [0.0, 1.0]], ids=repr)
def test_simulate_refuses_bodies_that_are_not_profiles(
    pair: tuple[Profile, Profile], body: object
) -> None:
    lower, _ = pair
    with pytest.raises(ParameterError, match="upper"):
        simulate(lower, body, steps=5)  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="lower"):
        simulate(body, "flat", steps=5)  # type: ignore[arg-type]


def test_flat_spelled_otherwise_gets_a_hint(pair: tuple[Profile, Profile]) -> None:
    with pytest.raises(ParameterError, match="did you mean 'flat'"):
        simulate(pair[0], "Flat", steps=5)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    "keyword",
    ["n_points", "length", "wavelength", "gamma", "directions", "n_max", "ra", "max_points",
     "max_work"],
)  # fmt: skip
@pytest.mark.parametrize("value", BAD_VALUES, ids=repr)
def test_generator_refuses_every_wrong_type_with_a_parameter_error(
    keyword: str, value: object
) -> None:
    with pytest.raises(ParameterError):
        weierstrass_mandelbrot(1.5, **{"n_points": 1000, keyword: value})  # type: ignore[arg-type]


@pytest.mark.parametrize("value", BAD_VALUES, ids=repr)
def test_generator_refuses_a_wrong_dimension(value: object) -> None:
    with pytest.raises(ParameterError, match="dimension"):
        weierstrass_mandelbrot(value, n_points=1000)  # type: ignore[arg-type]


def test_spline_and_spheres_refuse_wrong_inputs(pair: tuple[Profile, Profile]) -> None:
    with pytest.raises(ParameterError, match=r"not a splinecontact\.Profile"):
        fit_spline(np.zeros(10))  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="alpha"):
        fit_spline(pair[0], alpha="2")  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="not a SplineFit"):
        surface_spheres(pair[0])  # type: ignore[arg-type]
    with pytest.raises(ParameterError, match="r_min"):
        surface_spheres(fit_spline(pair[0]), r_min="1")  # type: ignore[arg-type]


def test_diagnostics_can_be_switched_off(pair: tuple[Profile, Profile]) -> None:
    """simulate(diagnostics=False) skips the checks (ensembles use it) and changes nothing else."""
    import warnings

    from splinecontact.diagnostics import SimulationWarning

    lower, upper = pair
    tilted = Profile(lower.x, lower.z + 0.5 * lower.x)  # a tilt dominates: a FormWarning
    with pytest.warns(SimulationWarning):
        warned = simulate(tilted, upper, steps=10)
    with warnings.catch_warnings():
        warnings.simplefilter("error", SimulationWarning)
        quiet = simulate(tilted, upper, steps=10, diagnostics=False)
    for name, curve in warned.curves.items():
        np.testing.assert_array_equal(curve, quiet.curves[name])
