"""Raw scans and the preprocessing policy: :class:`RawProfile`, :class:`Preprocessing`.

The readers of :mod:`splinecontact.io` return a :class:`RawProfile`; a :class:`Preprocessing`
says what :func:`~splinecontact.preprocess.to_profile` may do to it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..errors import PreprocessingOptionError, ProfileError, ProfileShapeError

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
