"""The fast loading loop against the plain reference implementation (issue 3: 1e−12 relative)."""

from __future__ import annotations

import numpy as np
import pytest

from splinecontact import Profile, simulate, weierstrass_mandelbrot_pair

from conftest import ANGSTROM, circle_cap
from reference_sad import reference_simulate

# Analytic geometries (single circles, cups, a rigid flat) are one curved form by construction:
# simulate()'s FormWarning/LargeContactWarning on them are true and irrelevant here; the
# diagnostics themselves are tested in tests/test_cli_measured.py.
pytestmark = pytest.mark.filterwarnings("ignore::splinecontact.diagnostics.SimulationWarning")


def _compare(fast, slow, rtol: float, first_step: int = 0) -> None:  # type: ignore[no-untyped-def]
    np.testing.assert_array_equal(fast.n_contacts[first_step:], slow["count"][first_step:])
    for name, key in (
        ("normal_force", "F_N"),
        ("tangential_force", "F_T"),
        ("contact_area", "A_S"),
    ):
        got = fast.curves[name][first_step:]
        want = slow[key][first_step:]
        # relative to the step's own sum of |forces| (F_T sums terms of both signs)
        scale = np.abs(slow["F_N"][first_step:]) + np.abs(want)
        assert np.all(np.abs(got - want) <= rtol * scale), name


@pytest.mark.parametrize(("dimension", "seed"), [(1.2, 0), (1.5, 1), (1.8, 2)])
@pytest.mark.parametrize("upper_kind", ["rough", "flat"])
def test_fast_path_equals_reference_on_fractal_pairs(
    dimension: float, seed: int, upper_kind: str
) -> None:
    lower, upper = weierstrass_mandelbrot_pair(
        dimension, seed=seed, n_points=1000, length=0.1, wavelength=0.02
    )
    counter = "flat" if upper_kind == "flat" else upper
    fast = simulate(lower, counter, steps=40)
    slow = reference_simulate(
        lower,
        counter,
        steps=40,
        final_displacement=fast.final_displacement,
        formulation="curvature",
    )
    assert fast.n_contacts.max() > 0
    _compare(fast, slow, rtol=1e-12)


def test_fast_path_equals_reference_on_circles() -> None:
    x = np.arange(-300, 301) * ANGSTROM
    lower = Profile(x, circle_cap(x, 0.7, 0.3 * ANGSTROM))
    upper = Profile(x, circle_cap(x, 0.4))
    fast = simulate(lower, upper, steps=30, final_displacement=2e-4)
    slow = reference_simulate(
        lower, upper, steps=30, final_displacement=2e-4, formulation="curvature"
    )
    _compare(fast, slow, rtol=1e-12)


@pytest.mark.parametrize(("dimension", "seed"), [(1.2, 0), (1.5, 1), (1.8, 2)])
@pytest.mark.parametrize("upper_kind", ["rough", "flat"])
def test_curvature_formulas_agree_with_radius_form_of_eqs_7_to_10(
    dimension: float, seed: int, upper_kind: str
) -> None:
    """Independent physics check: eqs. 7–10 written with radii, as in the paper.

    The radius form computes δ = R^u + R^l − |X| by cancellation: its rounding error is about
    ε·R/δ. With R ≤ 1/κ_min and δ ≥ 1e−4·δ_N(final) from step 1 on, ε·R/δ ≤ 1e−7 here, so the
    tolerance is 1e−7; step 0 (δ → 0) is excluded because there the radius form has no digits.
    """
    lower, upper = weierstrass_mandelbrot_pair(
        dimension, seed=seed, n_points=1000, length=0.1, wavelength=0.02
    )
    counter = "flat" if upper_kind == "flat" else upper
    fast = simulate(lower, counter, steps=40)
    slow = reference_simulate(lower, counter, steps=40, final_displacement=fast.final_displacement)
    _compare(fast, slow, rtol=1e-7, first_step=1)
