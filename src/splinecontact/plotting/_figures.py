"""Every figure of the paper at once: the study figures and, if given, the illustrative ones."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import xarray as xr
from matplotlib.figure import Figure

from ..errors import SplineContactError
from ..outputs import OutputFolder
from ._base import write_figures
from ._illustrative import IllustrativeInputs, illustrative_figures
from ._study import drawable_study, study_figures

__all__ = ["FIGURE_FILES", "build_figures", "make_figures"]

#: Base names of the figures :func:`make_figures` writes (each as .png and .svg). Per-grid-point
#: figures get a suffix naming the contact type (and any further swept parameter).
FIGURE_FILES: dict[str, str] = {
    "fig03_profiles": "Fig. 3a: profiles across D",
    "fig04_spline_alpha": "Fig. 4: spline fits for several α",
    "fig05_spheres": "Fig. 5: surface spheres and normals on a segment",
    "fig08_first_contact": "Fig. 8: opposing profiles at first contact",
    "fig09_contact_zoom": "Fig. 9: zoom with the accepted contact spheres",
    "fig10": "Fig. 10: (a) F_N vs δ_N, (b) mean separation vs F_N",
    "fig11": "Fig. 11: (a) k/E* vs F_N/(E* L0), (b) A_S vs F_N",
    "fig12_kappa": "Fig. 12: κ vs H with the Persson and Bush values",
    "diag_force_split": "Diagnostics: tangential part of F_N and tilted contacts vs D",
}


def build_figures(
    ds: xr.Dataset,
    *,
    illustrative: IllustrativeInputs | None = None,
    measured_hurst: Mapping[float, float] | None = None,
    kappa_options: Mapping[str, Any] | None = None,
) -> tuple[dict[str, Figure], list[str]]:
    """Every figure of the paper from a study Dataset, in memory (nothing is written).

    Figs. 10, 11, 12 and the force-split diagnostics are drawn from ``ds``
    (:func:`study_figures`); Figs. 3a, 4, 5, 8 and 9 from ``illustrative`` when it is given
    (:func:`illustrative_figures`; the profiles are the caller's: nothing is generated here).

    Parameters
    ----------
    ds : xarray.Dataset
        Study Dataset.
    illustrative : IllustrativeInputs, optional
        Profiles, splines and contact record of the illustrative figures (omitted: not drawn).
    measured_hurst : mapping of float to float, optional
        D → measured Hurst exponent [1], drawn in Fig. 12 beside the nominal H = 2 − D.
    kappa_options : mapping, optional
        Keyword arguments of :func:`splinecontact.analysis.kappa` for Fig. 12.

    Returns
    -------
    (dict, list of str)
        Figures by name; notes on what could not be drawn.

    Raises
    ------
    AnalysisError
        The study has nothing to draw (see :func:`drawable_study`).
    """
    ds, notes = drawable_study(ds)
    figures: dict[str, Figure] = {}
    if illustrative is not None:
        try:
            figures.update(illustrative_figures(illustrative))
        except (SplineContactError, ValueError, FloatingPointError) as exc:
            notes.append(f"illustrative figures not drawn: {exc}")
    figures.update(study_figures(ds, measured_hurst=measured_hurst, kappa_options=kappa_options))
    return figures, notes


def make_figures(
    ds: xr.Dataset,
    out_dir: str | Path | OutputFolder,
    *,
    illustrative: IllustrativeInputs | None = None,
    measured_hurst: Mapping[float, float] | None = None,
    kappa_options: Mapping[str, Any] | None = None,
    overwrite: bool = False,
    prefix: str = "",
) -> dict[str, list[Path]]:
    """Every figure of the paper from a study Dataset, as PNG and SVG in ``out_dir``.

    Every figure is drawn in memory first (:func:`build_figures`), so a study with nothing to
    draw raises before anything is written; the files then follow the package's output rule
    (:func:`write_figures`), one draw per format.

    Parameters
    ----------
    ds : xarray.Dataset
        Study Dataset.
    out_dir : path or OutputFolder
        Output folder.
    illustrative : IllustrativeInputs, optional
        Profiles, splines and contact record of Figs. 3a, 4, 5, 8, 9 (omitted: not drawn).
    measured_hurst : mapping of float to float, optional
        D → measured Hurst exponent [1] for Fig. 12.
    kappa_options : mapping, optional
        Keyword arguments of :func:`splinecontact.analysis.kappa` for Fig. 12.
    overwrite : bool
        Whether a folder splinecontact wrote earlier may be reused.
    prefix : str
        Sub-folder of ``out_dir`` for the files.

    Returns
    -------
    dict of str to list of Path
        Written files per figure.
    """
    figures, _ = build_figures(
        ds,
        illustrative=illustrative,
        measured_hurst=measured_hurst,
        kappa_options=kappa_options,
    )
    return write_figures(figures, out_dir, overwrite=overwrite, prefix=prefix)
