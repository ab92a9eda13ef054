"""The area–load relation: the coefficient of proportionality κ (eq. 15), A_S(F_N) power law."""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike

from ..errors import ParameterError
from ._defaults import (
    DEFAULT_FIT_FRACTION,
    DEFAULT_RSQ_METHOD,
    DEFAULT_RSQ_SOURCE,
    RsqMethod,
    RsqSource,
)
from .ensemble import (
    _check_fraction,
    _grid_coords,
    _ordered,
    _require,
    _step_arrays,
    ensemble_statistics,
    grid_dims,
    ok_mask,
    parameter,
)

__all__ = [
    "BUSH_KAPPA",
    "PERSSON_KAPPA",
    "kappa",
    "kappa_alternatives",
    "linear_fit_through_origin",
    "power_law_exponent",
]

#: Persson's (2001) coefficient of proportionality κ = √(8/π) ≈ 1.596.
PERSSON_KAPPA: float = math.sqrt(8.0 / math.pi)
#: Bush, Gibson & Thomas (1975) coefficient of proportionality κ = √(2π) ≈ 2.507.
BUSH_KAPPA: float = math.sqrt(2.0 * math.pi)

# --- κ (eq. 15) -------------------------------------------------------------------------------


def linear_fit_through_origin(x: ArrayLike, y: ArrayLike) -> float:
    """Least-squares slope s of y = s·x (no intercept): s = Σxy / Σx².

    Returns NaN if there is no point with x ≠ 0.
    """
    xa = np.asarray(x, dtype=np.float64)
    ya = np.asarray(y, dtype=np.float64)
    good = np.isfinite(xa) & np.isfinite(ya)
    sxx = float(np.sum(xa[good] ** 2))
    if sxx == 0.0:
        return math.nan
    return float(np.sum(xa[good] * ya[good]) / sxx)


def _contact_type_of(ds: xr.Dataset) -> xr.DataArray | str:
    if "contact_type" in ds.coords:
        return ds.coords["contact_type"]
    return str(ds.attrs.get("contact_type", "rough-on-rough"))


def _rsq(ds: xr.Dataset, source: RsqSource, method: RsqMethod) -> xr.DataArray:
    if source not in ("auto", "gap", "lower", "upper"):
        raise ParameterError(
            f"rsq_source must be 'auto', 'gap', 'lower' or 'upper', got {source!r}"
        )
    if method not in ("grid", "spline"):
        raise ParameterError(f"rsq_method must be 'grid' or 'spline', got {method!r}")
    suffix = "_spline" if method == "spline" else ""
    if source != "auto":
        name = f"rsq_{source}{suffix}"
        _require(ds, [name])
        return ds[name]
    gap, lower = f"rsq_gap{suffix}", f"rsq_lower{suffix}"
    _require(ds, [gap, lower])
    ctype = _contact_type_of(ds)
    if isinstance(ctype, str):
        return ds[lower] if ctype == "rough-on-flat" else ds[gap]
    return xr.where(ctype == "rough-on-flat", ds[lower], ds[gap]).assign_attrs(units="1")


def kappa(
    ds: xr.Dataset,
    *,
    fit_fraction: float = DEFAULT_FIT_FRACTION,
    rsq_source: RsqSource = DEFAULT_RSQ_SOURCE,
    rsq_method: RsqMethod = DEFAULT_RSQ_METHOD,
    confidence: float = 0.95,
) -> xr.Dataset:
    """Coefficient of proportionality κ = R_Sq · A_S · E* / F_N (eq. 15) per realization.

    A_S/F_N is the least-squares slope s through the origin of A_S against F_N over the steps
    with 0 < F_N ≤ ``fit_fraction`` × the realization's final F_N (the low-load, near-linear part);
    κ = R_Sq · E* · s. Units: A_S [µm] · E* [mN/µm²] / F_N [mN/µm] is a pure number.

    Parameters
    ----------
    ds : xarray.Dataset
        Study Dataset.
    fit_fraction : float
        Upper end of the fitted load range as a fraction of the final load (default 0.3) [1].
    rsq_source : {"auto", "gap", "lower", "upper"}
        Whose rms slope R_Sq: ``"auto"`` (default) takes the gap z^u − z^l for rough-on-rough and
        the rough (lower) profile for rough-on-flat (``contact_type`` coordinate or attribute).
    rsq_method : {"grid", "spline"}
        R_Sq from grid differences of the heights (eq. 15; default) or from the spline slope f′
        (``rsq_*_spline``; up to 10× smaller at high D).
    confidence : float
        Level of the confidence interval of the mean [1].

    Returns
    -------
    xarray.Dataset
        Per realization (grid…, realization): ``kappa`` [1], ``area_load_slope`` [µm²/mN],
        ``rsq`` [1], ``fit_max_force`` [mN/µm], ``n_fit_points`` [1]; over realizations:
        ``kappa_mean``, ``kappa_std``, ``kappa_ci_low``, ``kappa_ci_high``, ``kappa_count``.
        Attributes record the choices.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from splinecontact.study import run_study, open_study
    >>> from splinecontact.analysis import kappa
    >>> config = {"study": {"name": "tiny", "seed": 1, "realizations": 2},
    ...           "fixed": {"n_points": 2048, "length": 10.0, "steps": 20},
    ...           "sweep": {"dimension": [1.3, 1.7]}}
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     summary = run_study(config, pathlib.Path(folder) / "tiny.zarr", workers=1)
    ...     ds = open_study(pathlib.Path(folder) / "tiny.zarr")
    >>> kappa(ds)["kappa"].dims
    ('dimension', 'realization')
    """
    _check_fraction("fit_fraction", fit_fraction)
    _require(ds, ["normal_force", "contact_area", "status"])
    gdims = grid_dims(ds)
    f, a = _step_arrays(ds, ["normal_force", "contact_area"], gdims)
    ok = _ordered(ok_mask(ds), gdims, ("realization",))
    slope = np.full(ok.shape, np.nan)
    fmax = np.full(ok.shape, np.nan)
    npts = np.zeros(ok.shape, dtype=np.int64)
    for idx in np.ndindex(*ok.shape):
        if not ok[idx]:
            continue
        fi, ai = f[idx], a[idx]
        limit = fit_fraction * float(np.nanmax(fi))
        sel = (fi > 0) & (fi <= limit) & np.isfinite(ai)
        npts[idx] = int(sel.sum())
        fmax[idx] = limit
        if npts[idx] >= 2:
            slope[idx] = linear_fit_through_origin(fi[sel], ai[sel])
    dims = (*gdims, "realization")
    coords = _grid_coords(ds, gdims)
    if "realization" in ds.coords:
        coords["realization"] = ds.coords["realization"]
    slope_da = xr.DataArray(
        slope,
        dims=dims,
        coords=coords,
        attrs={"units": "µm²/mN", "long_name": "slope of A_S against F_N through the origin"},
    )
    rsq = _rsq(ds, rsq_source, rsq_method).where(ok_mask(ds)).transpose(*dims)
    e_star = parameter(ds, "e_star")
    kap = (rsq * e_star * slope_da).assign_attrs(
        units="1", long_name="κ = R_Sq A_S E*/F_N (eq. 15)"
    )
    out = xr.Dataset(
        {
            "kappa": kap,
            "area_load_slope": slope_da,
            "rsq": rsq.assign_attrs(units="1", long_name=f"R_Sq ({rsq_source}, {rsq_method})"),
            "fit_max_force": xr.DataArray(
                fmax,
                dims=dims,
                coords=coords,
                attrs={"units": "mN/µm", "long_name": "upper end of the fitted load range"},
            ),
            "n_fit_points": xr.DataArray(
                npts,
                dims=dims,
                coords=coords,
                attrs={"units": "1", "long_name": "number of steps in the fit"},
            ),
        }
    )
    out = out.merge(ensemble_statistics(out["kappa"], confidence=confidence, name="kappa"))
    out.attrs.update(
        fit_fraction=fit_fraction,
        rsq_source=rsq_source,
        rsq_method=rsq_method,
        confidence=confidence,
    )
    return out


def kappa_alternatives(
    ds: xr.Dataset,
    *,
    fit_fractions: Sequence[float] = (0.1, 0.3, 1.0),
    rsq_methods: Sequence[RsqMethod] = ("grid", "spline"),
) -> xr.Dataset:
    """Mean κ for every combination of R_Sq method and fit range (sensitivity of eq. 15).

    Returns
    -------
    xarray.Dataset
        ``kappa_mean`` [1] and ``kappa_ci_low``/``kappa_ci_high`` on (grid…, rsq_method,
        fit_fraction).
    """
    rows = []
    for method in rsq_methods:
        cols = []
        for frac in fit_fractions:
            k = kappa(ds, fit_fraction=frac, rsq_method=method)
            cols.append(k[["kappa_mean", "kappa_ci_low", "kappa_ci_high"]])
        rows.append(xr.concat(cols, dim=xr.Variable("fit_fraction", list(fit_fractions))))
    out = xr.concat(rows, dim=xr.Variable("rsq_method", list(rsq_methods)))
    out.coords["fit_fraction"].attrs["units"] = "1"
    return out


def power_law_exponent(x: ArrayLike, y: ArrayLike) -> float:
    """Exponent m of the least-squares fit log y = m log x + c over the positive finite points."""
    xa = np.asarray(x, dtype=np.float64)
    ya = np.asarray(y, dtype=np.float64)
    good = np.isfinite(xa) & np.isfinite(ya) & (xa > 0) & (ya > 0)
    if good.sum() < 2:
        return math.nan
    return float(np.polyfit(np.log(xa[good]), np.log(ya[good]), 1)[0])
