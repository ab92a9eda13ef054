"""Figures of one simulation result (the netCDF file of ``splinecontact simulate``)."""

from __future__ import annotations

import numpy as np
import xarray as xr
from matplotlib.figure import Figure

from ..errors import ParameterError
from ._base import figure_of, new_axes

__all__ = ["RESULT_FIGURES", "result_figures"]

#: Figures of one simulation result: file stem -> (x variable, y variable, title).
RESULT_FIGURES: dict[str, tuple[str, str, str]] = {
    "normal_force_displacement": ("displacement", "normal_force", "F_N vs δ_N"),
    "tangential_force_displacement": ("displacement", "tangential_force", "F_T vs δ_N"),
    "area_force": ("normal_force", "contact_area", "A_S vs F_N"),
    "separation_force": ("normal_force", "mean_separation", "mean separation vs F_N"),
}

_RESULT_LABELS: dict[str, str] = {
    "displacement": "δ_N",
    "normal_force": "F_N",
    "tangential_force": "F_T",
    "contact_area": "A_S",
    "mean_separation": "mean separation",
}


def result_figures(ds: xr.Dataset, *, title: str = "") -> dict[str, Figure]:
    """The four curves of one simulation result (netCDF of ``splinecontact simulate``).

    F_N and F_T against δ_N, A_S and the mean separation against F_N, each on its own figure
    with the units stored in the file.

    Parameters
    ----------
    ds : xarray.Dataset
        A result written by :meth:`splinecontact.results.SimulationResult.to_netcdf`.
    title : str
        Prefix of every figure title (e.g. the file name).

    Returns
    -------
    dict of str to Figure
        One figure per key of :data:`RESULT_FIGURES`.

    Raises
    ------
    ParameterError
        A variable is missing, or a curve has fewer than two finite points.
    """
    figures: dict[str, Figure] = {}
    for stem, (xname, yname, what) in RESULT_FIGURES.items():
        for name in (xname, yname):
            if name not in ds.variables or ds[name].dims != ("step",):
                raise ParameterError(
                    f"the result has no per-step variable {name!r}: not a file written by "
                    "`splinecontact simulate`"
                )
        x = np.asarray(ds[xname].values, dtype=np.float64)
        y = np.asarray(ds[yname].values, dtype=np.float64)
        ok = np.isfinite(x) & np.isfinite(y)
        if int(ok.sum()) < 2:
            raise ParameterError(
                f"{what}: fewer than two finite points in the result; nothing to draw"
            )
        ax = new_axes(figsize=(5.6, 4.2))
        ax.plot(x[ok], y[ok], "C0-", lw=1.2)
        for axis, name in ((ax.set_xlabel, xname), (ax.set_ylabel, yname)):
            units = ds[name].attrs.get("units", "?")
            axis(f"{_RESULT_LABELS[name]} [{units}]")
        ax.grid(True, alpha=0.3)
        ax.set_title(f"{title}: {what}" if title else what, fontsize=9)
        figures[stem] = figure_of(ax)
    return figures
