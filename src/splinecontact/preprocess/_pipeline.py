"""The steps of :func:`to_profile`: from a :class:`RawProfile` to a
:class:`~splinecontact.Profile`."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from ..errors import (
    CropError,
    DuplicatePositionError,
    GridNotUniformError,
    GridOrderError,
    PreprocessingOptionError,
    ProfileError,
    UndefinedPointsError,
)
from ..profile import MIN_POINTS, UNIFORM_GRID_RTOL, Profile
from ._raw import MAX_RESAMPLE_POINTS, Preprocessing, RawProfile, detrend_degree
from ._steps import _detrend_record, _fit_form

#: Number of offending positions listed in an error message.
_MAX_LISTED = 5


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

    Rounding a uniform grid of step s to multiples of r moves each point by at most r/2, so a
    printed step lies in [s − r, s + r]: it is k·r or (k+1)·r, k = ⌊s/r⌋, and when s/r is an
    integer (a grid that falls on rounding ties, e.g. 0.005 + 2i printed to two decimals) also
    (s/r ± 1)·r. A missing sample gives a step of at least 2s − r, which can only be told from
    these when 2s/r − 1 ≥ the largest rounded step (for s/r not an integer: 2s/r ≥ k + 2); with a
    coarser print (s/r < 1.5, say) the two cannot be told apart and the grid is not
    regularised. (The fitted step s is compared with the individual steps, never merely with
    the print resolution.)
    """
    if not resolution > 0 or diffs.size == 0:
        return False
    q = fitted_step / resolution
    if not (np.isfinite(q) and q >= 1.0):
        return False
    slack = 1e-6  # q within this of an integer: the grid falls on rounding ties
    lowest, highest = math.ceil(q - 1.0 - slack), math.floor(q + 1.0 + slack)
    units = diffs / resolution
    m = np.rint(units)
    if not np.all(np.abs(units - m) <= 1e-3):
        return False
    return bool(np.all((m >= lowest) & (m <= highest)) and 2.0 * q - 1.0 + slack >= highest)


def _least_squares_grid(x: NDArray[np.float64]) -> NDArray[np.float64]:
    """Uniform grid a + b·i closest to ``x`` in the least-squares sense."""
    i = np.arange(x.size, dtype=np.float64)
    i_mean, x_mean = i.mean(), x.mean()
    slope = np.sum((i - i_mean) * (x - x_mean)) / np.sum((i - i_mean) ** 2)
    grid = x_mean + slope * (i - i_mean)
    # exact uniform steps (Profile checks every step): rebuild from the first point and step
    return grid[0] + slope * i


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
