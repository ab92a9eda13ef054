"""Form removal and cropping: the steps shared by :func:`~splinecontact.preprocess.to_profile`
and applied to finished profiles (:func:`detrend`, :func:`crop`)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.polynomial import Polynomial
from numpy.typing import NDArray

from ..errors import CropError, ProfileError
from ..profile import MIN_POINTS, Profile
from ._raw import detrend_degree

#: Largest |height| [µm] a form is fitted to (squares must stay finite in the least squares).
_FIT_LIMIT = 1e150


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
