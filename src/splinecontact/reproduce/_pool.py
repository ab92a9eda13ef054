"""Figure work of ``reproduce`` done in the study's worker processes.

The illustrative figures (Figs. 3a, 4, 5, 8, 9) need only the study's seed rule, not its
results, so they are made in a worker while the study runs (:func:`illustrative_job`,
:func:`draw_illustrative`); the study figures, drawn here once the study is stored, are turned
into PNG and SVG bytes by the workers, one figure per task (:func:`render_job`). The bytes are
the ones :func:`splinecontact.plotting.save_figure` would write; the main process writes every
file under the package's output rule.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from matplotlib.figure import Figure

__all__ = ["IllustrativeJob", "IllustrativeOutcome", "draw_illustrative", "illustrative_job"]


@dataclass(frozen=True)
class IllustrativeJob:
    """What a worker needs to make the illustrative figures of a study before it has run.

    Attributes
    ----------
    dimensions : tuple of float
        The study's fractal dimensions D [1] (one profile each in Fig. 3a).
    params : dict
        The study's fixed parameters (units of :mod:`splinecontact.parameters`).
    seed : int
        The study seed (the profiles are those of its realization 0).
    focus : float
        D [1] of the pair of Figs. 4, 5, 8, 9.
    measure_hurst : bool
        Also measure the Hurst exponent of each profile (Fig. 12).
    formats : tuple of str
        File formats.
    dpi : int
        Resolution of raster formats [dots per inch].
    """

    dimensions: tuple[float, ...]
    params: dict[str, Any]
    seed: int
    focus: float
    measure_hurst: bool
    formats: tuple[str, ...] = ("png", "svg")
    dpi: int = 150


@dataclass(frozen=True)
class IllustrativeOutcome:
    """The illustrative figures' bytes (name → format → bytes, empty if not drawn), the measured
    Hurst exponents (D → H, or None), the final displacement [µm] of the pair simulated for
    Fig. 9 (to check it against the stored one) and notes on what could not be drawn."""

    rendered: dict[str, dict[str, bytes]]
    measured_hurst: dict[float, float] | None
    final_displacement: float
    notes: tuple[str, ...]


def illustrative_job(
    dimensions: Sequence[float],
    params: Mapping[str, Any],
    seed: int,
    *,
    hurst_profiles: int,
) -> IllustrativeJob:
    """The job for a study sweeping ``dimensions`` (focus D = 1.4, else the middle one)."""
    dims = tuple(float(d) for d in dimensions)
    focus = 1.4 if 1.4 in dims else dims[len(dims) // 2]
    return IllustrativeJob(dims, dict(params), int(seed), focus, hurst_profiles == 1)


def draw_illustrative(job: IllustrativeJob) -> IllustrativeOutcome:
    """Generate, fit and simulate what Figs. 3a, 4, 5, 8, 9 draw, draw them, return the bytes.

    The same inputs as :func:`splinecontact.reproduce.figures.figure_inputs` makes from the
    stored study, with the final displacement of the default rule (the caller checks it against
    the stored one).
    """
    import numpy as np

    from .. import analysis
    from ..errors import SplineContactError
    from ..plotting import illustrative_figures, render_figure
    from .figures import illustrative_inputs

    notes: list[str] = []
    final = job.params.get("final_displacement")
    try:
        inputs = illustrative_inputs(
            dimensions=job.dimensions,
            params=job.params,
            seed=job.seed,
            focus_dimension=job.focus,
            study_seed=True,
        )
    except (SplineContactError, ValueError, FloatingPointError) as exc:
        notes.append(f"illustrative figures not drawn: {exc}")
        return IllustrativeOutcome({}, None, float("nan"), tuple(notes))
    if final is None:
        factor = float(job.params.get("final_displacement_factor", 0.2))
        final = factor * float(np.ptp(inputs.lower.z))
    measured = None
    if job.measure_hurst:
        values = analysis.measured_hurst(inputs.profiles)
        measured = dict(zip(job.dimensions, (float(h) for h in values), strict=True))
    rendered: dict[str, dict[str, bytes]] = {}
    try:
        figures = illustrative_figures(inputs)
    except (SplineContactError, ValueError, FloatingPointError) as exc:
        notes.append(f"illustrative figures not drawn: {exc}")
    else:
        for name, fig in figures.items():
            rendered[name] = render_figure(fig, formats=job.formats, dpi=job.dpi)
    return IllustrativeOutcome(rendered, measured, float(final), tuple(notes))


def render_job(job: tuple[Figure, tuple[str, ...], int]) -> dict[str, bytes]:
    """The bytes of one figure in each format: ``(figure, formats, dpi)`` → format → bytes."""
    from ..plotting import render_figure

    fig, formats, dpi = job
    return render_figure(fig, formats=formats, dpi=dpi)
