"""Contact widths and centres from the local profile (2D frictionless punch relations).

Each interacting contact's half-width and centre follow from its load and the smoothed gap
profile around its summit, plus the displacement gradients of its near neighbours; Hertz
(a² = 4PR/(πE*), the tip curvature of eq. 10) for contacts narrower than the grid. Used by
:mod:`.interaction`.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

from .halfplane import NEAR_WIDTHS, _Operator

__all__ = ["MIN_PUNCH_WIDTH", "PUNCH_NODES"]

#: Contacts with a Hertz half-width below this many grid spacings keep the Hertz width [1].
MIN_PUNCH_WIDTH = 0.5

#: Gauss–Legendre nodes (in θ, s = b sin θ) of the punch integrals.
PUNCH_NODES = 16


def _hertz_width(
    load: NDArray[np.float64], reff: NDArray[np.float64], e_star: float, floor: float
) -> NDArray[np.float64]:
    """Hertz half-width a = √(2 P R_eff/(πE*)) = √(δ^eff R_eff/2) [µm], at least ``floor``."""
    return np.maximum(np.sqrt(2.0 * np.clip(load, 0.0, None) * reff / (math.pi * e_star)), floor)


@numba.njit(cache=True, nogil=True)
def _sample(values: NDArray[np.float64], pos: float, dx: float) -> float:  # pragma: no cover
    """Linear interpolation of a grid array at position ``pos`` [µm]; NaN outside it."""
    t = pos / dx
    i0 = math.floor(t)
    if i0 < 0 or i0 + 1 >= values.size:
        return math.nan
    frac = t - i0
    return values[i0] * (1.0 - frac) + values[i0 + 1] * frac


@numba.njit(cache=True, nogil=True)
def _neighbour_slope(
    pos: float,
    first: int,
    last: int,
    src: NDArray[np.int64],
    src_pos: NDArray[np.float64],
    src_a: NDArray[np.float64],
    src_q: NDArray[np.float64],
    own: int,
    period: float,
    c0: float,
    reach: float,
) -> float:  # pragma: no cover - compiled
    """Slope of the surface displacement of the near neighbours (Hertz fields) at ``pos``.

    Neighbours farther than ``reach`` plus NEAR_WIDTHS of their own half-widths only tilt the
    contact uniformly and are left out.
    """
    total = 0.0
    for k in range(first, last):
        s = src[k]
        q = src_q[s]
        if s == own or q == 0.0:
            continue
        r = pos - src_pos[s]
        r -= period * math.floor(r / period + 0.5)
        a = src_a[s]
        t = abs(r)
        if t > reach + NEAR_WIDTHS * a:
            continue
        if t <= a:
            g = r
        else:
            g = r - math.copysign(math.sqrt(t * t - a * a), r)
        total -= 2.0 * c0 * q * g / (a * a)
    return total


@numba.njit(cache=True, nogil=True)
def _punch(
    slope: NDArray[np.float64],
    curvature: NDArray[np.float64],
    x: float,
    dx: float,
    b: float,
    c: float,
    e_star: float,
    sines: NDArray[np.float64],
    weights: NDArray[np.float64],
    first: int,
    last: int,
    src: NDArray[np.int64],
    src_pos: NDArray[np.float64],
    src_a: NDArray[np.float64],
    src_q: NDArray[np.float64],
    own: int,
    period: float,
) -> tuple[float, float]:  # pragma: no cover - compiled
    """Centre and load of a 2D frictionless punch of the local gap profile of half-width b.

    The contact [x + c − b, x + c + b] of a rigid profile with gap slope f′ has bounded pressure
    at both edges when ∫ f′(x + c + s)/√(b² − s²) ds = 0 (solved for c by Newton's method),
    and then carries P = (E*/2) ∫ s f′(x + c + s)/√(b² − s²) ds (Hertz for a parabola; the
    plane-strain punch relations, e.g. Johnson, *Contact Mechanics*, §2.8). Integrals with
    s = b sin θ and Gauss–Legendre nodes in θ. Returns (c, P), NaN beyond the candidates.
    """
    c0 = 2.0 / (math.pi * e_star)
    reach = NEAR_WIDTHS * b
    for _ in range(20):
        i0 = 0.0
        i1 = 0.0
        for k in range(sines.size):
            pos = x + c + b * sines[k]
            v = _sample(slope, pos, dx) + _neighbour_slope(
                pos, first, last, src, src_pos, src_a, src_q, own, period, c0, reach
            )
            w = _sample(curvature, pos, dx)
            if math.isnan(v) or math.isnan(w):
                return math.nan, math.nan
            i0 += weights[k] * v
            i1 += weights[k] * w
        if i1 <= 0.0:
            break
        dc = -i0 / i1
        if dc > 0.5 * b:
            dc = 0.5 * b
        elif dc < -0.5 * b:
            dc = -0.5 * b
        c += dc
        if abs(dc) <= 1e-9 * b:
            break
    total = 0.0
    for k in range(sines.size):
        s = b * sines[k]
        pos = x + c + s
        v = _sample(slope, pos, dx) + _neighbour_slope(
            pos, first, last, src, src_pos, src_a, src_q, own, period, c0, reach
        )
        if math.isnan(v):
            return math.nan, math.nan
        total += weights[k] * s * v
    return c, 0.5 * e_star * total


@numba.njit(cache=True, nogil=True)
def _bridges(
    x_sorted: NDArray[np.float64], x: float, c: float, b: float
) -> bool:  # pragma: no cover
    """Does the interval [x + c − b, x + c + b] contain another contact's summit?"""
    centre = x + c
    inside = np.searchsorted(x_sorted, centre + b) - np.searchsorted(x_sorted, centre - b)
    if abs(x - centre) < b:
        inside -= 1
    return bool(inside > 0)


@numba.njit(cache=True, nogil=True)
def _profile_widths(
    load: NDArray[np.float64],
    a_hertz: NDArray[np.float64],
    x: NDArray[np.float64],
    b_start: NDArray[np.float64],
    c_start: NDArray[np.float64],
    slope: NDArray[np.float64],
    curvature: NDArray[np.float64],
    dx: float,
    e_star: float,
    sines: NDArray[np.float64],
    weights: NDArray[np.float64],
    start: NDArray[np.int64],
    src: NDArray[np.int64],
    src_pos: NDArray[np.float64],
    src_a: NDArray[np.float64],
    src_q: NDArray[np.float64],
    period: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:  # pragma: no cover - compiled
    """Half-widths and centre shifts at which each contact's punch load equals its load.

    Secant iteration in log b (exact in one step for a parabola), warm-started from
    ``b_start``/``c_start``; contacts narrower than two grid spacings, or reaching beyond the
    candidates, keep the Hertz width and no shift.
    """
    n = load.size
    out_b = a_hertz.copy()
    out_c = np.zeros(n)
    x_sorted = np.sort(x)
    for i in range(n):
        target = load[i]
        if target <= 0.0 or a_hertz[i] < MIN_PUNCH_WIDTH * dx:
            continue
        b = b_start[i] if b_start[i] > 0.0 else a_hertz[i]
        c = c_start[i]
        b_old = 0.0
        p_old = 0.0
        ok = False
        for _ in range(40):
            c, p = _punch(
                slope,
                curvature,
                x[i],
                dx,
                b,
                c,
                e_star,
                sines,
                weights,
                start[i],
                start[i + 1],
                src,
                src_pos,
                src_a,
                src_q,
                i,
                period,
            )
            if math.isnan(p) or p <= 0.0:
                break
            if abs(p / target - 1.0) <= 1e-6:
                ok = True
                break
            m = 2.0
            if b_old > 0.0 and p_old > 0.0 and b_old != b and p_old != p:
                m = math.log(p / p_old) / math.log(b / b_old)
                m = min(max(m, 0.5), 4.0)
            b_old = b
            p_old = p
            b = b * (target / p) ** (1.0 / m)
        if ok:
            # a punch that reaches over another contact's summit is not this contact's
            # solution (it would bridge the valley between them)
            ok = not _bridges(x_sorted, x[i], c, b)
        if not ok and b_start[i] > 0.0 and not _bridges(x_sorted, x[i], c_start[i], b_start[i]):
            # keep the previous width and centre if they are admissible, else Hertz
            b = b_start[i]
            c = c_start[i]
            ok = True
        if ok:
            out_b[i] = b
            out_c[i] = c
    return out_b, out_c


class _Widths:
    """Contact half-widths from the loads: Hertz (tip curvature) or the local punch profile."""

    def __init__(
        self, slope: NDArray[np.float64] | None, dx: float, e_star: float, floor: float
    ) -> None:
        self.slope = slope
        self.curvature = None if slope is None else np.gradient(slope, dx)
        self.dx = dx
        self.e_star = e_star
        self.floor = floor
        nodes, weights = np.polynomial.legendre.leggauss(PUNCH_NODES)
        self.sines = np.sin(0.5 * np.pi * nodes)
        self.weights = 0.5 * np.pi * weights

    def __call__(
        self,
        load: NDArray[np.float64],
        reff: NDArray[np.float64],
        x: NDArray[np.float64],
        b_start: NDArray[np.float64],
        c_start: NDArray[np.float64],
        op: _Operator | None = None,
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        a = _hertz_width(load, reff, self.e_star, self.floor)
        if self.slope is None or self.curvature is None:
            return a, np.zeros_like(a)
        if op is None:  # no neighbours known yet
            start = np.zeros(load.size + 1, dtype=np.int64)
            src = np.zeros(0, dtype=np.int64)
            src_pos = src_a = src_q = np.zeros(1)
            period = 1.0
        else:
            start, src, src_pos, src_a = op.start, op.src, op.pos, op.a
            src_q = op.ez_src * load[op.owner]
            period = op.period
        b, c = _profile_widths(
            load,
            a,
            x,
            b_start,
            c_start,
            self.slope,
            self.curvature,
            self.dx,
            self.e_star,
            self.sines,
            self.weights,
            start,
            src,
            src_pos,
            src_a,
            src_q,
            period,
        )
        return np.maximum(b, self.floor), c
