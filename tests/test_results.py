"""Result schema: every variable has units; netCDF round trip (issue 2, item 7)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from splinecontact import simulate, weierstrass_mandelbrot_pair
from splinecontact.errors import GridMismatchError, ParameterError
from splinecontact.results import SCALAR_VARIABLES, STEP_VARIABLES


@pytest.fixture(scope="module")
def pair():  # type: ignore[no-untyped-def]
    return weierstrass_mandelbrot_pair(1.5, seed=4, n_points=20_000, length=2.0)


def test_dataset_has_units_everywhere_and_parameters(pair, tmp_path: Path) -> None:  # type: ignore[no-untyped-def]
    lower, upper = pair
    result = simulate(lower, upper, steps=30, record_contacts=[10, 30])
    ds = result.to_xarray()
    assert ds.sizes["step"] == 31
    for name in (*STEP_VARIABLES, *SCALAR_VARIABLES):
        assert name in ds
    for name, variable in ds.variables.items():
        assert "units" in variable.attrs, name
    for key in ("e_star", "g_star", "mu0", "alpha", "x0", "steps", "contact_type"):
        assert key in ds.attrs
    assert set(np.unique(ds["contact_step"].values)) <= {10, 30}
    path = result.to_netcdf(tmp_path / "r.nc")
    back = xr.open_dataset(path)
    np.testing.assert_array_equal(back["normal_force"].values, result.normal_force)
    assert back["normal_force"].attrs["units"] == "mN/µm"
    back.close()


def test_recorded_contacts_match_counts(pair) -> None:  # type: ignore[no-untyped-def]
    lower, upper = pair
    result = simulate(lower, upper, steps=20, record_contacts="all")
    assert len(result.contacts) == 21
    for record in result.contacts:
        assert record.point.size == result.n_contacts[record.step]


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"steps": 0}, "steps"),
        ({"steps": 2.5}, "steps"),
        ({"e_star": 0.0}, "e_star"),
        ({"e_star": -10.0}, "e_star"),
        ({"g_star": -1.0}, "g_star"),
        ({"mu0": -0.1}, "mu0"),
        ({"alpha": 0.0}, "alpha"),
        ({"alpha": -2.0}, "alpha"),
        ({"x0": 0.0}, "x0"),
        ({"final_displacement": -1e-3}, "final_displacement"),
        ({"final_displacement_factor": 0.0}, "final_displacement_factor"),
        ({"record_contacts": [5000]}, "record_contacts"),
        ({"record_contacts": "some"}, "record_contacts"),
    ],
)
def test_bad_simulation_parameters(pair, kwargs: dict, fragment: str) -> None:  # type: ignore[no-untyped-def]
    lower, upper = pair
    with pytest.raises(ParameterError, match=fragment):
        simulate(lower, upper, **{"steps": 10, **kwargs})


def test_grid_mismatch_and_bad_upper(pair) -> None:  # type: ignore[no-untyped-def]
    lower, _ = pair
    other, _ = weierstrass_mandelbrot_pair(1.5, seed=4, n_points=10_000, length=2.0)
    with pytest.raises(GridMismatchError, match="points"):
        simulate(lower, other, steps=5)
    stretched, _ = weierstrass_mandelbrot_pair(1.5, seed=4, n_points=20_000, length=3.0)
    with pytest.raises(GridMismatchError, match="spacings differ"):
        simulate(lower, stretched, steps=5)
    with pytest.raises(ParameterError, match="flat"):
        simulate(lower, "plane", steps=5)  # type: ignore[arg-type]
