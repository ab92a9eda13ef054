"""Figures of the contact-law studies: pull-off, work of separation, residual approach,
dissipation and κ against D, with confidence bands (from :func:`~splinecontact.analysis.
laws_study.laws_study` datasets).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from ..errors import ParameterError
from ._base import draw_ensemble_vs_dimension, new_axes

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["LAWS_STUDY_LABELS", "plot_laws_study"]

#: Axis label of each :data:`~splinecontact.analysis.laws_study.LAWS_STUDY_VARIABLES` name.
LAWS_STUDY_LABELS: dict[str, str] = {
    "pull_off_force": "pull-off force −min F_N",
    "work_of_separation": "work of separation",
    "residual_displacement": "residual approach δ_r",
    "residual_fraction": "residual approach δ_r / δ_max",
    "dissipated_energy": "energy dissipated per cycle",
    "kappa": "κ = R_Sq E* dA_S/dF_N",
    "zero_area_force": "force at vanishing area F_0",
}


def plot_laws_study(
    studies: dict[str, Any], name: str = "pull_off_force", ax: Axes | None = None
) -> Axes:
    """Ensemble mean of one ``laws_study`` variable against D, one curve per study, with its
    Student-t confidence band.

    Parameters
    ----------
    studies : dict of str to xarray.Dataset
        Label (e.g. the law's name) -> result of ``laws_study``.
    name : str
        A ``LAWS_STUDY_VARIABLES`` name.
    ax : matplotlib Axes, optional
        Axes to draw on (a new figure when omitted).
    """
    if name not in LAWS_STUDY_LABELS:
        raise ParameterError(
            f"{name!r} is not a laws_study variable; give one of {sorted(LAWS_STUDY_LABELS)}"
        )
    ax = new_axes(ax)
    units, level = draw_ensemble_vs_dimension(ax, studies, name)
    ax.set_xlabel("fractal dimension D [1]")
    ax.set_ylabel(f"{LAWS_STUDY_LABELS[name]} [{units}]")
    ax.set_title(f"band: {level:.0%} confidence interval of the mean", fontsize="small")
    if studies:
        ax.legend()
    return ax
