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

from ..errors import (
    CropError,
    DuplicatePositionError,
    GridOrderError,
    PreprocessingOptionError,
    UndefinedPointsError,
)
from ._pipeline import to_profile
from ._raw import (  # noqa: F401
    MAX_RESAMPLE_POINTS,
    DuplicatePolicy,
    GridPolicy,
    OrderPolicy,
    Preprocessing,
    RawProfile,
    UndefinedPolicy,
    detrend_degree,
)
from ._resolution import CURVATURE_BIAS_LIMIT, SplineResolution, spline_resolution
from ._steps import (
    _fit_form,  # noqa: F401  (tests check the form fit directly)
    crop,
    detrend,
)

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
