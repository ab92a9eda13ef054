"""Candidate culling of the load-path kernel (:mod:`splinecontact.contact.path_kernel`).

The two bodies on the lower grid (:class:`Surfaces`) and the block maxima (:class:`Culling`)
with which :func:`candidate_bounds` finds, in O(n/1024) plus the blocks near contact, the points
whose rigid gap can close at a tangential shift within a window and a normal displacement; the
vector pass that flags a sliding step's points (:func:`sliding_flags`, the runs of
:mod:`._sliding`).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numba
import numpy as np
from numpy.typing import NDArray

from ._filter import _touches, widenings

__all__ = [
    "SPHERE_BLOCK",
    "Culling",
    "Surfaces",
    "block_max",
    "candidate_bounds",
    "fill_spheres",
    "first_at_least",
    "interval_envelope",
    "sliding_flags",
    "sphere_ready",
]


#: Points per block of the lazily evaluated lower spheres (a power of two).
SPHERE_BLOCK = 64
_SPHERE_SHIFT = 6


class Surfaces(NamedTuple):
    """The two bodies on the lower grid (n points) and the upper spline's knots."""

    f_l: NDArray[np.float64]  # lower smoothed heights [µm]
    kappa_l: NDArray[np.float64]  # lower own-frame curvature [1/µm] (clamped)
    nl_x: NDArray[np.float64]  # lower outward normal [1]
    nl_z: NDArray[np.float64]
    f_u: NDArray[np.float64]  # upper spline knot values [µm]
    gamma_u: NDArray[np.float64]  # upper second differences f″·dx² [µm]
    slope_u: NDArray[np.float64]  # upper f′ at the knots [1]
    curv_u: NDArray[np.float64]  # upper f″ at the knots [1/µm]
    flat: bool  # rigid flat upper body
    placement: float  # C: zero minimum gap at δ_N = 0, u_T = 0 [µm]
    dx: float  # grid spacing [µm]
    kappa_max: float  # 1/r_min [1/µm]
    # The lower spheres (kappa_l, nl_x, nl_z) are evaluated lazily, a block of SPHERE_BLOCK
    # points at a time, where a point can close (:func:`fill_spheres`): not at every point.
    slope_l: NDArray[np.float64]  # lower f′ [1]
    curv_l: NDArray[np.float64]  # lower f″ [1/µm]
    sphere_done: NDArray[np.uint8]  # per block of SPHERE_BLOCK points: spheres evaluated


class Culling(NamedTuple):
    """Block maxima for the candidate culling of :func:`candidate_bounds`."""

    f_l_block: NDArray[np.float64]
    envelope: NDArray[np.float64]
    envelope_block: NDArray[np.float64]
    block: int
    f_l_super: NDArray[np.float64]
    envelope_super: NDArray[np.float64]
    per_super: int
    margin: float  # rounding margin of the bounds [µm]
    f_l_sub: NDArray[np.float64]  # maxima of sub-blocks of ``sub`` points (block = 4 sub-blocks)
    envelope_sub: NDArray[np.float64]
    sub: int


@numba.njit(cache=True, nogil=True)
def interval_envelope(
    f: NDArray[np.float64], gamma: NDArray[np.float64]
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Upper bound of the cubic spline on each knot interval k (n − 1 values) [µm].

    On [k, k+1] the spline is the chord plus [γ_k a(t) + γ_{k+1} b(t)]/6 with a, b ≤ 0 and
    a + b ≥ −3/4, so it never exceeds max(f_k, f_{k+1}) + max(|γ_k|, |γ_{k+1}|)/8.
    """
    n = f.size
    out = np.empty(n - 1)
    for k in range(n - 1):
        out[k] = _interval_top(f[k], f[k + 1], gamma[k], gamma[k + 1])
    return out


@numba.njit(cache=True, nogil=True, inline="always")
def _interval_top(f0: float, f1: float, g0: float, g1: float) -> float:  # pragma: no cover
    """:func:`interval_envelope` of one interval (knot values f0, f1, γ values g0, g1)."""
    hi = f0 if f0 > f1 else f1
    g0 = abs(g0)
    g1 = abs(g1)
    return hi + 0.125 * (g0 if g0 > g1 else g1)


@numba.njit(cache=True, nogil=True)
def block_max(values: NDArray[np.float64], block: int) -> NDArray[np.float64]:  # pragma: no cover
    """Maximum of each run of ``block`` consecutive values."""
    nb = (values.size + block - 1) // block
    out = np.empty(nb)
    for b in range(nb):
        hi = values[b * block]
        for i in range(b * block + 1, min(values.size, (b + 1) * block)):
            if values[i] > hi:
                hi = values[i]
        out[b] = hi
    return out


@numba.njit(cache=True, nogil=True, inline="always")
def _window_max(
    coarse: NDArray[np.float64], c_lo: int, c_hi: int
) -> float:  # pragma: no cover - compiled
    """Largest of coarse[c_lo … c_hi] (−∞ if none)."""
    e_max = -np.inf
    for c in range(c_lo, c_hi + 1):
        if coarse[c] > e_max:
            e_max = coarse[c]
    return e_max


@numba.njit(cache=True, nogil=True, inline="always")
def _window_bound(
    f_l_max: float,
    coarse: NDArray[np.float64],
    width: int,
    first: int,
    last: int,
    offset_lo: int,
    offset_hi: int,
    m: int,
    margin: float,
) -> float:  # pragma: no cover - compiled
    """Upper bound of f^l + f^u over the points first … last [µm] (−∞ if they see no interval).

    ``f_l_max`` is the maximum of f^l over them, ``coarse`` the maxima of ``width`` consecutive
    interval envelopes; the points see the knot intervals
    [first + offset_lo, last + offset_hi] ∩ [0, m − 1].
    """
    k_lo = max(0, first + offset_lo)
    k_hi = min(m - 1, last + offset_hi)
    if k_hi < k_lo:
        return -np.inf
    return (
        f_l_max + _window_max(coarse, k_lo // width, min(coarse.size - 1, k_hi // width)) + margin
    )


@numba.njit(cache=True, nogil=True, inline="always")
def _super_bound(
    cull: Culling, n: int, m: int, sb: int, offset_lo: int, offset_hi: int
) -> float:  # pragma: no cover - compiled
    """:func:`_window_bound` of super-block sb (n points, m knot intervals) [µm]."""
    span = cull.block * cull.per_super
    p0 = sb * span
    last = min(n, p0 + span) - 1
    return _window_bound(
        cull.f_l_super[sb], cull.envelope_super, span, p0, last, offset_lo, offset_hi, m,
        cull.margin,
    )  # fmt: skip


@numba.njit(cache=True, nogil=True, inline="always")
def _block_bound(
    cull: Culling, n: int, m: int, b: int, offset_lo: int, offset_hi: int
) -> float:  # pragma: no cover - compiled
    """:func:`_window_bound` of block b (n points, m knot intervals) [µm]."""
    block = cull.block
    i0 = b * block
    last = min(n, i0 + block) - 1
    return _window_bound(
        cull.f_l_block[b], cull.envelope_block, block, i0, last, offset_lo, offset_hi, m,
        cull.margin,
    )  # fmt: skip


@numba.njit(cache=True, nogil=True)
def candidate_bounds(
    surf: Surfaces,
    cull: Culling,
    offset_lo: int,
    offset_hi: int,
    threshold: float,
    out_idx: NDArray[np.int64],
    out_bound: NDArray[np.float64],
) -> int:  # pragma: no cover - compiled
    """Points whose rigid gap can close, in grid order, with an upper bound of f^l_i + f^u(ξ).

    For lower point i the upper spline is evaluated on the knot intervals
    k ∈ [i + offset_lo, i + offset_hi] (clipped to the upper body); the bound is f^l_i plus the
    largest interval envelope there. Only points with bound ≥ ``threshold`` (= C − δ_N) are
    kept. Super-blocks of ``per_super`` blocks, then blocks of ``block`` points, are first culled
    with their maxima (``f_l_super``, ``envelope_super``: maxima of ``per_super`` consecutive
    block maxima), so the cost is O(n/(block·per_super)) plus the blocks near contact.
    """
    f_l = surf.f_l
    flat = surf.flat
    f_l_block = cull.f_l_block
    envelope = cull.envelope
    block = cull.block
    f_l_super = cull.f_l_super
    per_super = cull.per_super
    margin = cull.margin
    n = f_l.size
    count = 0
    nb = f_l_block.size
    n_super = f_l_super.size
    if flat:
        for sb in range(n_super):
            if f_l_super[sb] + margin < threshold:
                continue
            for b in range(sb * per_super, min(nb, (sb + 1) * per_super)):
                if f_l_block[b] + margin < threshold:
                    continue
                for i in range(b * block, min(n, (b + 1) * block)):
                    v = f_l[i] + margin
                    if v >= threshold:
                        out_idx[count] = i
                        out_bound[count] = v
                        count += 1
        return count
    m = envelope.size
    # Monotonic queue of knot intervals (decreasing envelope): the window maximum of every point
    # of a block in O(block + window) instead of O(block × window).
    queue = np.empty(block + max(0, offset_hi - offset_lo) + 2, dtype=np.int64)
    for sb in range(n_super):
        if _super_bound(cull, n, m, sb, offset_lo, offset_hi) < threshold:
            continue
        for b in range(sb * per_super, min(nb, (sb + 1) * per_super)):
            if _block_bound(cull, n, m, b, offset_lo, offset_hi) < threshold:
                continue
            i0 = b * block
            i1 = min(n, i0 + block) - 1
            head = 0
            tail = 0
            nxt = max(0, i0 + offset_lo)  # next knot interval to enter the queue
            for i in range(i0, i1 + 1):
                lo = max(0, i + offset_lo)
                hi = min(m - 1, i + offset_hi)
                if hi < lo:
                    continue
                while nxt <= hi:
                    e_new = envelope[nxt]
                    while tail > head and envelope[queue[tail - 1]] <= e_new:
                        tail -= 1
                    queue[tail] = nxt
                    tail += 1
                    nxt += 1
                while queue[head] < lo:
                    head += 1
                v = f_l[i] + envelope[queue[head]] + margin
                if v >= threshold:
                    out_idx[count] = i
                    out_bound[count] = v
                    count += 1
    return count


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _run_flags(
    i0: int,
    k0: int,
    shift: float,
    d: float,
    reach: float,
    placement: float,
    kappa_max: float,
    dx: float,
    f_l: NDArray[np.float64],
    kappa_l: NDArray[np.float64],
    nl_x: NDArray[np.float64],
    nl_z: NDArray[np.float64],
    f_u: NDArray[np.float64],
    gamma_u: NDArray[np.float64],
    flags: NDArray[np.uint8],
    values: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    e_d: float,
    e_9: float,
) -> int:  # pragma: no cover - compiled
    """:func:`sliding_flags` on a run of consecutive points i0 + p, knot intervals k0 + p.

    The arrays are views starting at point i0 (lower), knot k0 (upper) and the run's first
    flag; contiguous, so that the loop runs on vector units. A point whose knot interval
    ⌊i0 + p − shift⌋ is not k0 + p, or which falls on a knot (t = 0, rounding), is flagged 2
    (evaluated again alone). The scalars are those of :class:`Surfaces` (not the record
    itself). ``e_d``, ``e_9``: the filter's widenings (:func:`._filter.widenings`) at an upper
    bound of |g| over the run's closed points, the same for every point. ``values`` receives
    each point's gap g, S′ and S″ (read back for the points flagged 1). Inlined into the loop
    over the runs (a call per run costs more than a short run's arithmetic).
    """
    inv_dx = 1.0 / dx
    g_out, s1_out, s2_out = values
    n_closed = 0
    dk = float(k0 - i0)
    for p in range(flags.size):
        # ⌊ξ⌋ and the test ⌊ξ⌋ = k0 + p in floating point (whole numbers, exact; t is the
        # same as with the integer ⌊ξ⌋), with no conversion to and from integers
        ip = float(i0 + p)
        xi = ip - shift
        kf = np.floor(xi)
        t = xi - kf
        same = (kf == ip + dk) & (t != 0.0)
        w = 1.0 - t
        fk = f_u[p]
        fk1 = f_u[p + 1]
        g0 = gamma_u[p]
        g1 = gamma_u[p + 1]
        h_u = w * fk + t * fk1 + (g0 * (w * w * w - w) + g1 * (t * t * t - t)) / 6.0
        s1 = (fk1 - fk + (g1 * (3.0 * t * t - 1.0) - g0 * (3.0 * w * w - 1.0)) / 6.0) * inv_dx
        s2 = (w * g0 + t * g1) * (inv_dx * inv_dx)
        g = (placement - (h_u + f_l[p])) - d
        g_out[p] = g
        s1_out[p] = s1
        s2_out[p] = s2
        closed = same & (not g > reach)
        n_closed += closed
        keep = closed & _touches(
            g, s1, s2, kappa_l[p], nl_x[p], nl_z[p], kappa_max, dx, reach, e_d, e_9
        )
        flags[p] = np.uint8(keep) | (np.uint8(not same) << np.uint8(1))
    return n_closed


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _knot_flags(
    d: float,
    reach: float,
    placement: float,
    kappa_max: float,
    dx: float,
    f_l: NDArray[np.float64],
    kappa_l: NDArray[np.float64],
    nl_x: NDArray[np.float64],
    nl_z: NDArray[np.float64],
    f_u: NDArray[np.float64],
    slope_u: NDArray[np.float64],
    curv_u: NDArray[np.float64],
    flags: NDArray[np.uint8],
    values: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    e_d: float,
    e_9: float,
) -> int:  # pragma: no cover - compiled
    """:func:`_run_flags` at a whole-number shift: every point on a knot (the fitted values)."""
    g_out, s1_out, s2_out = values
    n_closed = 0
    for p in range(flags.size):
        s1 = slope_u[p]
        g = (placement - (f_u[p] + f_l[p])) - d
        g_out[p] = g
        s1_out[p] = s1
        s2_out[p] = curv_u[p]
        closed = not g > reach
        n_closed += closed
        keep = closed & _touches(
            g, s1, curv_u[p], kappa_l[p], nl_x[p], nl_z[p], kappa_max, dx, reach, e_d, e_9
        )
        flags[p] = np.uint8(keep)
    return n_closed


@numba.njit(cache=True, nogil=True, inline="always")
def _gap_widening(
    surf: Surfaces, top: float, d: float, reach: float
) -> tuple[float, float]:  # pragma: no cover - compiled
    """The filter's widenings (E_δ, E₉) for every closed point whose f^l + f^u(ξ) ≤ ``top``.

    Such a point's gap g = C − (f^u + f^l) − δ_N (as rounded) lies in
    [C − δ_N − top, reach]: |g| ≤ G = max(reach, top − C + δ_N), enlarged by 10⁻¹² of the
    magnitudes (far above the rounding of g and of G). :func:`._filter.widenings` at K·G is
    then at least that at the point's own K·|g|: the pass refuses no point that
    :func:`._filter._may_touch` keeps. ``top`` = −∞ (no point): G = reach.
    """
    gap = reach
    if top > -np.inf:
        c = surf.placement
        slack = 1e-12 * (abs(top) + abs(c) + abs(d) + reach)
        gap = max(reach, ((top - c) + d) + slack)
    return widenings(surf.kappa_max * gap, surf.kappa_max, surf.dx, reach)


@numba.njit(cache=True, nogil=True, inline="always")
def _run_span(
    surf: Surfaces, i0: int, length: int, shift: float, flags: NDArray[np.uint8], o: int
) -> tuple[int, int, int]:  # pragma: no cover - compiled
    """The part p_lo … p_hi − 1 of the run i0 … i0 + length − 1 inside the upper body (its
    points' knot intervals k0 + p exist); the others flagged 2 (``flags[o + p]``)."""
    top = surf.f_u.size - 2  # last knot interval
    k0 = math.floor(i0 - shift)
    p_lo = min(max(0, -k0), length)
    p_hi = max(min(length, top - k0 + 1), p_lo)
    for p in range(o, o + p_lo):
        flags[p] = 2
    for p in range(o + p_hi, o + length):
        flags[p] = 2
    return p_lo, p_hi, k0


@numba.njit(cache=True, nogil=True, inline="always")
def _flag_run(
    surf: Surfaces,
    i0: int,
    length: int,
    shift: float,
    d: float,
    reach: float,
    widening: tuple[float, float],
    flags: NDArray[np.uint8],
    values: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
    o: int,
) -> int:  # pragma: no cover - compiled
    """Flags of the points i0 … i0 + length − 1 (:func:`sliding_flags`); returns the closed.

    The run's flags are ``flags[o : o + length]``; ``values`` (three arrays aligned with
    ``flags``) receives g, S′ and S″ of the points inside the upper body (those not flagged 2
    for it); ``widening``: the filter's (E_δ, E₉) (:func:`._filter.widenings`) at an upper
    bound of |g| over the closed points. (Each array is sliced once: a slice costs.)"""
    p_lo, p_hi, k0 = _run_span(surf, i0, length, shift, flags, o)
    if p_hi == p_lo:
        return 0
    a = i0 + p_lo
    b = k0 + p_lo
    e = i0 + p_hi
    for blk in range(a >> _SPHERE_SHIFT, ((e - 1) >> _SPHERE_SHIFT) + 1):
        if not surf.sphere_done[blk]:  # (a call costs more than the test)
            fill_spheres(surf, a, e)
            break
    q0 = o + p_lo
    q1 = o + p_hi
    part = (values[0][q0:q1], values[1][q0:q1], values[2][q0:q1])
    if shift == math.floor(shift):
        # i − shift is exact: every point is on knot k0 + p
        return _knot_flags(
            d, reach, surf.placement, surf.kappa_max, surf.dx, surf.f_l[a:e], surf.kappa_l[a:e],
            surf.nl_x[a:e], surf.nl_z[a:e], surf.f_u[b : b + e - a], surf.slope_u[b : b + e - a],
            surf.curv_u[b : b + e - a], flags[q0:q1], part, widening[0], widening[1],
        )  # fmt: skip
    return _run_flags(
        a, b, shift, d, reach, surf.placement, surf.kappa_max, surf.dx, surf.f_l[a:e],
        surf.kappa_l[a:e], surf.nl_x[a:e], surf.nl_z[a:e], surf.f_u[b : b + e - a + 1],
        surf.gamma_u[b : b + e - a + 1], flags[q0:q1], part, widening[0], widening[1],
    )  # fmt: skip


@numba.njit(cache=True, nogil=True)
def sliding_flags(
    surf: Surfaces,
    cand: NDArray[np.int64],
    bound: NDArray[np.float64],
    shift: float,
    d: float,
    threshold: float,
    reach: float,
    flags: NDArray[np.uint8],
    values: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
) -> int:  # pragma: no cover - compiled
    """Closed candidates that may pass Table 1, δ > −reach and eq. 9 at shift u/dx (``flags``).

    A branch-free pass over the candidates (grid order) of a rough upper body, run by runs of
    consecutive points (:func:`_run_flags`): the shifted spline's height, slope and f″ at
    ξ = i − shift (the same arithmetic, operation for operation, as the kernel's scalar
    evaluation, so the values are the same to the bit; written to ``values``, three arrays
    aligned with ``flags``: g, S′, S″), the gap g, and the conservative filter
    :func:`._filter._may_touch` (with the widenings of the largest |g| the bounds allow,
    :func:`_gap_widening`). ``flags[j]`` is 1 for the candidates that are inside the
    upper body, have ``bound[j] ≥ threshold`` and g ≤ reach, and pass the filter (a superset
    of those the exact tests accept), 2 for the few the pass could not decide (to be evaluated
    alone), 0 for the rest. Returns the number of closed candidates (inside, bound ≥ threshold,
    g ≤ reach) among those flagged 0 or 1.
    """
    m = cand.size
    top = -np.inf
    for j in range(m):
        top = max(top, bound[j])
    widening = _gap_widening(surf, top, d, reach)
    n_closed = 0
    j0 = 0
    while j0 < m:
        i0 = cand[j0]
        j1 = j0 + 1
        while j1 < m and cand[j1] == i0 + (j1 - j0):
            j1 += 1
        n_closed += _flag_run(surf, i0, j1 - j0, shift, d, reach, widening, flags, values, j0)
        j0 = j1
    return n_closed


@numba.njit(cache=True, nogil=True)
def fill_spheres(surf: Surfaces, i0: int, i1: int) -> None:  # pragma: no cover - compiled
    """Evaluate the lower spheres of the blocks holding points i0 … i1 − 1, where not done.

    :func:`splinecontact.spheres.own_frame_geometry`, operation for operation (the same
    values): κ = −f″/(1 + f′²)^{3/2} clamped to |κ| ≤ κ_max [1/µm], n = (−f′, 1)/√(1 + f′²) [1].
    """
    done = surf.sphere_done
    n = surf.f_l.size
    hi = surf.kappa_max
    lo = -hi
    for b in range(i0 >> _SPHERE_SHIFT, ((i1 - 1) >> _SPHERE_SHIFT) + 1):
        if done[b]:
            continue
        for i in range(b << _SPHERE_SHIFT, min(n, (b + 1) << _SPHERE_SHIFT)):
            slope = surf.slope_l[i]
            norm = math.sqrt(1.0 + slope * slope)
            k = -surf.curv_l[i] / (norm * norm * norm)
            k = lo if k < lo else k
            surf.kappa_l[i] = hi if k > hi else k
            surf.nl_x[i] = -slope / norm
            surf.nl_z[i] = 1.0 / norm
        done[b] = 1


@numba.njit(cache=True, nogil=True, inline="always")
def sphere_ready(surf: Surfaces, i: int) -> None:  # pragma: no cover - compiled
    """Make sure the lower sphere of point i is evaluated (:func:`fill_spheres`)."""
    if not surf.sphere_done[i >> _SPHERE_SHIFT]:
        fill_spheres(surf, i, i + 1)


@numba.njit(cache=True, nogil=True, inline="always")
def first_at_least(a: NDArray[np.int64], n: int, v: int) -> int:  # pragma: no cover - compiled
    """Index of the first of the ascending a[:n] that is ≥ v (n if none)."""
    lo = 0
    hi = n
    while lo < hi:
        mid = (lo + hi) >> 1
        if a[mid] < v:
            lo = mid + 1
        else:
            hi = mid
    return lo
