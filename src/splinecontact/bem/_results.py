"""Results of the BEM: contact statistics of a pressure field, one step, a load path."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .. import schema

if TYPE_CHECKING:  # xarray is imported when a Dataset is made, not with the package
    import xarray as xr

__all__ = [
    "STEP_UNITS",
    "BEMPath",
    "BEMStep",
    "ContactStatistics",
    "contact_statistics",
]

# --- contact statistics ---------------------------------------------------------------------


@dataclass(frozen=True)
class ContactStatistics:
    """Contact length and patch count of a pressure field.

    Attributes
    ----------
    contact_nodes : int
        Nodes with positive pressure.
    contact_length : float
        contact_nodes × dx [µm].
    contact_length_subgrid : float
        Sum over patches of the distance between the two edges, each edge placed where the
        square-root law p² ∝ (a − x), fitted to the edge node and its inner neighbour, reaches
        zero (at most dx beyond the edge node) [µm].
    n_patches : int
        Number of connected runs of loaded nodes.
    """

    contact_nodes: int
    contact_length: float
    contact_length_subgrid: float
    n_patches: int


def _edge_offset(p_edge: NDArray[np.float64], p_inner: NDArray[np.float64], dx: float) -> Any:
    """Distance [µm] beyond an edge node where p² extrapolated linearly vanishes, in [0, dx]."""
    e2 = p_edge**2
    i2 = p_inner**2
    with np.errstate(divide="ignore", invalid="ignore"):
        offset = np.where(i2 > e2, dx * e2 / (i2 - e2), 0.5 * dx)
    return np.clip(offset, 0.0, dx)


def contact_statistics(
    pressure: ArrayLike, dx: float, *, periodic: bool = True
) -> ContactStatistics:
    """Contact nodes, contact length (node count and sub-grid) and patches of a pressure field.

    Parameters
    ----------
    pressure : array_like
        Nodal pressures [GPa] (≥ 0; positive means contact).
    dx : float
        Grid spacing [µm].
    periodic : bool
        True: the last node neighbours the first. False: the ends are symmetry walls (a patch
        touching an end extends to the wall, dx/2 beyond the end node).

    Returns
    -------
    ContactStatistics
    """
    p = np.asarray(pressure, dtype=np.float64)
    n = p.size
    inside = p > 0.0
    count = int(inside.sum())
    if count == 0:
        return ContactStatistics(0, 0.0, 0.0, 0)
    if count == n:
        return ContactStatistics(n, n * dx, n * dx, 1)
    if periodic:
        before = np.roll(inside, 1)
        after = np.roll(inside, -1)
    else:
        before = np.concatenate([[False], inside[:-1]])
        after = np.concatenate([inside[1:], [False]])
    starts = np.flatnonzero(inside & ~before)
    ends = np.flatnonzero(inside & ~after)
    if periodic:
        # pair each start with the first end at or after it (cyclically)
        pos = np.searchsorted(ends, starts)
        ends = ends[pos % ends.size]
        span = (ends - starts) % n
    else:
        span = ends - starts
    single = span == 0
    inner_left = np.where(single, starts, (starts + 1) % n)
    inner_right = np.where(single, ends, (ends - 1) % n)
    left = _edge_offset(p[starts], np.where(single, 0.0, p[inner_left]), dx)
    right = _edge_offset(p[ends], np.where(single, 0.0, p[inner_right]), dx)
    left = np.where(single, 0.5 * dx, left)
    right = np.where(single, 0.5 * dx, right)
    if not periodic:
        left = np.where(starts == 0, 0.5 * dx, left)
        right = np.where(ends == n - 1, 0.5 * dx, right)
    subgrid = float(np.sum(span * dx + left + right))
    return ContactStatistics(count, count * dx, subgrid, int(starts.size))


# --- results --------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class BEMStep:
    """The solution at one load (or mean gap).

    Attributes
    ----------
    mean_pressure : float
        p̄ [GPa].
    force : float
        Force per unit thickness p̄·L [mN/µm].
    mean_gap : float
        ḡ = s − z̄ [µm], distance between the mean lines of the deformed surfaces.
    approach : float
        Mean-gap reduction since first touch, (max z − z̄) − ḡ [µm].
    contact_nodes : int
        Loaded nodes.
    contact_length : float
        contact_nodes × dx [µm].
    contact_length_subgrid : float
        Sub-grid contact length from the pressure at the patch edges [µm].
    n_patches : int
        Connected contact patches.
    iterations : int
        Conjugate-gradient iterations used.
    residual : float
        Largest complementarity violation / rms height [1] at the end.
    pressure : ndarray or None
        Nodal pressures [GPa] (only with ``fields=True``).
    gap : ndarray or None
        Nodal gaps [µm], 0 where loaded (only with ``fields=True``).
    """

    mean_pressure: float
    force: float
    mean_gap: float
    approach: float
    contact_nodes: int
    contact_length: float
    contact_length_subgrid: float
    n_patches: int
    iterations: int
    residual: float
    pressure: NDArray[np.float64] | None = field(default=None, repr=False)
    gap: NDArray[np.float64] | None = field(default=None, repr=False)


#: Per-step quantities of :class:`BEMPath` with their units (the column schema of tables;
#: defined in :mod:`splinecontact.schema`, table ``bem_step``).
STEP_UNITS: dict[str, str] = {name: v.units for name, v in schema.table("bem_step").items()}


@dataclass(frozen=True, eq=False)
class BEMPath:
    """A sequence of solutions along a load path.

    Attributes
    ----------
    steps : tuple of BEMStep
        One per requested load (in the given order).
    e_star : float
        Effective modulus [GPa].
    dx : float
        Grid spacing [µm].
    n_points : int
        Nodes per period.
    tolerance : float
        Convergence tolerance used [1].
    """

    steps: tuple[BEMStep, ...]
    e_star: float
    dx: float
    n_points: int
    tolerance: float

    def column(self, name: str) -> NDArray[np.float64]:
        """One per-step quantity (a key of ``STEP_UNITS``) as an array, in its units."""
        if name not in STEP_UNITS:
            raise KeyError(f"unknown step quantity {name!r}; choose from {sorted(STEP_UNITS)}")
        return np.array([getattr(s, name) for s in self.steps], dtype=np.float64)

    @property
    def length(self) -> float:
        """Period L [µm]."""
        return float(self.n_points * self.dx)

    def to_xarray(self) -> xr.Dataset:
        """Return the path as an :class:`xarray.Dataset` (dimension ``load``, one per step).

        Every quantity of ``STEP_UNITS`` is a variable with ``units`` and ``long_name``
        (:mod:`splinecontact.schema`); the attributes hold ``e_star`` [GPa], ``dx`` [µm],
        ``n_points``, ``length`` [µm] and ``tolerance``. The nodal fields are not included.
        """
        import xarray as xr

        data_vars = {
            name: schema.xr_variable(
                name,
                np.array([getattr(s, name) for s in self.steps], dtype=variable.dtype),
            )
            for name, variable in schema.table("bem_step").items()
        }
        attrs = {
            "e_star_GPa": float(self.e_star),
            "dx_um": float(self.dx),
            "n_points": int(self.n_points),
            "length_um": self.length,
            "tolerance": float(self.tolerance),
            "units_convention": (
                "lengths µm, moduli GPa, forces mN per µm of out-of-plane thickness"
            ),
        }
        coords = {"load": schema.coordinate("load", len(self.steps))}
        return xr.Dataset(data_vars, coords=coords, attrs=attrs)
