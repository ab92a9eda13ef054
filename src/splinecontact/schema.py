"""The single registry of output variables: name, units, long name, dimensions and dtype.

Every array the package writes out (``SimulationResult.to_xarray``, the study store, the exact
reference's :class:`~splinecontact.bem.BEMPath`, the SAD-vs-exact
:class:`~splinecontact.compare.Comparison`, CSV headers) takes its ``units`` and ``long_name``
from here, so a variable has one definition wherever it appears.

Units follow the package convention: lengths µm, moduli GPa, forces mN per µm of out-of-plane
thickness; ``"1"`` marks a dimensionless quantity or a count.

Each variable belongs to one *table* (the object whose rows it describes):

``step``
    per-step curves of every :func:`splinecontact.simulate` run, dimension ``step``;
``path_step``
    per-step curves present only in some runs (``tangential_displacement`` in every run of this
    version, the rest on load paths), dimension ``step``;
``interaction_step``
    per-step curves of ``simulate(..., interaction=True)`` only, dimension ``step``;
``scalar``
    per-simulation scalars (surface statistics, final displacement), no dimension;
``contact``
    the recorded accepted contacts, flattened over the recorded steps, dimension ``contact``;
``bem_step``
    one solution of the exact reference per requested load, dimension ``load``;
``comparison``
    SAD and the exact reference at matched forces, dimension ``load``.

A study store puts the grid dimensions and ``realization`` before a variable's own ``dims``.

Examples
--------
>>> from splinecontact import schema
>>> schema.attrs("normal_force")["units"]
'mN/µm'
>>> schema.VARIABLES["n_contacts"].dims
('step',)
>>> sorted(schema.table("bem_step"))[:3]
['approach', 'contact_length', 'contact_length_subgrid']
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Literal

if TYPE_CHECKING:  # xarray is imported when a variable is made, not with the package
    import xarray as xr

__all__ = [
    "COORDINATES",
    "TABLES",
    "VARIABLES",
    "Table",
    "Variable",
    "attrs",
    "coordinate",
    "legacy_table",
    "table",
    "units",
    "xr_variable",
]

Table = Literal[
    "step", "path_step", "interaction_step", "scalar", "contact", "bem_step", "comparison"
]

#: The tables in the order their variables are listed.
TABLES: tuple[Table, ...] = (
    "step",
    "path_step",
    "interaction_step",
    "scalar",
    "contact",
    "bem_step",
    "comparison",
)

_DIMS: dict[str, tuple[str, ...]] = {
    "step": ("step",),
    "path_step": ("step",),
    "interaction_step": ("step",),
    "scalar": (),
    "contact": ("contact",),
    "bem_step": ("load",),
    "comparison": ("load",),
}


@dataclass(frozen=True)
class Variable:
    """One output variable.

    Attributes
    ----------
    name : str
        Variable name (unique over every table).
    units : str
        Units (``"1"`` for dimensionless quantities and counts).
    long_name : str
        What the variable is, with the paper's equation where there is one.
    table : str
        The table it belongs to (see the module docstring).
    dtype : str
        numpy dtype of the written array (``"float64"``, ``"int64"`` or ``"int8"``).
    flags : tuple of str
        For a coded variable, the meaning of the codes 0, 1, … in order (CF ``flag_values``
        and ``flag_meanings``, one word each); empty otherwise.
    """

    name: str
    units: str
    long_name: str
    table: Table
    dtype: str = "float64"
    flags: tuple[str, ...] = ()

    @property
    def dims(self) -> tuple[str, ...]:
        """Dimensions of the variable in its own object (a study store prepends its own)."""
        return _DIMS[self.table]

    def attrs(self) -> dict[str, Any]:
        """``{"units": ..., "long_name": ...}``, the attributes of a written variable, and for a
        coded variable ``flag_values`` (int8 array 0, 1, …) and ``flag_meanings`` (CF)."""
        out: dict[str, Any] = {"units": self.units, "long_name": self.long_name}
        if self.flags:
            import numpy as np

            out["flag_values"] = np.arange(len(self.flags), dtype=np.int8)
            out["flag_meanings"] = " ".join(self.flags)
        return out


_F, _I, _B = "float64", "int64", "int8"

# name, units, long_name, dtype; one list per table.
_ROWS: dict[Table, list[tuple[str, str, str, str]]] = {
    "step": [
        ("displacement", "µm", "normal displacement δ_N of the upper body from first contact", _F),
        ("normal_force", "mN/µm", "global normal force F_N on the upper body (eq. 14)", _F),
        ("tangential_force", "mN/µm", "global tangential force F_T on the upper body (eq. 14)", _F),
        (
            "contact_area",
            "µm",
            "contact area A_S = Σ √(δ_i R_eff,i) per unit thickness (eq. 10)",
            _F,
        ),
        ("n_contacts", "1", "number of accepted contacts", _I),
        ("mean_separation", "µm", "distance between the mean lines of the smoothed surfaces", _F),
        ("normal_force_normal_part", "mN/µm", "part of F_N from the local normal forces F^n", _F),
        (
            "normal_force_tangential_part",
            "mN/µm",
            "part of F_N from the local tangential forces F^t",
            _F,
        ),
        (
            "n_tilted_contacts",
            "1",
            "accepted contacts whose repulsive direction points below horizontal (e_z < 0)",
            _I,
        ),
        ("n_candidates", "1", "points whose gap has closed (detection, z^u ≤ z^l)", _I),
    ],
    "path_step": [
        (
            "tangential_displacement",
            "µm",
            "tangential displacement u_T of the upper body along +x (0 for a normal loading)",
            _F,
        ),
        (
            "n_slipping",
            "1",
            "accepted contacts whose tangential force is capped at μ0|F^n| (slip)",
            _I,
        ),
        (
            "dissipated_work",
            "mN·µm/µm",
            "frictional work dissipated since step 0, Σ slip × capped force (nJ per µm thickness)",
            _F,
        ),
        (
            "normal_force_target",
            "mN/µm",
            "F_N held by a force-controlled segment (NaN on displacement-controlled steps)",
            _F,
        ),
        (
            "force_control",
            "1",
            "how the step met F_N: 0 displacement-controlled; 1 F_N held, the contacts eq. 9 "
            "accepts at that δ_N; 2 F_N held with a contact set eq. 9 would not accept as a "
            "whole there (target inside a jump); 3 target inside a jump, nearer side kept, "
            "F_N ≠ target",
            _B,
        ),
    ],
    "interaction_step": [
        (
            "coalesced_contact_length",
            "µm",
            "interacting contacts: length of the union of the contact intervals",
            _F,
        ),
        (
            "n_contact_patches",
            "1",
            "interacting contacts: connected pieces of the union of the contact intervals",
            _I,
        ),
        ("interaction_iterations", "1", "interacting contacts: conjugate-gradient iterations", _I),
        (
            "reach_exceeded",
            "1",
            "interacting contacts: 1 where summits beyond the candidate set could touch",
            _I,
        ),
    ],
    "scalar": [
        ("final_displacement", "µm", "displacement at the last step", _F),
        ("ra_lower", "µm", "R_A of the lower profile heights", _F),
        ("ra_upper", "µm", "R_A of the upper profile heights (0 for a rigid flat)", _F),
        ("rq_lower", "µm", "R_q of the lower profile heights", _F),
        ("rq_upper", "µm", "R_q of the upper profile heights", _F),
        ("peak_to_valley_lower", "µm", "peak-to-valley height of the lower profile", _F),
        ("rsq_lower", "1", "rms slope of the lower heights, grid differences (eq. 15)", _F),
        ("rsq_upper", "1", "rms slope of the upper heights, grid differences (eq. 15)", _F),
        ("rsq_gap", "1", "rms slope of the gap z^u − z^l, grid differences (eq. 15)", _F),
        ("rsq_lower_spline", "1", "rms slope of the lower spline f′", _F),
        ("rsq_upper_spline", "1", "rms slope of the upper spline f′", _F),
        ("rsq_gap_spline", "1", "rms slope of the gap from the spline slopes", _F),
    ],
    "contact": [
        ("contact_step", "1", "step index at which the contact was recorded", _I),
        ("contact_point", "1", "grid index i of the contact", _I),
        ("contact_x", "µm", "x of the contact centre (eq. 9)", _F),
        ("contact_z", "µm", "z of the contact centre (global frame at that step)", _F),
        ("contact_overlap", "µm", "sphere overlap δ_i (eq. 10)", _F),
        ("contact_effective_radius", "µm", "R_eff,i = 2/(κ^u + κ^l) (eq. 10)", _F),
        ("contact_normal_force", "mN/µm", "|F^n_i| = (π/4) E* δ_i (eq. 10)", _F),
        ("contact_tangential_force", "mN/µm", "F^t_i along the contact tangent t (eqs. 11–13)", _F),
        ("contact_normal_x", "1", "x component of the repulsive direction e_i", _F),
        ("contact_normal_z", "1", "z component of the repulsive direction e_i", _F),
        (
            "contact_slipping",
            "1",
            "1 where the contact slips (|F^t| capped at μ0|F^n|), else 0",
            _B,
        ),
    ],
    "bem_step": [
        ("mean_pressure", "GPa", "applied mean pressure p̄ = F/L of the exact solution", _F),
        ("force", "mN/µm", "normal force F per unit thickness (in a comparison: SAD F_N)", _F),
        ("mean_gap", "µm", "exact mean gap between the deformed surfaces", _F),
        ("approach", "µm", "exact approach (mean-gap reduction) from first contact", _F),
        ("contact_nodes", "1", "exact solution: nodes in contact", _I),
        ("contact_length", "µm", "exact contact length, loaded nodes × dx", _F),
        ("contact_length_subgrid", "µm", "exact contact length, sub-grid edge estimate", _F),
        ("n_patches", "1", "exact number of connected contact patches", _I),
        ("iterations", "1", "conjugate-gradient iterations used", _I),
        ("residual", "1", "largest complementarity violation / rms height at the end", _F),
    ],
    "comparison": [
        ("sad_step", "1", "SAD displacement step", _F),
        ("sad_displacement", "µm", "SAD displacement δ_N from first contact", _F),
        ("sad_contact_width", "µm", "SAD Hertz contact width Σ 2a_i = √2 A_S", _F),
        ("sad_contact_area", "µm", "SAD A_S = Σ √(δ_i R_eff,i) (paper's definition)", _F),
        ("sad_n_contacts", "1", "SAD accepted contacts", _F),
        ("sad_mean_separation", "µm", "SAD mean separation of the (rigid) mean lines", _F),
        ("bem_contact_length", "µm", "exact contact length, loaded nodes × dx", _F),
        ("bem_contact_length_subgrid", "µm", "exact contact length, sub-grid edges", _F),
        ("bem_n_patches", "1", "exact number of contact patches", _F),
        ("bem_mean_gap", "µm", "exact mean gap between the deformed mean lines", _F),
        ("bem_approach", "µm", "exact approach (mean-gap reduction) from first contact", _F),
        ("ratio_width", "1", "sad_contact_width / bem_contact_length_subgrid", _F),
        ("ratio_area", "1", "sad_contact_area / bem_contact_length_subgrid", _F),
        ("mean_gap_error", "1", "sad_mean_separation / bem_mean_gap − 1", _F),
        ("ratio_approach", "1", "bem_approach / sad_displacement", _F),
        ("ratio_contacts", "1", "bem_n_patches / sad_n_contacts", _F),
        (
            "int_displacement",
            "µm",
            "interacting SAD: displacement δ_N at this force (interpolated between steps)",
            _F,
        ),
        (
            "int_contact_length",
            "µm",
            "interacting SAD: length of the union of the contact intervals",
            _F,
        ),
        ("int_contact_area", "µm", "interacting SAD: A_S = Σ √(δ^eff_i R_eff,i)", _F),
        ("int_n_contacts", "1", "interacting SAD: loaded contacts", _F),
        ("int_n_patches", "1", "interacting SAD: connected contact patches", _F),
        ("int_mean_separation", "µm", "interacting SAD: mean gap of the mean lines", _F),
        ("ratio_length_int", "1", "int_contact_length / bem_contact_length_subgrid", _F),
        ("mean_gap_error_int", "1", "int_mean_separation / bem_mean_gap − 1", _F),
        ("ratio_approach_int", "1", "bem_approach / int_displacement", _F),
        ("ratio_patches_int", "1", "bem_n_patches / int_n_patches", _F),
    ],
}


#: The codes of the coded variables: name -> meanings of 0, 1, … (CF ``flag_meanings``).
_FLAGS: dict[str, tuple[str, ...]] = {
    "force_control": (
        "displacement_controlled",
        "held_accepted_set",
        "held_fixed_set",
        "missed_inside_jump",
    ),
}


def _build() -> Mapping[str, Variable]:
    variables: dict[str, Variable] = {}
    for table_name in TABLES:
        for name, unit, long_name, dtype in _ROWS[table_name]:
            if name in variables:  # pragma: no cover - guarded by tests/test_schema.py
                raise AssertionError(f"output variable {name!r} defined twice")
            flags = _FLAGS.get(name, ())
            variables[name] = Variable(name, unit, long_name, table_name, dtype, flags)
    return MappingProxyType(variables)


#: Every output variable: name -> :class:`Variable` (read-only).
VARIABLES: Mapping[str, Variable] = _build()

#: The tables whose variables also appear in another table (``force`` is a column of a
#: comparison as well as of the exact reference's steps): table -> extra names, in order.
_SHARED: dict[Table, tuple[str, ...]] = {"comparison": ("force",)}


#: Index coordinates of the written datasets: name -> (units, long_name). A study store adds
#: its grid coordinates (the swept parameters, units from :mod:`splinecontact.parameters`).
COORDINATES: Mapping[str, tuple[str, str]] = MappingProxyType(
    {
        "step": ("1", "loading step (0 = first contact)"),
        "contact": ("1", "index of a recorded accepted contact"),
        "load": ("1", "index of the load (one exact solution or comparison per load)"),
        "realization": ("1", "realization index (its seed derives from the study seed)"),
    }
)


def coordinate(name: str, size: int) -> tuple[str, Any, dict[str, str]]:
    """An index coordinate ``0 … size − 1`` in the ``(dim, values, attrs)`` form of xarray."""
    import numpy as np

    units_, long_name = COORDINATES[name]
    values = np.arange(size, dtype=np.int64)
    return (name, values, {"units": units_, "long_name": long_name})


def table(name: Table) -> dict[str, Variable]:
    """The variables of one table, in their listed order: name -> :class:`Variable`.

    ``table("comparison")`` starts with ``force`` (shared with ``bem_step``).
    """
    if name not in _DIMS:
        raise KeyError(f"unknown output table {name!r}; choose from {list(TABLES)}")
    shared = {n: VARIABLES[n] for n in _SHARED.get(name, ())}
    return {**shared, **{v.name: v for v in VARIABLES.values() if v.table == name}}


def legacy_table(name: Table) -> dict[str, tuple[str, str]]:
    """One table as ``name -> (units, long_name)`` (the form of ``results.STEP_VARIABLES``)."""
    return {n: (v.units, v.long_name) for n, v in table(name).items()}


def attrs(name: str) -> dict[str, Any]:
    """The attributes of a written variable: ``{"units": ..., "long_name": ...}`` (and the CF
    ``flag_values``/``flag_meanings`` of a coded variable).

    Raises
    ------
    KeyError
        ``name`` is not an output variable.
    """
    return VARIABLES[name].attrs()


def units(name: str) -> str:
    """Units of one output variable."""
    return VARIABLES[name].units


def xr_variable(name: str, values: Any, dims: tuple[str, ...] | None = None) -> xr.Variable:
    """An :class:`xarray.Variable` of ``values`` with the registry's dims and attributes.

    ``dims`` overrides the registry's dimensions (a study store prepends its grid dimensions).
    """
    import xarray as xr

    return xr.Variable(VARIABLES[name].dims if dims is None else dims, values, attrs(name))
