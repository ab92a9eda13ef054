"""κ under adhesion, and pull-off / work of separation / residual approach against D with
confidence bands (small ensembles: the heavy studies are in benchmarks/)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from splinecontact.analysis import LAWS_STUDY_VARIABLES, adhesive_kappa, laws_study
from splinecontact.analysis.ensemble import confidence_halfwidth
from splinecontact.contact import make_law
from splinecontact.errors import ParameterError
from splinecontact.plotting import plot_laws_study

SMALL = {"n_points": 2000, "steps": 20}


@settings(max_examples=30, deadline=None)
@given(
    slope=st.floats(0.1, 100.0),
    f0=st.floats(-1.0, 0.0),
    rsq=st.floats(0.01, 2.0),
    e_star=st.floats(1.0, 300.0),
)
def test_adhesive_kappa_recovers_a_shifted_line(
    slope: float, f0: float, rsq: float, e_star: float
) -> None:
    """A_S = s (F_N − F_0) exactly: κ = R_Sq E* s and F_0 are recovered, whatever F_0 ≤ 0."""
    force = np.linspace(f0 - 0.5, f0 + 2.0, 60)
    area = np.where(force > f0, slope * (force - f0), 0.0)
    k, zero = adhesive_kappa(force, area, rsq, e_star, fit_fraction=0.5)
    assert k == pytest.approx(rsq * e_star * slope, rel=1e-9)
    assert zero == pytest.approx(f0, abs=1e-9 * (1.0 + abs(f0)))


def test_adhesive_kappa_bad_input() -> None:
    with pytest.raises(ParameterError, match="fit_fraction"):
        adhesive_kappa([1.0, 2.0, 3.0], [1.0, 2.0, 3.0], 1.0, 1.0, fit_fraction=0.0)
    assert all(math.isnan(v) for v in adhesive_kappa([1.0, 2.0], [0.0, 1.0], 1.0, 1.0))


@pytest.fixture(scope="module")
def studies() -> dict[str, object]:
    laws = {
        "hertz": None,
        "jkr": make_law("jkr", work_of_adhesion=0.1),
        "elastic-plastic": make_law("elastic-plastic", hardness=2.0),
    }
    return {name: laws_study([1.3, 1.7], [0, 1, 2], law=law, **SMALL) for name, law in laws.items()}


def test_laws_study_hertz_has_no_adhesion_and_no_hysteresis(studies: dict) -> None:
    ds = studies["hertz"]
    assert set(LAWS_STUDY_VARIABLES) <= set(ds.data_vars)
    assert np.all(ds["pull_off_force"].values == 0.0)
    assert np.all(ds["work_of_separation"].values == 0.0)
    assert np.all(np.abs(ds["dissipated_energy"].values) <= 1e-12)
    assert np.all(np.isfinite(ds["kappa"].values)) and np.all(ds["kappa"].values > 0)


def test_laws_study_adhesion_and_plasticity(studies: dict) -> None:
    jkr = studies["jkr"]
    assert np.all(jkr["pull_off_force"].values > 0.0)
    assert np.all(jkr["work_of_separation"].values >= 0.0)
    assert np.all(jkr["dissipated_energy"].values >= -1e-12)
    # with adhesion A_S vanishes at a tensile load
    assert np.nanmean(jkr["zero_area_force"].values) < np.nanmean(
        studies["hertz"]["zero_area_force"].values
    )
    plastic = studies["elastic-plastic"]
    frac = plastic["residual_fraction"].values
    # a realization that barely yields has δ_r ≈ 0 (up to the extrapolation over one step)
    assert np.all((frac > -1e-3) & (frac <= 1.0))
    assert np.all(plastic["residual_fraction_mean"].values > 0.0)
    energy = plastic["dissipated_energy"].values
    assert np.all(energy >= -1e-12) and energy.sum() > 0.0


def test_laws_study_bands_are_student_t(studies: dict) -> None:
    ds = studies["jkr"]
    for name in ("pull_off_force", "work_of_separation", "kappa"):
        v = ds[name]
        expected = confidence_halfwidth(
            v.std("realization", ddof=1).values, v.count("realization").values, 0.95
        )
        np.testing.assert_allclose(ds[f"{name}_ci"].values, expected, rtol=1e-12)
        np.testing.assert_allclose(ds[f"{name}_mean"].values, v.mean("realization").values)
        assert ds[f"{name}_ci"].attrs["units"] == LAWS_STUDY_VARIABLES[name]


def test_laws_study_one_seed_has_no_band() -> None:
    ds = laws_study([1.5], [0], **SMALL)
    assert np.isnan(ds["kappa_ci"].values).all()


def test_laws_study_bad_input() -> None:
    with pytest.raises(ParameterError):
        laws_study([], [0])
    with pytest.raises(ParameterError):
        laws_study([1.5], [0], steps=2)


def test_plot_laws_study(studies: dict) -> None:
    ax = plot_laws_study(studies, "pull_off_force")
    assert "mN/µm" in ax.get_ylabel() and "D" in ax.get_xlabel()
    assert len(ax.get_lines()) == len(studies)
    with pytest.raises(ParameterError, match="not a laws_study variable"):
        plot_laws_study(studies, "nonsense")
