"""Friction quantities derived from a load-path result (``simulate(..., path=...)``).

Sign convention: F_T is the force of the lower body on the upper body along +x, so a friction
force resisting a motion toward +x is negative. Stiffnesses are per µm of out-of-plane thickness:
[mN/µm per µm] = [GPa].

* μ_s — static friction coefficient: max |F_T|/F_N over the first segment that moves the upper body
  tangentially (steps with F_N > 0). Global sliding onset is the first step of that segment at
  which every accepted contact slips. Force-controlled steps that missed their target
  (``force_control`` = 3: the target lies inside a jump of F_N(δ_N), F_N is the nearer side)
  are skipped: their F_T/F_N belongs to a load other than the held one (the count is
  ``StaticFriction.skipped``). Steps held with a fixed contact set (code 2) are used: F_N is
  the held one there, on contacts eq. 9 would not accept as a whole (``force_control_counts``).
* k_T = −dF_T/du_T at the start of the first tangential segment, k_N = dF_N/dδ_N just
  before it (first differences, or least-squares slopes over several increments), and their
  ratio. For comparison: Mindlin's
  k_T/k_N = 2(1 − ν)/(2 − ν) for two identical elastic bodies (0.824 at ν = 0.3); the SAD model of
  one stuck contact on a flat has k_T/k_N = G*/((π/4)E*) (0.490 with the default G* = E*/2.6).
* The interface's elastic stiffness at a fixed contact configuration (``interface_stiffness``):
  K = Σ_c [(π/4)E* e e^T + G* t t^T] over the accepted contacts of one step (e the repulsive
  direction, t = (e_z, −e_x)), i.e. k_T = Σ[(π/4)E* e_x² + G* e_z²] and
  k_N = Σ[(π/4)E* e_z² + G* e_x²]: the response to an infinitesimal rigid displacement with every
  spring stuck and no contact appearing or vanishing. It is positive and stable for rough pairs,
  where the finite-difference k_T above is dominated by contacts appearing and vanishing.
* Dissipation over a step range: the increase of ``dissipated_work`` (Σ slip × capped force).
  The work done by the driver, W = ∫(F_N dδ_N − F_T du_T), equals it over a closed cycle of a
  single spring–slider; for rough pairs it also contains the energy released when contacts vanish.
* Dilatancy of a force-controlled segment: −(δ_N at its end − δ_N at its start) [µm], positive when
  the bodies move apart while F_N is held. An end step that missed its target (code 3) is used:
  its δ_N is where F_N(δ_N) jumps across the target (the solver's bracket closes on the jump
  to rounding), i.e. the δ_N at which the held load is passed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import schema
from ..errors import FrictionAnalysisError, ParameterError
from ..results import SimulationResult

__all__ = [
    "InterfaceStiffness",
    "StaticFriction",
    "dilatancy",
    "dissipated_energy",
    "driver_work",
    "force_control_counts",
    "interface_stiffness",
    "mindlin_stiffness_ratio",
    "normal_stiffness",
    "segment_steps",
    "spring_slider_stiffness_ratio",
    "static_friction",
    "tangential_stiffness",
]

#: The ``force_control`` code of a step that missed its force target (inside a jump of F_N).
_MISSED = schema.VARIABLES["force_control"].flags.index("missed_inside_jump")


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
    skipped : int
        Force-controlled steps of the segment left out because they missed their target
        (``force_control`` = 3) [1].
    """

    mu_s: float
    step: int
    onset_step: int | None
    segment: int
    skipped: int = 0


def static_friction(result: SimulationResult) -> StaticFriction:
    """μ_s = max |F_T|/F_N [1] over the first tangential segment (see module docstring).

    Steps that missed a force target (``force_control`` = 3) are skipped and counted.

    Raises
    ------
    FrictionAnalysisError
        No tangential segment in contact, or every step of it with F_N > 0 missed its target.
    """
    index, a, b = _first_tangential(result)
    fn = np.asarray(result.curves["normal_force"])[a + 1 : b + 1]
    ft = np.asarray(result.curves["tangential_force"])[a + 1 : b + 1]
    missed = _codes(result)[a + 1 : b + 1] == _MISSED
    ok = (fn > 0) & ~missed
    if not ok.any() and np.any(fn > 0):
        raise FrictionAnalysisError(
            f"every step of segment {index} with F_N > 0 missed its force target "
            "(force_control = 3): no μ_s at the held load; check normal_force_target"
        )
    ratio = np.where(ok, np.abs(ft) / np.where(ok, fn, 1.0), 0.0)
    k = int(np.argmax(ratio))
    onset = None
    if "n_slipping" in result.curves:
        n_c = np.asarray(result.curves["n_contacts"])[a + 1 : b + 1]
        n_s = np.asarray(result.curves["n_slipping"])[a + 1 : b + 1]
        hit = np.flatnonzero((n_c > 0) & (n_s == n_c))
        onset = None if hit.size == 0 else int(a + 1 + hit[0])
    return StaticFriction(
        mu_s=float(ratio[k]),
        step=a + 1 + k,
        onset_step=onset,
        segment=index,
        skipped=int(np.sum(missed & (fn > 0))),
    )


def _codes(result: SimulationResult) -> Any:
    """The ``force_control`` codes (all 0 for a result without them: no force control)."""
    codes = result.curves.get("force_control")
    if codes is None:
        return np.zeros(len(result.curves["displacement"]), dtype=np.int8)
    return np.asarray(codes)


def force_control_counts(result: SimulationResult, segment: int | None = None) -> dict[int, int]:
    """Force-controlled steps per ``force_control`` code [1]: 1 held on the contacts eq. 9
    accepts, 2 held with a contact set inside a jump, 3 missed inside a jump.

    Parameters
    ----------
    result : SimulationResult
        A load-path result.
    segment : int, optional
        Count one path segment only (default: the whole path).
    """
    codes = _codes(result)
    if segment is not None:
        bounds = segment_steps(result)
        if not 0 <= segment < len(bounds):
            raise FrictionAnalysisError(f"segment {segment} is outside 0…{len(bounds) - 1}")
        codes = codes[bounds[segment][0] + 1 : bounds[segment][1] + 1]
    values = np.asarray(codes, dtype=np.float64)  # (a study store's rows hold NaN)
    return {code: int(np.sum(values == code)) for code in range(1, _MISSED + 1)}


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


@dataclass(frozen=True)
class InterfaceStiffness:
    """Elastic stiffness of the contacts of one step (see :func:`interface_stiffness`).

    Attributes
    ----------
    k_t : float
        Tangential stiffness −∂F_T/∂u_T [GPa] (mN/µm per µm).
    k_n : float
        Normal stiffness ∂F_N/∂δ_N [GPa].
    k_tn : float
        Coupling K_xz = Σ ((π/4)E* − G*) e_x e_z = ∂F_T/∂δ_N = −∂F_N/∂u_T [GPa].
    ratio : float
        k_t / k_n [1] (NaN without contacts).
    n_contacts : int
        Accepted contacts of the step.
    step : int
        The step.
    """

    k_t: float
    k_n: float
    k_tn: float
    ratio: float
    n_contacts: int
    step: int


def interface_stiffness(result: SimulationResult, step: int | None = None) -> InterfaceStiffness:
    """The elastic stiffness of the accepted contacts of ``step`` (eqs. 10–11, eq. 14).

    Each contact is a normal spring dF^n/dδ = (π/4)E* (eq. 10, Hertz) along its repulsive
    direction e and a tangential spring G* (eq. 11) along t = (e_z, −e_x). For a rigid
    displacement (du_T, −dδ_N) of the upper body with every spring stuck, no contact appearing or
    vanishing and e held (its rotation is of order F^n/(E* R_eff), neglected):

        k_T = −∂F_T/∂u_T = Σ [(π/4)E* e_x² + G* e_z²],
        k_N = ∂F_N/∂δ_N = Σ [(π/4)E* e_z² + G* e_x²].

    Against a rigid flat (e = (0, 1)) k_T/k_N = G*/((π/4)E*) exactly (0.490 with G* = E*/2.6;
    Mindlin's 0.824 at ν = 0.3 is the 3D elastic value, :func:`mindlin_stiffness_ratio`). For
    rough pairs it lies between G*/((π/4)E*) and its inverse, weighted by the contact slopes.

    Parameters
    ----------
    result : SimulationResult
        A result whose contacts were recorded at ``step`` (``record_contacts``).
    step : int, optional
        Default: the start of the first tangential segment of a load path.

    Raises
    ------
    FrictionAnalysisError
        The contacts of ``step`` were not recorded, or the result used another contact law.
    """
    law = result.parameters.get("law", "hertz")
    if law != "hertz":
        raise FrictionAnalysisError(
            f"law = {law!r}: interface_stiffness uses the Hertz spring (π/4)E* of eq. 10"
        )
    if step is None:
        _, step, _ = _first_tangential(result)
    record = next((c for c in result.contacts if c.step == step), None)
    if record is None:
        raise FrictionAnalysisError(
            f"step {step}: its contacts were not recorded; pass record_contacts=[{step}, ...] "
            "to simulate"
        )
    kn_c = 0.25 * math.pi * float(result.parameters["e_star"])
    kt_c = float(result.parameters["g_star"])
    ex = np.asarray(record.normal_x, dtype=np.float64)
    ez = np.asarray(record.normal_z, dtype=np.float64)
    k_t = float(np.sum(kn_c * ex * ex + kt_c * ez * ez))
    k_n = float(np.sum(kn_c * ez * ez + kt_c * ex * ex))
    k_tn = float(np.sum((kn_c - kt_c) * ex * ez))
    ratio = k_t / k_n if k_n > 0 else math.nan
    return InterfaceStiffness(
        k_t=k_t, k_n=k_n, k_tn=k_tn, ratio=ratio, n_contacts=int(ex.size), step=int(step)
    )


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
    """−(δ_N(end) − δ_N(start)) [µm] of a force-controlled segment (positive: bodies separate).

    An end that missed its target (``force_control`` = 3) counts with its δ_N, where F_N(δ_N)
    jumps across the target (module docstring); :func:`force_control_counts` says how many.
    """
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
