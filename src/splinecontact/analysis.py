"""Analyses of study results: the quantities of the paper's Section 3.

Every function here is pure: it takes the study :class:`xarray.Dataset` (or arrays) and returns
new xarray objects whose variables carry a ``units`` attribute.

The study Dataset
-----------------
Dimensions: one per swept parameter, named by the parameter (``dimension``, ``contact_type``,
``alpha``, ...; the *grid dimensions*), then ``realization`` and ``step``. Data variables: every
name of :data:`splinecontact.results.STEP_VARIABLES` on (grid…, realization, step), every name of
:data:`splinecontact.results.SCALAR_VARIABLES` on (grid…, realization), and ``status`` on
(grid…, realization) with 0 = not run, 1 = ok, 2 = failed. Only realizations with ``status == 1``
enter any analysis. Fixed parameters are dataset attributes under their own names
(``e_star`` [GPa], ``length`` [µm], ...); a swept parameter is a coordinate instead.

Conventions (see ``docs/analysis.md`` for the reasoning)
--------------------------------------------------------
* **Common abscissa.** Realizations end at different displacements (the final displacement is a
  multiple of each lower profile's peak-to-valley height) and different forces. Before averaging,
  each realization is interpolated linearly onto a common abscissa that runs, per grid point, from
  0 to the *smallest* end value among that grid point's realizations, so that every realization
  contributes at every sample (no extrapolation, no survivor bias near the end). The abscissa is
  therefore a coordinate on (grid…, sample).
* **Force as abscissa.** F_N(δ_N) has plateaus (no new contact in a step) and, rough-on-rough, can
  step down where an accepted contact is rejected (``docs/conventions.md``). Only the steps at
  which F_N exceeds every earlier value are used as interpolation nodes (the first time each load
  is reached), so every load has one value.
* **Ensemble statistics.** Mean, sample standard deviation (ddof = 1) and the two-sided confidence
  interval of the mean from Student's t with n − 1 degrees of freedom (95 % by default).
* **Stiffness.** k = dF_N/dδ_N by a Savitzky–Golay derivative (local least-squares quadratic over a
  sliding window of ``window`` steps on the uniform displacement grid of each realization). See
  :func:`stiffness`. The paper's Fig. 11a shows the stiffness of the *ensemble-mean* curve
  instead (:func:`mean_curve_stiffness`); the two estimators can disagree on trends with D.
* **κ (eq. 15).** κ = R_Sq · E* · s with s the least-squares slope through the origin of A_S against
  F_N over F_N ≤ ``fit_fraction`` × the realization's final load. See :func:`kappa`.
"""

from __future__ import annotations

import functools
import math
import warnings
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike, NDArray
from scipy import signal, stats

from .errors import ParameterError, SplineContactError

__all__ = [
    "BUSH_KAPPA",
    "PERSSON_KAPPA",
    "AnalysisError",
    "TrendTest",
    "bootstrap_means",
    "confidence_halfwidth",
    "dimensionless_stiffness",
    "ensemble_statistics",
    "ensemble_vs_displacement",
    "ensemble_vs_force",
    "force_split",
    "grid_dims",
    "interpolate_realizations",
    "kappa",
    "kappa_alternatives",
    "linear_fit_through_origin",
    "mean_curve_stiffness",
    "measured_hurst",
    "nominal_hurst",
    "ok_mask",
    "parameter",
    "power_law_exponent",
    "spearman_pvalue",
    "stiffness",
    "study_hurst",
    "trend_from_estimates",
    "trend_test",
    "values_at",
]

#: Persson's (2001) coefficient of proportionality κ = √(8/π) ≈ 1.596.
PERSSON_KAPPA: float = math.sqrt(8.0 / math.pi)
#: Bush, Gibson & Thomas (1975) coefficient of proportionality κ = √(2π) ≈ 2.507.
BUSH_KAPPA: float = math.sqrt(2.0 * math.pi)

#: Defaults of parameters that may be neither swept nor stored as attributes.
_PARAMETER_DEFAULTS: dict[str, Any] = {"e_star": 10.0, "length": 100.0}

_NON_GRID_DIMS = ("realization", "step", "contact", "sample")


class AnalysisError(SplineContactError, ValueError):
    """A study Dataset cannot be analysed as asked (missing variable, no successful run, ...)."""


# --- dataset helpers --------------------------------------------------------------------------


def grid_dims(ds: xr.Dataset) -> tuple[str, ...]:
    """Names of the swept-parameter dimensions of a study Dataset, in storage order.

    Parameters
    ----------
    ds : xarray.Dataset
        Study Dataset (see the module docstring).

    Returns
    -------
    tuple of str
        The dimensions of ``status`` other than ``realization``.
    """
    _require(ds, ["status"])
    return tuple(str(d) for d in ds["status"].dims if d not in _NON_GRID_DIMS)


def ok_mask(ds: xr.Dataset) -> xr.DataArray:
    """Boolean mask (grid…, realization) of the realizations that ran successfully (status 1)."""
    _require(ds, ["status"])
    return ds["status"] == 1


def parameter(ds: xr.Dataset, name: str, default: Any = None) -> Any:
    """Value of a simulation parameter: the coordinate if swept, else the dataset attribute.

    Parameters
    ----------
    ds : xarray.Dataset
        Study Dataset.
    name : str
        Parameter name (``e_star``, ``length``, ``alpha``, ...).
    default : optional
        Returned when the parameter is neither a coordinate nor an attribute; if omitted the
        package defaults are used (E* = 10 GPa, profile length 100 µm).

    Returns
    -------
    xarray.DataArray or scalar
        A DataArray over the swept dimension if ``name`` is swept, otherwise the scalar.

    Raises
    ------
    AnalysisError
        The parameter is unknown and has no default.
    """
    if name in ds.coords:
        return ds.coords[name]
    if name in ds.attrs:
        return ds.attrs[name]
    if default is not None:
        return default
    if name in _PARAMETER_DEFAULTS:
        return _PARAMETER_DEFAULTS[name]
    raise AnalysisError(
        f"parameter {name!r} is neither a coordinate nor an attribute of the study Dataset; "
        "pass it explicitly"
    )


def _require(ds: xr.Dataset, names: Iterable[str]) -> None:
    missing = [n for n in names if n not in ds.variables]
    if missing:
        raise AnalysisError(
            f"the Dataset lacks variable(s) {missing}; expected a study Dataset with the "
            "variables of splinecontact.results.STEP_VARIABLES/SCALAR_VARIABLES and 'status'"
        )


def _check_fraction(name: str, value: float) -> None:
    if not (0.0 < value <= 1.0) or not math.isfinite(value):
        raise ParameterError(f"{name} must lie in (0, 1], got {value!r}")


def _check_samples(n_samples: int) -> None:
    if int(n_samples) < 2:
        raise ParameterError(f"n_samples must be at least 2, got {n_samples!r}")


def _grid_coords(ds: xr.Dataset, dims: Sequence[str]) -> dict[str, Any]:
    coords: dict[str, Any] = {}
    for name, coord in ds.coords.items():
        if all(d in dims for d in coord.dims):
            coords[str(name)] = coord
    return coords


def _ordered(da: xr.DataArray, gdims: Sequence[str], tail: Sequence[str]) -> NDArray[Any]:
    """Values of ``da`` broadcast and transposed to (grid…, *tail)."""
    return np.asarray(da.transpose(*gdims, *tail).values)


def _units(da: xr.DataArray, fallback: str = "1") -> str:
    return str(da.attrs.get("units", fallback))


# --- statistics -------------------------------------------------------------------------------


def confidence_halfwidth(
    std: ArrayLike, count: ArrayLike, confidence: float = 0.95
) -> NDArray[np.float64]:
    """Half-width of the two-sided Student-t confidence interval of a mean.

    Parameters
    ----------
    std : array_like
        Sample standard deviation (ddof = 1) [any unit].
    count : array_like
        Number of samples n (the interval is NaN for n < 2).
    confidence : float
        Confidence level in (0, 1) [1].

    Returns
    -------
    ndarray
        t_{(1+c)/2, n−1} · std / √n [unit of ``std``].
    """
    if not 0.0 < confidence < 1.0:
        raise ParameterError(f"confidence must lie in (0, 1), got {confidence!r}")
    n = np.asarray(count, dtype=np.float64)
    s = np.asarray(std, dtype=np.float64)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = stats.t.ppf(0.5 + confidence / 2.0, np.where(n >= 2, n - 1.0, np.nan))
        return np.asarray(t * s / np.sqrt(n), dtype=np.float64)


def ensemble_statistics(
    values: xr.DataArray, *, dim: str = "realization", confidence: float = 0.95, name: str = ""
) -> xr.Dataset:
    """Mean, standard deviation and confidence interval of ``values`` over ``dim``.

    NaN values (failed or not-run realizations, samples out of reach) are left out.

    Parameters
    ----------
    values : xarray.DataArray
        Values with a ``units`` attribute.
    dim : str
        Dimension to reduce (default ``realization``).
    confidence : float
        Level of the two-sided Student-t interval of the mean [1].
    name : str
        Prefix of the output variable names (default: ``values.name``).

    Returns
    -------
    xarray.Dataset
        ``{name}_mean``, ``{name}_std`` (ddof = 1), ``{name}_ci_low``, ``{name}_ci_high`` (units of
        ``values``) and ``{name}_count`` (number of finite values).
    """
    prefix = name or str(values.name)
    units = _units(values)
    count = values.notnull().sum(dim)
    mean = values.mean(dim, skipna=True)
    std = values.std(dim, ddof=1, skipna=True).where(count >= 2)
    half = xr.apply_ufunc(confidence_halfwidth, std, count, kwargs={"confidence": confidence})
    attrs = {"units": units}
    long = values.attrs.get("long_name", prefix)
    out = xr.Dataset(
        {
            f"{prefix}_mean": mean.assign_attrs(attrs, long_name=f"ensemble mean of {long}"),
            f"{prefix}_std": std.assign_attrs(attrs, long_name=f"standard deviation of {long}"),
            f"{prefix}_ci_low": (mean - half).assign_attrs(
                attrs, long_name=f"lower {confidence:.0%} confidence bound of the mean"
            ),
            f"{prefix}_ci_high": (mean + half).assign_attrs(
                attrs, long_name=f"upper {confidence:.0%} confidence bound of the mean"
            ),
            f"{prefix}_count": count.assign_attrs(
                units="1", long_name="number of realizations averaged"
            ),
        }
    )
    out.attrs["confidence"] = confidence
    return out


# --- interpolation onto a common abscissa -----------------------------------------------------


def _monotone_nodes(x: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Mask of the nodes where ``x`` exceeds every earlier value (first time each value is hit)."""
    keep = np.zeros(x.shape, dtype=bool)
    if x.size == 0:
        return keep
    finite = np.isfinite(x)
    previous = np.maximum.accumulate(np.where(finite, x, -np.inf))
    keep[0] = finite[0]
    keep[1:] = finite[1:] & (x[1:] > previous[:-1])
    return keep


def _step_arrays(ds: xr.Dataset, names: Sequence[str], gdims: Sequence[str]) -> list[NDArray[Any]]:
    return [
        _ordered(ds[n], gdims, ("realization", "step")).astype(np.float64, copy=False)
        for n in names
    ]


def interpolate_realizations(
    ds: xr.Dataset,
    abscissa: str,
    ordinates: Sequence[str] | Mapping[str, xr.DataArray],
    *,
    n_samples: int = 101,
    end_quantile: float = 0.0,
    spacing: Literal["linear", "log"] = "linear",
) -> xr.Dataset:
    """Interpolate each successful realization onto a common abscissa per grid point.

    Parameters
    ----------
    ds : xarray.Dataset
        Study Dataset.
    abscissa : str
        Per-step variable used as abscissa (``displacement`` or ``normal_force``). It must not
        decrease along ``step``; plateaus are handled by keeping the first step of each new value.
    ordinates : sequence of str or mapping of str to DataArray
        Per-step variables to interpolate (names in ``ds``), or derived DataArrays on
        (grid…, realization, step) with a ``units`` attribute.
    n_samples : int
        Number of points of the common abscissa. It starts at the largest first value among
        the grid point's realizations (0 for δ_N and, normally, for F_N at first contact).
    end_quantile : float
        Upper end of the abscissa per grid point, as a quantile [1] of the end values of the grid
        point's successful realizations: 0 (default) is the smallest, so every realization
        covers the whole range (no extrapolation, no survivor bias); a larger value extends the
        range, and samples beyond a realization's end are NaN (left out of the statistics,
        which report their count).
    spacing : {"linear", "log"}
        Uniform samples, or geometric samples over three decades below the upper end (for
        log–log plots; the lower end is then 10⁻³ × the upper end, or the common start if larger).

    Returns
    -------
    xarray.Dataset
        Dims (grid…, realization, sample); the abscissa is a coordinate named ``abscissa`` on
        (grid…, sample) with its units; each ordinate keeps its name and units. Failed and not-run
        realizations are NaN.

    Raises
    ------
    AnalysisError
        A variable is missing, or a grid point has no successful realization.
    """
    _check_samples(n_samples)
    if not 0.0 <= end_quantile <= 1.0:
        raise ParameterError(f"end_quantile must lie in [0, 1], got {end_quantile!r}")
    if spacing not in ("linear", "log"):
        raise ParameterError(f"spacing must be 'linear' or 'log', got {spacing!r}")
    ordinate_arrays: dict[str, xr.DataArray] = {}
    if isinstance(ordinates, Mapping):
        ordinate_arrays = dict(ordinates)
    else:
        _require(ds, [abscissa, *ordinates])
        ordinate_arrays = {n: ds[n] for n in ordinates}
    _require(ds, [abscissa, "status"])
    gdims = grid_dims(ds)
    ok = _ordered(ok_mask(ds), gdims, ("realization",))
    xs = _ordered(ds[abscissa], gdims, ("realization", "step")).astype(np.float64)
    ys = {
        n: _ordered(da.broadcast_like(ds[abscissa]), gdims, ("realization", "step")).astype(
            np.float64
        )
        for n, da in ordinate_arrays.items()
    }
    grid_shape = ok.shape[:-1]
    n_real = ok.shape[-1]
    x_out = np.full((*grid_shape, n_samples), np.nan)
    y_out = {n: np.full((*grid_shape, n_real, n_samples), np.nan) for n in ys}
    for gp in np.ndindex(*grid_shape):
        good = np.flatnonzero(ok[gp])
        if good.size == 0:
            label = {
                d: ds[d].values[i] if d in ds.coords else i for d, i in zip(gdims, gp, strict=True)
            }
            raise AnalysisError(
                f"grid point {label} has no successful realization (status == 1); "
                "run or resume the study, or drop that grid point with .sel/.drop_sel"
            )
        ends = [np.nanmax(xs[gp][r]) for r in good]
        end = float(np.quantile(ends, end_quantile))
        start = max(float(np.nanmin(xs[gp][r])) for r in good)
        if spacing == "log" and end > 0:
            grid = np.geomspace(max(start, 1e-3 * end), end, n_samples)
        else:
            grid = np.linspace(start, end, n_samples)
        x_out[gp] = grid
        for r in good:
            x_r = xs[gp][r]
            keep = _monotone_nodes(x_r)
            xn = x_r[keep]
            for n in ys:
                yn = ys[n][gp][r][keep]
                y_out[n][gp][r] = np.interp(grid, xn, yn, left=np.nan, right=np.nan)
    coords = _grid_coords(ds, gdims)
    coords["realization"] = (
        ds.coords["realization"] if "realization" in ds.coords else np.arange(n_real)
    )
    coords[abscissa] = xr.Variable(
        (*gdims, "sample"),
        x_out,
        {
            "units": _units(ds[abscissa]),
            "long_name": str(ds[abscissa].attrs.get("long_name", abscissa)),
        },
    )
    data = {
        n: xr.Variable(
            (*gdims, "realization", "sample"),
            y_out[n],
            {
                "units": _units(ordinate_arrays[n]),
                "long_name": str(ordinate_arrays[n].attrs.get("long_name", n)),
            },
        )
        for n in ys
    }
    out = xr.Dataset(data, coords=coords)
    out.attrs["abscissa"] = abscissa
    out.attrs["end_quantile"] = end_quantile
    return out


def _ensemble(interp: xr.Dataset, confidence: float) -> xr.Dataset:
    parts = [
        ensemble_statistics(interp[n], confidence=confidence, name=str(n)) for n in interp.data_vars
    ]
    out = xr.merge(parts, compat="override", combine_attrs="override")
    out = out.assign_coords({interp.attrs["abscissa"]: interp.coords[interp.attrs["abscissa"]]})
    out.attrs = {**interp.attrs, "confidence": confidence}
    return out


def ensemble_vs_displacement(
    ds: xr.Dataset,
    variables: Sequence[str] = ("normal_force", "tangential_force", "contact_area"),
    *,
    n_samples: int = 101,
    confidence: float = 0.95,
) -> xr.Dataset:
    """Ensemble mean, std and confidence band of per-step variables against δ_N (Fig. 10a).

    Each successful realization is interpolated linearly onto ``n_samples`` displacements from 0
    to the smallest final displacement of the grid point's realizations, then averaged.

    Parameters
    ----------
    ds : xarray.Dataset
        Study Dataset.
    variables : sequence of str
        Per-step variables (default F_N [mN/µm], F_T [mN/µm], A_S [µm]).
    n_samples : int
        Number of common displacements.
    confidence : float
        Level of the confidence interval of the mean [1].

    Returns
    -------
    xarray.Dataset
        Dims (grid…, sample), coordinate ``displacement`` [µm] on (grid…, sample); for each
        variable ``v``: ``v_mean``, ``v_std``, ``v_ci_low``, ``v_ci_high`` (units of ``v``) and
        ``v_count``.
    """
    interp = interpolate_realizations(ds, "displacement", list(variables), n_samples=n_samples)
    return _ensemble(interp, confidence)


def ensemble_vs_force(
    ds: xr.Dataset,
    variables: Sequence[str] = ("mean_separation", "contact_area"),
    *,
    n_samples: int = 101,
    confidence: float = 0.95,
    end_quantile: float = 0.25,
) -> xr.Dataset:
    """Ensemble statistics of per-step variables against the normal force F_N (Figs. 10b, 11b).

    Each realization is interpolated onto ``n_samples`` loads from 0 to the ``end_quantile``
    quantile of the final loads of the grid point's realizations (plateaus of F_N: first step of
    each new load), then averaged. Final loads scatter far more than final displacements (one
    realization in twenty may end at 1/100 of the median), so the default 0.25 keeps the range
    useful: beyond a realization's final load it is left out, and at least 75 % of the
    realizations contribute at every load (``*_count`` says how many). Use 0 for a range
    every realization covers.

    Parameters
    ----------
    ds : xarray.Dataset
        Study Dataset.
    variables : sequence of str
        Per-step variables (default mean separation [µm] and A_S [µm]).
    n_samples : int
        Number of common loads.
    confidence : float
        Level of the confidence interval of the mean [1].
    end_quantile : float
        Quantile [1] of the final loads that ends the load range (see
        :func:`interpolate_realizations`).

    Returns
    -------
    xarray.Dataset
        Dims (grid…, sample), coordinate ``normal_force`` [mN/µm] on (grid…, sample) and the
        statistics of :func:`ensemble_statistics` for each variable.
    """
    interp = interpolate_realizations(
        ds, "normal_force", list(variables), n_samples=n_samples, end_quantile=end_quantile
    )
    return _ensemble(interp, confidence)


def values_at(
    ds: xr.Dataset, abscissa: str, ordinate: str | xr.DataArray, value: float
) -> xr.DataArray:
    """Per-realization value of ``ordinate`` at ``abscissa == value`` (linear interpolation).

    Parameters
    ----------
    ds : xarray.Dataset
        Study Dataset.
    abscissa : str
        Non-decreasing per-step variable (``displacement`` [µm] or ``normal_force`` [mN/µm]).
    ordinate : str or xarray.DataArray
        Per-step variable name, or a derived DataArray on (grid…, realization, step).
    value : float
        Abscissa value [units of ``abscissa``].

    Returns
    -------
    xarray.DataArray
        On (grid…, realization); NaN for unsuccessful realizations and where ``value`` lies
        beyond the realization's last step.
    """
    _require(ds, [abscissa, "status"])
    da = ds[ordinate] if isinstance(ordinate, str) else ordinate
    gdims = grid_dims(ds)
    ok = _ordered(ok_mask(ds), gdims, ("realization",))
    xs = _ordered(ds[abscissa], gdims, ("realization", "step")).astype(np.float64)
    ys = _ordered(da.broadcast_like(ds[abscissa]), gdims, ("realization", "step")).astype(
        np.float64
    )
    out = np.full(ok.shape, np.nan)
    for idx in np.ndindex(*ok.shape):
        if not ok[idx]:
            continue
        keep = _monotone_nodes(xs[idx])
        out[idx] = np.interp(value, xs[idx][keep], ys[idx][keep], left=np.nan, right=np.nan)
    coords = _grid_coords(ds, gdims)
    if "realization" in ds.coords:
        coords["realization"] = ds.coords["realization"]
    return xr.DataArray(
        out,
        dims=(*gdims, "realization"),
        coords=coords,
        name=str(da.name),
        attrs={"units": _units(da), f"at_{abscissa}": value},
    )


# --- stiffness --------------------------------------------------------------------------------


def _default_window(n: int) -> int:
    w = max(5, round(0.05 * n))
    if w % 2 == 0:
        w += 1
    return min(w, n if n % 2 == 1 else n - 1)


def stiffness(ds: xr.Dataset, *, window: int | None = None, polyorder: int = 2) -> xr.DataArray:
    """Contact stiffness k = dF_N/dδ_N of every realization at every step.

    The derivative is a Savitzky–Golay derivative: at each step, a polynomial of degree
    ``polyorder`` is fitted by least squares to F_N over ``window`` consecutive steps (the steps
    are uniform in δ_N within a realization) and differentiated; near the ends the fit over the
    first/last window is used. This smooths the small jumps of F_N when contacts enter, keeps a
    quadratic exactly (and a power law to the truncation error of a local quadratic), and needs
    no choice of a global model. A fit in log–log space was rejected as default because F_N = 0
    at δ_N = 0 and on the first plateau, and because its derivative inherits the noise of the
    first contacts.

    Parameters
    ----------
    ds : xarray.Dataset
        Study Dataset (``displacement`` [µm], ``normal_force`` [mN/µm]).
    window : int, optional
        Odd number of steps of the local fit; default 5 % of the steps (at least 5), i.e. 51 for
        the paper's 1000 steps.
    polyorder : int
        Degree of the local polynomial (default 2; must be < window).

    Returns
    -------
    xarray.DataArray
        ``stiffness`` on (grid…, realization, step) [mN/µm² = GPa, per µm thickness]; NaN for
        unsuccessful realizations.

    Raises
    ------
    ParameterError
        ``window`` even, < ``polyorder`` + 2, or longer than the curve.
    """
    _require(ds, ["displacement", "normal_force", "status"])
    gdims = grid_dims(ds)
    x, f = _step_arrays(ds, ["displacement", "normal_force"], gdims)
    ok = _ordered(ok_mask(ds), gdims, ("realization",))
    n = x.shape[-1]
    w = _default_window(n) if window is None else int(window)
    if w % 2 == 0 or w <= polyorder or w > n:
        raise ParameterError(
            f"window must be odd, larger than polyorder={polyorder} and at most the "
            f"{n} steps of a curve; got {window!r}"
        )
    k = np.full(f.shape, np.nan)
    for idx in np.ndindex(*ok.shape):
        if not ok[idx]:
            continue
        xi = x[idx]
        dx = float(np.mean(np.diff(xi))) if n > 1 else 0.0
        if not dx > 0:
            raise AnalysisError(
                f"displacement of realization at index {idx} does not increase; "
                "stiffness needs uniform displacement steps"
            )
        k[idx] = signal.savgol_filter(f[idx], w, polyorder, deriv=1, delta=dx, mode="interp")
    dims = (*gdims, "realization", "step")
    return xr.DataArray(
        k,
        dims=dims,
        coords={n_: c for n_, c in ds["normal_force"].coords.items() if set(c.dims) <= set(dims)},
        name="stiffness",
        attrs={
            "units": "mN/µm²",
            "long_name": "contact stiffness k = dF_N/dδ_N (Savitzky–Golay)",
            "window": w,
            "polyorder": polyorder,
        },
    )


def dimensionless_stiffness(
    ds: xr.Dataset,
    *,
    n_samples: int = 101,
    window: int | None = None,
    polyorder: int = 2,
    confidence: float = 0.95,
    spacing: Literal["linear", "log"] = "log",
    end_quantile: float = 0.25,
) -> xr.Dataset:
    """Dimensionless stiffness k/E* against dimensionless load F_N/(E* L0) (Fig. 11a).

    For unit thickness, k [mN/µm²] / E* [GPa = mN/µm²] and F_N [mN/µm] / (E* [mN/µm²] · L0 [µm])
    are pure numbers (L0 = profile length). Each realization's k (see :func:`stiffness`) is
    interpolated onto a common load grid per grid point (as in :func:`ensemble_vs_force`,
    including its ``end_quantile``) and averaged there. The load samples are geometric by
    default (``spacing="log"``: three decades below the end of the range), as the figure is
    log–log.

    Returns
    -------
    xarray.Dataset
        Dims (grid…, sample); coordinates ``normal_force`` [mN/µm] and ``dimensionless_load`` [1]
        on (grid…, sample); statistics ``dimensionless_stiffness_{mean,std,ci_low,ci_high,count}``
        [1] and ``stiffness_mean`` [mN/µm²].
    """
    k = stiffness(ds, window=window, polyorder=polyorder)
    e_star = parameter(ds, "e_star")
    length = parameter(ds, "length")
    k_dimless = (k / e_star).assign_attrs(units="1", long_name="dimensionless stiffness k/E*")
    interp = interpolate_realizations(
        ds,
        "normal_force",
        {"stiffness": k, "dimensionless_stiffness": k_dimless},
        n_samples=n_samples,
        spacing=spacing,
        end_quantile=end_quantile,
    )
    out = _ensemble(interp, confidence)
    load = (out.coords["normal_force"] / (e_star * length)).assign_attrs(
        units="1", long_name="dimensionless load F_N/(E* L0)"
    )
    out = out.assign_coords(dimensionless_load=load)
    out.attrs.update(window=k.attrs["window"], polyorder=polyorder)
    return out


# --- κ (eq. 15) -------------------------------------------------------------------------------

RsqSource = Literal["auto", "gap", "lower", "upper"]
RsqMethod = Literal["grid", "spline"]


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
    fit_fraction: float = 0.3,
    rsq_source: RsqSource = "auto",
    rsq_method: RsqMethod = "grid",
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


# --- diagnostics of the method ----------------------------------------------------------------


def force_split(ds: xr.Dataset) -> xr.Dataset:
    """Split of F_N into its normal-force and tangential-spring parts (eq. 14), tilted contacts.

    Returns
    -------
    xarray.Dataset
        On (grid…, realization, step): ``normal_part_fraction`` and ``tangential_part_fraction``
        (parts of F_N over F_N, NaN where F_N = 0) [1] and ``tilted_fraction`` (accepted contacts
        whose repulsive direction points below horizontal, over accepted contacts; NaN without
        contacts) [1]. Unsuccessful realizations are NaN.
    """
    names = [
        "normal_force",
        "normal_force_normal_part",
        "normal_force_tangential_part",
        "n_contacts",
        "n_tilted_contacts",
    ]
    _require(ds, [*names, "status"])
    ok = ok_mask(ds)
    fn = ds["normal_force"].where(ok)
    nc = ds["n_contacts"].where(ok)
    with np.errstate(invalid="ignore", divide="ignore"):
        normal = (ds["normal_force_normal_part"].where(ok) / fn.where(fn != 0)).assign_attrs(
            units="1", long_name="fraction of F_N from the local normal forces"
        )
        tangential = (
            ds["normal_force_tangential_part"].where(ok) / fn.where(fn != 0)
        ).assign_attrs(units="1", long_name="fraction of F_N from the local tangential forces")
        tilted = (ds["n_tilted_contacts"].where(ok) / nc.where(nc > 0)).assign_attrs(
            units="1", long_name="fraction of accepted contacts tilted past horizontal"
        )
    return xr.Dataset(
        {
            "normal_part_fraction": normal,
            "tangential_part_fraction": tangential,
            "tilted_fraction": tilted,
        }
    )


def power_law_exponent(x: ArrayLike, y: ArrayLike) -> float:
    """Exponent m of the least-squares fit log y = m log x + c over the positive finite points."""
    xa = np.asarray(x, dtype=np.float64)
    ya = np.asarray(y, dtype=np.float64)
    good = np.isfinite(xa) & np.isfinite(ya) & (xa > 0) & (ya > 0)
    if good.sum() < 2:
        return math.nan
    return float(np.polyfit(np.log(xa[good]), np.log(ya[good]), 1)[0])


# --- Hurst exponent ---------------------------------------------------------------------------


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
    from .spectra import hurst_exponent

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
    from .generate import GENERATOR_PARAMETERS, child_seed, weierstrass_mandelbrot
    from .study import realization_seed

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


# --- stiffness of the ensemble-mean curve (the paper's Fig. 11a) -------------------------------


def _mean_curve_pieces(
    ds: xr.Dataset, n_samples: int
) -> tuple[tuple[str, ...], xr.Dataset, NDArray[np.float64], NDArray[np.float64]]:
    interp = interpolate_realizations(ds, "displacement", ["normal_force"], n_samples=n_samples)
    gdims = grid_dims(ds)
    f = _ordered(interp["normal_force"], gdims, ("realization", "sample")).astype(np.float64)
    x = _ordered(interp.coords["displacement"], gdims, ("sample",)).astype(np.float64)
    return gdims, interp, f, x


@functools.lru_cache(maxsize=8)
def _savgol_matrix(n: int, window: int, polyorder: int) -> NDArray[np.float64]:
    """Matrix K with K @ f = the Savitzky–Golay derivative of f (unit spacing, ``interp`` ends).

    The filter is linear, so applying it once to the identity gives the matrix; derivatives of
    many curves (bootstrap resamples) are then one matrix product.
    """
    eye = np.eye(n)
    return np.asarray(
        signal.savgol_filter(eye, window, polyorder, deriv=1, delta=1.0, axis=0, mode="interp")
    )


def _savgol_rows(
    f: NDArray[np.float64], dx: float, window: int, polyorder: int
) -> NDArray[np.float64]:
    k = _savgol_matrix(f.shape[-1], window, polyorder)
    return np.asarray(f @ k.T / dx)


def _first_crossing(
    f: NDArray[np.float64], y: NDArray[np.float64], loads: NDArray[np.float64]
) -> NDArray[np.float64]:
    """y where each row of f first reaches each load (linear between the two samples around it).

    ``f`` and ``y`` are (m, n); returns (m, loads). NaN where a row never reaches the load or
    starts above it.
    """
    m = f.shape[0]
    out = np.full((m, loads.size), np.nan)
    rows = np.arange(m)
    for j, load in enumerate(loads):
        reached = f >= load
        idx = reached.argmax(axis=1)
        ok = reached[rows, idx] & (idx > 0)
        exact = reached[rows, idx] & (idx == 0) & (f[:, 0] == load)
        i1 = np.where(ok, idx, 1)
        f0, f1 = f[rows, i1 - 1], f[rows, i1]
        y0, y1 = y[rows, i1 - 1], y[rows, i1]
        with np.errstate(invalid="ignore", divide="ignore"):
            w = np.where(f1 > f0, (load - f0) / (f1 - f0), 1.0)
        out[:, j] = np.where(ok, y0 + w * (y1 - y0), np.nan)
        out[exact, j] = y[exact, 0]
    return out


def _mean_curve_window(n_samples: int, window: int | None, polyorder: int) -> int:
    w = _default_window(n_samples) if window is None else int(window)
    if w % 2 == 0 or w <= polyorder or w > n_samples:
        raise ParameterError(
            f"window must be odd, larger than polyorder={polyorder} and at most n_samples="
            f"{n_samples}; got {window!r}"
        )
    return w


def mean_curve_stiffness(
    ds: xr.Dataset,
    *,
    loads: ArrayLike | None = None,
    n_samples: int = 201,
    window: int | None = None,
    polyorder: int = 2,
    n_boot: int = 400,
    confidence: float = 0.95,
    seed: int = 0,
) -> xr.Dataset:
    """Stiffness of the ensemble-mean F_N(δ_N) curve: the estimator of the paper's Fig. 11a.

    The paper averages F_N, δ_N and A_S over the realizations of each D and shows the stiffness
    of the averaged curves. Here every successful realization is interpolated onto
    ``n_samples`` displacements from 0 to the smallest final displacement of its grid point
    (:func:`ensemble_vs_displacement`), the curves are averaged, and the mean curve F̄(δ_N) is
    differentiated with the Savitzky–Golay derivative of :func:`stiffness` (``window`` samples,
    default 5 % of them). k̄ is then a function of the mean load F̄; at a given load it is read
    where F̄ first reaches that load (linear between the two samples around it). This is *not*
    the mean of the realizations' stiffness at a load (:func:`dimensionless_stiffness`): a mean
    curve mixes realizations at different loads, and the two estimators can disagree on trends
    with D.

    The uncertainty is a bootstrap over realizations (``n_boot`` resamples within each grid
    point, seeded): the interval is k̄ ± z·SE_boot (normal bootstrap), so it always contains k̄.

    Parameters
    ----------
    ds : xarray.Dataset
        Study Dataset.
    loads : array_like, optional
        Loads F_N [mN/µm] at which to also return k̄ and its bootstrap replicates.
    n_samples : int
        Displacement samples of the mean curve.
    window : int, optional
        Odd Savitzky–Golay window [samples]; default 5 % of ``n_samples`` (at least 5).
    polyorder : int
        Degree of the local polynomial.
    n_boot : int
        Bootstrap resamples (≥ 2; 0 skips the uncertainty).
    confidence : float
        Level of the intervals [1].
    seed : int
        Seed of the bootstrap generator.

    Returns
    -------
    xarray.Dataset
        On (grid…, sample): coordinates ``displacement`` [µm], ``normal_force`` (the mean load
        F̄ [mN/µm]) and ``dimensionless_load`` [1]; ``stiffness_mean`` [mN/µm²] and
        ``dimensionless_stiffness_{mean,ci_low,ci_high}`` [1]. With ``loads``, on
        (grid…, load): ``stiffness_at_load`` [mN/µm²], ``stiffness_at_load_se`` [mN/µm²] and
        on (grid…, boot, load) ``stiffness_at_load_boot`` [mN/µm²] (the same resamples for every
        load); and ``count`` on (grid…) (realizations averaged).
    """
    _check_samples(n_samples)
    if not 0.0 < confidence < 1.0:
        raise ParameterError(f"confidence must lie in (0, 1), got {confidence!r}")
    if n_boot < 0 or n_boot == 1:
        raise ParameterError(f"n_boot must be 0 or at least 2, got {n_boot!r}")
    w = _mean_curve_window(n_samples, window, polyorder)
    gdims, _, f, x = _mean_curve_pieces(ds, n_samples)
    load_arr = (
        np.atleast_1d(np.asarray(loads, dtype=np.float64)) if loads is not None else np.empty(0)
    )
    grid_shape = x.shape[:-1]
    fbar = np.full(x.shape, np.nan)
    kbar = np.full(x.shape, np.nan)
    k_se = np.full(x.shape, np.nan)
    counts = np.zeros(grid_shape, dtype=np.int64)
    at = np.full((*grid_shape, load_arr.size), np.nan)
    at_boot = np.full((*grid_shape, n_boot, load_arr.size), np.nan)
    z = float(stats.norm.ppf(0.5 + confidence / 2.0))
    for flat, gp in enumerate(np.ndindex(*grid_shape)):
        rows = f[gp][np.isfinite(f[gp]).all(axis=-1)]
        n_r = rows.shape[0]
        counts[gp] = n_r
        dx = float(np.mean(np.diff(x[gp])))
        if n_r == 0 or not dx > 0:
            continue
        fbar[gp] = rows.mean(axis=0)
        kbar[gp] = _savgol_rows(fbar[gp], dx, w, polyorder)
        at[gp] = _first_crossing(fbar[gp][None], kbar[gp][None], load_arr)[0]
        if n_boot and n_r >= 2:
            rng = np.random.default_rng([seed, flat])
            weights = rng.multinomial(n_r, np.full(n_r, 1.0 / n_r), size=n_boot) / n_r
            fb = weights @ rows
            kb = _savgol_rows(fb, dx, w, polyorder)
            k_se[gp] = kb.std(axis=0, ddof=1)
            at_boot[gp] = _first_crossing(fb, kb, load_arr)
    e_star = float(np.asarray(parameter(ds, "e_star")).ravel()[0])
    length = float(np.asarray(parameter(ds, "length")).ravel()[0])
    coords = _grid_coords(ds, gdims)
    s_dims = (*gdims, "sample")
    coords["displacement"] = xr.Variable(s_dims, x, {"units": "µm"})
    coords["normal_force"] = xr.Variable(
        s_dims, fbar, {"units": "mN/µm", "long_name": "ensemble-mean normal force F̄_N"}
    )
    coords["dimensionless_load"] = xr.Variable(
        s_dims, fbar / (e_star * length), {"units": "1", "long_name": "F̄_N/(E* L0)"}
    )
    k1 = {"units": "1", "long_name": "k/E* of the ensemble-mean curve"}
    data: dict[str, Any] = {
        "stiffness_mean": xr.Variable(
            s_dims, kbar, {"units": "mN/µm²", "long_name": "dF̄_N/dδ_N of the mean curve"}
        ),
        "dimensionless_stiffness_mean": xr.Variable(s_dims, kbar / e_star, k1),
        "dimensionless_stiffness_ci_low": xr.Variable(s_dims, (kbar - z * k_se) / e_star, k1),
        "dimensionless_stiffness_ci_high": xr.Variable(s_dims, (kbar + z * k_se) / e_star, k1),
        "count": xr.Variable(gdims, counts, {"units": "1"}),
    }
    if load_arr.size:
        coords["load"] = xr.Variable(("load",), load_arr, {"units": "mN/µm"})
        data["stiffness_at_load"] = xr.Variable((*gdims, "load"), at, {"units": "mN/µm²"})
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            se = np.nanstd(at_boot, axis=-2, ddof=1) if n_boot else np.full(at.shape, np.nan)
        data["stiffness_at_load_se"] = xr.Variable((*gdims, "load"), se, {"units": "mN/µm²"})
        data["stiffness_at_load_boot"] = xr.Variable(
            (*gdims, "boot", "load"), at_boot, {"units": "mN/µm²"}
        )
    out = xr.Dataset(data, coords=coords)
    out.attrs.update(
        estimator="ensemble-mean curve",
        window=w,
        polyorder=polyorder,
        n_boot=n_boot,
        confidence=confidence,
    )
    return out


# --- trend tests for the report ---------------------------------------------------------------

Verdict = Literal["reproduced", "partly reproduced", "not reproduced", "undetermined"]
TrendShape = Literal["decreasing", "increasing", "not monotone", "no clear trend"]


@dataclass(frozen=True)
class TrendTest:
    """Is a quantity monotone in a parameter? Rank correlation plus adjacent differences.

    Two pieces of evidence, because either alone misleads with a handful of parameter values:

    * Spearman's ρ between the parameter and the group estimates, with its **exact** two-sided
      p-value over the groups (:func:`spearman_pvalue`). A bootstrap interval of ρ is not a test
      of a monotone trend: a U-shape can give ρ < 0 in every resample.
    * The difference between each pair of adjacent groups with a simultaneous (Bonferroni)
      confidence interval: a step is *down* (*up*) when its whole interval lies below (above) 0.

    :attr:`shape` combines them: ``decreasing`` when ρ < 0 is significant (p ≤ ``alpha``) or
    every step is down, and no step is up; ``not monotone`` when some step is down and another
    up; ``no clear trend`` otherwise (symmetrically for ``increasing``).

    Attributes
    ----------
    x : ndarray
        Parameter value of each group (e.g. D).
    means : ndarray
        Estimate of each group (the mean of its realizations for :func:`trend_test`).
    ci_low, ci_high : ndarray
        Confidence interval of each group estimate (contains the estimate).
    counts : ndarray
        Number of realizations behind each estimate.
    rho : float
        Spearman ρ [1] of the group estimates with ``x`` (NaN with fewer than 3 finite groups).
    p_value : float
        Exact two-sided p-value [1] of ρ.
    step_x : ndarray
        (n_steps, 2): the two parameter values of each adjacent pair (finite groups only).
    step_diff, step_low, step_high : ndarray
        Difference (later − earlier) and its simultaneous interval, per adjacent pair.
    step_sign : ndarray
        −1 (down), +1 (up) or 0 (interval contains 0, or not computable) per adjacent pair.
    alpha : float
        Significance level of ρ [1].
    confidence : float
        Level of the group intervals and the family level of the step intervals [1].
    """

    x: NDArray[np.float64]
    means: NDArray[np.float64]
    ci_low: NDArray[np.float64]
    ci_high: NDArray[np.float64]
    counts: NDArray[np.int64]
    rho: float
    p_value: float
    step_x: NDArray[np.float64]
    step_diff: NDArray[np.float64]
    step_low: NDArray[np.float64]
    step_high: NDArray[np.float64]
    step_sign: NDArray[np.int64]
    alpha: float = 0.05
    confidence: float = 0.95
    extra: Mapping[str, Any] = field(default_factory=dict)

    @property
    def enough(self) -> bool:
        """At least three groups with an estimate and an interval."""
        ok = np.isfinite(self.means) & np.isfinite(self.ci_low) & np.isfinite(self.ci_high)
        return bool(ok.sum() >= 3 and math.isfinite(self.rho))

    @property
    def shape(self) -> TrendShape:
        """``decreasing``, ``increasing``, ``not monotone`` or ``no clear trend`` (see class)."""
        down = bool((self.step_sign == -1).any())
        up = bool((self.step_sign == 1).any())
        if down and up:
            return "not monotone"
        significant = math.isfinite(self.p_value) and self.p_value <= self.alpha
        every = self.step_sign.size >= 2
        if not up and ((significant and self.rho < 0) or (every and (self.step_sign == -1).all())):
            return "decreasing"
        if not down and ((significant and self.rho > 0) or (every and (self.step_sign == 1).all())):
            return "increasing"
        return "no clear trend"

    @property
    def decreasing(self) -> bool:
        """True if :attr:`shape` is ``decreasing``."""
        return self.shape == "decreasing"

    @property
    def increasing(self) -> bool:
        """True if :attr:`shape` is ``increasing``."""
        return self.shape == "increasing"

    def verdict(self, direction: Literal["decreasing", "increasing"]) -> Verdict:
        """Verdict on the claim "the quantity is monotone ``direction`` in x".

        ``reproduced`` when :attr:`shape` equals ``direction``; ``partly reproduced`` when the
        groups are not monotone but ρ has the claimed sign, or when there is no clear trend
        but some step goes the claimed way and none the other; ``not reproduced`` otherwise;
        ``undetermined`` with fewer than three usable groups.
        """
        if direction not in ("decreasing", "increasing"):
            raise ParameterError(
                f"direction must be 'decreasing' or 'increasing', got {direction!r}"
            )
        if not self.enough:
            return "undetermined"
        sign = -1 if direction == "decreasing" else 1
        shape = self.shape
        if shape == direction:
            return "reproduced"
        along = bool((self.step_sign == sign).any())
        against = bool((self.step_sign == -sign).any())
        rho_along = math.isfinite(self.rho) and self.rho * sign > 0
        if shape == "not monotone":
            return "partly reproduced" if rho_along else "not reproduced"
        if shape == "no clear trend" and along and not against and rho_along:
            return "partly reproduced"
        return "not reproduced"

    def describe(self) -> str:
        """One phrase: the shape, ρ with its exact p, and the significant steps."""
        words = {
            "decreasing": "falls",
            "increasing": "rises",
            "not monotone": "not monotone",
            "no clear trend": "no clear trend",
        }
        text = f"{words[self.shape]} (ρ = {_num(self.rho, 2)}, exact p = {_num(self.p_value, 2)}"
        steps = [
            f"{'↓' if s < 0 else '↑'} {a:g}→{b:g}"
            for (a, b), s in zip(self.step_x, self.step_sign, strict=True)
            if s != 0
        ]
        n = int(self.step_sign.size)
        text += f"; significant steps {len(steps)} of {n}" + (
            f": {', '.join(steps)}" if steps else ""
        )
        return text + ")"


def _num(x: float, digits: int) -> str:
    return f"{x:.{digits}g}" if math.isfinite(x) else "–"


@functools.lru_cache(maxsize=32)
def _spearman_null(n: int) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Exact null distribution of Spearman's ρ for n untied values: (ρ values, probabilities).

    Counts the permutations π by S = Σ i·π(i) with a dynamic programme over subsets (2ⁿ states),
    so n = 12 costs milliseconds where enumerating 12! orders would not finish.
    """
    s_max = sum(i * i for i in range(n))
    dp = np.zeros((1 << n, s_max + 1), dtype=np.float64)
    dp[0, 0] = 1.0
    for mask in range(1 << n):
        row = dp[mask]
        if not row.any():
            continue
        i = mask.bit_count()
        for v in range(n):
            if not (mask >> v) & 1:
                shift = i * v
                dp[mask | (1 << v), shift:] += row[: s_max + 1 - shift]
    counts = dp[-1]
    s = np.arange(s_max + 1, dtype=np.float64)
    sum_d2 = 2.0 * s_max - 2.0 * s
    rho = 1.0 - 6.0 * sum_d2 / (n * (n * n - 1.0))
    keep = counts > 0
    return rho[keep], counts[keep] / counts.sum()


#: Largest number of groups with an exact p-value (above: Student-t approximation).
EXACT_SPEARMAN_MAX = 12


def spearman_pvalue(rho: float, n: int) -> float:
    """Two-sided p-value of Spearman's ρ for n groups without ties.

    Exact for n ≤ :data:`EXACT_SPEARMAN_MAX` (all n! orders, counted by a dynamic programme);
    the Student-t approximation of scipy above. For the handful of parameter values of a study
    the t approximation is far off (it gives p = 0 for ρ = ±1 with n = 3, where the exact value
    is 1/3).
    """
    if not math.isfinite(rho) or n < 3:
        return math.nan
    if n <= EXACT_SPEARMAN_MAX:
        values, probs = _spearman_null(n)
        return float(probs[np.abs(values) >= abs(rho) - 1e-12].sum())
    t = rho * math.sqrt((n - 2) / max(1e-300, 1.0 - rho * rho))
    return float(2 * stats.t.sf(abs(t), n - 2))


def _spearman(x: NDArray[np.float64], y: NDArray[np.float64]) -> float:
    good = np.isfinite(y)
    if good.sum() < 3 or np.ptp(y[good]) == 0 or np.ptp(x[good]) == 0:
        return math.nan
    return float(stats.spearmanr(x[good], y[good]).statistic)


def bootstrap_means(
    groups: Sequence[NDArray[np.float64]], n_boot: int, rng: np.random.Generator
) -> NDArray[np.float64]:
    """Means of ``n_boot`` resamples (with replacement) of every group: shape (n_boot, groups).

    NaN values are left out of the means; an empty group gives NaN.
    """
    out = np.full((n_boot, len(groups)), np.nan)
    for g, v in enumerate(groups):
        if v.size:
            idx = rng.integers(0, v.size, (n_boot, v.size))
            with np.errstate(invalid="ignore"), warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                out[:, g] = np.nanmean(v[idx], axis=1)
    return out


def trend_from_estimates(
    x: ArrayLike,
    estimates: ArrayLike,
    standard_errors: ArrayLike,
    *,
    dof: ArrayLike | None = None,
    counts: ArrayLike | None = None,
    confidence: float = 0.95,
    alpha: float = 0.05,
) -> TrendTest:
    """Trend test (see :class:`TrendTest`) from per-group estimates and standard errors.

    Parameters
    ----------
    x : array_like
        Parameter of each group, increasing.
    estimates : array_like
        Estimate of each group (NaN: no estimate).
    standard_errors : array_like
        Standard error of each estimate [unit of the estimates].
    dof : array_like, optional
        Degrees of freedom of each standard error (n − 1 for a mean): Student-t and Welch
        intervals. Without it (e.g. bootstrap standard errors) normal quantiles are used.
    counts : array_like, optional
        Realizations behind each estimate (reported only).
    confidence : float
        Level of the group intervals, and the family-wise level of the step intervals [1].
    alpha : float
        Significance level of the exact Spearman test [1].

    Returns
    -------
    TrendTest
    """
    if not 0.0 < confidence < 1.0:
        raise ParameterError(f"confidence must lie in (0, 1), got {confidence!r}")
    if not 0.0 < alpha < 1.0:
        raise ParameterError(f"alpha must lie in (0, 1), got {alpha!r}")
    xa = np.asarray(x, dtype=np.float64)
    est = np.asarray(estimates, dtype=np.float64)
    se = np.asarray(standard_errors, dtype=np.float64)
    if not xa.shape == est.shape == se.shape or xa.ndim != 1:
        raise ParameterError(
            f"x, estimates and standard_errors must be 1-D of one length, got shapes "
            f"{xa.shape}, {est.shape}, {se.shape}"
        )
    nu = np.asarray(dof, dtype=np.float64) if dof is not None else np.full(xa.shape, np.inf)
    cnt = (
        np.asarray(counts, dtype=np.int64)
        if counts is not None
        else np.where(np.isfinite(est), 1, 0).astype(np.int64)
    )

    def quantile(level: float, df: NDArray[np.float64]) -> NDArray[np.float64]:
        with np.errstate(invalid="ignore"):
            return np.asarray(
                np.where(
                    np.isinf(df),
                    stats.norm.ppf(level),
                    stats.t.ppf(level, np.where(df > 0, df, np.nan)),
                )
            )

    half = quantile(0.5 + confidence / 2.0, nu) * se
    good = np.flatnonzero(np.isfinite(est))
    rho = _spearman(xa, est)
    p_value = spearman_pvalue(rho, int(good.size))
    a, b = good[:-1], good[1:]
    m = max(1, a.size)
    diff = est[b] - est[a]
    with np.errstate(invalid="ignore", divide="ignore"):
        se_d = np.sqrt(se[a] ** 2 + se[b] ** 2)
        welch = se_d**4 / (se[a] ** 4 / nu[a] + se[b] ** 4 / nu[b])
    welch = np.where(np.isinf(nu[a]) & np.isinf(nu[b]), np.inf, welch)
    half_d = quantile(1.0 - (1.0 - confidence) / (2.0 * m), welch) * se_d
    low, high = diff - half_d, diff + half_d
    sign = np.where(high < 0, -1, np.where(low > 0, 1, 0)).astype(np.int64)
    sign[~np.isfinite(low) | ~np.isfinite(high)] = 0
    return TrendTest(
        x=xa,
        means=est,
        ci_low=est - half,
        ci_high=est + half,
        counts=cnt,
        rho=rho,
        p_value=p_value,
        step_x=np.column_stack([xa[a], xa[b]]) if a.size else np.empty((0, 2)),
        step_diff=diff,
        step_low=low,
        step_high=high,
        step_sign=sign,
        alpha=alpha,
        confidence=confidence,
    )


def trend_test(
    x: ArrayLike,
    groups: Sequence[ArrayLike],
    *,
    confidence: float = 0.95,
    alpha: float = 0.05,
) -> TrendTest:
    """Does the group mean rise or fall monotonically with ``x``?

    Group means with Student-t intervals, adjacent differences with simultaneous Welch
    intervals (Bonferroni over the adjacent pairs), and Spearman's ρ of the means with its
    exact p-value; see :class:`TrendTest` for how they are combined.

    Parameters
    ----------
    x : array_like
        Parameter of each group, increasing (at least 3 groups for a verdict).
    groups : sequence of array_like
        Per-realization values of each group (NaN are dropped).
    confidence : float
        Level of the intervals [1].
    alpha : float
        Significance level of the exact Spearman test [1].

    Returns
    -------
    TrendTest
    """
    xa = np.asarray(x, dtype=np.float64)
    vals = [np.asarray(g, dtype=np.float64).ravel() for g in groups]
    vals = [v[np.isfinite(v)] for v in vals]
    if xa.size != len(vals):
        raise ParameterError(f"x has {xa.size} values but there are {len(vals)} groups")
    counts = np.array([v.size for v in vals], dtype=np.int64)
    means = np.array([v.mean() if v.size else np.nan for v in vals])
    stds = np.array([v.std(ddof=1) if v.size >= 2 else np.nan for v in vals])
    with np.errstate(invalid="ignore", divide="ignore"):
        se = stds / np.sqrt(counts)
    return trend_from_estimates(
        xa,
        means,
        se,
        dof=np.where(counts >= 2, counts - 1.0, np.nan),
        counts=counts,
        confidence=confidence,
        alpha=alpha,
    )
