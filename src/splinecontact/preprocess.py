"""Preprocessing of measured line scans: from raw arrays to a :class:`~splinecontact.Profile`.

A :class:`~splinecontact.Profile` only accepts finite heights on a strictly increasing, uniform
grid. Measured data often is not like that: instruments flag undefined points, exports repeat
rows or step back in ``x``, and text files print positions with a few decimals so that a
uniform grid looks irregular. The readers of :mod:`splinecontact.io` therefore return a
:class:`RawProfile` (plain arrays in µm, undefined points as NaN), and :func:`to_profile`
applies an explicit :class:`Preprocessing` policy before the profile is built.

Every policy refuses questionable data by default, with an error naming the index (and file
line) and the option that handles it. Every step that changes the data is recorded, in order,
in ``Profile.metadata["preprocessing"]`` (a list of dicts), so a result file says exactly what
was done to the measurement.

Order of the steps in :func:`to_profile`:

1. undefined points (NaN heights or positions, instrument "invalid" flags) — refused, or kept
   for step 5 (rows whose *position* is undefined are dropped: their place is unknown);
2. cropping to an ``x`` range;
3. order — ``x`` stepping back is refused, or the points are sorted by ``x`` (stable);
4. duplicate positions — refused, or averaged (heights of equal ``x`` are averaged);
5. filling undefined heights by linear interpolation between defined neighbours (undefined
   points at either end cannot be interpolated and are trimmed, and that is recorded);
6. the grid: a grid that is uniform to within the resolution the file was written with is
   regularised (positions replaced by the least-squares uniform grid, heights untouched); any other
   non-uniform grid is refused, or resampled onto a uniform grid by linear interpolation;
7. origin shift (``x`` starts at 0) on request;
8. form removal: mean, tilt or a polynomial of given degree (least squares).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.polynomial import Polynomial
from numpy.typing import ArrayLike, NDArray

from .errors import (
    CropError,
    DuplicatePositionError,
    GridNotUniformError,
    GridOrderError,
    PreprocessingOptionError,
    ProfileError,
    ProfileShapeError,
    UndefinedPointsError,
)
from .profile import MIN_POINTS, UNIFORM_GRID_RTOL, Profile

__all__ = [
    "CURVATURE_BIAS_LIMIT",
    "MAX_RESAMPLE_POINTS",
    "CropError",
    "DuplicatePositionError",
    "GridOrderError",
    "Preprocessing",
    "PreprocessingOptionError",
    "RawProfile",
    "SplineResolution",
    "UndefinedPointsError",
    "crop",
    "detrend",
    "detrend_degree",
    "spline_resolution",
    "to_profile",
]

#: Number of offending positions listed in an error message.
_MAX_LISTED = 5

#: Largest |height| [µm] a form is fitted to (squares must stay finite in the least squares).
_FIT_LIMIT = 1e150

#: Default ceiling on the number of points resampling may create (``Preprocessing.max_points``).
MAX_RESAMPLE_POINTS = 100_000_000


# --- data -----------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class RawProfile:
    """A line scan as read from a file, before any check or correction.

    Parameters
    ----------
    x : array_like
        Lateral positions [µm], in file order; may be unsorted, repeated or non-finite.
    z : array_like
        Heights [µm], pointing out of the body; NaN marks an undefined point.
    rows : array_like of int, optional
        1-based line number in the source file of each point (text formats), used in error
        messages. ``None`` for binary formats (messages then give the index only).
    x_resolution : float, optional
        Resolution [µm] with which the positions were written: for text, one unit of the last
        printed decimal, the finest over all non-zero positions (``4`` next to ``4.5`` was
        printed without trailing zeros, so the resolution is 0.1). ``0`` when the positions
        are exact (binary formats).
    metadata : mapping, optional
        Provenance: ``source`` (file), ``format``, units and conversions, instrument data.
    """

    x: NDArray[np.float64]
    z: NDArray[np.float64]
    rows: NDArray[np.int64] | None = None
    x_resolution: float = 0.0
    metadata: Mapping[str, Any] = field(default_factory=dict)

    def __init__(
        self,
        x: ArrayLike,
        z: ArrayLike,
        *,
        rows: ArrayLike | None = None,
        x_resolution: float = 0.0,
        metadata: Mapping[str, Any] | None = None,
    ) -> None:
        x_in, z_in = np.asarray(x), np.asarray(z)
        if x_in.ndim != 1 or z_in.ndim != 1:
            raise ProfileShapeError(
                f"x has shape {x_in.shape} and z {z_in.shape}; a raw scan is one line of "
                "points (choose one row of areal data with line=, never a flattened map)"
            )
        for name, values in (("x", x_in), ("z", z_in)):
            if np.iscomplexobj(values) or not (
                np.issubdtype(values.dtype, np.number) or values.dtype == bool
            ):
                raise ProfileShapeError(
                    f"{name} has dtype {values.dtype}; a raw scan needs real numbers"
                )
        x_arr = np.array(x_in, dtype=np.float64)
        z_arr = np.array(z_in, dtype=np.float64)
        if x_arr.size != z_arr.size:
            raise ProfileError(
                f"x has {x_arr.size} points but z has {z_arr.size}; they must have the same length"
            )
        rows_arr = None
        if rows is not None:
            rows_arr = np.array(rows, dtype=np.int64).ravel()
            if rows_arr.size != x_arr.size:
                raise ProfileError("rows must have one line number per point")
        object.__setattr__(self, "x", x_arr)
        object.__setattr__(self, "z", z_arr)
        object.__setattr__(self, "rows", rows_arr)
        object.__setattr__(self, "x_resolution", float(x_resolution))
        object.__setattr__(self, "metadata", dict(metadata) if metadata is not None else {})

    @property
    def n_points(self) -> int:
        """Number of points in the file (defined or not)."""
        return int(self.x.size)


UndefinedPolicy = Literal["refuse", "interpolate"]
OrderPolicy = Literal["refuse", "sort"]
DuplicatePolicy = Literal["refuse", "average"]
GridPolicy = Literal["refuse", "resample"]


@dataclass(frozen=True)
class Preprocessing:
    """What :func:`to_profile` may do to a measured scan. The defaults change nothing and refuse.

    Parameters
    ----------
    undefined : {"refuse", "interpolate"}
        Undefined points (NaN, instrument "invalid" flags): refuse (default, the error gives
        their count and positions) or fill the heights by linear interpolation between the
        nearest defined neighbours. Undefined points at either end are trimmed.
    order : {"refuse", "sort"}
        ``x`` stepping back: refuse (default) or sort the points by ``x`` (stable sort).
    duplicates : {"refuse", "average"}
        Repeated ``x`` positions: refuse (default) or replace each group by one point with
        the mean of their (defined) heights.
    nonuniform : {"refuse", "resample"}
        A grid that is not uniform (beyond the printing resolution of the file, see
        :func:`to_profile`): refuse (default) or resample onto a uniform grid by linear
        interpolation.
    resample_spacing : float, optional
        Spacing [µm] of the uniform grid when resampling; default: the same number of points
        over the same range. Only used with ``nonuniform="resample"``.
    crop : (float, float), optional
        Keep only points with ``crop[0] <= x <= crop[1]`` [µm] (positions after unit
        conversion, before any origin shift). ``None`` keeps everything.
    zero_origin : bool
        Shift ``x`` so that the profile starts at 0 µm (heights untouched).
    detrend : {"none", "mean", "tilt"} or int
        Form removal by least squares: nothing, the mean height, a straight line, or a
        polynomial of the given degree (0 is the mean, 1 the tilt). Applied last.
    max_points : int
        Largest number of points [1] resampling may create (default 10⁸); a
        ``resample_spacing`` that would create more is refused before anything is allocated.
    """

    undefined: UndefinedPolicy = "refuse"
    order: OrderPolicy = "refuse"
    duplicates: DuplicatePolicy = "refuse"
    nonuniform: GridPolicy = "refuse"
    resample_spacing: float | None = None
    crop: tuple[float, float] | None = None
    zero_origin: bool = False
    detrend: str | int = "none"
    max_points: int = MAX_RESAMPLE_POINTS

    def __post_init__(self) -> None:
        choices: dict[str, tuple[str, ...]] = {
            "undefined": ("refuse", "interpolate"),
            "order": ("refuse", "sort"),
            "duplicates": ("refuse", "average"),
            "nonuniform": ("refuse", "resample"),
        }
        for name, allowed in choices.items():
            value = getattr(self, name)
            if value not in allowed:
                raise PreprocessingOptionError(
                    f"{name}={value!r} is not one of {', '.join(map(repr, allowed))}"
                )
        if isinstance(self.max_points, bool) or not (
            isinstance(self.max_points, int | np.integer) and self.max_points >= 1
        ):
            raise PreprocessingOptionError(
                f"max_points={self.max_points!r} must be a positive integer"
            )
        if self.resample_spacing is not None and not (
            isinstance(self.resample_spacing, int | float | np.floating | np.integer)
            and not isinstance(self.resample_spacing, bool)
            and np.isfinite(self.resample_spacing)
            and self.resample_spacing > 0
        ):
            raise PreprocessingOptionError(
                f"resample_spacing={self.resample_spacing!r} µm must be positive"
            )
        if self.crop is not None:
            try:
                lo, hi = (float(v) for v in self.crop)
            except (TypeError, ValueError):
                raise PreprocessingOptionError(
                    f"crop={self.crop!r} is not a range; give (x_min, x_max) [µm]"
                ) from None
            if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
                raise PreprocessingOptionError(
                    f"crop=({lo!r}, {hi!r}) µm is not a range; give (x_min, x_max) with "
                    "x_min < x_max"
                )
        detrend_degree(self.detrend)  # validates


def detrend_degree(detrend: str | int) -> int | None:
    """Polynomial degree of a form-removal option (``None`` for no form removal).

    Parameters
    ----------
    detrend : {"none", "mean", "tilt", "polyN"} or int
        ``"mean"`` is degree 0, ``"tilt"`` degree 1, ``"polyN"`` or ``N`` degree N (0–10).
    """
    if isinstance(detrend, bool):
        raise PreprocessingOptionError(f"detrend={detrend!r} is not a form-removal option")
    if isinstance(detrend, int | np.integer):
        degree = int(detrend)
    else:
        text = str(detrend).strip().lower()
        named = {"none": None, "mean": 0, "tilt": 1}
        if text in named:
            return named[text]
        digits = text.removeprefix("poly").removeprefix("nomial").strip(" :=")
        if not digits.isdigit():
            raise PreprocessingOptionError(
                f"detrend={detrend!r} is not understood; use 'none', 'mean', 'tilt' or "
                "'polyN' (N = polynomial degree, e.g. 'poly2')"
            )
        degree = int(digits)
    if not 0 <= degree <= 10:
        raise PreprocessingOptionError(
            f"detrend degree {degree} is outside 0–10; a form of higher degree removes roughness"
        )
    return degree


# --- helpers --------------------------------------------------------------------------------


def _where(
    indices: NDArray[np.int64], rows: NDArray[np.int64] | None, x: NDArray[np.float64]
) -> str:
    """Describe positions for an error message: index, file line and x."""
    parts = []
    for i in indices[:_MAX_LISTED]:
        line = f", line {int(rows[i])}" if rows is not None else ""
        parts.append(f"index {int(i)}{line} (x={x[i]:.9g} µm)")
    more = f" and {indices.size - _MAX_LISTED} more" if indices.size > _MAX_LISTED else ""
    return "; ".join(parts) + more


def _source(raw: RawProfile) -> str:
    return str(raw.metadata.get("file", raw.metadata.get("source", "the scan")))


def _uniform_grid(x0: float, x1: float, n: int) -> NDArray[np.float64]:
    return np.linspace(x0, x1, n)


def _is_uniform(x: NDArray[np.float64]) -> bool:
    """Same test as :class:`~splinecontact.Profile` (every step within UNIFORM_GRID_RTOL)."""
    if x.size < 2:
        return True
    steps = np.diff(x)
    mean_step = (x[-1] - x[0]) / (x.size - 1)
    return bool(
        mean_step > 0 and np.all(np.abs(steps - mean_step) <= UNIFORM_GRID_RTOL * mean_step)
    )


def _rounded_grid_steps(diffs: NDArray[np.float64], fitted_step: float, resolution: float) -> bool:
    """Whether printed steps are those of a uniform grid rounded to ``resolution``.

    Rounding a uniform grid of step s to multiples of r gives steps of exactly k·r or (k+1)·r,
    k = ⌊s/r⌋. A missing sample gives a step of ⌊2s/r⌋·r or more, which can only be told from
    these when 2s/r ≥ k + 2; with a coarser print (s/r < 1.5, say) the two cannot be told apart
    and the grid is not regularised. So: s/r ≥ 1, every step a multiple k or k+1 of r, and
    2s/r ≥ k + 2. (The fitted step s is compared with the individual and median steps, never
    merely with the print resolution.)
    """
    if not resolution > 0 or diffs.size == 0:
        return False
    q = fitted_step / resolution
    if not (np.isfinite(q) and q >= 1.0):
        return False
    k = int(np.floor(q))
    units = diffs / resolution
    m = np.rint(units)
    if not np.all(np.abs(units - m) <= 1e-3):
        return False
    return bool(np.all((m == k) | (m == k + 1)) and 2.0 * q >= k + 2)


def _least_squares_grid(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """Uniform grid a + b·i closest to ``x`` in the least-squares sense."""
    i = np.arange(x.size, dtype=np.float64)
    i_mean, x_mean = i.mean(), x.mean()
    slope = np.sum((i - i_mean) * (x - x_mean)) / np.sum((i - i_mean) ** 2)
    grid = x_mean + slope * (i - i_mean)
    # exact uniform steps (Profile checks every step): rebuild from the first point and step
    return grid[0] + slope * i


def _fit_form(
    x: NDArray[np.float64], z: NDArray[np.float64], degree: int
) -> tuple[NDArray[np.float64], list[float]]:
    """Least-squares polynomial of ``degree`` through (x, z): its values and its coefficients.

    Coefficients are in increasing powers of ``x`` [µm^(1-k)], for the record.
    """
    with np.errstate(all="ignore"):
        span = float(np.max(x) - np.min(x)) if x.size else 0.0
        height = float(np.max(np.abs(z))) if z.size else 0.0
    if degree > 0 and not (
        np.isfinite(span)
        and span / max(x.size - 1, 1) >= np.finfo(np.float64).tiny
        and height <= _FIT_LIMIT
    ):
        # checked first: LAPACK would print to stderr before failing
        raise ProfileError(
            f"the form of degree {degree} cannot be fitted to these positions and heights "
            f"(x spans {span:.3g} µm over {x.size} points, heights up to {height:.3g} µm: "
            "beyond what floating point resolves); check the file's units and increments"
        )
    with np.errstate(all="ignore"):
        if degree == 0:
            mean = float(z.mean())
            form, coefficients = np.full_like(z, mean), [mean]
        else:
            try:
                poly = Polynomial.fit(x, z, degree)  # scaled domain: well conditioned
                form = poly(x)
                coefficients = [float(c) for c in poly.convert().coef]
            except (np.linalg.LinAlgError, ValueError, ZeroDivisionError):
                form, coefficients = np.full_like(z, np.nan), []
    if not np.all(np.isfinite(form)):
        raise ProfileError(
            f"the form of degree {degree} cannot be fitted to these positions and heights "
            f"(x spans {float(x[0]):.3g}…{float(x[-1]):.3g} µm, heights up to "
            f"{float(np.max(np.abs(z))):.3g} µm: beyond what floating point resolves); check "
            "the file's units and increments"
        )
    return form, coefficients


# --- the pipeline ---------------------------------------------------------------------------


def _resample(
    x: NDArray[np.float64],
    z: NDArray[np.float64],
    spacing: float | None,
    max_deviation: float,
    max_points: int = MAX_RESAMPLE_POINTS,
) -> tuple[NDArray[np.float64], NDArray[np.float64], dict[str, Any]]:
    """Linear interpolation onto a uniform grid (``spacing`` [µm], or as many points as x).

    Returns the new (x, z) [µm] and the ``resample`` step record.
    """
    if spacing is None:
        new_x = _uniform_grid(float(x[0]), float(x[-1]), x.size)
    else:
        with np.errstate(over="ignore"):
            n_float = float(np.floor((x[-1] - x[0]) / spacing + 1e-9)) + 1
        if not n_float <= max_points:
            raise PreprocessingOptionError(
                f"resample_spacing={spacing!r} µm over {float(x[-1] - x[0]):.6g} µm would "
                f"create {n_float:.3g} points, more than max_points={max_points:,}; choose a "
                "larger spacing (or raise Preprocessing.max_points)"
            )
        n_new = int(n_float)
        new_x = x[0] + spacing * np.arange(n_new)
    record = {
        "step": "resample",
        "method": "linear",
        "n_points_before": int(x.size),
        "n_points": int(new_x.size),
        "spacing_um": float((new_x[-1] - new_x[0]) / max(new_x.size - 1, 1)),
        "max_deviation_before_um": max_deviation,
    }
    return new_x, np.interp(new_x, x, z), record


@dataclass(frozen=True, eq=False)
class _Scan:
    """The scan between two steps of :func:`to_profile`: positions and heights [µm], the file
    line of each point (or ``None``) and the records of the steps applied so far."""

    x: NDArray[np.float64]
    z: NDArray[np.float64]
    rows: NDArray[np.int64] | None
    source: str
    steps: tuple[dict[str, Any], ...] = ()

    def keep(self, index: Any, record: dict[str, Any] | None = None) -> _Scan:
        """The points selected by ``index`` (mask, permutation or slice), with ``record``."""
        return _Scan(
            self.x[index],
            self.z[index],
            None if self.rows is None else self.rows[index],
            self.source,
            self.steps if record is None else (*self.steps, record),
        )

    def with_data(
        self,
        x: NDArray[np.float64],
        z: NDArray[np.float64],
        record: dict[str, Any],
        rows: NDArray[np.int64] | Literal["same"] | None = "same",
    ) -> _Scan:
        """New positions and heights (file lines unchanged unless given), with ``record``."""
        return _Scan(
            x, z, self.rows if isinstance(rows, str) else rows, self.source, (*self.steps, record)
        )


def _start(raw: RawProfile, options: Preprocessing | None) -> tuple[_Scan, Preprocessing]:
    """Check the arguments of :func:`to_profile`; the scan as read and the policy."""
    if options is not None and not isinstance(options, Preprocessing):
        raise PreprocessingOptionError(
            f"preprocessing={str(options)[:60]!r} is not a Preprocessing(...) policy"
        )
    if not isinstance(raw, RawProfile):
        raise ProfileError(f"to_profile needs a RawProfile, got {type(raw).__name__}")
    source = _source(raw)
    earlier = raw.metadata.get("preprocessing", [])
    if not isinstance(earlier, list) or not all(
        isinstance(step, Mapping) and isinstance(step.get("step"), str) for step in earlier
    ):
        raise ProfileError(
            f"{source}: metadata['preprocessing'] is {str(earlier)[:60]!r}, not a list of step "
            "records; the stored metadata is damaged"
        )
    rows = None if raw.rows is None else raw.rows.copy()
    scan = _Scan(raw.x.copy(), raw.z.copy(), rows, source)
    return scan, options if options is not None else Preprocessing()


def _undefined_points(scan: _Scan, raw: RawProfile, opts: Preprocessing) -> _Scan:
    """Step 1: refuse undefined points, or drop those without a position (heights: step 5)."""
    x, z = scan.x, scan.z
    undefined = ~np.isfinite(x) | ~np.isfinite(z)
    if not undefined.any():
        return scan
    if opts.undefined == "refuse":
        bad = np.flatnonzero(undefined)
        flagged = raw.metadata.get("n_flagged_invalid", 0)
        why = f" ({flagged} flagged invalid by the instrument)" if flagged else ""
        raise UndefinedPointsError(
            f"{scan.source}: {bad.size} undefined point(s) of {x.size}{why}: "
            f"{_where(bad, scan.rows, x)}; fill them with undefined='interpolate' "
            "(CLI: --undefined interpolate) or crop them away"
        )
    no_position = ~np.isfinite(x)
    if not no_position.any():
        return scan
    record = {"step": "drop_undefined_positions", "n_dropped": int(no_position.sum())}
    scan = scan.keep(~no_position, record)
    if scan.x.size < MIN_POINTS:
        raise UndefinedPointsError(
            f"{scan.source}: only {scan.x.size} of {no_position.size} point(s) have a defined "
            f"position; a profile needs at least {MIN_POINTS} — check the x column"
        )
    return scan


def _crop(scan: _Scan, opts: Preprocessing) -> _Scan:
    """Step 2: keep the points with x in ``opts.crop``."""
    if opts.crop is None:
        return scan
    lo, hi = opts.crop
    x = scan.x
    keep = (x >= lo) & (x <= hi)
    if keep.sum() < MIN_POINTS:
        span = f"x spans {np.min(x):.9g}…{np.max(x):.9g} µm" if x.size else "no points"
        raise CropError(
            f"{scan.source}: crop=({lo:g}, {hi:g}) µm keeps {int(keep.sum())} point(s) of "
            f"{x.size} ({span}); choose a range inside the scan with at least {MIN_POINTS} "
            "points"
        )
    record = {"step": "crop", "x_min_um": lo, "x_max_um": hi, "n_removed": int((~keep).sum())}
    return scan.keep(keep, record)


def _order(scan: _Scan, opts: Preprocessing) -> _Scan:
    """Step 3: refuse ``x`` stepping back, or sort the points by ``x`` (stable)."""
    x, rows = scan.x, scan.rows
    back = np.flatnonzero(np.diff(x) < 0) + 1
    if not back.size:
        return scan
    if opts.order == "refuse":
        i = int(back[0])
        line = f" (line {int(rows[i])})" if rows is not None else ""
        raise GridOrderError(
            f"{scan.source}: x steps back at index {i}{line}: x[{i - 1}]={x[i - 1]:.9g} µm, "
            f"x[{i}]={x[i]:.9g} µm ({back.size} step(s) back in total); sort the points "
            "with order='sort' (CLI: --order sort) or crop to the ordered part (--crop)"
        )
    perm = np.argsort(x, kind="stable")
    return scan.keep(perm, {"step": "sort", "n_steps_back": int(back.size)})


def _duplicates(scan: _Scan, opts: Preprocessing) -> _Scan:
    """Step 4: refuse repeated positions, or average the (defined) heights at each."""
    x, z, rows = scan.x, scan.z, scan.rows
    dup = np.flatnonzero(np.diff(x) == 0) + 1
    if not dup.size:
        return scan
    if opts.duplicates == "refuse":
        i = int(dup[0])
        line = f" (lines {int(rows[i - 1])} and {int(rows[i])})" if rows is not None else ""
        raise DuplicatePositionError(
            f"{scan.source}: x repeats at index {i}{line}: x[{i - 1}] = x[{i}] = {x[i]:.9g} µm "
            f"({dup.size} repeated position(s) in total); average the heights of repeated "
            "positions with duplicates='average' (CLI: --duplicates average) or crop them away"
        )
    unique_x, inverse = np.unique(x, return_inverse=True)
    defined = np.isfinite(z)
    sums = np.bincount(inverse, weights=np.where(defined, z, 0.0), minlength=unique_x.size)
    counts = np.bincount(inverse, weights=defined.astype(float), minlength=unique_x.size)
    with np.errstate(invalid="ignore", divide="ignore"):
        averaged = np.where(counts > 0, sums / np.maximum(counts, 1), np.nan)
    first = np.unique(inverse, return_index=True)[1]
    record = {"step": "average_duplicates", "n_merged": int(x.size - unique_x.size)}
    return scan.with_data(unique_x, averaged, record, None if rows is None else rows[first])


def _fill_undefined(scan: _Scan) -> _Scan:
    """Step 5: trim undefined heights at the ends, interpolate the others linearly."""
    missing = ~np.isfinite(scan.z)
    if not missing.any():
        return scan
    defined = np.flatnonzero(~missing)
    if defined.size < MIN_POINTS:
        raise UndefinedPointsError(
            f"{scan.source}: only {defined.size} defined point(s) remain; nothing to interpolate"
        )
    i_first, i_last = int(defined[0]), int(defined[-1])
    n_trimmed = i_first + (scan.x.size - 1 - i_last)
    scan = scan.keep(slice(i_first, i_last + 1))
    x, z = scan.x, scan.z
    missing = ~np.isfinite(z)
    n_filled = int(missing.sum())
    if n_filled:
        z[missing] = np.interp(x[missing], x[~missing], z[~missing])
    record = {
        "step": "interpolate_undefined",
        "method": "linear",
        "n_filled": n_filled,
        "n_trimmed_at_ends": int(n_trimmed),
    }
    return _Scan(x, z, scan.rows, scan.source, (*scan.steps, record))


def _check_grid_step(scan: _Scan) -> None:
    """Refuse a mean grid step floating point cannot resolve (before step 6)."""
    x = scan.x
    if x.size < 2:
        return
    with np.errstate(over="ignore"):
        mean_step = float((x[-1] - x[0]) / (x.size - 1))
    if not (np.isfinite(mean_step) and mean_step >= np.finfo(np.float64).tiny):
        raise GridNotUniformError(
            f"{scan.source}: the grid step {mean_step!r} µm is beyond the range floating point "
            f"resolves (x spans {float(x[0]):.3g}…{float(x[-1]):.3g} µm); check the file's "
            "units and increments"
        )


def _nonuniform_error(
    scan: _Scan, x_resolution: float, deviation: NDArray[np.float64]
) -> GridNotUniformError:
    """The error for a non-uniform grid that is not regularised: where and why."""
    x, rows = scan.x, scan.rows
    worst = int(np.argmax(deviation))
    diffs = np.diff(x)
    median_step = float(np.median(diffs))
    mean_step = (x[-1] - x[0]) / (x.size - 1)
    k = int(np.argmax(np.abs(diffs - mean_step)))
    line = f" (lines {int(rows[k])}–{int(rows[k + 1])})" if rows is not None else ""
    resolution = (
        f", more than the printed resolution {x_resolution:.3g} µm" if x_resolution > 0 else ""
    )
    gap = np.flatnonzero(np.abs(diffs - median_step) >= 0.5 * median_step)
    q = mean_step / x_resolution if x_resolution > 0 else np.inf
    if 2.0 * q < np.floor(q) + 2.0:
        why = (
            f"; the positions are printed so coarsely ({x_resolution:.3g} µm for a "
            f"step of {mean_step:.3g} µm) that a missing sample cannot be told from "
            "rounding (export more decimals)"
        )
    elif gap.size:
        why = (
            f"; {gap.size} step(s) differ from the median step {median_step:.9g} µm by "
            f"half a step or more (first {gap[0]}→{gap[0] + 1}): a sample is missing "
            "or extra"
        )
    else:
        why = ""
    return GridNotUniformError(
        f"{scan.source}: the grid is not uniform: step {k}→{k + 1}{line} is "
        f"{diffs[k]:.9g} µm but the mean step is {mean_step:.9g} µm; point {worst} "
        f"is {deviation[worst]:.3g} µm off the uniform grid{resolution}{why}; "
        "resample with nonuniform='resample' (CLI: --nonuniform resample)"
    )


def _resampled(scan: _Scan, opts: Preprocessing, max_deviation: float) -> _Scan:
    """``scan`` resampled onto ``opts.resample_spacing`` (file lines no longer apply)."""
    x, z, record = _resample(scan.x, scan.z, opts.resample_spacing, max_deviation, opts.max_points)
    return scan.with_data(x, z, record, None)


def _grid(scan: _Scan, raw: RawProfile, opts: Preprocessing) -> _Scan:
    """Step 6: regularise a grid that is uniform up to its printed resolution; refuse or
    resample any other non-uniform grid; resample a uniform one on an explicit spacing."""
    _check_grid_step(scan)
    x = scan.x
    explicit = opts.resample_spacing is not None and opts.nonuniform == "resample"
    if x.size < 2:
        return scan
    if _is_uniform(x):
        return _resampled(scan, opts, 0.0) if explicit else scan
    grid = _uniform_grid(float(x[0]), float(x[-1]), x.size)
    deviation = np.abs(x - grid)
    fitted = _least_squares_grid(x)
    fit_deviation = float(np.max(np.abs(x - fitted)))
    tolerance = raw.x_resolution * (1 + 1e-9) + 4 * np.finfo(float).eps * np.max(np.abs(x))
    steps_consistent = _rounded_grid_steps(
        np.diff(x), float(fitted[1] - fitted[0]), raw.x_resolution
    )
    if raw.x_resolution > 0 and fit_deviation <= tolerance and steps_consistent:
        record = {
            "step": "regularize_grid",
            "max_deviation_um": fit_deviation,
            "print_resolution_um": raw.x_resolution,
            "spacing_um": float(fitted[1] - fitted[0]),
        }
        scan = scan.with_data(fitted, scan.z, record)
        # an explicit spacing asked for (e.g. to share another scan's grid)
        return _resampled(scan, opts, 0.0) if explicit else scan
    if opts.nonuniform == "refuse":
        raise _nonuniform_error(scan, raw.x_resolution, deviation)
    return _resampled(scan, opts, float(deviation[int(np.argmax(deviation))]))


def _zero_origin(scan: _Scan, opts: Preprocessing) -> _Scan:
    """Step 7: shift ``x`` to start at 0 on request."""
    if not (opts.zero_origin and scan.x.size):
        return scan
    record = {"step": "zero_origin", "shift_um": float(-scan.x[0])}
    return scan.with_data(scan.x - scan.x[0], scan.z, record)


def _remove_form(scan: _Scan, opts: Preprocessing) -> _Scan:
    """Step 8: subtract the least-squares mean, tilt or polynomial of ``opts.detrend``."""
    degree = detrend_degree(opts.detrend)
    if degree is None or scan.x.size <= degree:
        return scan
    form, coefficients = _fit_form(scan.x, scan.z, degree)
    return scan.with_data(scan.x, scan.z - form, _detrend_record(degree, coefficients, form))


def to_profile(raw: RawProfile, options: Preprocessing | None = None) -> Profile:
    """Apply a preprocessing policy to a raw scan and build the :class:`~splinecontact.Profile`.

    Parameters
    ----------
    raw : RawProfile
        Positions and heights [µm] as read, undefined points as NaN.
    options : Preprocessing, optional
        What may be done to the data; the default refuses every irregularity and changes
        nothing.

    Returns
    -------
    Profile
        Its metadata is ``raw.metadata`` plus ``"preprocessing"``: the list of steps applied,
        each a dict with ``"step"`` and its parameters, in order.

    Raises
    ------
    UndefinedPointsError
        Undefined points and ``undefined="refuse"`` (message: count and first positions).
    GridOrderError
        ``x`` steps back and ``order="refuse"`` (message: first index and file line).
    DuplicatePositionError
        Repeated ``x`` and ``duplicates="refuse"``.
    GridNotUniformError
        Non-uniform grid and ``nonuniform="refuse"``.
    CropError
        The crop range keeps fewer than ``MIN_POINTS`` points.
    TooFewPointsError
        Fewer than ``MIN_POINTS`` points remain.

    Notes
    -----
    *Grid regularisation.* Text files print positions with a fixed number of decimals, so a
    uniform grid of step 0.0995613 µm printed with 6 decimals has steps of 0.099 and 0.100.
    When every position lies within one unit of the last printed decimal
    (``raw.x_resolution``) of the least-squares uniform grid, the positions are replaced by
    that grid; the heights are not changed. (Rounding moves each printed position by at most
    half a unit, and the fitted grid itself may be off by up to another half.) This is recorded
    as step ``"regularize_grid"`` with the largest deviation. Any larger deviation is a real
    non-uniformity.

    A missing sample is never regularised away: the fitted step s is also compared with every
    printed step and with the median step. Rounding to a resolution r gives steps of exactly
    k·r or (k+1)·r (k = ⌊s/r⌋) and a missing sample a step near 2s, so every step must be k·r
    or (k+1)·r and 2s/r ≥ k + 2 (else a double step could pass for a single one: with
    s < 1.5 r the grid is refused as too coarsely printed to tell).

    Examples
    --------
    >>> import numpy as np
    >>> from splinecontact.preprocess import Preprocessing, RawProfile, to_profile
    >>> raw = RawProfile(np.array([0.0, 0.2, 0.1, 0.3, 0.4]), np.array([0.0, 0.2, 0.1, 0.0, -0.1]))
    >>> to_profile(raw)
    Traceback (most recent call last):
    ...
    splinecontact.errors.GridOrderError: the scan: x steps back at index 2: ...
    >>> profile = to_profile(raw, Preprocessing(order="sort"))
    >>> profile.x
    array([0. , 0.1, 0.2, 0.3, 0.4])
    >>> [step["step"] for step in profile.metadata["preprocessing"]]
    ['sort']
    """
    scan, opts = _start(raw, options)
    scan = _undefined_points(scan, raw, opts)
    scan = _crop(scan, opts)
    scan = _order(scan, opts)
    scan = _duplicates(scan, opts)
    scan = _fill_undefined(scan)
    scan = _grid(scan, raw, opts)
    scan = _zero_origin(scan, opts)
    scan = _remove_form(scan, opts)
    metadata = dict(raw.metadata)
    metadata["preprocessing"] = [*list(metadata.get("preprocessing", [])), *scan.steps]
    return Profile(scan.x, scan.z, metadata=metadata)


def _detrend_record(
    degree: int, coefficients: Sequence[float], form: NDArray[Any]
) -> dict[str, Any]:
    names = {0: "remove_mean", 1: "remove_tilt"}
    return {
        "step": names.get(degree, "remove_polynomial"),
        "degree": degree,
        "coefficients": [float(c) for c in coefficients],
        "coefficients_note": "increasing powers of x [µm]: c0 [µm], c1 [1], c2 [1/µm], ...",
        "removed_rms_um": float(np.sqrt(np.mean((form - form.mean()) ** 2))),
    }


# --- steps on finished profiles -------------------------------------------------------------


def _append(profile: Profile, step: Mapping[str, Any]) -> dict[str, Any]:
    metadata = dict(profile.metadata)
    metadata["preprocessing"] = [*list(metadata.get("preprocessing", [])), dict(step)]
    return metadata


def detrend(profile: Profile, form: str | int = "tilt") -> Profile:
    """Remove the mean, the tilt or a polynomial form from a profile (least squares).

    Parameters
    ----------
    profile : Profile
        Heights [µm] on a uniform grid [µm].
    form : {"mean", "tilt", "polyN"} or int
        Degree of the form: ``"mean"`` (0), ``"tilt"`` (1), ``"polyN"`` or ``N``.

    Returns
    -------
    Profile
        Same grid, heights minus the fitted form; the step is appended to
        ``metadata["preprocessing"]``.
    """
    degree = detrend_degree(form)
    if degree is None:
        return profile
    fitted, coefficients = _fit_form(profile.x, profile.z, degree)
    record = _detrend_record(degree, coefficients, fitted)
    return Profile(profile.x, profile.z - fitted, metadata=_append(profile, record))


def crop(profile: Profile, x_min: float, x_max: float) -> Profile:
    """Keep the part of a profile with ``x_min <= x <= x_max``.

    Parameters
    ----------
    profile : Profile
        The profile to crop.
    x_min, x_max : float
        Range of positions to keep [µm].

    Raises
    ------
    CropError
        The range is empty, inverted, or keeps fewer than ``MIN_POINTS`` points.
    """
    if not (np.isfinite(x_min) and np.isfinite(x_max) and x_min < x_max):
        raise CropError(f"crop range ({x_min!r}, {x_max!r}) µm is not a range; need x_min < x_max")
    keep = (profile.x >= x_min) & (profile.x <= x_max)
    if keep.sum() < MIN_POINTS:
        raise CropError(
            f"crop=({x_min:g}, {x_max:g}) µm keeps {int(keep.sum())} point(s) of "
            f"{profile.n_points} (x spans {profile.x[0]:.9g}…{profile.x[-1]:.9g} µm); choose a "
            f"range with at least {MIN_POINTS} points"
        )
    record = {
        "step": "crop",
        "x_min_um": float(x_min),
        "x_max_um": float(x_max),
        "n_removed": int((~keep).sum()),
    }
    return Profile(profile.x[keep], profile.z[keep], metadata=_append(profile, record))


# --- resolution of the spline on a measured grid --------------------------------------------

#: Curvature bias (relative) at the smoothing wavelength above which :func:`spline_resolution`
#: flags the grid as too coarse.
CURVATURE_BIAS_LIMIT = 0.05


@dataclass(frozen=True)
class SplineResolution:
    """What the smoothing spline of eqs. 2–3 resolves on a grid of spacing ``dx``.

    Attributes
    ----------
    dx : float
        Grid spacing [µm].
    lam : float
        λ = (dx/x0)^α / 10 · x0³ [µm³] (eq. 3).
    cutoff_wavelength : float
        ℓ_c = 2π (λ·dx)^{1/4} [µm]: a sinusoid of this wavelength keeps half its amplitude in
        the spline; shorter ones are smoothed away, longer ones kept.
    points_per_cutoff : float
        ℓ_c / dx [1]: grid points per shortest kept wavelength.
    curvature_bias : float
        Relative error [1] of the spline's curvature f'' (hence of the sphere radii, eq. 5) for
        a sinusoid of wavelength ℓ_c sampled by ``points_per_cutoff`` points:
        6(1 − cos θ)/(θ²(2 + cos θ)) − 1 with θ = 2π dx/ℓ_c.
    interpolates : bool
        ℓ_c < 2 dx (the Nyquist wavelength): the spline smooths nothing, it passes through
        every measured point, noise included.
    coarse : bool
        ``curvature_bias`` exceeds ``CURVATURE_BIAS_LIMIT`` (5 %), or ``interpolates``.
    x0_for_limit : float or None
        Unit length x0 [µm] at which the bias would equal the limit at this ``dx`` and α
        (``None`` if no x0 can reach it, α ≥ 3).
    """

    dx: float
    lam: float
    cutoff_wavelength: float
    points_per_cutoff: float
    curvature_bias: float
    interpolates: bool
    coarse: bool
    x0_for_limit: float | None


def _curvature_bias(points: float) -> float:
    theta = 2.0 * np.pi / points
    return float(6.0 * (1.0 - np.cos(theta)) / (theta**2 * (2.0 + np.cos(theta))) - 1.0)


def spline_resolution(dx: float, *, alpha: float = 2.0, x0: float = 1.0) -> SplineResolution:
    """Smallest feature the smoothing spline of eqs. 2–3 keeps on a grid, and how well.

    On a uniform grid the spline minimising Σ(z_i − f_i)² + λ∫f''² attenuates a sinusoid of
    wavenumber k by 1/(1 + λ·dx·k⁴) (the sum over points is the integral divided by dx), so the
    half-amplitude wavelength is ℓ_c = 2π (λ·dx)^{1/4}. With eq. 3,
    ℓ_c/dx = 2π·10^{−1/4}·(dx/x0)^{(α−3)/4}: at the paper's grid (dx = 0.1 nm, α = 2,
    x0 = 1 µm) ℓ_c = 3.5 nm = 35 dx; on coarser grids the spline keeps features of only a
    few grid spacings, whose curvature (sphere radii, eq. 5) the cubic spline estimates with
    the bias given in :class:`SplineResolution`.

    Parameters
    ----------
    dx : float
        Grid spacing [µm].
    alpha : float, optional
        Tightness exponent α [1] (eq. 3; paper: 2).
    x0 : float, optional
        Unit length x0 [µm] (eqs. 2–3; paper: 1 µm).
    """
    for name, value in (("dx", dx), ("alpha", alpha), ("x0", x0)):
        if not (np.isfinite(value) and value > 0):
            raise PreprocessingOptionError(f"{name} = {value!r} must be a positive number")
    lam = (dx / x0) ** alpha / 10.0 * x0**3
    cutoff = 2.0 * np.pi * (lam * dx) ** 0.25
    points = cutoff / dx
    interpolates = points < 2.0
    bias = _curvature_bias(points) if not interpolates else float("inf")
    x0_for_limit = None
    if alpha < 3:
        # points(x0) = 2π·10^(−1/4)·(dx/x0)^((α−3)/4) grows with x0; bias(points) falls.
        lo, hi = 2.0, 1e6
        for _ in range(200):  # bisection on the number of points per cutoff
            mid = 0.5 * (lo + hi)
            if _curvature_bias(mid) > CURVATURE_BIAS_LIMIT:
                lo = mid
            else:
                hi = mid
        ratio = hi / (2.0 * np.pi * 10.0**-0.25)
        try:
            x0_for_limit = float(dx * ratio ** (4.0 / (3.0 - alpha)))
        except OverflowError:  # α just below 3: no representable x0 reaches the limit
            x0_for_limit = None
    return SplineResolution(
        dx=float(dx),
        lam=float(lam),
        cutoff_wavelength=float(cutoff),
        points_per_cutoff=float(points),
        curvature_bias=bias,
        interpolates=bool(interpolates),
        coarse=bool(interpolates or bias > CURVATURE_BIAS_LIMIT),
        x0_for_limit=x0_for_limit,
    )
