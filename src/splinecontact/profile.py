"""Surface profiles: a uniform grid ``x`` [µm] and heights ``z`` [µm].

A :class:`Profile` is the input of every later stage. Heights are stored as a profilometer
records them: pointing *out of the body* the profile belongs to (a peak is a maximum of ``z``).
:func:`splinecontact.simulate` turns the upper body over to face the lower one.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ._checks import LENGTH_LIMIT
from .errors import (
    GridNotIncreasingError,
    GridNotUniformError,
    NonFiniteValueError,
    ProfileRangeError,
    ProfileShapeError,
    ProfileTypeError,
    TooFewPointsError,
)

__all__ = [
    "LENGTH_LIMIT",
    "MIN_POINTS",
    "MIN_STEP",
    "UNIFORM_GRID_RTOL",
    "Profile",
    "rms_slope",
    "roughness_average",
    "roughness_rms",
    "slope_rms",
    "surface_statistics",
]

#: Fewest points a profile may have (the spline of eqs. 2–3 needs a few interior knots).
MIN_POINTS = 5

#: Smallest grid step accepted [µm] (10⁻³⁰ µm; the spline needs dx³, which must stay a normal
#: floating-point number).
MIN_STEP = 1e-30

#: Largest allowed deviation of any grid step from the mean step, relative to the mean step.
UNIFORM_GRID_RTOL = 1e-6


def _as_float_vector(values: ArrayLike, name: str) -> NDArray[np.float64]:
    try:
        raw = np.asarray(values)
    except (TypeError, ValueError) as exc:
        raise ProfileShapeError(
            f"{name} cannot be read as an array ({exc}); pass a one-dimensional array of numbers"
        ) from None
    if raw.dtype.kind == "c":
        raise ProfileTypeError(
            f"{name} holds complex numbers (dtype {raw.dtype}); positions and heights must be "
            f"real: pass {name}.real (or the modulus) explicitly"
        )
    if raw.dtype.kind not in "biuf":
        try:
            raw = raw.astype(np.float64)
        except (TypeError, ValueError) as exc:
            raise ProfileTypeError(
                f"{name} is not an array of real numbers (dtype {raw.dtype}: {exc}); "
                "pass numbers in µm"
            ) from None
    array = np.array(raw, dtype=np.float64, copy=True)
    if array.ndim != 1:
        raise ProfileShapeError(
            f"{name} must be a one-dimensional array, got shape {array.shape}; "
            "pass a single line scan"
        )
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class Profile:
    """A line profile of a rough surface on a uniform grid.

    Parameters
    ----------
    x : array_like
        Lateral positions [µm], strictly increasing and uniformly spaced (every step within
        ``UNIFORM_GRID_RTOL`` = 1e-6 of the mean step, relative).
    z : array_like
        Heights [µm], pointing out of the body the profile belongs to.
    metadata : mapping, optional
        Provenance: ``source`` (generator name or file), generator parameters, seed,
        preprocessing steps. Stored as a plain ``dict``; treat it as read-only.

    Raises
    ------
    ProfileShapeError
        ``x`` or ``z`` is not one-dimensional, or their lengths differ.
    TooFewPointsError
        Fewer than ``MIN_POINTS`` (5) points.
    ProfileTypeError
        ``x`` or ``z`` holds complex numbers or values that are not numbers, or ``metadata`` is
        not a mapping.
    NonFiniteValueError
        A value of ``x`` or ``z`` is NaN or infinite (the message names the first index).
    ProfileRangeError
        A value of ``x`` or ``z`` is beyond ±``LENGTH_LIMIT`` (10⁵⁰ µm), or the grid step is
        below ``MIN_STEP`` (10⁻³⁰ µm): the computation would overflow or underflow.
    GridNotIncreasingError
        ``x`` is not strictly increasing (the message names the first offending index).
    GridNotUniformError
        A grid step differs from the mean step by more than ``UNIFORM_GRID_RTOL``.

    Notes
    -----
    The arrays are copied and made read-only, so a profile never changes after construction.

    Examples
    --------
    >>> import numpy as np
    >>> from splinecontact import Profile
    >>> profile = Profile(np.linspace(0.0, 1.0, 5), np.array([0.0, 1.0, 0.0, -1.0, 0.0]))
    >>> profile.dx, profile.ra, round(profile.rq, 6)
    (0.25, 0.4, 0.632456)
    """

    x: NDArray[np.float64]
    z: NDArray[np.float64]
    metadata: Mapping[str, Any] = field(default_factory=dict)

    def __init__(
        self, x: ArrayLike, z: ArrayLike, *, metadata: Mapping[str, Any] | None = None
    ) -> None:
        x_arr = _as_float_vector(x, "x")
        z_arr = _as_float_vector(z, "z")
        if x_arr.size != z_arr.size:
            raise ProfileShapeError(
                f"x has {x_arr.size} points but z has {z_arr.size}; they must have the same length"
            )
        if x_arr.size < MIN_POINTS:
            raise TooFewPointsError(
                f"a profile needs at least {MIN_POINTS} points, got {x_arr.size}"
            )
        for name, arr in (("x", x_arr), ("z", z_arr)):
            bad = np.flatnonzero(~np.isfinite(arr))
            if bad.size:
                i = int(bad[0])
                raise NonFiniteValueError(
                    f"{name}[{i}] = {float(arr[i])!r} is not finite ({bad.size} non-finite "
                    f"value(s) in {name}); remove or fill undefined points first"
                )
        for name, arr in (("x", x_arr), ("z", z_arr)):
            big = np.flatnonzero(np.abs(arr) > LENGTH_LIMIT)
            if big.size:
                i = int(big[0])
                raise ProfileRangeError(
                    f"{name}[{i}] = {float(arr[i])!r} µm is beyond ±{LENGTH_LIMIT:g} µm, where "
                    "the contact computation would overflow; check the unit (lengths are in µm)"
                )
        steps = np.diff(x_arr)
        bad = np.flatnonzero(steps <= 0.0)
        if bad.size:
            i = int(bad[0]) + 1
            raise GridNotIncreasingError(
                f"x is not strictly increasing at index {i} "
                f"(x[{i - 1}]={float(x_arr[i - 1])!r} µm, x[{i}]={float(x_arr[i])!r} µm); "
                "sort or deduplicate the scan first"
            )
        mean_step = (x_arr[-1] - x_arr[0]) / (x_arr.size - 1)
        if mean_step < MIN_STEP:
            raise ProfileRangeError(
                f"the grid step dx = {float(mean_step)!r} µm is below {MIN_STEP:g} µm, where the "
                "spline's dx³ underflows; check the lateral unit (lengths are in µm)"
            )
        deviation = np.abs(steps - mean_step)
        worst = int(np.argmax(deviation))
        if deviation[worst] > UNIFORM_GRID_RTOL * mean_step:
            raise GridNotUniformError(
                f"x is not uniformly spaced: step {worst}→{worst + 1} is "
                f"{float(steps[worst])!r} µm but the mean step is {float(mean_step)!r} µm "
                f"(relative deviation {deviation[worst] / mean_step:.3g} > {UNIFORM_GRID_RTOL:g});"
                " resample the scan onto a uniform grid first"
            )
        object.__setattr__(self, "x", x_arr)
        object.__setattr__(self, "z", z_arr)
        if metadata is not None and not isinstance(metadata, Mapping):
            raise ProfileTypeError(
                f"metadata = {metadata!r} is not a mapping; pass a dict (or nothing)"
            )
        object.__setattr__(self, "metadata", dict(metadata) if metadata is not None else {})

    @classmethod
    def _from_trusted(
        cls, x: NDArray[np.float64], z: NDArray[np.float64], metadata: Mapping[str, Any]
    ) -> Profile:
        """Wrap arrays the package itself just made (uniform grid, finite, read-only float64).

        No copy and no validation: for generators whose output satisfies the invariants by
        construction. Everything else goes through ``Profile(x, z)``.
        """
        profile = object.__new__(cls)
        object.__setattr__(profile, "x", x)
        object.__setattr__(profile, "z", z)
        object.__setattr__(profile, "metadata", dict(metadata))
        return profile

    # -- derived quantities -------------------------------------------------------------------

    @property
    def n_points(self) -> int:
        """Number of grid points."""
        return int(self.x.size)

    @property
    def dx(self) -> float:
        """Grid spacing [µm] (mean step)."""
        return float((self.x[-1] - self.x[0]) / (self.x.size - 1))

    @property
    def length(self) -> float:
        """Extent of the grid, ``x[-1] - x[0]`` [µm]."""
        return float(self.x[-1] - self.x[0])

    @property
    def ra(self) -> float:
        """Arithmetic mean roughness R_A = mean |z − mean(z)| [µm]."""
        return roughness_average(self.z)

    @property
    def rq(self) -> float:
        """Root-mean-square roughness R_q [µm]."""
        return roughness_rms(self.z)

    @property
    def rsq(self) -> float:
        """Root-mean-square slope R_Sq [1] from grid differences (paper eq. 15)."""
        return rms_slope(self.z, self.dx)

    @property
    def peak_to_valley(self) -> float:
        """Peak-to-valley height max(z) − min(z) [µm]."""
        return float(self.z.max() - self.z.min())

    def __repr__(self) -> str:
        source = self.metadata.get("source", "?")
        return (
            f"Profile(n_points={self.n_points}, dx={self.dx:.4g} µm, length={self.length:.4g} µm, "
            f"ra={self.ra:.4g} µm, source={source!r})"
        )


# --- roughness parameters: the one place they are computed ------------------------------------


def roughness_average(z: NDArray[np.float64]) -> float:
    """Arithmetic mean roughness R_A = mean |z − mean(z)| [µm] of heights ``z`` [µm]."""
    return float(np.mean(np.abs(z - z.mean())))


def roughness_rms(z: NDArray[np.float64]) -> float:
    """Root-mean-square roughness R_q = √mean (z − mean(z))² [µm] of heights ``z`` [µm]."""
    return float(np.sqrt(np.mean((z - z.mean()) ** 2)))


def rms_slope(z: NDArray[np.float64], dx: float) -> float:
    """Root-mean-square slope R_Sq [1] of heights ``z`` [µm] on a grid of step ``dx`` [µm].

    Grid differences, paper eq. 15: R_Sq = √(Σ_i ((z_i − z_{i−1})/dx)² / (n − 1)).
    """
    return float(np.sqrt(np.mean((np.diff(z) / dx) ** 2)))


def slope_rms(slope: NDArray[np.float64]) -> float:
    """Root-mean-square of given slopes [1] (e.g. a spline's f′ at the grid points)."""
    return float(np.sqrt(np.mean(slope * slope)))


def surface_statistics(
    lower: Profile,
    upper: Profile | None,
    spline_slope_lower: NDArray[np.float64],
    spline_slope_upper: NDArray[np.float64] | None,
) -> dict[str, float]:
    """The roughness scalars a simulation records (``SCALAR_VARIABLES`` of the results).

    Parameters
    ----------
    lower : Profile
        Lower body (heights [µm]).
    upper : Profile or None
        Upper body sharing the grid, or ``None`` for a rigid flat (its roughness is 0).
    spline_slope_lower, spline_slope_upper : ndarray or None
        Smoothing-spline slopes f′ [1] at the grid points (eqs. 2–3); ``None`` for a flat.

    Returns
    -------
    dict
        R_A, R_q [µm], peak-to-valley [µm] of the lower body, R_Sq [1] (eq. 15) of each body
        and of the gap z^u + z^l (the gap's slope up to sign), and the same slopes from the
        spline (``*_spline``).
    """
    rsq_lower = lower.rsq
    if upper is None:
        ra_u = rq_u = rsq_u = rsq_upper_spline = 0.0
        rsq_gap = rsq_lower
        rsq_gap_spline = slope_rms(spline_slope_lower)
    else:
        assert spline_slope_upper is not None
        ra_u, rq_u, rsq_u = upper.ra, upper.rq, upper.rsq
        rsq_gap = rms_slope(lower.z + upper.z, lower.dx)
        rsq_upper_spline = slope_rms(spline_slope_upper)
        rsq_gap_spline = slope_rms(spline_slope_lower + spline_slope_upper)
    return {
        "ra_lower": lower.ra,
        "rq_lower": lower.rq,
        "peak_to_valley_lower": lower.peak_to_valley,
        "rsq_lower": rsq_lower,
        "rsq_lower_spline": slope_rms(spline_slope_lower),
        "ra_upper": ra_u,
        "rq_upper": rq_u,
        "rsq_upper": rsq_u,
        "rsq_upper_spline": rsq_upper_spline,
        "rsq_gap": rsq_gap,
        "rsq_gap_spline": rsq_gap_spline,
    }
