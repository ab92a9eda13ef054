"""Exact reference: a rigid rough profile on an elastic half-space (plane strain, periodic).

The boundary element method (BEM) here solves the non-adhesive, frictionless hard-wall contact of
a rigid line profile pressed against an elastic half-space of effective modulus E*, exactly within
linear elasticity and the small-slope approximation. It is the reference against which the
independent-contact model of SAD (paper eq. 10, F = (π/4) E* δ per contact) is measured
(``splinecontact compare``, ``docs/accuracy.md``).

Model
-----
* The surface is periodic with period L = n·dx (``n`` nodes; the node after the last is the
  first one again, so do not repeat the first point at the end).
* Surface response in Fourier space (plane strain): p̂(q) = E*|q|/2 · û(q), q_k = 2πk/L, i.e.
  û(q) = 2 p̂(q)/(E*|q|) for q ≠ 0. The q = 0 mode of the displacement is set to zero: the
  elastic surface's mean line stays at the reference position s.
* Rough on rough: the composite profile z = z_lower + z_upper (both heights as a profilometer
  records them, pointing out of their own body) against a flat, with one effective modulus —
  the standard reduction. Local contact normals and tangential forces are beyond it (that is
  where SAD is needed; see ``docs/accuracy.md``).
* Gap g(x) = s + u(x) − z(x) ≥ 0, pressure p ≥ 0, p·g = 0. The mean gap is ḡ = s − z̄
  (u has zero mean), the distance between the mean lines of the two deformed surfaces.
* Discretisation: nodal pressures, the displacement from the exact spectral response of their
  trigonometric interpolant (collocation). Checked against Westergaard's and Hertz's solutions
  (:mod:`splinecontact.reference`).

Solvers
-------
* Load control (given mean pressure p̄ [GPa], force p̄·L [mN/µm]): constrained conjugate
  gradients of Polonsky & Keer (Wear 231, 1999, 206–219), with the mean-pressure constraint
  enforced at every iteration.
* Displacement control (given mean gap ḡ [µm]): the same projected conjugate gradients without
  the force constraint.
* Convergence: the largest complementarity violation — |g| at a loaded node, or the overlap −g at
  an unloaded one — divided by the rms height of the composite profile, below ``tol``.
  Otherwise :class:`~splinecontact.errors.NoConvergenceError`.
* Load paths (:func:`load_path`, :func:`gap_path`) warm-start every step from the previous
  pressure field.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Literal

import numba
import numpy as np
import scipy.fft as sfft
from numpy.typing import ArrayLike, NDArray

from . import schema
from .errors import (
    BEMGridError,
    BEMInputError,
    BEMParameterError,
    FullContactError,
    NegativeLoadError,
    NoConvergenceError,
    NonPeriodicProfileError,
)
from .profile import Profile

if TYPE_CHECKING:  # xarray is imported when a Dataset is made, not with the package
    import xarray as xr

__all__ = [
    "DEFAULT_MAX_ITERATIONS",
    "DEFAULT_TOLERANCE",
    "MIN_BEM_POINTS",
    "PERIODIC_JUMP_FACTOR",
    "STEP_UNITS",
    "BEMGridError",
    "BEMInputError",
    "BEMParameterError",
    "BEMPath",
    "BEMStep",
    "ContactProblem",
    "ContactStatistics",
    "FullContactError",
    "NegativeLoadError",
    "NonPeriodicProfileError",
    "contact_problem",
    "contact_statistics",
    "gap_path",
    "load_path",
    "mirror_extend",
    "solve_gap",
    "solve_pressure",
]

#: Fewest nodes the periodic solver accepts.
MIN_BEM_POINTS = 8

#: Default convergence tolerance: largest complementarity violation / rms height [1].
DEFAULT_TOLERANCE = 1e-10

#: Default iteration limit of the conjugate-gradient solvers.
DEFAULT_MAX_ITERATIONS = 100_000

#: A profile is periodic-compatible when its wrap-around step |z[0] − z[n−1]| is at most this
#: factor times the largest step between neighbours inside the profile.
PERIODIC_JUMP_FACTOR = 2.0


# --- the problem ----------------------------------------------------------------------------


def _heights_of(body: Profile | ArrayLike, name: str) -> tuple[NDArray[np.float64], float | None]:
    if isinstance(body, Profile):
        return np.array(body.z, dtype=np.float64), body.dx
    z = np.array(body, dtype=np.float64)
    if z.ndim != 1:
        raise BEMGridError(f"{name} heights must be one-dimensional, got shape {z.shape}")
    return z, None


def _check_periodic(z: NDArray[np.float64]) -> None:
    steps = np.abs(np.diff(z))
    largest = float(steps.max())
    jump = abs(float(z[0] - z[-1]))
    if jump > PERIODIC_JUMP_FACTOR * largest and jump > 0.0:
        raise NonPeriodicProfileError(
            f"the profile does not wrap around: |z[0] − z[{z.size - 1}]| = {jump:.4g} µm is more "
            f"than {PERIODIC_JUMP_FACTOR:g}× the largest step between neighbours "
            f"({largest:.4g} µm); the BEM is periodic with period n·dx — make the profile "
            "periodic first (for example splinecontact.bem.mirror_extend) or pass "
            "check_periodic=False"
        )


@dataclass(frozen=True, eq=False)
class ContactProblem:
    """A periodic contact problem: composite heights, grid and modulus, ready to solve.

    Build it with :func:`contact_problem`.

    Attributes
    ----------
    heights : ndarray
        Composite heights z = z_lower + z_upper [µm] (read-only), one period.
    dx : float
        Grid spacing [µm].
    e_star : float
        Effective modulus E* [GPa].
    response : ndarray
        Displacement per unit pressure of each real Fourier mode, 2/(E*|q_k|) [µm/GPa]
        (0 for q = 0), length n//2 + 1 (read-only).
    full_contact_pressure : float
        Mean pressure at which every node touches [GPa] (of the discrete problem).
    """

    heights: NDArray[np.float64]
    dx: float
    e_star: float
    response: NDArray[np.float64] = field(repr=False)
    full_contact_pressure: float

    @property
    def n_points(self) -> int:
        """Number of nodes per period."""
        return int(self.heights.size)

    @property
    def length(self) -> float:
        """Period L = n·dx [µm]."""
        return float(self.heights.size * self.dx)

    @property
    def mean_height(self) -> float:
        """Mean composite height z̄ [µm]."""
        return float(self.heights.mean())

    @property
    def rms_height(self) -> float:
        """Rms composite height about its mean [µm] (the scale of the tolerance)."""
        return float(np.sqrt(np.mean((self.heights - self.heights.mean()) ** 2)))

    @property
    def first_contact_gap(self) -> float:
        """Mean gap at first touch, max(z) − z̄ [µm]."""
        return float(self.heights.max() - self.heights.mean())

    def displacement(self, pressure: ArrayLike) -> NDArray[np.float64]:
        """Zero-mean surface displacement u [µm] caused by nodal pressures [GPa]."""
        p = np.asarray(pressure, dtype=np.float64)
        return _apply(self.response, p)


def _apply(response: NDArray[np.float64], values: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.asarray(sfft.irfft(response * sfft.rfft(values), values.size), dtype=np.float64)


def contact_problem(
    lower: Profile | ArrayLike,
    upper: Profile | ArrayLike | Literal["flat"] = "flat",
    *,
    e_star: float,
    dx: float | None = None,
    check_periodic: bool = True,
) -> ContactProblem:
    """Set up the periodic contact of two rough profiles (or one against a flat).

    Parameters
    ----------
    lower : Profile or array_like
        Lower body heights [µm] (pointing out of the body). With an array, ``dx`` is required.
    upper : Profile, array_like or "flat"
        Upper body heights [µm] in its own frame (pointing out of the upper body, i.e. towards
        the lower one once turned over), on the same grid; "flat" for a flat counter-surface.
    e_star : float
        Effective modulus E* [GPa] of the pair (one elastic half-space carries all compliance).
    dx : float, optional
        Grid spacing [µm]; required for arrays, checked against the profiles' spacing otherwise.
    check_periodic : bool
        Refuse a profile whose wrap-around step is an outlier (see ``PERIODIC_JUMP_FACTOR``).

    Returns
    -------
    ContactProblem

    Raises
    ------
    BEMGridError
        Fewer than ``MIN_BEM_POINTS`` nodes, missing or non-positive ``dx``, different grids of
        the two bodies, non-finite heights.
    NonPeriodicProfileError
        The composite profile does not wrap around (``check_periodic``).
    BEMParameterError
        E* not positive and finite.
    """
    e = float(e_star)
    if not np.isfinite(e) or e <= 0.0:
        raise BEMParameterError(f"e_star must be a positive finite modulus [GPa], got {e_star!r}")
    z, dx_lower = _heights_of(lower, "lower")
    spacing = [s for s in (dx_lower, dx) if s is not None]
    if isinstance(upper, str):
        if upper != "flat":
            raise BEMGridError(f"upper must be a Profile, an array or 'flat', got {upper!r}")
    else:
        zu, dx_upper = _heights_of(upper, "upper")
        if zu.size != z.size:
            raise BEMGridError(
                f"lower has {z.size} points but upper has {zu.size}; both bodies must share one "
                "grid — resample one of them"
            )
        if dx_upper is not None:
            spacing.append(dx_upper)
        z = z + zu
    if not spacing:
        raise BEMGridError("heights were given as an array: pass the grid spacing dx [µm]")
    step = float(spacing[0])
    for other in spacing[1:]:
        if abs(float(other) - step) > 1e-9 * abs(step):
            raise BEMGridError(
                f"grid spacings differ: {step!r} µm and {float(other)!r} µm; both bodies (and dx)"
                " must describe the same grid"
            )
    if not np.isfinite(step) or step <= 0.0:
        raise BEMGridError(f"grid spacing dx must be positive and finite [µm], got {step!r}")
    if z.size < MIN_BEM_POINTS:
        raise BEMGridError(f"the BEM needs at least {MIN_BEM_POINTS} nodes, got {z.size}")
    bad = np.flatnonzero(~np.isfinite(z))
    if bad.size:
        raise BEMGridError(
            f"height {bad[0]} is {z[bad[0]]!r} ({bad.size} non-finite); fill or remove them first"
        )
    if check_periodic:
        _check_periodic(z)
    n = z.size
    q = 2.0 * np.pi * np.arange(n // 2 + 1) / (n * step)
    response = np.zeros_like(q)
    response[1:] = 2.0 / (e * q[1:])
    stiffness = np.zeros_like(q)
    stiffness[1:] = 1.0 / response[1:]
    # full contact: u = z − z̄  ⇒  p = p̄ + K⁻¹(z − z̄) ≥ 0 everywhere
    fluctuation = np.asarray(sfft.irfft(stiffness * sfft.rfft(z), n), dtype=np.float64)
    p_full = float(max(-fluctuation.min(), 0.0))
    z.setflags(write=False)
    response.setflags(write=False)
    return ContactProblem(
        heights=z, dx=step, e_star=e, response=response, full_contact_pressure=p_full
    )


def mirror_extend(profile: Profile) -> Profile:
    """Make a non-periodic profile periodic by appending its mirror image.

    The result has 2n points, z_ext = (z₀ … z_{n−1}, z_{n−1} … z₀): it is even about
    x_{n−1} + dx/2 and about x₀ − dx/2, so it has no wrap-around step. Its contact solution is
    mirror-symmetric and equals that of the original segment between two frictionless symmetry
    walls; statistics of the first n nodes are those of the original profile.

    Parameters
    ----------
    profile : Profile
        Heights [µm] on a uniform grid [µm].

    Returns
    -------
    Profile
        2n points with the same spacing; metadata gains ``"mirror_extended": True``.
    """
    n = profile.n_points
    x = profile.x[0] + profile.dx * np.arange(2 * n)
    z = np.concatenate([profile.z, profile.z[::-1]])
    return Profile(x, z, metadata={**dict(profile.metadata), "mirror_extended": True})


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


# --- solvers --------------------------------------------------------------------------------


def _check_solver_args(tol: float, max_iterations: int) -> None:
    if not np.isfinite(tol) or tol <= 0.0:
        raise BEMParameterError(f"tol must be positive and finite, got {tol!r}")
    if int(max_iterations) < 1:
        raise BEMParameterError(f"max_iterations must be ≥ 1, got {max_iterations!r}")


def _diagonal(response: NDArray[np.float64], n: int) -> float:
    """Diagonal element of the (circulant) influence matrix [µm/GPa]."""
    full = 2.0 * response[1:].sum()
    if n % 2 == 0:
        full -= response[-1]
    return float(full / n)


@dataclass
class _Solution:
    pressure: NDArray[np.float64]
    gap: NDArray[np.float64]
    separation: float
    iterations: int
    residual: float


def _dot(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    """Scalar product without BLAS (threaded BLAS costs milliseconds per call on busy cores)."""
    return float(np.multiply(a, b).sum())


def _residual(g: NDArray[np.float64], loaded: NDArray[np.bool_], scale: float) -> float:
    worst = 0.0
    if loaded.any():
        worst = float(np.abs(g[loaded]).max())
    free = ~loaded
    if free.any():
        worst = max(worst, float(-min(g[free].min(), 0.0)))
    return worst / scale


# --- fused kernels of the load-control loop ---------------------------------------------------
#
# Each kernel is one pass over the nodes. ``fastmath`` lets the reductions be vectorised (their
# order of summation differs from numpy's pairwise sums by rounding only); NaN/Inf semantics are
# kept, so a broken input cannot hide behind the flags.

_FAST = True


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_loaded_sum(
    p: NDArray[np.float64], u: NDArray[np.float64], z: NDArray[np.float64]
) -> tuple[float, int]:  # pragma: no cover - compiled
    """Σ over loaded nodes (p > 0) of u − z, and their count."""
    total = 0.0
    count = 0
    for i in range(p.size):
        loaded = p[i] > 0.0
        total += u[i] - z[i] if loaded else 0.0
        count += 1 if loaded else 0
    return total, count


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_gap(
    p: NDArray[np.float64],
    u: NDArray[np.float64],
    z: NDArray[np.float64],
    separation: float,
    g: NDArray[np.float64],
) -> tuple[float, float, float]:  # pragma: no cover - compiled
    """g = u − z + s; return max |g| on loaded nodes, max overlap −g on free ones, Σ_loaded g²."""
    worst_loaded = 0.0
    worst_free = 0.0
    norm = 0.0
    for i in range(p.size):
        value = (u[i] - z[i]) + separation
        g[i] = value
        loaded = p[i] > 0.0
        worst_loaded = max(worst_loaded, abs(value) if loaded else 0.0)
        worst_free = max(worst_free, 0.0 if loaded else -value)
        norm += value * value if loaded else 0.0
    return worst_loaded, worst_free, norm


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_direction(
    p: NDArray[np.float64],
    g: NDArray[np.float64],
    t: NDArray[np.float64],
    beta: float,
    conjugate: bool,
) -> tuple[float, float]:  # pragma: no cover - compiled
    """t = (β t + g) on loaded nodes, 0 elsewhere (β = 0 restarts); return Σ t and Σ g·t."""
    total = 0.0
    gt = 0.0
    for i in range(p.size):
        value = (t[i] * beta + g[i] if conjugate else g[i]) if p[i] > 0.0 else 0.0
        t[i] = value
        total += value
        gt += g[i] * value
    return total, gt


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_curvature(
    p: NDArray[np.float64], r: NDArray[np.float64], t: NDArray[np.float64]
) -> tuple[float, float]:  # pragma: no cover - compiled
    """Σ r·t and Σ over loaded nodes of r."""
    rt = 0.0
    r_loaded = 0.0
    for i in range(p.size):
        rt += r[i] * t[i]
        r_loaded += r[i] if p[i] > 0.0 else 0.0
    return rt, r_loaded


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_step(
    p: NDArray[np.float64],
    t: NDArray[np.float64],
    g: NDArray[np.float64],
    tau: float,
    changed: NDArray[np.int64],
    delta: NDArray[np.float64],
) -> tuple[float, int, bool]:  # pragma: no cover - compiled
    """p ← max(p − τ t, 0), then p = −τ g where p = 0 and g < 0 (new contact).

    Records the nodes where the result differs from p − τ t (and by how much) in ``changed`` and
    ``delta`` while they fit; returns Σ p, the number of such nodes and whether any node overlapped.
    """
    total = 0.0
    n_changed = 0
    overlap = False
    capacity = changed.size
    for i in range(p.size):
        linear = p[i] - tau * t[i]
        value = linear if linear > 0.0 else 0.0
        if value == 0.0 and g[i] < 0.0:
            value = -tau * g[i]
            overlap = True
        if value != linear:
            if n_changed < capacity:
                changed[n_changed] = i
                delta[n_changed] = value - linear
            n_changed += 1
        p[i] = value
        total += value
    return total, n_changed, overlap


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_add_columns(
    u: NDArray[np.float64],
    column2: NDArray[np.float64],
    changed: NDArray[np.int64],
    delta: NDArray[np.float64],
    n_changed: int,
) -> None:  # pragma: no cover - compiled
    """u += Σ_k δ_k a(· − j_k): the response to a few point loads.

    ``column2`` is the response a to a unit load at node 0, stored twice (length 2n), so that
    a((i − j) mod n) = column2[n − j + i] is one contiguous run for every i.
    """
    n = u.size
    for k in range(n_changed):
        start = n - changed[k]
        d = delta[k]
        run = column2[start : start + n]
        for i in range(n):
            u[i] += d * run[i]


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_rescale(
    p: NDArray[np.float64],
    u: NDArray[np.float64],
    r: NDArray[np.float64],
    z: NDArray[np.float64],
    tau: float,
    factor: float,
    update_u: bool,
) -> tuple[float, int]:  # pragma: no cover - compiled
    """p ← c p, and u ← c (u − τ r) if asked; return Σ_loaded (u − z) and the loaded count."""
    total = 0.0
    count = 0
    for i in range(p.size):
        value = p[i] * factor
        p[i] = value
        if update_u:
            u[i] = (u[i] - tau * r[i]) * factor
        if value > 0.0:
            total += u[i] - z[i]
            count += 1
    return total, count


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_gap_and_direction(
    p: NDArray[np.float64],
    u: NDArray[np.float64],
    z: NDArray[np.float64],
    g: NDArray[np.float64],
    t: NDArray[np.float64],
    separation: float,
    scale: float,
    tol: float,
    conjugate: bool,
    g_norm_old: float,
    may_step: bool,
) -> tuple[float, float, float, float]:  # pragma: no cover - compiled
    """The gap and residual; unless converged (or ``may_step`` is False), the new direction t.

    Returns the residual, Σ_loaded g², Σ t and Σ g·t (the last two 0 when no direction).
    """
    worst_loaded, worst_free, g_norm = _k_gap(p, u, z, separation, g)
    residual = max(worst_loaded, worst_free) / scale
    if residual <= tol or not may_step:
        return residual, g_norm, 0.0, 0.0
    use_beta = conjugate and g_norm_old > 0.0
    beta = g_norm / g_norm_old if use_beta else 0.0
    t_sum, gt = _k_direction(p, g, t, beta, use_beta)
    return residual, g_norm, t_sum, gt


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_advance(
    p: NDArray[np.float64],
    u: NDArray[np.float64],
    r: NDArray[np.float64],
    t: NDArray[np.float64],
    g: NDArray[np.float64],
    z: NDArray[np.float64],
    count: int,
    t_sum: float,
    gt: float,
    tau_fallback: float,
    mean_pressure: float,
    column2: NDArray[np.float64],
    changed: NDArray[np.int64],
    delta: NDArray[np.float64],
    limit: int,
) -> tuple[float, int, bool, bool]:  # pragma: no cover - compiled
    """Line search along t (r = A t), projected step, rescale to the mean pressure.

    u follows p incrementally when few nodes changed (then returns Σ_loaded (u − z) and the
    loaded count for the next iteration, and ``incremental`` True); otherwise u is left for the
    caller to recompute. Also returns whether a node overlapped (conjugacy is then lost).
    """
    rt, r_loaded = _k_curvature(p, r, t)
    denominator = rt - r_loaded / count * t_sum
    tau = gt / denominator if denominator > 0.0 else tau_fallback
    total, n_changed, overlap = _k_step(p, t, g, tau, changed, delta)
    restart = total <= 0.0
    if restart:  # every node was released: restart at the deepest overlap
        p[np.argmin(g)] = 1.0
        total = 1.0
        overlap = True
    factor = mean_pressure * p.size / total
    incremental = not restart and n_changed <= limit
    if incremental:
        _k_add_columns(u, column2, changed, delta, n_changed)
    loaded_sum, new_count = _k_rescale(p, u, r, z, tau, factor, incremental)
    return loaded_sum, new_count, overlap, incremental


class _Operator:
    """u = A p by a real FFT pair.

    Large grids write into preallocated buffers (numpy.fft with ``out=``): a fresh
    half-megabyte spectrum per call costs page faults that double the time at 2¹⁶ nodes. Small
    grids (≤ ``_SMALL_FFT`` nodes) use scipy.fft's allocating calls, measured faster there.
    """

    def __init__(self, response: NDArray[np.float64], n: int) -> None:
        self.response = response
        self.n = n
        self.small = n <= _SMALL_FFT
        self.spectrum = np.empty(response.size, dtype=np.complex128)

    def __call__(self, values: NDArray[np.float64], out: NDArray[np.float64]) -> None:
        if self.small:
            spectrum = sfft.rfft(values)
            spectrum *= self.response
            out[:] = sfft.irfft(spectrum, self.n, overwrite_x=True)
            return
        np.fft.rfft(values, out=self.spectrum)
        np.multiply(self.spectrum, self.response, out=self.spectrum)
        np.fft.irfft(self.spectrum, self.n, out=out)


#: Largest grid [nodes] whose operator uses scipy.fft's allocating transforms.
_SMALL_FFT = 2**14


#: Point loads changed in one iteration up to which their response is added column by column
#: (k·n multiply-adds) instead of re-applying the operator with an FFT pair; per grid size
#: (a negative limit re-applies the operator after every iteration).
def _sparse_limit(n: int) -> int:
    return 3 * max(4, int(math.log2(max(n, 2))))


def _pk_load(
    problem: ContactProblem,
    mean_pressure: float,
    initial: NDArray[np.float64],
    tol: float,
    max_iterations: int,
) -> _Solution:
    """Polonsky–Keer constrained conjugate gradients at fixed mean pressure.

    The displacement u = A p is carried from one iteration to the next: after the step
    p ← c (p − τ t + δ), u ← c (u − τ r + A δ) with r = A t already known and δ the few nodes that
    were released or newly loaded, whose response is added column by column. Only when many nodes
    change is u recomputed with an FFT pair, and always before convergence is declared, so the
    returned gap is that of the returned pressure to FFT accuracy.
    """
    z = problem.heights
    lam = problem.response
    n = z.size
    scale = problem.rms_height
    tau_fallback = 1.0 / _diagonal(lam, n)
    apply = _Operator(lam, n)
    column = np.empty(n)
    unit = np.zeros(n)
    unit[0] = 1.0
    apply(unit, column)
    column2 = np.concatenate([column, column])
    limit = _sparse_limit(n)
    changed = np.empty(max(limit, 0), dtype=np.int64)
    delta = np.empty(max(limit, 0))
    p = initial * (mean_pressure / initial.mean())
    t = np.zeros(n)
    g = np.empty(n)
    r = np.empty(n)
    u = np.empty(n)
    apply(p, u)
    exact = True
    loaded_sum, count = _k_loaded_sum(p, u, z)
    g_norm_old = 0.0
    conjugate = False
    residual = np.inf
    iteration = 0
    while True:
        separation = -loaded_sum / count
        residual, g_norm, t_sum, gt = _k_gap_and_direction(
            p, u, z, g, t, separation, scale, tol, conjugate, g_norm_old,
            iteration < max_iterations,
        )  # fmt: skip
        if residual <= tol:
            if exact:
                return _Solution(p, g, separation, iteration, residual)
            # confirm with the displacement recomputed from the pressure itself
            apply(p, u)
            exact = True
            loaded_sum, count = _k_loaded_sum(p, u, z)
            continue
        if iteration == max_iterations:
            break
        iteration += 1
        g_norm_old = g_norm
        apply(t, r)
        loaded_sum, new_count, overlap, incremental = _k_advance(
            p, u, r, t, g, z, count, t_sum, gt, tau_fallback, mean_pressure, column2, changed,
            delta, limit,
        )  # fmt: skip
        conjugate = not overlap
        count = new_count
        if not incremental:
            apply(p, u)
            loaded_sum, count = _k_loaded_sum(p, u, z)
        exact = not incremental
    raise NoConvergenceError(
        f"load control at mean pressure {mean_pressure:.6g} GPa did not converge in "
        f"{max_iterations} iterations (residual {residual:.3g} > tol {tol:.3g}); raise "
        "max_iterations or tol, or approach this load in smaller steps (load_path)"
    )


def _pcg_gap(
    problem: ContactProblem,
    separation: float,
    initial: NDArray[np.float64],
    tol: float,
    max_iterations: int,
) -> _Solution:
    """Projected conjugate gradients at fixed rigid position s (displacement control)."""
    z = problem.heights
    lam = problem.response
    n = z.size
    scale = problem.rms_height
    tau_fallback = 1.0 / _diagonal(lam, n)
    p = initial.copy()
    t = np.zeros(n)
    g_norm_old = 0.0
    conjugate = False
    residual = np.inf
    for iteration in range(max_iterations + 1):
        g = _apply(lam, p) + separation - z
        loaded = p > 0.0
        residual = _residual(g, loaded, scale)
        if residual <= tol:
            return _Solution(p, g, separation, iteration, residual)
        if iteration == max_iterations:
            break
        g_loaded = np.where(loaded, g, 0.0)
        g_norm = float(_dot(g_loaded, g_loaded))
        if conjugate and g_norm_old > 0.0:
            t = g_loaded + (g_norm / g_norm_old) * t
        else:
            t = g_loaded
        t[~loaded] = 0.0
        g_norm_old = g_norm
        if not loaded.any():
            # nothing loaded yet: exact line search along the overlap d = max(−g, 0)
            d = np.clip(-g, 0.0, None)
            curvature = _dot(d, _apply(lam, d))
            step = _dot(d, d) / curvature if curvature > 0.0 else tau_fallback
            p = step * d
            conjugate = False
            continue
        r = _apply(lam, t)
        denominator = float(_dot(r[loaded], t[loaded]))
        tau = float(_dot(g_loaded, t)) / denominator if denominator > 0.0 else tau_fallback
        if loaded.all():
            # every node loaded: the uniform mode costs no elastic energy, so do not step
            # beyond the first node that unloads
            positive = t > 0.0
            if positive.any():
                tau = min(tau, float(np.min(p[positive] / t[positive])))
        p = p - tau * t
        p[p < 0.0] = 0.0
        overlap = (p == 0.0) & (g < 0.0)
        if overlap.any():
            conjugate = False
            p[overlap] = -tau * g[overlap]
        else:
            conjugate = True
    raise NoConvergenceError(
        f"displacement control at mean gap {separation - problem.mean_height:.6g} µm did not "
        f"converge in {max_iterations} iterations (residual {residual:.3g} > tol {tol:.3g}); "
        "raise max_iterations or tol, or approach this gap in smaller steps (gap_path)"
    )


def _initial_guess(problem: ContactProblem, mean_pressure: float) -> NDArray[np.float64]:
    """Bearing-area guess: pressure ∝ height above the level that leaves a fraction in contact."""
    z = problem.heights
    fraction = min(max(mean_pressure / problem.full_contact_pressure, 1.0 / z.size), 0.5)
    level = float(np.quantile(z, 1.0 - fraction))
    p = np.clip(z - level, 0.0, None)
    if p.sum() <= 0.0:
        p = np.zeros_like(z)
        p[np.argmax(z)] = 1.0
    return p


def _make_step(
    problem: ContactProblem, sol: _Solution, mean_pressure: float, fields: bool
) -> BEMStep:
    stats = contact_statistics(sol.pressure, problem.dx)
    mean_gap = sol.separation - problem.mean_height
    pressure = gap = None
    if fields:
        pressure = sol.pressure.copy()
        gap = np.where(sol.pressure > 0.0, 0.0, np.clip(sol.gap, 0.0, None))
        pressure.setflags(write=False)
        gap.setflags(write=False)
    return BEMStep(
        mean_pressure=float(mean_pressure),
        force=float(mean_pressure * problem.length),
        mean_gap=float(mean_gap),
        approach=float(problem.first_contact_gap - mean_gap),
        contact_nodes=stats.contact_nodes,
        contact_length=stats.contact_length,
        contact_length_subgrid=stats.contact_length_subgrid,
        n_patches=stats.n_patches,
        iterations=sol.iterations,
        residual=sol.residual,
        pressure=pressure,
        gap=gap,
    )


def _touching(problem: ContactProblem, fields: bool) -> BEMStep:
    """Zero load: the flat touches the highest node(s) without pressure."""
    z = problem.heights
    gap_field = z.max() - z
    pressure = gap = None
    if fields:
        pressure = np.zeros_like(z)
        gap = gap_field
        pressure.setflags(write=False)
        gap.setflags(write=False)
    return BEMStep(
        mean_pressure=0.0,
        force=0.0,
        mean_gap=problem.first_contact_gap,
        approach=0.0,
        contact_nodes=0,
        contact_length=0.0,
        contact_length_subgrid=0.0,
        n_patches=0,
        iterations=0,
        residual=0.0,
        pressure=pressure,
        gap=gap,
    )


def _check_load(problem: ContactProblem, mean_pressure: float) -> float:
    value = float(mean_pressure)
    if not np.isfinite(value):
        raise NegativeLoadError(f"mean pressure must be finite [GPa], got {mean_pressure!r}")
    if value < 0.0:
        raise NegativeLoadError(
            f"mean pressure {value!r} GPa is negative; the contact is non-adhesive — pass p̄ ≥ 0"
        )
    if value >= problem.full_contact_pressure:
        raise FullContactError(
            f"mean pressure {value!r} GPa is at or beyond full contact "
            f"(p_full = {problem.full_contact_pressure!r} GPa, force "
            f"{problem.full_contact_pressure * problem.length!r} mN/µm): every node touches "
            "there; pass a smaller load"
        )
    return value


def _solve_load_state(
    problem: ContactProblem,
    mean_pressure: float,
    initial: NDArray[np.float64] | None,
    tol: float,
    max_iterations: int,
) -> _Solution:
    guess = initial
    if guess is None or guess.shape != problem.heights.shape or not np.any(guess > 0.0):
        guess = _initial_guess(problem, mean_pressure)
    else:
        guess = np.clip(np.asarray(guess, dtype=np.float64), 0.0, None)
    return _pk_load(problem, mean_pressure, guess, tol, max_iterations)


def solve_pressure(
    problem: ContactProblem,
    mean_pressure: float,
    *,
    initial_pressure: ArrayLike | None = None,
    tol: float = DEFAULT_TOLERANCE,
    max_iterations: int = DEFAULT_MAX_ITERATIONS,
    fields: bool = False,
) -> BEMStep:
    """Solve the contact at a given mean pressure (load control).

    Parameters
    ----------
    problem : ContactProblem
        From :func:`contact_problem`.
    mean_pressure : float
        p̄ [GPa], 0 ≤ p̄ < ``problem.full_contact_pressure``; the force is p̄·L [mN/µm].
    initial_pressure : array_like, optional
        Warm start [GPa] (for example the previous step's field); rescaled to p̄.
    tol : float
        Largest complementarity violation / rms height at convergence [1].
    max_iterations : int
        Iteration limit.
    fields : bool
        Also return the pressure and gap fields.

    Returns
    -------
    BEMStep

    Raises
    ------
    NegativeLoadError
        p̄ < 0 or not finite.
    FullContactError
        p̄ ≥ full-contact pressure.
    NoConvergenceError
        The tolerance was not reached within ``max_iterations``.
    BEMParameterError
        tol ≤ 0 or max_iterations < 1.
    """
    _check_solver_args(tol, max_iterations)
    value = _check_load(problem, mean_pressure)
    if value == 0.0:
        return _touching(problem, fields)
    initial = None if initial_pressure is None else np.asarray(initial_pressure, dtype=np.float64)
    sol = _solve_load_state(problem, value, initial, tol, max_iterations)
    return _make_step(problem, sol, value, fields)


def _check_gap(problem: ContactProblem, mean_gap: float) -> float:
    value = float(mean_gap)
    if not np.isfinite(value):
        raise FullContactError(f"mean gap must be finite [µm], got {mean_gap!r}")
    if value <= 0.0:
        raise FullContactError(
            f"mean gap {value!r} µm is at or beyond full contact (reached at mean gap 0, mean "
            f"pressure {problem.full_contact_pressure!r} GPa); pass a positive mean gap"
        )
    return value


def solve_gap(
    problem: ContactProblem,
    mean_gap: float,
    *,
    initial_pressure: ArrayLike | None = None,
    tol: float = DEFAULT_TOLERANCE,
    max_iterations: int = DEFAULT_MAX_ITERATIONS,
    fields: bool = False,
) -> BEMStep:
    """Solve the contact at a given mean gap (displacement control).

    Parameters
    ----------
    problem : ContactProblem
        From :func:`contact_problem`.
    mean_gap : float
        ḡ [µm], 0 < ḡ; at ḡ ≥ max z − z̄ the surfaces do not touch (zero load).
    initial_pressure : array_like, optional
        Warm start [GPa].
    tol, max_iterations, fields
        As in :func:`solve_pressure`.

    Returns
    -------
    BEMStep
        With the resulting mean pressure and force.

    Raises
    ------
    FullContactError
        ḡ ≤ 0 or not finite.
    NoConvergenceError
        The tolerance was not reached within ``max_iterations``.
    """
    _check_solver_args(tol, max_iterations)
    value = _check_gap(problem, mean_gap)
    if value >= problem.first_contact_gap:
        step = _touching(problem, fields)
        if value == problem.first_contact_gap:
            return step
        return BEMStep(
            **{
                **{k: getattr(step, k) for k in STEP_UNITS},
                "mean_gap": value,
                "approach": problem.first_contact_gap - value,
                "pressure": step.pressure,
                "gap": None if step.gap is None else step.gap + (value - step.mean_gap),
            }
        )
    separation = value + problem.mean_height
    if initial_pressure is None:
        guess = np.zeros(problem.n_points)
    else:
        guess = np.clip(np.asarray(initial_pressure, dtype=np.float64), 0.0, None)
        if guess.shape != problem.heights.shape:
            guess = np.zeros(problem.n_points)
    sol = _pcg_gap(problem, separation, guess, tol, max_iterations)
    return _make_step(problem, sol, float(sol.pressure.mean()), fields)


def load_path(
    problem: ContactProblem,
    mean_pressures: Sequence[float] | NDArray[np.float64],
    *,
    tol: float = DEFAULT_TOLERANCE,
    max_iterations: int = DEFAULT_MAX_ITERATIONS,
    fields: bool = False,
) -> BEMPath:
    """Solve a sequence of loads, each warm-started from the previous solution.

    Parameters
    ----------
    problem : ContactProblem
        From :func:`contact_problem`.
    mean_pressures : sequence of float
        p̄ per step [GPa] (any order; increasing is fastest). Forces are p̄·L [mN/µm].
    tol, max_iterations, fields
        As in :func:`solve_pressure`.

    Returns
    -------
    BEMPath

    Raises
    ------
    NegativeLoadError, FullContactError
        For the first offending step, before anything is solved.
    NoConvergenceError
        A step did not converge.

    Examples
    --------
    A sinusoid pressed flat (Westergaard): p̄/p* = sin²(πa/λ), so at half the full-contact
    pressure p* the contact covers half the wavelength.

    >>> import numpy as np
    >>> from splinecontact import bem
    >>> n, wavelength = 256, 10.0
    >>> x = np.arange(n) * (wavelength / n)
    >>> z = 0.01 * np.cos(2 * np.pi * x / wavelength)
    >>> problem = bem.contact_problem(z, e_star=10.0, dx=wavelength / n)
    >>> path = bem.load_path(problem, [0.25 * problem.full_contact_pressure,
    ...                                0.5 * problem.full_contact_pressure])
    >>> round(path.steps[-1].contact_length_subgrid, 1), path.steps[-1].n_patches
    (5.0, 1)
    >>> path.to_xarray()["contact_length_subgrid"].attrs["units"]
    'µm'
    """
    _check_solver_args(tol, max_iterations)
    loads = [_check_load(problem, p) for p in np.asarray(mean_pressures, dtype=np.float64)]
    steps: list[BEMStep] = []
    previous: NDArray[np.float64] | None = None
    for load in loads:
        if load == 0.0:
            steps.append(_touching(problem, fields))
            continue
        sol = _solve_load_state(problem, load, previous, tol, max_iterations)
        previous = sol.pressure
        steps.append(_make_step(problem, sol, load, fields))
    return BEMPath(tuple(steps), problem.e_star, problem.dx, problem.n_points, float(tol))


def gap_path(
    problem: ContactProblem,
    mean_gaps: Sequence[float] | NDArray[np.float64],
    *,
    tol: float = DEFAULT_TOLERANCE,
    max_iterations: int = DEFAULT_MAX_ITERATIONS,
    fields: bool = False,
) -> BEMPath:
    """Solve a sequence of mean gaps (displacement control), each warm-started.

    Parameters
    ----------
    problem : ContactProblem
        From :func:`contact_problem`.
    mean_gaps : sequence of float
        ḡ per step [µm], each > 0 (decreasing is fastest).
    tol, max_iterations, fields
        As in :func:`solve_pressure`.

    Returns
    -------
    BEMPath
    """
    _check_solver_args(tol, max_iterations)
    gaps = [_check_gap(problem, g) for g in np.asarray(mean_gaps, dtype=np.float64)]
    steps: list[BEMStep] = []
    previous: NDArray[np.float64] | None = None
    for value in gaps:
        step = solve_gap(
            problem,
            value,
            initial_pressure=previous,
            tol=tol,
            max_iterations=max_iterations,
            fields=True,
        )
        previous = None if step.pressure is None else np.array(step.pressure)
        if not fields:
            step = BEMStep(**{k: getattr(step, k) for k in STEP_UNITS})
        steps.append(step)
    return BEMPath(tuple(steps), problem.e_star, problem.dx, problem.n_points, float(tol))
