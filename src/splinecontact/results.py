"""Results of one SAD simulation and their xarray/netCDF form.

The per-step curves of :func:`splinecontact.simulate` live in :class:`SimulationResult`;
:meth:`SimulationResult.to_xarray` gives a :class:`xarray.Dataset` whose every variable carries a
``units`` attribute and whose attributes hold the full parameter set. The variable names here are
the schema used by studies, analyses and plots.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from . import schema
from .errors import ResultSchemaError

if TYPE_CHECKING:  # xarray is imported when a Dataset is made, not with the package
    import xarray as xr

__all__ = [
    "CONTACT_VARIABLES",
    "INTERACTION_STEP_VARIABLES",
    "PATH_STEP_VARIABLES",
    "SCALAR_VARIABLES",
    "STEP_VARIABLES",
    "ContactRecord",
    "SimulationResult",
]

# The variable tables of :mod:`splinecontact.schema` in their ``name -> (units, long_name)`` form
# (the registry is the definition; these are views kept for the modules that iterate over them).

#: Per-step variables: name -> (units, description). Forces are per µm of out-of-plane thickness.
STEP_VARIABLES: dict[str, tuple[str, str]] = schema.legacy_table("step")

#: Per-step variables written when present in the curves: ``tangential_displacement`` (every
#: ``simulate`` result) and the load-path variables of ``simulate(..., path=...)``.
PATH_STEP_VARIABLES: dict[str, tuple[str, str]] = schema.legacy_table("path_step")

#: Per-step variables of ``simulate(..., interaction=True)`` (written when present).
INTERACTION_STEP_VARIABLES: dict[str, tuple[str, str]] = schema.legacy_table("interaction_step")

#: Per-simulation scalar variables: name -> (units, description).
SCALAR_VARIABLES: dict[str, tuple[str, str]] = schema.legacy_table("scalar")

#: Variables of the accepted-contact records (dimension ``contact``).
CONTACT_VARIABLES: dict[str, tuple[str, str]] = schema.legacy_table("contact")


@dataclass(frozen=True, eq=False)
class ContactRecord:
    """The accepted contacts at one recorded step.

    Attributes
    ----------
    step : int
        Step index (0 is first contact).
    point : ndarray of int
        Grid index i of each accepted contact.
    x, z : ndarray
        Contact centre [µm] in the global frame (eqs. 8–9).
    overlap : ndarray
        Sphere overlap δ_i [µm].
    effective_radius : ndarray
        R_eff,i [µm].
    normal_force : ndarray
        Magnitude of the local normal force [mN/µm].
    tangential_force : ndarray
        Local tangential force along the contact tangent t = (e_z, −e_x) [mN/µm].
    normal_x, normal_z : ndarray
        Repulsive direction e_i (unit vector, force on the upper body) [1].
    slipping : ndarray of bool or None
        Whether each contact slips (load paths only; ``None`` for a plain normal loading).
    """

    step: int
    point: NDArray[np.int64]
    x: NDArray[np.float64]
    z: NDArray[np.float64]
    overlap: NDArray[np.float64]
    effective_radius: NDArray[np.float64]
    normal_force: NDArray[np.float64]
    tangential_force: NDArray[np.float64]
    normal_x: NDArray[np.float64]
    normal_z: NDArray[np.float64]
    slipping: NDArray[np.bool_] | None = None

    def __repr__(self) -> str:
        return f"ContactRecord(step={self.step}, n_contacts={np.size(self.point)})"


def jsonable(value: Any) -> Any:
    """``value`` with numpy scalars/arrays and tuples turned into JSON-serialisable types."""
    if isinstance(value, Mapping):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [jsonable(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    return value


_FLOAT = NDArray[np.float64]
_COUNT = NDArray[np.int64]


@dataclass(frozen=True, eq=False)
class SimulationResult:
    """Per-step output of one SAD simulation (units: :mod:`splinecontact.schema`).

    Built from the two mappings ``curves`` and ``scalars``; every variable of the schema is
    also a declared, typed attribute (``result.normal_force``, ``result.rsq_gap``), so a typo
    is a type-checker error and ``dir(result)`` lists them.

    Attributes
    ----------
    curves : dict of str to ndarray
        The per-step variables of ``STEP_VARIABLES`` (and those of ``PATH_STEP_VARIABLES`` the
        run produced), each of length ``steps + 1`` (step 0 is the configuration of first
        contact, zero minimum gap).
    scalars : dict of str to float
        The per-simulation variables of ``SCALAR_VARIABLES``.
    parameters : dict
        Every parameter of the run (material, spline, stepping, grid, contact type).
    contacts : tuple of ContactRecord
        Accepted contacts at the steps requested with ``record_contacts``.
    lower_metadata, upper_metadata : dict
        Metadata of the two input profiles (``upper_metadata`` is ``{"source": "flat"}`` for a
        rigid flat).
    displacement : ndarray
        Normal displacement δ_N of the upper body from first contact [µm].
    normal_force, tangential_force : ndarray
        Global forces F_N, F_T on the upper body (eq. 14) [mN/µm].
    contact_area : ndarray
        A_S = Σ √(δ_i R_eff,i) per unit thickness (eq. 10) [µm].
    n_contacts, n_tilted_contacts, n_candidates : ndarray of int
        Accepted contacts, those whose repulsive direction points below horizontal, and the
        points whose gap has closed [1].
    mean_separation : ndarray
        Distance between the mean lines of the smoothed surfaces [µm].
    normal_force_normal_part, normal_force_tangential_part : ndarray
        Parts of F_N from the local normal and tangential forces [mN/µm].
    tangential_displacement : ndarray or None
        u_T along +x [µm] (every ``simulate`` result of this version has it; ``None`` only for
        a result built without it).
    n_slipping : ndarray of int or None
        Slipping contacts [1] (load paths only, else ``None``).
    dissipated_work : ndarray or None
        Frictional work since step 0 [mN·µm/µm] (load paths only, else ``None``).
    normal_force_target : ndarray or None
        F_N held by a force-controlled segment [mN/µm], NaN elsewhere (load paths only).
    force_control : ndarray of int8 or None
        How each step met F_N [1] (load paths only): 0 displacement-controlled, 1 held with the
        contacts eq. 9 accepts, 2 held with a contact set eq. 9 would not accept as a whole
        (target inside a jump), 3 target inside a jump, F_N ≠ target (the nearer side).
    final_displacement : float
        Displacement at the last step [µm].
    ra_lower, ra_upper, rq_lower, rq_upper, peak_to_valley_lower : float
        Height statistics of the profiles [µm].
    rsq_lower, rsq_upper, rsq_gap, rsq_lower_spline, rsq_upper_spline, rsq_gap_spline : float
        rms slopes (eq. 15) [1].

    Raises
    ------
    ResultSchemaError
        ``curves`` or ``scalars`` lacks a variable of ``STEP_VARIABLES``/``SCALAR_VARIABLES``.
    """

    curves: Mapping[str, NDArray[Any]]
    scalars: Mapping[str, float]
    parameters: Mapping[str, Any]
    contacts: tuple[ContactRecord, ...] = ()
    lower_metadata: Mapping[str, Any] = field(default_factory=dict)
    upper_metadata: Mapping[str, Any] = field(default_factory=dict)

    # --- per-step curves (schema table "step"), set from ``curves`` -------------------------
    displacement: _FLOAT = field(init=False)
    normal_force: _FLOAT = field(init=False)
    tangential_force: _FLOAT = field(init=False)
    contact_area: _FLOAT = field(init=False)
    n_contacts: _COUNT = field(init=False)
    mean_separation: _FLOAT = field(init=False)
    normal_force_normal_part: _FLOAT = field(init=False)
    normal_force_tangential_part: _FLOAT = field(init=False)
    n_tilted_contacts: _COUNT = field(init=False)
    n_candidates: _COUNT = field(init=False)
    # --- optional per-step curves (schema tables "path_step", "interaction_step") ------------
    tangential_displacement: _FLOAT | None = field(init=False, default=None)
    n_slipping: _COUNT | None = field(init=False, default=None)
    dissipated_work: _FLOAT | None = field(init=False, default=None)
    normal_force_target: _FLOAT | None = field(init=False, default=None)
    force_control: NDArray[np.int8] | None = field(init=False, default=None)
    coalesced_contact_length: _FLOAT | None = field(init=False, default=None)
    n_contact_patches: _COUNT | None = field(init=False, default=None)
    interaction_iterations: _COUNT | None = field(init=False, default=None)
    reach_exceeded: _COUNT | None = field(init=False, default=None)
    # --- per-simulation scalars (schema table "scalar"), set from ``scalars`` ---------------
    final_displacement: float = field(init=False)
    ra_lower: float = field(init=False)
    ra_upper: float = field(init=False)
    rq_lower: float = field(init=False)
    rq_upper: float = field(init=False)
    peak_to_valley_lower: float = field(init=False)
    rsq_lower: float = field(init=False)
    rsq_upper: float = field(init=False)
    rsq_gap: float = field(init=False)
    rsq_lower_spline: float = field(init=False)
    rsq_upper_spline: float = field(init=False)
    rsq_gap_spline: float = field(init=False)

    def __post_init__(self) -> None:
        for source, names, required in (
            (self.curves, STEP_VARIABLES, True),
            (self.curves, PATH_STEP_VARIABLES, False),
            (self.curves, INTERACTION_STEP_VARIABLES, False),
            (self.scalars, SCALAR_VARIABLES, True),
        ):
            for name in names:
                if name in source:
                    object.__setattr__(self, name, source[name])
                elif required:
                    raise ResultSchemaError(
                        f"a SimulationResult needs the variable {name!r} (missing from "
                        f"{'curves' if source is self.curves else 'scalars'}, which has "
                        f"{sorted(source)}); build it with every variable of the schema"
                    )

    @property
    def n_steps(self) -> int:
        """Number of displacement increments (records are ``n_steps + 1``)."""
        return int(len(self.curves["displacement"]) - 1)

    def __repr__(self) -> str:
        parameters = self.parameters
        parts = [
            f"{parameters.get('contact_type', '?')}",
            f"steps={self.n_steps}",
            f"n_points={parameters.get('n_points', '?')}",
        ]
        for label, name, unit in (
            ("final_displacement", "displacement", "µm"),
            ("normal_force[-1]", "normal_force", "mN/µm"),
            ("contact_area[-1]", "contact_area", "µm"),
            ("n_contacts[-1]", "n_contacts", ""),
        ):
            values = np.asarray(self.curves.get(name, ()))
            if values.size:
                last = values[-1]
                text = f"{int(last)}" if values.dtype.kind in "iu" else f"{float(last):.4g}"
                parts.append(f"{label}={text}{' ' + unit if unit else ''}")
        if self.contacts:
            parts.append(f"recorded_steps={len(self.contacts)}")
        return f"SimulationResult({', '.join(parts)})"

    def to_xarray(self) -> xr.Dataset:
        """Return the result as an :class:`xarray.Dataset`.

        Dimension ``step`` (0 … steps) for the curves; dimension ``contact`` for the recorded
        accepted contacts (flattened over the recorded steps, ``contact_step`` says which);
        0-d variables for the per-simulation scalars. Every variable has ``units`` and
        ``long_name`` attributes; the dataset attributes hold the parameters (scalars as
        attributes, the profile metadata as JSON strings).
        """
        import xarray as xr

        steps = np.arange(self.n_steps + 1)
        data_vars: dict[str, Any] = {}
        for name in (*STEP_VARIABLES, *PATH_STEP_VARIABLES, *INTERACTION_STEP_VARIABLES):
            if name in self.curves:
                data_vars[name] = schema.xr_variable(name, np.asarray(self.curves[name]))
        for name in SCALAR_VARIABLES:
            data_vars[name] = schema.xr_variable(name, float(self.scalars[name]))
        if self.contacts:
            columns = {
                "contact_step": np.concatenate(
                    [np.full(c.point.size, c.step, dtype=np.int64) for c in self.contacts]
                ),
                "contact_point": np.concatenate([c.point for c in self.contacts]),
                "contact_x": np.concatenate([c.x for c in self.contacts]),
                "contact_z": np.concatenate([c.z for c in self.contacts]),
                "contact_overlap": np.concatenate([c.overlap for c in self.contacts]),
                "contact_effective_radius": np.concatenate(
                    [c.effective_radius for c in self.contacts]
                ),
                "contact_normal_force": np.concatenate([c.normal_force for c in self.contacts]),
                "contact_tangential_force": np.concatenate(
                    [c.tangential_force for c in self.contacts]
                ),
                "contact_normal_x": np.concatenate([c.normal_x for c in self.contacts]),
                "contact_normal_z": np.concatenate([c.normal_z for c in self.contacts]),
            }
            if all(c.slipping is not None for c in self.contacts):
                columns["contact_slipping"] = np.concatenate(
                    [np.asarray(c.slipping, dtype=np.int8) for c in self.contacts]
                )
            for name, values in columns.items():
                data_vars[name] = schema.xr_variable(name, values)
        attrs: dict[str, Any] = {}
        for key, value in self.parameters.items():
            attrs[key] = (
                value if isinstance(value, int | float | str) else json.dumps(jsonable(value))
            )
        attrs["lower_metadata"] = json.dumps(jsonable(self.lower_metadata))
        attrs["upper_metadata"] = json.dumps(jsonable(self.upper_metadata))
        attrs["units_convention"] = (
            "lengths µm, moduli GPa, forces mN per µm of out-of-plane thickness"
        )
        from ._version import __version__

        attrs["splinecontact_version"] = __version__
        coords = {"step": schema.coordinate("step", steps.size)}
        return xr.Dataset(data_vars, coords=coords, attrs=attrs)

    def to_netcdf(self, path: str | Path) -> Path:
        """Write :meth:`to_xarray` to a netCDF-4 file (h5netcdf engine) and return its path."""
        path = Path(path)
        self.to_xarray().to_netcdf(path, engine="h5netcdf")
        return path
