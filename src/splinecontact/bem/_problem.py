"""The periodic contact problem of the BEM: composite heights, grid, modulus and response.

The surface response (plane strain) û(q) = 2 p̂(q)/(E*|q|), q_k = 2πk/L, its q = 0 mode set to
zero; the composite profile z = z_lower + z_upper against a flat (see :mod:`splinecontact.bem`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np
import scipy.fft as sfft
from numpy.typing import ArrayLike, NDArray

from ..errors import BEMGridError, BEMParameterError, NonPeriodicProfileError
from ..profile import Profile

__all__ = [
    "DEFAULT_MAX_ITERATIONS",
    "DEFAULT_TOLERANCE",
    "MIN_BEM_POINTS",
    "PERIODIC_JUMP_FACTOR",
    "ContactProblem",
    "contact_problem",
    "mirror_extend",
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
