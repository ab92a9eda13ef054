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

if TYPE_CHECKING:  # xarray is imported when a Dataset is made, not with the package
    import xarray as xr

__all__ = [
    "CONTACT_VARIABLES",
    "PATH_STEP_VARIABLES",
    "SCALAR_VARIABLES",
    "STEP_VARIABLES",
    "ContactRecord",
    "SimulationResult",
]

#: Per-step variables: name -> (units, description). Forces are per µm of out-of-plane thickness.
STEP_VARIABLES: dict[str, tuple[str, str]] = {
    "displacement": ("µm", "normal displacement δ_N of the upper body from first contact"),
    "normal_force": ("mN/µm", "global normal force F_N on the upper body (eq. 14)"),
    "tangential_force": ("mN/µm", "global tangential force F_T on the upper body (eq. 14)"),
    "contact_area": ("µm", "contact area A_S = Σ √(δ_i R_eff,i) per unit thickness (eq. 10)"),
    "n_contacts": ("1", "number of accepted contacts"),
    "mean_separation": ("µm", "distance between the mean lines of the smoothed surfaces"),
    "normal_force_normal_part": ("mN/µm", "part of F_N from the local normal forces F^n"),
    "normal_force_tangential_part": ("mN/µm", "part of F_N from the local tangential forces F^t"),
    "n_tilted_contacts": (
        "1",
        "accepted contacts whose repulsive direction points below horizontal (e_z < 0)",
    ),
    "n_candidates": ("1", "points whose gap has closed (detection, z^u ≤ z^l)"),
}

#: Per-step variables written when present in the curves: ``tangential_displacement`` (every
#: ``simulate`` result) and the load-path variables of ``simulate(..., path=...)``.
PATH_STEP_VARIABLES: dict[str, tuple[str, str]] = {
    "tangential_displacement": (
        "µm",
        "tangential displacement u_T of the upper body along +x (0 for a normal loading)",
    ),
    "n_slipping": ("1", "accepted contacts whose tangential force is capped at μ0|F^n| (slip)"),
    "dissipated_work": (
        "mN·µm/µm",
        "frictional work dissipated since step 0, Σ slip × capped force (nJ per µm thickness)",
    ),
    "normal_force_target": (
        "mN/µm",
        "F_N held by a force-controlled segment (NaN on displacement-controlled steps)",
    ),
}

#: Per-simulation scalar variables: name -> (units, description).
SCALAR_VARIABLES: dict[str, tuple[str, str]] = {
    "final_displacement": ("µm", "displacement at the last step"),
    "ra_lower": ("µm", "R_A of the lower profile heights"),
    "ra_upper": ("µm", "R_A of the upper profile heights (0 for a rigid flat)"),
    "rq_lower": ("µm", "R_q of the lower profile heights"),
    "rq_upper": ("µm", "R_q of the upper profile heights"),
    "peak_to_valley_lower": ("µm", "peak-to-valley height of the lower profile"),
    "rsq_lower": ("1", "rms slope of the lower heights, grid differences (eq. 15)"),
    "rsq_upper": ("1", "rms slope of the upper heights, grid differences (eq. 15)"),
    "rsq_gap": ("1", "rms slope of the gap z^u − z^l, grid differences (eq. 15)"),
    "rsq_lower_spline": ("1", "rms slope of the lower spline f′"),
    "rsq_upper_spline": ("1", "rms slope of the upper spline f′"),
    "rsq_gap_spline": ("1", "rms slope of the gap from the spline slopes"),
}

#: Variables of the accepted-contact records (dimension ``contact``).
CONTACT_VARIABLES: dict[str, tuple[str, str]] = {
    "contact_step": ("1", "step index at which the contact was recorded"),
    "contact_point": ("1", "grid index i of the contact"),
    "contact_x": ("µm", "x of the contact centre (eq. 9)"),
    "contact_z": ("µm", "z of the contact centre (global frame at that step)"),
    "contact_overlap": ("µm", "sphere overlap δ_i (eq. 10)"),
    "contact_effective_radius": ("µm", "R_eff,i = 2/(κ^u + κ^l) (eq. 10)"),
    "contact_normal_force": ("mN/µm", "|F^n_i| = (π/4) E* δ_i (eq. 10)"),
    "contact_tangential_force": ("mN/µm", "F^t_i along the contact tangent t (eqs. 11–13)"),
    "contact_normal_x": ("1", "x component of the repulsive direction e_i"),
    "contact_normal_z": ("1", "z component of the repulsive direction e_i"),
    "contact_slipping": ("1", "1 where the contact slips (|F^t| capped at μ0|F^n|), else 0"),
}


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


@dataclass(frozen=True, eq=False)
class SimulationResult:
    """Per-step output of one SAD simulation (see ``STEP_VARIABLES`` for units).

    Attributes
    ----------
    curves : dict of str to ndarray
        The per-step variables of ``STEP_VARIABLES``, each of length ``steps + 1`` (step 0 is
        the configuration of first contact, zero minimum gap).
    scalars : dict of str to float
        The per-simulation variables of ``SCALAR_VARIABLES``.
    parameters : dict
        Every parameter of the run (material, spline, stepping, grid, contact type).
    contacts : tuple of ContactRecord
        Accepted contacts at the steps requested with ``record_contacts``.
    lower_metadata, upper_metadata : dict
        Metadata of the two input profiles (``upper_metadata`` is ``{"source": "flat"}`` for a
        rigid flat).
    """

    curves: Mapping[str, NDArray[Any]]
    scalars: Mapping[str, float]
    parameters: Mapping[str, Any]
    contacts: tuple[ContactRecord, ...] = ()
    lower_metadata: Mapping[str, Any] = field(default_factory=dict)
    upper_metadata: Mapping[str, Any] = field(default_factory=dict)

    def __getattr__(self, name: str) -> Any:
        # Convenience: result.normal_force etc. (only for the schema's names).
        curves = object.__getattribute__(self, "curves")
        if name in curves:
            return curves[name]
        scalars = object.__getattribute__(self, "scalars")
        if name in scalars:
            return scalars[name]
        raise AttributeError(name)

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
        for name, (units, description) in STEP_VARIABLES.items():
            data_vars[name] = xr.Variable(
                ("step",), np.asarray(self.curves[name]), {"units": units, "long_name": description}
            )
        for name, (units, description) in PATH_STEP_VARIABLES.items():
            if name in self.curves:
                data_vars[name] = xr.Variable(
                    ("step",),
                    np.asarray(self.curves[name]),
                    {"units": units, "long_name": description},
                )
        for name, (units, description) in SCALAR_VARIABLES.items():
            data_vars[name] = xr.Variable(
                (), float(self.scalars[name]), {"units": units, "long_name": description}
            )
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
                units, description = CONTACT_VARIABLES[name]
                data_vars[name] = xr.Variable(
                    ("contact",), values, {"units": units, "long_name": description}
                )
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
        step_attrs = {"units": "1", "long_name": "loading step (0 = first contact)"}
        coords = {"step": ("step", steps, step_attrs)}
        return xr.Dataset(data_vars, coords=coords, attrs=attrs)

    def to_netcdf(self, path: str | Path) -> Path:
        """Write :meth:`to_xarray` to a netCDF-4 file (h5netcdf engine) and return its path."""
        path = Path(path)
        self.to_xarray().to_netcdf(path, engine="h5netcdf")
        return path
