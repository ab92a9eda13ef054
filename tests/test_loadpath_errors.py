"""Every malformed load path gets its own error, naming the value; path results' schema."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from splinecontact import (
    ParameterError,
    Profile,
    Segment,
    SplineContactError,
    simulate,
    weierstrass_mandelbrot_pair,
)
from splinecontact.analysis import FrictionAnalysisError, dilatancy, static_friction
from splinecontact.contact import ForceControlError, LoadPathError
from splinecontact.results import PATH_STEP_VARIABLES, STEP_VARIABLES

from conftest import ANGSTROM, circle_cap, circle_cup


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"normal": 1e-3, "normal_force": 1.0, "steps": 3}, "at most one of normal"),
        ({"normal": 1e-3, "steps": 0}, "steps = 0 must be an integer ≥ 1"),
        ({"normal": 1e-3, "steps": 2.5}, "steps = 2.5"),
        ({"normal": 1e-3, "steps": True}, "steps = True"),
        ({"normal": float("nan"), "steps": 3}, "normal = nan µm must be finite"),
        ({"normal": "1", "steps": 3}, "normal = '1' must be a number µm"),
        ({"tangential": float("inf"), "steps": 3}, "tangential = inf µm must be finite"),
        ({"normal_force": 0.0, "steps": 3}, "normal_force = 0.0 mN/µm must be > 0"),
        ({"normal_force": -2.0, "steps": 3}, "normal_force = -2.0 mN/µm must be > 0"),
    ],
)
def test_bad_segments_are_refused(kwargs: dict, match: str) -> None:  # type: ignore[type-arg]
    with pytest.raises(LoadPathError, match=match) as info:
        Segment(**kwargs)
    assert isinstance(info.value, ParameterError)
    assert isinstance(info.value, SplineContactError)


def _circle() -> Profile:
    x = np.arange(-200, 201) * ANGSTROM
    return Profile(x, circle_cap(x, 1.0))


@pytest.mark.parametrize(
    ("path", "match"),
    [
        ([], "path is empty"),
        (Segment(normal=1e-3, steps=2), "give a sequence of Segment"),
        ([Segment(normal=1e-3, steps=2), (1e-3, 0.0, 5)], r"path\[1\] = \(0.001, 0.0, 5\) is not"),
        (42, "path = 42 is not a sequence"),
    ],
)
def test_bad_paths_are_refused(path: object, match: str) -> None:
    with pytest.raises(LoadPathError, match=match):
        simulate(_circle(), "flat", path=path)  # type: ignore[arg-type]


def test_path_and_final_displacement_conflict() -> None:
    with pytest.raises(LoadPathError, match=r"final_displacement = 0\.001 µm and path"):
        simulate(_circle(), "flat", final_displacement=1e-3, path=[Segment(normal=1e-3, steps=2)])


def test_path_and_steps_conflict() -> None:
    with pytest.raises(LoadPathError, match="steps = 50 and path were both given"):
        simulate(_circle(), "flat", steps=50, path=[Segment(normal=1e-3, steps=2)])


def test_unreachable_force_is_refused() -> None:
    """Two cups never make a contact (Table 1): no δ_N carries a force."""
    x = np.arange(-200, 201) * ANGSTROM
    cup = Profile(x, circle_cup(x, 1.0))
    with pytest.raises(ForceControlError, match=r"normal_force = 1\.0 mN/µm cannot be reached"):
        simulate(cup, cup, path=[Segment(normal_force=1.0, steps=2)])


# the sample scans and random parameters can legitimately trigger simulate()'s diagnostics
@pytest.mark.filterwarnings("ignore::splinecontact.diagnostics.SimulationWarning")
def test_friction_analysis_needs_a_path_and_a_tangential_segment() -> None:
    plain = simulate(_circle(), "flat", steps=4, final_displacement=1e-4)
    with pytest.raises(FrictionAnalysisError, match="no load path"):
        static_friction(plain)
    normal_only = simulate(_circle(), "flat", path=[Segment(normal=1e-4, steps=4)])
    with pytest.raises(FrictionAnalysisError, match="no segment that moves"):
        static_friction(normal_only)
    with pytest.raises(FrictionAnalysisError, match="displacement-controlled"):
        dilatancy(normal_only, 0)


# the sample scans and random parameters can legitimately trigger simulate()'s diagnostics
@pytest.mark.filterwarnings("ignore::splinecontact.diagnostics.SimulationWarning")
def test_path_dataset_has_units_and_the_path(tmp_path: Path) -> None:
    lower, upper = weierstrass_mandelbrot_pair(1.5, seed=4, n_points=5_000, length=0.5)
    d = 0.1 * lower.peak_to_valley
    path = [Segment(normal=d, steps=10), Segment(tangential=0.005, steps=10)]
    result = simulate(lower, upper, path=path, record_contacts=[5, 20])
    ds = result.to_xarray()
    assert ds.sizes["step"] == 21
    for name in (*STEP_VARIABLES, *PATH_STEP_VARIABLES):
        assert name in ds, name
        assert ds[name].dims == ("step",)
    for name, variable in ds.variables.items():
        assert "units" in variable.attrs, name
    assert ds["tangential_displacement"].attrs["units"] == "µm"
    assert float(ds["tangential_displacement"][-1]) == 0.005
    assert "contact_slipping" in ds
    stored = json.loads(ds.attrs["path"])
    assert stored[1] == {"normal": None, "normal_force": None, "tangential": 0.005, "steps": 10}
    out = result.to_netcdf(tmp_path / "p.nc")
    with xr.open_dataset(out) as back:
        np.testing.assert_array_equal(back["dissipated_work"].values, result.dissipated_work)
    plain = simulate(lower, upper, steps=10, final_displacement=d).to_xarray()
    assert "tangential_displacement" in plain and "n_slipping" not in plain
