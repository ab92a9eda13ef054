"""The one registry of output variables drives every written dataset and table."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from splinecontact import Profile, SimulationResult, bem, schema, simulate
from splinecontact.compare import COLUMNS, compare_profiles
from splinecontact.errors import ResultSchemaError
from splinecontact.results import (
    CONTACT_VARIABLES,
    INTERACTION_STEP_VARIABLES,
    PATH_STEP_VARIABLES,
    SCALAR_VARIABLES,
    STEP_VARIABLES,
)


def test_every_variable_has_units_long_name_dims_and_dtype() -> None:
    assert len(schema.VARIABLES) == sum(
        1 for t in schema.TABLES for v in schema.VARIABLES.values() if v.table == t
    )
    for name, variable in schema.VARIABLES.items():
        assert variable.name == name
        assert variable.units and variable.long_name, name
        assert variable.dtype in {"float64", "int64", "int8"}, name
        attrs = schema.attrs(name)
        assert {k: attrs[k] for k in ("units", "long_name")} == {
            "units": variable.units,
            "long_name": variable.long_name,
        }
        if variable.flags:  # a coded variable: CF flag_values 0, 1, … and one word per code
            assert set(attrs) == {"units", "long_name", "flag_values", "flag_meanings"}, name
            assert attrs["flag_values"].dtype == np.dtype(variable.dtype)
            assert attrs["flag_values"].tolist() == list(range(len(variable.flags)))
            assert attrs["flag_meanings"].split() == list(variable.flags)
        else:
            assert set(attrs) == {"units", "long_name"}, name
        assert schema.units(name) == variable.units
        assert variable.dims == {"scalar": ()}.get(variable.table, variable.dims)
    assert schema.VARIABLES["normal_force"].dims == ("step",)
    assert schema.VARIABLES["rsq_gap"].dims == ()
    assert schema.VARIABLES["contact_x"].dims == ("contact",)
    assert schema.VARIABLES["mean_pressure"].dims == ("load",)
    with pytest.raises(KeyError):
        schema.attrs("normal_forse")
    with pytest.raises(KeyError, match="unknown output table"):
        schema.table("nonsense")  # type: ignore[arg-type]


def test_legacy_tables_are_views_of_the_registry() -> None:
    for legacy, table in (
        (STEP_VARIABLES, "step"),
        (PATH_STEP_VARIABLES, "path_step"),
        (SCALAR_VARIABLES, "scalar"),
        (CONTACT_VARIABLES, "contact"),
        (COLUMNS, "comparison"),
    ):
        assert legacy == {
            n: (v.units, v.long_name)
            for n, v in schema.table(table).items()  # type: ignore[arg-type]
        }
    assert bem.STEP_UNITS == {n: v.units for n, v in schema.table("bem_step").items()}
    assert next(iter(COLUMNS)) == "force"


def test_result_fields_are_declared_for_every_schema_variable() -> None:
    declared = {f.name for f in dataclasses.fields(SimulationResult) if not f.init}
    assert declared == {
        *STEP_VARIABLES,
        *PATH_STEP_VARIABLES,
        *INTERACTION_STEP_VARIABLES,
        *SCALAR_VARIABLES,
    }


def _small_result(**kwargs):  # type: ignore[no-untyped-def]
    n, dx, radius = 256, 0.01, 20.0
    x = np.arange(n) * dx
    s = x - x[n // 2]
    z = -(s * s) / (radius + np.sqrt(radius * radius - s * s))
    return simulate(
        Profile(x, z), "flat", steps=5, final_displacement=1e-3, diagnostics=False, **kwargs
    )


def test_result_attributes_are_real_and_typos_fail() -> None:
    result = _small_result()
    assert "normal_force" in dir(result) and "rsq_gap" in dir(result)
    assert result.normal_force is result.curves["normal_force"]
    assert result.rsq_gap == result.scalars["rsq_gap"]
    assert result.tangential_displacement is not None
    assert result.n_slipping is None  # a plain normal loading has no load-path variables
    with pytest.raises(AttributeError):
        _ = result.normal_forse  # type: ignore[attr-defined]
    with pytest.raises(dataclasses.FrozenInstanceError):
        result.normal_force = np.zeros(3)  # type: ignore[misc]


def test_result_without_a_required_variable_is_refused() -> None:
    result = _small_result()
    curves = {k: v for k, v in result.curves.items() if k != "contact_area"}
    with pytest.raises(ResultSchemaError, match="contact_area"):
        SimulationResult(curves=curves, scalars=result.scalars, parameters=result.parameters)


def _check_units(ds, table: str) -> None:  # type: ignore[no-untyped-def]
    for name, variable in schema.table(table).items():  # type: ignore[arg-type]
        assert ds[name].attrs == variable.attrs(), name
        assert ds[name].dtype == np.dtype(variable.dtype), name
        assert ds[name].dims == variable.dims, name


def test_bem_path_to_xarray_has_units_on_every_variable() -> None:
    rng = np.random.default_rng(3)
    z = np.fft.irfft(np.r_[0, rng.normal(size=32) + 1j * rng.normal(size=32)], 128) * 0.1
    problem = bem.contact_problem(z, e_star=10.0, dx=0.05)
    loads = np.array([0.05, 0.1, 0.2]) * problem.full_contact_pressure
    path = bem.load_path(problem, loads)
    ds = path.to_xarray()
    assert ds.sizes["load"] == 3
    _check_units(ds, "bem_step")
    for name in bem.STEP_UNITS:
        np.testing.assert_array_equal(ds[name].values, path.column(name))
    assert ds.attrs["e_star_GPa"] == 10.0 and ds.attrs["n_points"] == 128
    for variable in ds.variables.values():
        assert "units" in variable.attrs


# A single circular asperity is "all form" by design.
@pytest.mark.filterwarnings("ignore::splinecontact.diagnostics.FormWarning")
def test_comparison_to_xarray_has_units_on_every_variable() -> None:
    n, dx, radius = 512, 0.01, 50.0
    x = np.arange(n) * dx
    s = x - x[n // 2]
    z = -(s * s) / (radius + np.sqrt(radius * radius - s * s))
    comparison = compare_profiles(
        Profile(x, z), "flat", steps=20, final_displacement=2e-3, n_forces=3
    )
    ds = comparison.to_xarray()
    _check_units(ds, "comparison")
    for name in COLUMNS:
        np.testing.assert_array_equal(ds[name].values, comparison.columns[name])
    assert ds.attrs["n_points"] == n
    for variable in ds.variables.values():
        assert "units" in variable.attrs
