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

from .halfplane import NEAR_WIDTHS

__all__ = ["MIN_PUNCH_WIDTH", "PUNCH_NODES"]

#: Contacts with a Hertz half-width below this many grid spacings keep the Hertz width [1].
MIN_PUNCH_WIDTH = 0.5

#: Gauss–Legendre nodes (in θ, s = b sin θ) of the punch integrals.
PUNCH_NODES = 16

#: Most Newton (or bisection) steps of a punch centre, and secant (or bisection) steps of a
#: punch width, per contact and width update.
_NEWTON_ITERATIONS = 30
_SECANT_ITERATIONS = 40

#: A contact's previous (Hertz-scaled) width and centre are kept when their punch load is
#: within this fraction of the width tolerance of the contact's load (P ∝ b² near Hertz, so
#: the width is within half of it) and one centre step is below ``_CENTRE_TOL`` × the width
#: tolerance × b: together within the width tolerance (the outer width loop's own test);
#: otherwise the width is solved for (load to 1e−6, centre to 1e−9 b).
_LOAD_TOL = 0.5
_CENTRE_TOL = 0.5


@numba.njit(cache=True, nogil=True)
def _neighbour_slope(pos: float, near: tuple, c0: float, reach: float) -> float:  # pragma: no cover
    """Slope of the surface displacement of the near neighbours (Hertz fields) at ``pos``.

    ``near`` = (first, last, src, src_pos, src_a, src_q, own, period, relevant): the contact's
    near sources src[first:last] (positions [µm], half-widths [µm], vertical loads [mN/µm]),
    its own index, the period [µm] and the number of entries of ``relevant`` that hold the
    sources able to reach the punch (:func:`_relevant`). Neighbours farther than ``reach`` plus
    NEAR_WIDTHS of their own half-widths only tilt the contact uniformly and are left out.
    """
    _, _, _, src_pos, src_a, src_q, _, period, relevant = near
    total = 0.0
    for m in range(relevant[0]):
        s = relevant[m + 1]
        q = src_q[s]
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
def _relevant(centre: float, b: float, near: tuple, reach: float) -> None:  # pragma: no cover
    """Collect in ``near``'s ``relevant`` the near sources that reach a node of the punch.

    A source (not the contact itself, loaded) is kept when its periodic distance to the centre
    minus the half-width b is within ``reach`` plus NEAR_WIDTHS of its own half-width: the
    periodic distance is 1-Lipschitz, so every node of [centre − b, centre + b] that
    :func:`_neighbour_slope` would include is kept, in the same order.
    """
    first, last, src, src_pos, src_a, src_q, own, period, relevant = near
    kept = 0
    for k in range(first, last):
        s = src[k]
        if s == own or src_q[s] == 0.0:
            continue
        r = centre - src_pos[s]
        r -= period * math.floor(r / period + 0.5)
        if abs(r) - b > reach + NEAR_WIDTHS * src_a[s]:
            continue
        kept += 1
        relevant[kept] = s
    relevant[0] = kept


@numba.njit(cache=True, nogil=True)
def _punch(
    slope: NDArray[np.float64],
    x: float,
    dx: float,
    b: float,
    c: float,
    e_star: float,
    sines: NDArray[np.float64],
    weights: NDArray[np.float64],
    near: tuple,
    centre_tol: float,
    iterations: int,
) -> tuple[float, float, bool]:  # pragma: no cover - compiled
    """Centre and load of a 2D frictionless punch of the local gap profile of half-width b.

    The contact [x + c − b, x + c + b] of a rigid profile with gap slope f′ has bounded pressure
    at both edges when ∫ f′(x + c + s)/√(b² − s²) ds = 0, and then carries
    P = (E*/2) ∫ s f′(x + c + s)/√(b² − s²) ds (Hertz for a parabola; the plane-strain punch
    relations, e.g. Johnson, *Contact Mechanics*, §2.8). Integrals with s = b sin θ and
    Gauss–Legendre nodes in θ; c by a safeguarded secant method (first step: Newton with the
    exact derivative of the linearly interpolated f′ of the profile; bisection where a step
    leaves the bracket of the root), P in the same pass, at most ``iterations`` steps, until a
    step is below ``centre_tol`` × b. Returns (c, P, whether the last step was below it), NaN
    beyond the candidates.
    """
    c0 = 2.0 / (math.pi * e_star)
    reach = NEAR_WIDTHS * b
    total = math.nan
    lo = -math.inf
    hi = math.inf
    c_old = i0_old = 0.0
    c_kept = math.inf
    settled = False
    for iteration in range(iterations):
        if abs(c - c_kept) > 0.5 * b:
            # the sources within reach of any punch centre c_kept ± b/2
            _relevant(x + c, 1.5 * b, near, reach)
            c_kept = c
        i0 = 0.0
        i1 = 0.0
        total = 0.0
        for k in range(sines.size):
            s = b * sines[k]
            pos = x + c + s
            t = pos / dx
            j = math.floor(t)
            if j < 0 or j + 1 >= slope.size:
                return math.nan, math.nan, False
            frac = t - j
            v = slope[j] * (1.0 - frac) + slope[j + 1] * frac
            w = (slope[j + 1] - slope[j]) / dx
            if math.isnan(v):
                return math.nan, math.nan, False
            v += _neighbour_slope(pos, near, c0, reach)
            i0 += weights[k] * v
            i1 += weights[k] * w
            total += weights[k] * s * v
        # I0 grows with c on a summit: keep the bracket of its root; the slope of I0 is the
        # profile's (first step) or the secant of the last two steps (it then includes the
        # neighbours' fields); bisect where a step leaves the bracket
        if i0 > 0.0:
            hi = c
        else:
            lo = c
        slope_c = i1
        if iteration > 0 and c != c_old and i0 != i0_old:
            slope_c = (i0 - i0_old) / (c - c_old)
        bracketed = not (math.isinf(lo) or math.isinf(hi))
        if slope_c > 0.0:
            dc = min(max(-i0 / slope_c, -0.5 * b), 0.5 * b)
        elif bracketed:
            dc = 0.5 * (lo + hi) - c
        else:
            break
        if bracketed and not lo < c + dc < hi:
            dc = 0.5 * (lo + hi) - c
        c_old = c
        i0_old = i0
        settled = abs(dc) <= centre_tol * b
        if settled or iteration == iterations - 1:
            break
        c += dc
    return c, 0.5 * e_star * total, settled


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
    width_tol: float,
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
    longest = 0
    for i in range(n):
        longest = max(longest, start[i + 1] - start[i])
    relevant = np.empty(longest + 1, dtype=np.int64)
    for i in range(n):
        target = load[i]
        if target <= 0.0 or a_hertz[i] < MIN_PUNCH_WIDTH * dx:
            continue
        b = b_start[i] if b_start[i] > 0.0 else a_hertz[i]
        c = c_start[i]
        b_old = 0.0
        p_old = 0.0
        b_lo = 0.0
        b_hi = math.inf
        near = (start[i], start[i + 1], src, src_pos, src_a, src_q, i, period, relevant)
        if b_start[i] > 0.0:
            # a contact kept from the last update, its width scaled as Hertz to the expected
            # load: kept if it still balances this load (centre and load, neighbours' fields
            # included) to a fraction of the width tolerance
            _, p, settled = _punch(
                slope, x[i], dx, b, c, e_star, sines, weights, near, _CENTRE_TOL * width_tol, 1
            )
            if settled and abs(p / target - 1.0) <= _LOAD_TOL * width_tol:
                if not _bridges(x_sorted, x[i], c, b):
                    out_b[i] = b
                    out_c[i] = c
                    continue
        ok = False
        for _ in range(_SECANT_ITERATIONS):
            c, p, _ = _punch(
                slope, x[i], dx, b, c, e_star, sines, weights, near, 1e-9, _NEWTON_ITERATIONS
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
            # P grows with b: keep the bracket of the target, bisect (in log b) outside it
            if p > target:
                b_hi = b
            else:
                b_lo = b
            b_old = b
            p_old = p
            b = b * (target / p) ** (1.0 / m)
            if not b_lo < b < b_hi and b_lo > 0.0 and not math.isinf(b_hi):
                b = math.sqrt(b_lo * b_hi)
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


def _punch_quadrature() -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Nodes sin θ_k and weights of ∫ f(b sin θ) dθ over [−π/2, π/2] (Gauss–Legendre in θ)."""
    nodes, weights = np.polynomial.legendre.leggauss(PUNCH_NODES)
    return np.sin(0.5 * np.pi * nodes), 0.5 * np.pi * weights
