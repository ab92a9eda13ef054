"""Contact stiffness k = dF_N/dδ_N: per realization, dimensionless, and of the ensemble-mean curve.

Two estimators (see :mod:`splinecontact.analysis`): the Savitzky–Golay derivative of every
realization's F_N(δ_N) (:func:`stiffness`, :func:`dimensionless_stiffness`), and the derivative
of the ensemble-mean curve shown in the paper's Fig. 11a (:func:`mean_curve_stiffness`).
"""

from __future__ import annotations

import functools
import warnings
from typing import Any, Literal

import numpy as np
import xarray as xr
from numpy.typing import ArrayLike, NDArray
from scipy import signal, stats

from ..errors import AnalysisError, ParameterError
from .ensemble import (
    _check_samples,
    _ensemble,
    _grid_coords,
    _ordered,
    _require,
    _step_arrays,
    grid_dims,
    interpolate_realizations,
    ok_mask,
    parameter,
)

__all__ = ["dimensionless_stiffness", "mean_curve_stiffness", "stiffness"]

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
