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
* **Force as abscissa.** F_N(δ_N) never decreases, but it has plateaus (no new contact in a step).
  Only the steps at which F_N exceeds every earlier value are used as interpolation nodes (the first
  time each load is reached).
* **Ensemble statistics.** Mean, sample standard deviation (ddof = 1) and the two-sided confidence
  interval of the mean from Student's t with n − 1 degrees of freedom (95 % by default).
* **Stiffness.** k = dF_N/dδ_N by a Savitzky–Golay derivative (local least-squares quadratic over a
  sliding window of ``window`` steps on the uniform displacement grid of each realization). See
  :func:`stiffness`.
* **κ (eq. 15).** κ = R_Sq · E* · s with s the least-squares slope through the origin of A_S against
  F_N over F_N ≤ ``fit_fraction`` × the realization's final load. See :func:`kappa`.
"""

from __future__ import annotations

import functools
import itertools
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
    "measured_hurst",
    "nominal_hurst",
    "ok_mask",
    "parameter",
    "power_law_exponent",
    "spearman_pvalue",
    "stiffness",
    "study_hurst",
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
        Upper end of the abscissa per grid point, as a quantile of the end values of the grid
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
        Quantile of the final loads that ends the load range (see
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


# --- trend tests for the report ---------------------------------------------------------------


@dataclass(frozen=True)
class TrendTest:
    """Spearman rank correlation of group means with a parameter, with a bootstrap interval.

    Attributes
    ----------
    x : ndarray
        Parameter value of each group (e.g. D).
    means : ndarray
        Mean of each group.
    ci_low, ci_high : ndarray
        Student-t confidence interval of each group mean.
    counts : ndarray
        Number of finite values per group.
    rho : float
        Spearman ρ of the group means with ``x``.
    rho_low, rho_high : float
        Percentile bootstrap interval of ρ (realizations resampled within each group).
    p_value : float
        Two-sided p-value of ρ over the groups (exact for ≤ 9 groups, see
        :func:`spearman_pvalue`).
    """

    x: NDArray[np.float64]
    means: NDArray[np.float64]
    ci_low: NDArray[np.float64]
    ci_high: NDArray[np.float64]
    counts: NDArray[np.int64]
    rho: float
    rho_low: float
    rho_high: float
    p_value: float
    extra: Mapping[str, Any] = field(default_factory=dict)

    @property
    def decreasing(self) -> bool:
        """True if the whole bootstrap interval of ρ lies below 0."""
        return bool(self.rho_high < 0)

    @property
    def increasing(self) -> bool:
        """True if the whole bootstrap interval of ρ lies above 0."""
        return bool(self.rho_low > 0)


@functools.lru_cache(maxsize=16)
def _spearman_null(n: int) -> NDArray[np.float64]:
    """Exact null distribution of Spearman's ρ for n untied values (all n! rank orders)."""
    perms = np.array(list(itertools.permutations(range(n))), dtype=np.float64)
    d2 = ((perms - np.arange(n)) ** 2).sum(axis=1)
    return np.asarray(1.0 - 6.0 * d2 / (n * (n * n - 1.0)))


def spearman_pvalue(rho: float, n: int) -> float:
    """Two-sided p-value of Spearman's ρ for n groups without ties.

    Exact (enumeration of all n! orders) for n ≤ 9, the t approximation of scipy above. For the
    handful of parameter values of a study the t approximation is far off (it gives p = 0 for
    ρ = ±1 with n = 3, where the exact value is 1/3).
    """
    if not math.isfinite(rho) or n < 3:
        return math.nan
    if n <= 9:
        null = _spearman_null(n)
        return float(np.mean(np.abs(null) >= abs(rho) - 1e-12))
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


def _ranks(a: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.argsort(np.argsort(a, axis=-1), axis=-1).astype(np.float64)


def _bootstrap_spearman(
    x: NDArray[np.float64],
    groups: Sequence[NDArray[np.float64]],
    n_boot: int,
    rng: np.random.Generator,
) -> NDArray[np.float64]:
    """Spearman ρ of x with resampled group means, vectorized over the resamples."""
    keep = np.array([g.size > 0 for g in groups])
    if keep.sum() < 3:
        return np.full(n_boot, np.nan)
    means = bootstrap_means([g for g, k in zip(groups, keep, strict=True) if k], n_boot, rng)
    rx = _ranks(x[keep])
    rx = rx - rx.mean()
    ry = _ranks(means)
    ry = ry - ry.mean(axis=1, keepdims=True)
    denom = np.sqrt((rx**2).sum() * (ry**2).sum(axis=1))
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.asarray((ry * rx).sum(axis=1) / denom)


def trend_test(
    x: ArrayLike,
    groups: Sequence[ArrayLike],
    *,
    n_boot: int = 2000,
    confidence: float = 0.95,
    seed: int = 0,
) -> TrendTest:
    """Does the group mean rise or fall monotonically with ``x``?

    The statistic is Spearman's ρ between ``x`` and the group means; its uncertainty is a
    percentile bootstrap: the values of every group are resampled with replacement (realizations
    are independent), the means and ρ recomputed ``n_boot`` times. A trend is called decreasing
    (increasing) when the whole bootstrap interval lies below (above) zero.

    Parameters
    ----------
    x : array_like
        Parameter of each group (at least 3 groups).
    groups : sequence of array_like
        Per-realization values of each group (NaN are dropped).
    n_boot : int
        Number of bootstrap resamples.
    confidence : float
        Level of the intervals [1].
    seed : int
        Seed of the bootstrap generator (results are reproducible).

    Returns
    -------
    TrendTest
    """
    xa = np.asarray(x, dtype=np.float64)
    vals = [np.asarray(g, dtype=np.float64) for g in groups]
    vals = [v[np.isfinite(v)] for v in vals]
    if xa.size != len(vals):
        raise ParameterError(f"x has {xa.size} values but there are {len(vals)} groups")
    counts = np.array([v.size for v in vals], dtype=np.int64)
    means = np.array([v.mean() if v.size else np.nan for v in vals])
    stds = np.array([v.std(ddof=1) if v.size >= 2 else np.nan for v in vals])
    half = confidence_halfwidth(stds, counts, confidence)
    rho = _spearman(xa, means)
    good = np.isfinite(means)
    p_value = spearman_pvalue(rho, int(good.sum()))
    rng = np.random.default_rng(seed)
    boots = _bootstrap_spearman(xa, vals, n_boot, rng)
    alpha = (1.0 - confidence) / 2.0
    finite = boots[np.isfinite(boots)]
    if finite.size and math.isfinite(rho):
        lo, hi = (float(q) for q in np.quantile(finite, [alpha, 1.0 - alpha]))
    else:
        lo = hi = math.nan
    return TrendTest(
        x=xa,
        means=means,
        ci_low=means - half,
        ci_high=means + half,
        counts=counts,
        rho=rho,
        rho_low=lo,
        rho_high=hi,
        p_value=p_value,
    )
