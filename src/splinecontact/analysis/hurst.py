"""Hurst exponent of a study's profiles: nominal H = 2 − D and measured from the PSD slope."""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike, NDArray

from ..errors import AnalysisError, ParameterError
from .ensemble import ensemble_statistics, parameter

__all__ = ["measured_hurst", "nominal_hurst", "study_hurst"]


def nominal_hurst(dimension: ArrayLike) -> NDArray[np.float64]:
    """Nominal Hurst exponent H = 2 − D of a profile of fractal dimension D [1]."""
    return np.asarray(2.0 - np.asarray(dimension, dtype=np.float64))


def measured_hurst(profiles: Iterable[Any]) -> NDArray[np.float64]:
    """Hurst exponents of profiles from the slope of their power spectrum.

    Parameters
    ----------
    profiles : iterable of Profile
        Profiles (heights [µm] on a uniform grid [µm]).

    Returns
    -------
    ndarray
        One H [1] per profile, from :func:`splinecontact.spectra.hurst_exponent`.
    """
    from ..spectra import hurst_exponent

    return np.array([float(hurst_exponent(p)) for p in profiles], dtype=np.float64)


def study_hurst(ds: xr.Dataset, *, n_profiles: int = 3) -> xr.Dataset:
    """Measured Hurst exponent of a study's lower profiles beside the nominal H = 2 − D.

    The lower profiles of the first ``n_profiles`` realizations of every fractal dimension are
    regenerated from the study's seeds (``study_seed`` attribute; the seed rule of
    :func:`splinecontact.study.realization_seed`, lower profile = child 0) and the study's fixed
    generator parameters, and their PSD slope measured by
    :func:`splinecontact.spectra.hurst_exponent`.

    Parameters
    ----------
    ds : xarray.Dataset
        Study Dataset with a ``dimension`` coordinate.
    n_profiles : int
        Profiles per D (≥ 1; each costs about 0.2 s at 10⁶ points).

    Returns
    -------
    xarray.Dataset
        On ``dimension``: ``hurst_nominal`` [1], ``hurst_measured_mean`` [1],
        ``hurst_measured_std`` [1] (ddof = 1; NaN for one profile), ``hurst_measured_count``.
    """
    from ..generate import GENERATOR_PARAMETERS, child_seed, weierstrass_mandelbrot
    from ..study import realization_seed

    if n_profiles < 1:
        raise ParameterError(f"n_profiles must be ≥ 1, got {n_profiles!r}")
    dims = np.atleast_1d(np.asarray(parameter(ds, "dimension", default=np.nan), dtype=float))
    if not np.isfinite(dims).all():
        raise AnalysisError("the study has no 'dimension' coordinate or attribute")
    seed = int(ds.attrs.get("study_seed", ds.attrs.get("seed", 0)))
    gen: dict[str, Any] = {}
    for key in GENERATOR_PARAMETERS:
        value = parameter(ds, key, default=None) if key in ds.attrs or key in ds.coords else None
        if value is None:
            continue
        if isinstance(value, xr.DataArray):
            value = value.values.ravel()[0]
        gen[key] = value.item() if isinstance(value, np.generic) else value
    n_real = int(ds.sizes.get("realization", n_profiles))
    values = np.full((dims.size, n_profiles), np.nan)
    for i, d in enumerate(dims):
        profiles = [
            weierstrass_mandelbrot(float(d), seed=child_seed(realization_seed(seed, r), 0), **gen)
            for r in range(min(n_profiles, n_real))
        ]
        values[i, : len(profiles)] = measured_hurst(profiles)
    measured = xr.DataArray(
        values,
        dims=("dimension", "profile"),
        coords={"dimension": dims},
        attrs={"units": "1", "long_name": "Hurst exponent from the PSD slope"},
        name="hurst_measured",
    )
    out = ensemble_statistics(measured, dim="profile", name="hurst_measured")
    out["hurst_nominal"] = xr.DataArray(
        nominal_hurst(dims), dims=("dimension",), attrs={"units": "1", "long_name": "H = 2 − D"}
    )
    return out
