"""Friction figures: F_T against u_T (hysteresis loops), the force history, μ_s or k_T/k_N vs D.

Figures are :class:`matplotlib.figure.Figure` objects (Agg backend), axes labelled with units.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from ..results import SimulationResult
from ._base import draw_ensemble_vs_dimension, new_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["plot_friction_loop", "plot_path_history", "plot_study_vs_dimension"]


def plot_friction_loop(
    result: SimulationResult, ax: Axes | None = None, *, label: str | None = None, **kw: Any
) -> Axes:
    """F_T [mN/µm] against u_T [nm]; cycles show as hysteresis loops.

    Parameters
    ----------
    result : SimulationResult
        From ``simulate(..., path=...)``.
    ax : matplotlib Axes, optional
        Axes to draw on (a new figure when omitted).
    label : str, optional
        Legend label of the curve.
    """
    ax = new_axes(ax)
    u = 1e3 * np.asarray(result.curves["tangential_displacement"])
    ax.plot(u, result.curves["tangential_force"], label=label, **kw)
    ax.axhline(0.0, color="0.7", lw=0.5)
    ax.set_xlabel("tangential displacement u_T [nm]")
    ax.set_ylabel("tangential force F_T on the upper body [mN/µm]")
    if label is not None:
        ax.legend()
    return ax


def plot_path_history(result: SimulationResult, ax: Axes | None = None) -> Axes:
    """δ_N and u_T [nm] (left axis) and F_N, F_T [mN/µm] (right axis) against the step."""
    ax = new_axes(ax)
    steps = np.arange(len(result.curves["displacement"]))
    ax.plot(steps, 1e3 * np.asarray(result.curves["displacement"]), label="δ_N")
    ax.plot(steps, 1e3 * np.asarray(result.curves["tangential_displacement"]), label="u_T")
    ax.set_xlabel("step")
    ax.set_ylabel("displacement [nm]")
    right = ax.twinx()
    right.plot(steps, result.curves["normal_force"], "k-", lw=0.8, label="F_N")
    right.plot(steps, result.curves["tangential_force"], "r-", lw=0.8, label="F_T")
    right.set_ylabel("force [mN/µm]")
    lines = ax.get_lines() + right.get_lines()
    ax.legend(lines, [str(line.get_label()) for line in lines], loc="best")
    return ax


def plot_study_vs_dimension(
    studies: dict[str, Any], name: str = "mu_s", ax: Axes | None = None
) -> Axes:
    """Ensemble mean of a :func:`splinecontact.analysis.friction_study` variable against D.

    Parameters
    ----------
    studies : dict of str to xarray.Dataset
        Label (e.g. "rough-on-rough") -> result of ``friction_study``.
    name : str
        Variable of ``FRICTION_STUDY_VARIABLES``; the band is its confidence interval.
    ax : matplotlib Axes, optional
        Axes to draw on.
    """
    ax = new_axes(ax)
    units, level = draw_ensemble_vs_dimension(ax, studies, name)
    ax.set_xlabel("fractal dimension D [1]")
    ax.set_ylabel(f"{name} [{units}]  (band: {level:.0%} CI of the mean)")
    ax.legend()
    return ax
