"""Friction quantities derived from a load-path result (``simulate(..., path=...)``).

Sign convention: F_T is the force of the lower body on the upper body along +x, so a friction
force resisting a motion toward +x is negative. Stiffnesses are per µm of out-of-plane thickness:
[mN/µm per µm] = [GPa].

* μ_s — static friction coefficient: max |F_T|/F_N over the first segment that moves the upper body
  tangentially (steps with F_N > 0). Global sliding onset is the first step of that segment at
  which every accepted contact slips.
* k_T = −dF_T/du_T at the start of the first tangential segment, k_N = dF_N/dδ_N just
  before it (first differences, or least-squares slopes over several increments), and their
  ratio. For comparison: Mindlin's
  k_T/k_N = 2(1 − ν)/(2 − ν) for two identical elastic bodies (0.824 at ν = 0.3); the SAD model of
  one stuck contact on a flat has k_T/k_N = G*/((π/4)E*) (0.490 with the default G* = E*/2.6).
* Dissipation over a step range: the increase of ``dissipated_work`` (Σ slip × capped force).
  The work done by the driver, W = ∫(F_N dδ_N − F_T du_T), equals it over a closed cycle of a
  single spring–slider; for rough pairs it also contains the energy released when contacts vanish.
* Dilatancy of a force-controlled segment: −(δ_N at its end − δ_N at its start) [µm], positive when
  the bodies move apart while F_N is held.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import FrictionAnalysisError, ParameterError
from ..results import SimulationResult

__all__ = [
    "StaticFriction",
    "dilatancy",
    "dissipated_energy",
    "driver_work",
    "mindlin_stiffness_ratio",
    "normal_stiffness",
    "segment_steps",
    "spring_slider_stiffness_ratio",
    "static_friction",
    "tangential_stiffness",
]


def segment_steps(result: SimulationResult) -> list[tuple[int, int]]:
    """(first, last) step of each path segment; ``first`` is the step where it starts.

    Segment j runs from step ``first`` (the end of segment j − 1, or 0) to step ``last``.
    """
    ends = result.parameters.get("path_segment_end")
    if ends is None:
        raise FrictionAnalysisError(
            "this result has no load path; run simulate(..., path=[Segment(...), ...])"
        )
    bounds = []
    start = 0
    for end in ends:
        bounds.append((start, int(end)))
        start = int(end)
    return bounds


def _first_tangential(result: SimulationResult) -> tuple[int, int, int]:
    u = np.asarray(result.curves["tangential_displacement"])
    d = np.asarray(result.curves["normal_force"])
    for index, (a, b) in enumerate(segment_steps(result)):
        if u[b] != u[a] and np.any(d[a : b + 1] > 0):
            return index, a, b
    raise FrictionAnalysisError(
        "the path has no segment that moves the upper body tangentially while in contact"
    )


@dataclass(frozen=True)
class StaticFriction:
    """Static friction of the first tangential segment.

    Attributes
    ----------
    mu_s : float
        max |F_T|/F_N [1].
    step : int
        Step of the maximum.
    onset_step : int or None
        First step at which every accepted contact slips (global sliding), if any.
    segment : int
        Index of the segment.
    """

    mu_s: float
    step: int
    onset_step: int | None
    segment: int


def static_friction(result: SimulationResult) -> StaticFriction:
    """μ_s = max |F_T|/F_N [1] over the first tangential segment (see module docstring)."""
    index, a, b = _first_tangential(result)
    fn = np.asarray(result.curves["normal_force"])[a + 1 : b + 1]
    ft = np.asarray(result.curves["tangential_force"])[a + 1 : b + 1]
    ok = fn > 0
    ratio = np.where(ok, np.abs(ft) / np.where(ok, fn, 1.0), 0.0)
    k = int(np.argmax(ratio))
    onset = None
    if "n_slipping" in result.curves:
        n_c = np.asarray(result.curves["n_contacts"])[a + 1 : b + 1]
        n_s = np.asarray(result.curves["n_slipping"])[a + 1 : b + 1]
        hit = np.flatnonzero((n_c > 0) & (n_s == n_c))
        onset = None if hit.size == 0 else int(a + 1 + hit[0])
    return StaticFriction(mu_s=float(ratio[k]), step=a + 1 + k, onset_step=onset, segment=index)


def _slope(x: Any, y: Any) -> float:
    """Least-squares slope dy/dx."""
    x = np.asarray(x, dtype=np.float64)
    y = np.asarray(y, dtype=np.float64)
    dx = x - x.mean()
    return float(np.sum(dx * (y - y.mean())) / np.sum(dx * dx))


def tangential_stiffness(result: SimulationResult, increments: int = 1) -> float:
    """k_T = −dF_T/du_T [GPa] at the start of the first tangential segment.

    Parameters
    ----------
    result : SimulationResult
        A load-path result.
    increments : int
        Number of its first increments [1] over which the slope is fitted (least squares
        through the segment's start and these steps); 1 is the first difference.
    """
    _, a, b = _first_tangential(result)
    if not 1 <= increments <= b - a:
        raise FrictionAnalysisError(
            f"increments = {increments!r}: the first tangential segment has {b - a} increments"
        )
    u = np.asarray(result.curves["tangential_displacement"])[a : a + increments + 1]
    ft = np.asarray(result.curves["tangential_force"])[a : a + increments + 1]
    return -_slope(u, ft)


def normal_stiffness(
    result: SimulationResult, step: int | None = None, increments: int = 1
) -> float:
    """k_N = dF_N/dδ_N [GPa] over the ``increments`` increments ending at ``step``.

    Default ``step``: the start of the first tangential segment. With more than one increment
    the slope is a least-squares fit through the ``increments + 1`` steps.
    """
    if step is None:
        _, step, _ = _first_tangential(result)
    d = np.asarray(result.curves["displacement"])
    fn = np.asarray(result.curves["normal_force"])
    lo = step - increments
    if increments < 1 or lo < 0 or step >= d.size or np.ptp(d[lo : step + 1]) == 0:
        raise FrictionAnalysisError(
            f"step {step}, increments {increments}: k_N needs normal increments ending at this "
            "step (δ_N must change)"
        )
    return _slope(d[lo : step + 1], fn[lo : step + 1])


def mindlin_stiffness_ratio(poisson: float = 0.3) -> float:
    """Mindlin's k_T/k_N = 2(1 − ν)/(2 − ν) for two identical elastic spheres [1].

    Parameters
    ----------
    poisson : float
        Poisson's ratio ν [1], in (−1, 0.5].
    """
    if not -1.0 < poisson <= 0.5:
        raise ParameterError(f"poisson = {poisson!r} must lie in (−1, 0.5]")
    return 2.0 * (1.0 - poisson) / (2.0 - poisson)


def spring_slider_stiffness_ratio(e_star: float, g_star: float) -> float:
    """k_T/k_N = G*/((π/4)E*) [1] of one stuck SAD contact on a flat (E*, G* in [GPa])."""
    if not (e_star > 0 and g_star >= 0):
        raise ParameterError(f"e_star = {e_star!r} GPa must be > 0, g_star = {g_star!r} GPa ≥ 0")
    return g_star / (0.25 * math.pi * e_star)


def _range(result: SimulationResult, start: int, stop: int) -> tuple[int, int]:
    n = len(result.curves["displacement"])
    if not 0 <= start <= stop < n:
        raise FrictionAnalysisError(f"steps {start}…{stop} are outside 0…{n - 1}")
    return start, stop


def dissipated_energy(result: SimulationResult, start: int, stop: int) -> float:
    """Frictional work [mN·µm/µm] dissipated between steps ``start`` and ``stop``."""
    start, stop = _range(result, start, stop)
    w = np.asarray(result.curves["dissipated_work"])
    return float(w[stop] - w[start])


def driver_work(result: SimulationResult, start: int, stop: int) -> float:
    """Work [mN·µm/µm] done on the upper body by the driver, ∫(F_N dδ_N − F_T du_T), trapezoidal."""
    start, stop = _range(result, start, stop)
    c: Any = result.curves
    d = np.asarray(c["displacement"])[start : stop + 1]
    u = np.asarray(c["tangential_displacement"])[start : stop + 1]
    fn = np.asarray(c["normal_force"])[start : stop + 1]
    ft = np.asarray(c["tangential_force"])[start : stop + 1]
    return float(
        np.sum(0.5 * (fn[1:] + fn[:-1]) * np.diff(d))
        - np.sum(0.5 * (ft[1:] + ft[:-1]) * np.diff(u))
    )


def dilatancy(result: SimulationResult, segment: int) -> float:
    """−(δ_N(end) − δ_N(start)) [µm] of a force-controlled segment (positive: bodies separate)."""
    bounds = segment_steps(result)
    if not 0 <= segment < len(bounds):
        raise FrictionAnalysisError(f"segment {segment} is outside 0…{len(bounds) - 1}")
    a, b = bounds[segment]
    target = np.asarray(result.curves["normal_force_target"])
    if not np.all(np.isfinite(target[a + 1 : b + 1])):
        raise FrictionAnalysisError(
            f"segment {segment} is displacement-controlled; dilatancy needs a constant-F_N segment"
        )
    d = np.asarray(result.curves["displacement"])
    return float(-(d[b] - d[a]))
