"""Ensemble statistics of a study Dataset: dataset helpers, the common abscissa, means and bands.

See :mod:`splinecontact.analysis` for the layout of the study Dataset and the conventions
(common abscissa, force as abscissa, Student-t intervals of the mean).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from typing import Any, Literal

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike, NDArray
from scipy import stats

from ..errors import AnalysisError, ParameterError
from ._defaults import _PARAMETER_DEFAULTS

__all__ = [
    "confidence_halfwidth",
    "ensemble_statistics",
    "ensemble_vs_displacement",
    "ensemble_vs_force",
    "grid_dims",
    "interpolate_realizations",
    "ok_mask",
    "parameter",
    "values_at",
]

_NON_GRID_DIMS = ("realization", "step", "contact", "sample")

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

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from splinecontact.study import run_study, open_study
    >>> from splinecontact.analysis import ensemble_vs_displacement
    >>> config = {"study": {"name": "tiny", "seed": 1, "realizations": 2},
    ...           "fixed": {"n_points": 2048, "length": 10.0, "steps": 20},
    ...           "sweep": {"dimension": [1.3, 1.7]}}
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     summary = run_study(config, pathlib.Path(folder) / "tiny.zarr", workers=1)
    ...     ds = open_study(pathlib.Path(folder) / "tiny.zarr")
    >>> ensemble_vs_displacement(ds, ["normal_force"], n_samples=11)["normal_force_mean"].shape
    (2, 11)
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
