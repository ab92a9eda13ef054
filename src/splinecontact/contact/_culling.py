"""Candidate culling of the load-path kernel (:mod:`splinecontact.contact.path_kernel`).

The two bodies on the lower grid (:class:`Surfaces`) and the block maxima (:class:`Culling`)
with which :func:`candidate_bounds` finds, in O(n/1024) plus the blocks near contact, the points
whose rigid gap can close at a tangential shift within a window and a normal displacement.
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np
from numpy.typing import NDArray

__all__ = ["Culling", "Surfaces", "block_max", "candidate_bounds", "interval_envelope"]


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
        hi = f[k] if f[k] > f[k + 1] else f[k + 1]
        gk = abs(gamma[k])
        gk1 = abs(gamma[k + 1])
        out[k] = hi + 0.125 * (gk if gk > gk1 else gk1)
    return out


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
    envelope_block = cull.envelope_block
    block = cull.block
    f_l_super = cull.f_l_super
    envelope_super = cull.envelope_super
    per_super = cull.per_super
    margin = cull.margin
    n = f_l.size
    count = 0
    nb = f_l_block.size
    n_super = f_l_super.size
    span = block * per_super
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
    m_super = envelope_super.size
    # Monotonic queue of knot intervals (decreasing envelope): the window maximum of every point
    # of a block in O(block + window) instead of O(block × window).
    queue = np.empty(block + max(0, offset_hi - offset_lo) + 2, dtype=np.int64)
    for sb in range(n_super):
        p0 = sb * span
        p1 = min(n, p0 + span) - 1
        s_lo = max(0, p0 + offset_lo)
        s_hi = min(m - 1, p1 + offset_hi)
        if s_hi < s_lo:
            continue
        e_super = -np.inf
        for ks in range(s_lo // span, min(m_super - 1, s_hi // span) + 1):
            if envelope_super[ks] > e_super:
                e_super = envelope_super[ks]
        if f_l_super[sb] + e_super + margin < threshold:
            continue
        for b in range(sb * per_super, min(nb, (sb + 1) * per_super)):
            i0 = b * block
            i1 = min(n, i0 + block) - 1
            k_lo = max(0, i0 + offset_lo)
            k_hi = min(m - 1, i1 + offset_hi)
            if k_hi < k_lo:
                continue
            e_max = -np.inf
            for kb in range(k_lo // block, k_hi // block + 1):
                if envelope_block[kb] > e_max:
                    e_max = envelope_block[kb]
            if f_l_block[b] + e_max + margin < threshold:
                continue
            head = 0
            tail = 0
            nxt = k_lo  # next knot interval to enter the queue
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
