"""Interacting SAD along load paths: normal paths here (loading, unloading, reloading).

The coupled contacts of :mod:`.interaction` under a displacement-controlled normal path given
as :class:`~splinecontact.contact.Segment` pieces: the upper body's normal displacement δ_N
goes from 0 through each segment's target in equal increments, and every step solves the
coupled contact problem (eqs. 7–10 with the elastic half-plane) warm-started from the previous
one, whatever the direction. With SAD's elastic law (eq. 10) the normal state depends on δ_N
only, so unloading retraces loading; the tangential springs (eqs. 11–13) follow the normal
increments as in the monotone loading, with their history.

A path with tangential sliding (``tangential=``) or force control (``normal_force=``) is
followed by :mod:`.interaction_slide` (one coupled solve per step on the shifted geometry,
with every contact law: its history per lower grid point carried across the steps);
a path of normal displacement segments only runs here, unchanged.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from ..errors import LoadPathError
from ..profile import Profile
from ..results import SimulationResult
from ..spline import SplineFit
from .geometry import check_bodies, contact_geometry
from .interaction import InteractionSettings, extended_geometry, interacting_loading
from .loadpath import path_segments
from .segments import Segment, validate_path

__all__ = ["normal_path_displacements", "simulate_interacting_path"]


def normal_path_displacements(segments: Iterable[Segment]) -> NDArray[np.float64]:
    """δ_N [µm] at every step of a normal, displacement-controlled path (step 0: δ_N = 0).

    Raises
    ------
    LoadPathError
        A segment moves the upper body tangentially or holds a normal force (such paths are
        followed by :func:`.interaction_slide.run_interacting_path`).
    """
    values = [0.0]
    current = 0.0
    for index, segment in enumerate(validate_path(segments)):
        if _moves_or_holds(segment):
            raise LoadPathError(
                f"path segment {index} ({segment!r}) slides or holds a normal force: it has no "
                "δ_N given in advance; give normal= (δ_N [µm]) and no tangential, or follow "
                "the path with simulate(..., path=...)"
            )
        target = current if segment.normal is None else float(segment.normal)
        k = np.arange(1, segment.steps + 1, dtype=np.float64)
        values.extend((current + (target - current) * k / segment.steps).tolist())
        current = target
    return np.asarray(values, dtype=np.float64)


def simulate_interacting_path(
    lower: Profile,
    upper: Profile | Literal["flat"],
    path: Iterable[Segment],
    settings: InteractionSettings,
    record_contacts: Iterable[int] | str | None,
    *,
    steps: int,
    final_displacement: float | None,
    e_star: float,
    g_star: float,
    mu0: float,
    alpha: float,
    x0: float,
    law: Any = None,
) -> SimulationResult:
    """``simulate(..., path=..., interaction=True)`` (units as there; ``law`` a bound contact
    law, on every path)."""
    from .simulation import _record_steps, build_result, spline_fits

    segments = path_segments(path, steps, final_displacement)
    check_bodies(lower, upper)
    fits = spline_fits(lower, upper, alpha=alpha, x0=x0)
    if any(_moves_or_holds(s) for s in segments):
        return _sliding_result(
            lower, upper, segments, fits, settings, record_contacts, e_star=e_star,
            g_star=g_star, mu0=mu0, alpha=alpha, x0=x0, law=law,
        )  # fmt: skip
    displacement = normal_path_displacements(segments)
    total = displacement.size - 1
    record_steps = _record_steps(record_contacts, total)
    extent = max(float(displacement.max()), lower.dx)
    geometry = extended_geometry(
        lower, upper, steps=1, final_displacement=extent, final_displacement_factor=0.2,
        alpha=alpha, x0=x0, fits=fits, reach_fraction=settings.reach_fraction,
    )  # fmt: skip
    geometry = dataclasses.replace(geometry, displacement=displacement)
    curves, contacts = interacting_loading(
        geometry, e_star=e_star, g_star=g_star, mu0=mu0, n_points=lower.n_points,
        settings=settings, record_steps=record_steps, law=law,
    )  # fmt: skip
    extra = _law_parameters(segments, settings, law)
    return build_result(
        lower, upper, fits, curves, contacts, steps=total, final_displacement_factor=0.2,
        e_star=e_star, g_star=g_star, mu0=mu0, alpha=alpha, x0=x0, extra=extra,
    )  # fmt: skip


def _moves_or_holds(segment: Segment) -> bool:
    """Whether a segment slides the upper body or holds a normal force."""
    return segment.force_controlled or (
        segment.tangential is not None and segment.tangential != 0.0
    )


def _path_parameters(segments: tuple[Segment, ...], settings: InteractionSettings) -> dict:
    """The result's parameters that describe the path and the coupled solve."""
    return {
        "path": [dataclasses.asdict(s) for s in segments],
        "path_segment_end": np.cumsum([s.steps for s in segments]).tolist(),
        "interaction": "elastic half-plane",
        "interaction_boundary": "periodic" if settings.periodic else "symmetry walls",
        "interaction_tol": settings.tol,
        "interaction_width": settings.width,
    }


def _law_parameters(segments: tuple[Segment, ...], settings: InteractionSettings, law: Any) -> dict:
    """The parameters of :func:`_path_parameters` and, with a law other than Hertz, the law's."""
    extra = _path_parameters(segments, settings)
    if law is not None and law.code != 0:
        from .laws import law_record

        extra.update(law_record(law))
    return extra


def _sliding_result(
    lower: Profile,
    upper: Profile | Literal["flat"],
    segments: tuple[Segment, ...],
    fits: tuple[SplineFit, SplineFit | None],
    settings: InteractionSettings,
    record_contacts: Iterable[int] | str | None,
    *,
    e_star: float,
    g_star: float,
    mu0: float,
    alpha: float,
    x0: float,
    law: Any = None,
) -> SimulationResult:
    """A path with tangential or force-controlled segments (:mod:`.interaction_slide`)."""
    from .interaction_slide import run_interacting_path
    from .simulation import _record_steps, build_result

    total = sum(s.steps for s in segments)
    curves, contacts = run_interacting_path(
        lower, upper, segments, fits, settings, e_star=e_star, g_star=g_star, mu0=mu0,
        record_steps=_record_steps(record_contacts, total), law=law,
    )  # fmt: skip
    rigid = contact_geometry(
        lower, upper, steps=1, final_displacement=lower.dx, final_displacement_factor=0.2,
        alpha=alpha, x0=x0, fits=fits,
    )  # fmt: skip
    curves["mean_separation"] = rigid.mean_gap0 - curves["displacement"]
    return build_result(
        lower, upper, fits, curves, contacts, steps=total, final_displacement_factor=0.2,
        e_star=e_star, g_star=g_star, mu0=mu0, alpha=alpha, x0=x0,
        extra=_law_parameters(segments, settings, law),
    )  # fmt: skip
