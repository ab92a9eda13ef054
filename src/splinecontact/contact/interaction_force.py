"""Force control of the interacting path: δ_N solved so that the coupled F_N meets a target.

A force-controlled step of :mod:`.interaction_slide` solves δ_N at its shift u_T with the
driver's coupled evaluations. The free coupled F_N(δ_N) jumps where eq. 9 accepts or drops a
contact, so, as the non-interacting path does, the step's contact set (and the springs'
migration window) is held through the solve (:func:`_force_step`): eq. 9 is not re-tested, a
held contact whose effective approach falls to ≤ 0 still carries nothing, and F_N(δ_N) is
continuous (secant steps, :func:`_solve_continuous`). The set is re-taken from the free model
at the solved δ_N until the two agree or ``SET_ROUNDS`` sets were tried; ``force_control``
codes each step's outcome (:mod:`._force_status`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..results import ContactRecord
from . import _force_status as _fs
from .loadpath import FORCE_RTOL, _solve_force

__all__ = ["MAX_FALLS", "SET_ROUNDS"]

#: Most contact sets tried in a force-controlled step [1] (:func:`_force_step`).
SET_ROUNDS = 4

#: Steps on which the held F_N falls before a held set is given up [1] (:func:`_solve_continuous`).
MAX_FALLS = 8

#: A held contact set: grid points [1] and the springs' migration window [cells].
Held = tuple[NDArray[np.int64], int]


class _HeldSetFails(Exception):
    """A held contact set whose F_N(δ_N) stops rising before the target."""


def _solve_continuous(
    target: float, evaluate: Any, d0: float, f0: float, scale: float
) -> tuple[float, float]:
    """δ_N with F_N(δ_N) = target [mN/µm] for an F_N continuous and increasing in δ_N (the
    contact set held): secant steps from (d0, f0) [µm, mN/µm], kept inside the bracket once
    one is known (Illinois regula falsi where a secant step leaves it). Returns (δ_N, F_N);
    where F_N still jumps across the target (the remaining bracket at rounding level), the
    nearer side. Raises :class:`_HeldSetFails` where F_N falls ``MAX_FALLS`` times while δ_N
    moves towards the target before a bracket is found (the held set cannot carry it: its
    sphere geometry, eqs. 4–8, holds for small overlaps only), or beyond 2 × ``scale`` [µm]."""
    limit = 2.0 * scale  # beyond this the bodies interpenetrate over their full height
    r0 = f0 - target
    if abs(r0) <= FORCE_RTOL * target:
        return d0, f0
    lo, r_lo, hi, r_hi = -math.inf, -math.inf, math.inf, math.inf
    if r0 < 0.0:
        lo, r_lo = d0, r0
    else:
        hi, r_hi = d0, r0
    step = math.copysign(max(1e-6 * scale, 1e-3 * abs(d0), 1e-12), -r0)
    x0, x1 = d0, d0 + step
    side = 0
    falls = 0
    for _ in range(200):
        x1 = min(max(x1, -limit), limit)
        r1 = float(evaluate(x1)) - target
        if abs(r1) <= FORCE_RTOL * target:
            return x1, r1 + target
        if r1 < 0.0:
            lo, r_lo = x1, r1
            side = -1 if side != -1 else -2
        else:
            hi, r_hi = x1, r1
            side = 1 if side != 1 else 2
        if math.isfinite(lo) and math.isfinite(hi):
            if abs(hi - lo) <= 4.0 * np.spacing(max(abs(hi), abs(lo), 1e-300)):
                break
            guess = x1 - r1 * (x1 - x0) / (r1 - r0) if r1 != r0 else math.nan
            if not lo < guess < hi:  # Illinois: halve the weight of the side kept twice
                w_lo = r_hi * (0.5 if side == 2 else 1.0)
                w_hi = r_lo * (0.5 if side == -2 else 1.0)
                guess = (lo * w_lo - hi * w_hi) / (w_lo - w_hi)
                if not lo < guess < hi:
                    guess = 0.5 * (lo + hi)
        else:
            # extrapolate by the secant, at most 100 times the last step; where F_N falls as
            # δ_N rises (tilted contacts, e_z < 0, push down), four times the step instead
            falling = (r1 - r0) * (x1 - x0) <= 0.0
            falls += falling
            if abs(x1) >= limit or falls > MAX_FALLS:
                raise _HeldSetFails
            last = abs(x1 - x0)
            guess = x1 - r1 * (x1 - x0) / (r1 - r0) if not falling else math.nan
            if not math.isfinite(guess):
                guess = x1 + math.copysign(4.0 * last, -r1)
            guess = x1 + math.copysign(min(abs(guess - x1), 100.0 * last), -r1)
        x0, r0, x1 = x1, r1, guess
    if abs(r_lo) < abs(r_hi):
        return lo, r_lo + target
    return hi, r_hi + target


def _loaded(record: ContactRecord | None) -> NDArray[np.int64]:
    """The grid points of the loaded contacts of an evaluation (sorted)."""
    if record is None:
        return np.zeros(0, dtype=np.int64)
    return np.sort(record.point.astype(np.int64))


def _force_step(driver: Any, u: float, target: float, tol: float) -> tuple[float, Held | None, int]:
    """δ_N of a force-controlled step at shift u [µm] holding F_N = target [mN/µm], the
    contact set to hold through it (grid points and migration window; ``None``: eq. 9 free)
    and the step's ``force_control`` code (:mod:`._force_status`; a miss is marked later).

    With the contact set held (eq. 9 not re-tested; a held contact whose effective approach
    falls to ≤ 0 carries nothing) the coupled F_N(δ_N) is continuous, and the target is met
    by :func:`_solve_continuous`. The set is first that of the loaded contacts at the previous
    δ_N; the free model (eq. 9) is then evaluated at the solved δ_N, and while it loads
    another set, that set is held and δ_N solved again from there (at most ``SET_ROUNDS``
    sets). Where a held set cannot carry the target (F_N stops rising before it: its sphere
    geometry, eqs. 4–8, holds for small overlaps only), the free bracketing of the
    non-interacting path (:func:`.loadpath._solve_force`) finds δ_N, and where the free F_N
    jumps across the target the set below the jump is held from there. The step is the held
    set at the solved δ_N: the free model's step wherever the two load the same contacts,
    F_N held to the target in any case. The springs' migration window (which depends on
    Δδ_N) is held with the set and is part of its consistency.
    """
    scale = driver.geo.scale
    seen: dict[float, ContactRecord | None] = {}

    def trial(value: float, held: Held | None) -> float:
        out, seen[value] = driver.evaluate(u, value, False, tol, held)
        return out[0]

    def hold_from(d: float, cells: NDArray[np.int64]) -> tuple[float, Held, int]:
        """δ_N, the held set and the code of the held solves from δ_N = d."""
        held, code = (cells, driver.window(u, d)), _fs.HELD_FIXED_SET
        for round_ in range(SET_ROUNDS):
            seen.clear()
            d, _ = _solve_continuous(
                target, lambda v, _h=held: trial(v, _h), d, trial(d, held), scale
            )
            loaded = _loaded(driver.evaluate(u, d, False, tol)[1])
            window = driver.window(u, d)
            if window == held[1] and np.array_equal(loaded, _loaded(seen[d])):
                code = _fs.HELD
                break  # the free model's contacts: consistent
            if round_ == SET_ROUNDS - 1 or loaded.size == 0:
                break  # the target lies in a jump of the free model: F_N held
            held = (loaded, window)
        return d, held, code

    f = trial(driver.d, None)
    if abs(f - target) <= FORCE_RTOL * target or math.isinf(f):
        return driver.d, None, _fs.HELD  # met, or beyond validity (raised when committed)
    held = _loaded(seen[driver.d])
    if held.size:
        try:
            return hold_from(driver.d, held)
        except _HeldSetFails:
            pass
    # no contact at the previous δ_N, or its set cannot carry the target
    d, _, lo, hi = _solve_force(target, lambda v: (trial(v, None),), driver.d, scale)
    held = _loaded(driver.evaluate(u, lo, False, tol)[1])
    if lo == hi or held.size == 0:
        return d, None, _fs.HELD if lo == hi else _fs.MISSED
    try:
        return hold_from(lo, held)
    except _HeldSetFails:
        return d, None, _fs.MISSED
