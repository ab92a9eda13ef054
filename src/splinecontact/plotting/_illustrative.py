"""Figs. 3a, 4, 5, 8 and 9 together, from the profiles, splines and contacts passed in.

:class:`IllustrativeInputs` holds everything these figures draw; the caller makes it once
(``splinecontact reproduce`` and ``splinecontact plot`` regenerate the study's realization-0
profiles from its seed rule, since the store keeps curves, not profiles). Nothing here
generates a profile, fits a spline or runs a simulation.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from matplotlib.figure import Figure

from ..errors import ParameterError
from ..outputs import OutputFolder
from ._base import NM_PER_UM, figure_of, new_axes, write_figures
from ._profiles import (
    plot_contact_zoom,
    plot_first_contact,
    plot_profiles,
    plot_spheres,
    plot_spline_fits,
    upper_global,
)

if TYPE_CHECKING:
    from ..profile import Profile
    from ..results import ContactRecord
    from ..spline import SplineFit

__all__ = ["IllustrativeInputs", "illustrative_figures", "make_illustrative_figures"]


@dataclass(frozen=True)
class IllustrativeInputs:
    """What Figs. 3a, 4, 5, 8 and 9 draw, made once by the caller.

    Attributes
    ----------
    dimensions : tuple of float
        Fractal dimension D [1] of each profile of Fig. 3a.
    profiles : tuple of Profile
        One profile per D (Fig. 3a), heights and grid [µm].
    focus_dimension : float
        D [1] of the pair drawn in Figs. 4, 5, 8 and 9.
    lower : Profile
        Lower profile of that pair (its points are drawn in Fig. 4).
    fits : tuple of SplineFit
        Splines of ``lower`` for several tightness exponents α (Fig. 4, eq. 3).
    lower_fit, upper_fit : SplineFit
        Splines of the pair at the simulation's α (Figs. 5, 8, 9); ``upper_fit`` is None for a
        rigid flat.
    record : ContactRecord
        Accepted contacts of the pair at the step drawn in Fig. 9.
    displacement : float
        δ_N at that step [µm].
    """

    dimensions: tuple[float, ...]
    profiles: tuple[Profile, ...]
    focus_dimension: float
    lower: Profile
    fits: tuple[SplineFit, ...]
    lower_fit: SplineFit
    upper_fit: SplineFit | None
    record: ContactRecord
    displacement: float

    def __post_init__(self) -> None:
        if len(self.dimensions) != len(self.profiles) or not self.profiles:
            raise ParameterError(
                f"IllustrativeInputs needs one profile per dimension, got {len(self.profiles)} "
                f"profiles for {len(self.dimensions)} dimensions; pass matching sequences"
            )


def illustrative_figures(inputs: IllustrativeInputs) -> dict[str, Figure]:
    """Figs. 3a, 4, 5, 8 and 9 as in-memory figures, from the profiles passed in.

    Fig. 3a: the first 10 µm of each profile of ``inputs.profiles`` (decimated to the pixel
    resolution). Fig. 4: ``inputs.lower`` and its splines ``inputs.fits`` on 120 grid spacings
    around its highest point. Figs. 5 and 8: the pair at δ_N = 0 around its first contact
    point (spheres and normals of eqs. 4–6; the whole window of 10 µm). Fig. 9: the accepted
    contact spheres of ``inputs.record``.

    Parameters
    ----------
    inputs : IllustrativeInputs
        Profiles, splines and contact record to draw.

    Returns
    -------
    dict of str to Figure
        ``fig03_profiles``, ``fig04_spline_alpha``, ``fig05_spheres``, ``fig08_first_contact``
        and ``fig09_contact_zoom``.
    """
    figures: dict[str, Figure] = {}
    profiles = list(inputs.profiles)
    length = float(profiles[0].length)
    ax = new_axes(figsize=(8, 6))
    plot_profiles(
        profiles,
        labels=[f"D = {d:g}" for d in inputs.dimensions],
        ax=ax,
        xlim=(0.0, min(10.0, length)),
    )
    ax.set_title(
        f"first {min(10.0, length):g} µm of {length:g} µm profiles, "
        f"R_A = {profiles[0].ra * NM_PER_UM:.3g} nm",
        fontsize="small",
    )
    figures["fig03_profiles"] = figure_of(ax)

    focus = inputs.focus_dimension
    lower, fit_l, fit_u = inputs.lower, inputs.lower_fit, inputs.upper_fit
    dx = lower.dx
    centre = float(lower.x[np.argmax(lower.z)])
    ax = new_axes()
    plot_spline_fits(lower, inputs.fits, ax=ax, xlim=(centre - 60 * dx, centre + 60 * dx))
    ax.set_title(f"D = {focus:g}, dx = {dx * NM_PER_UM:.3g} nm", fontsize="small")
    figures["fig04_spline_alpha"] = figure_of(ax)

    zu, _ = upper_global(fit_l, fit_u)
    i0 = int(np.argmin(zu - fit_l.f))
    x_first = float(fit_l.x[i0])
    ax = new_axes(figsize=(8, 5.2))
    plot_spheres(
        fit_l, upper_fit=fit_u, ax=ax, xlim=(x_first - 60 * dx, x_first + 60 * dx), every=6
    )
    ax.set_title(
        f"D = {focus:g}, at the first contact point, α = {fit_l.alpha:g}", fontsize="small"
    )
    figures["fig05_spheres"] = figure_of(ax)

    ax = new_axes(figsize=(9, 4))
    half = min(5.0, float(lower.length) / 2)
    lo = max(float(lower.x[0]), x_first - half)
    plot_first_contact(fit_l, fit_u, ax=ax, xlim=(lo, lo + 2 * half))
    ax.set_title(f"D = {focus:g}, δ_N = 0 (10 µm around the first contact)", fontsize="small")
    figures["fig08_first_contact"] = figure_of(ax)

    ax = new_axes(figsize=(8, 5.2))
    plot_contact_zoom(fit_l, fit_u, inputs.record, inputs.displacement, ax=ax)
    figures["fig09_contact_zoom"] = figure_of(ax)
    return figures


def make_illustrative_figures(
    inputs: IllustrativeInputs,
    out_dir: str | Path | OutputFolder,
    *,
    overwrite: bool = False,
    formats: Sequence[str] = ("png", "svg"),
) -> dict[str, list[Path]]:
    """Figs. 3a, 4, 5, 8 and 9 written as PNG and SVG (see :func:`illustrative_figures`).

    ``out_dir`` follows the package's output rule
    (:func:`~splinecontact.plotting.write_figures`).

    Returns
    -------
    dict of str to list of Path
        Written files per figure.
    """
    return write_figures(
        illustrative_figures(inputs), out_dir, overwrite=overwrite, formats=formats
    )
