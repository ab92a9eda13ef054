"""The culling and the vector pass of a sliding step (a rough upper body moving tangentially).

:func:`candidate_blocks` lists the blocks that can touch within a chunk of travel,
:func:`step_runs` the runs of sub-blocks that can touch at one shift (with a bound of f^l + f^u
over them), :func:`run_flags` flags their points in one vector pass (the kernel of
:mod:`._culling`, the filter's widening constant for the step).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

from ._culling import (
    _SPHERE_SHIFT,
    Culling,
    Surfaces,
    _block_bound,
    _flag_run,
    _gap_widening,
    _run_flags,
    _run_span,
    _super_bound,
    _window_max,
    fill_spheres,
)

__all__ = ["candidate_blocks", "run_flags", "step_runs"]


@numba.njit(cache=True, nogil=True)
def candidate_blocks(
    surf: Surfaces,
    cull: Culling,
    offset_lo: int,
    offset_hi: int,
    threshold: float,
    out_blocks: NDArray[np.int64],
) -> int:  # pragma: no cover - compiled
    """Blocks (of ``cull.block`` points, grid order) whose rigid gap can close (rough upper body).

    The block and super-block culling of :func:`candidate_bounds` (knot intervals
    k ∈ [i + offset_lo, i + offset_hi]), without the point level: a block is kept when the
    maximum of f^l over it plus the largest interval envelope over its window is ≥
    ``threshold``. Returns how many were written to ``out_blocks``.
    """
    n = surf.f_l.size
    m = cull.envelope.size
    per_super = cull.per_super
    nb = cull.f_l_block.size
    block = cull.block
    span = block * per_super
    f_l_super = cull.f_l_super
    envelope_super = cull.envelope_super
    f_l_block = cull.f_l_block
    envelope_block = cull.envelope_block
    margin = cull.margin
    # Away from the ends, super-block sb (whole, points sb·span …) sees the coarse entries
    # sb + a_s … sb + a_s + w_s, block b those b + a_b … b + a_b + w_b: the same windows as
    # _super_bound's and _block_bound's, without their divisions.
    a_s = offset_lo // span
    w_s = (span - 1 + offset_hi) // span - a_s
    a_b = offset_lo // block
    w_b = (block - 1 + offset_hi) // block - a_b
    count = 0
    for sb in range(f_l_super.size):
        p0 = sb * span
        if p0 + offset_lo >= 0 and p0 + span - 1 + offset_hi <= m - 1 and p0 + span <= n:
            e_max = _window_max(envelope_super, sb + a_s, sb + a_s + w_s)
            if f_l_super[sb] + e_max + margin < threshold:
                continue
        elif _super_bound(cull, n, m, sb, offset_lo, offset_hi) < threshold:
            continue
        for b in range(sb * per_super, min(nb, (sb + 1) * per_super)):
            i0 = b * block
            if i0 + offset_lo >= 0 and i0 + block - 1 + offset_hi <= m - 1 and i0 + block <= n:
                e_max = _window_max(envelope_block, b + a_b, b + a_b + w_b)
                bound = f_l_block[b] + e_max + margin
            else:
                bound = _block_bound(cull, n, m, b, offset_lo, offset_hi)
            out_blocks[count] = b
            count += bound >= threshold
    return count


@numba.njit(cache=True, nogil=True)
def _kept_runs(
    f_l_sub: NDArray[np.float64],
    envelope_sub: NDArray[np.float64],
    blocks: NDArray[np.int64],
    per_block: int,
    a: int,
    width: int,
    margin: float,
    threshold: float,
    run_start: NDArray[np.int64],
    run_len: NDArray[np.int64],
) -> tuple[int, float]:  # pragma: no cover - compiled
    """:func:`step_runs` by sub-blocks: sub-block q (of the ``blocks``) is kept when
    f_l_sub[q] + max(envelope_sub[q + a … q + a + width]) (clipped) + margin ≥ ``threshold``
    (width 1 or 2). Without a branch per sub-block: run_start[r] receives the first sub-block
    of run r, run_len[r + 1] one past its last (rewritten while the run grows). Returns the
    number of runs and the largest bound of a kept sub-block (−∞ if none)."""
    n_sub = f_l_sub.size
    last = envelope_sub.size - 1
    n_runs = 0
    top = -np.inf
    end = -2  # one past the last kept sub-block
    for blk in blocks:
        q0 = blk * per_block
        q1 = min(n_sub, q0 + per_block)
        inside = q0 + a >= 0 and q1 - 1 + a + width <= last
        for q in range(q0, q1):
            lo = q + a
            if inside:  # max of entries lo, lo + 1, lo + width (no loop, no clipping)
                e_max = max(
                    max(envelope_sub[np.uint64(lo)], envelope_sub[np.uint64(lo + 1)]),
                    envelope_sub[np.uint64(lo + width)],
                )
            else:
                e_max = _window_max(envelope_sub, max(0, lo), min(last, lo + width))
            v = f_l_sub[np.uint64(q)] + e_max + margin
            kept = v >= threshold
            top = max(top, v if kept else -np.inf)
            run_start[np.uint64(n_runs)] = q
            n_runs += kept & (q != end)
            end = q + 1 if kept else end
            run_len[np.uint64(n_runs)] = end
    return n_runs, top


@numba.njit(cache=True, nogil=True)
def step_runs(
    surf: Surfaces,
    cull: Culling,
    blocks: NDArray[np.int64],
    shift: float,
    threshold: float,
    run_start: NDArray[np.int64],
    run_len: NDArray[np.int64],
) -> tuple[int, float]:  # pragma: no cover - compiled
    """Runs of consecutive points whose rigid gap can close at one shift (grid order).

    Within the given ``blocks`` (which must hold every block that can touch at this shift,
    :func:`candidate_blocks`), each sub-block of ``cull.sub`` points i0 … i1 is kept when the
    maximum of f^l over it plus the largest interval envelope on (at least) the knot intervals
    ⌊i0 − shift⌋ − 1 … ⌊i1 − shift⌋ + 1 (those its points evaluate, with one interval to spare
    for rounding) is ≥ ``threshold``; kept neighbours are merged. The intervals are taken by
    whole sub-blocks of the envelope, the same offset for every sub-block. Returns the number
    of runs (start point, length) written and the largest bound of a kept sub-block (an upper
    bound of f^l + f^u(ξ) over the runs' points [µm], for :func:`run_flags`; −∞ if none).
    """
    n = surf.f_l.size
    f_l_sub = cull.f_l_sub
    envelope_sub = cull.envelope_sub
    sub = cull.sub
    per_block = cull.block // sub
    margin = cull.margin
    # ⌊i − shift⌋ (as rounded) is i + c or i + c + 1: sub-block q's points (16q … 16q + 15)
    # see the knot intervals 16q + c − 1 … 16q + 15 + c + 2, in the envelope's sub-blocks
    # q + a … q + b whatever q (a window at least as wide as the one stated above): two or
    # three of them (b − a is 1 or 2, as the window spans sub + 3 ≤ 2·sub intervals)
    c = math.floor(-shift)
    a = (c - 1) // sub
    b = (sub + 1 + c) // sub
    n_runs, top = _kept_runs(
        f_l_sub, envelope_sub, blocks, per_block, a, b - a, margin, threshold, run_start, run_len
    )
    for r in range(n_runs):  # sub-blocks → points (the last sub-block may be short)
        first = run_start[r] * sub
        run_start[r] = first
        run_len[r] = min(run_len[r + 1] * sub, n) - first
    return n_runs, top


@numba.njit(cache=True, nogil=True)
def run_flags(
    surf: Surfaces,
    run_start: NDArray[np.int64],
    run_len: NDArray[np.int64],
    n_runs: int,
    shift: float,
    d: float,
    reach: float,
    top: float,
    flags: NDArray[np.uint8],
    values: tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]],
) -> int:  # pragma: no cover - compiled
    """:func:`sliding_flags` on the points of runs (``flags`` in run order, points in order);
    ``values`` (aligned with ``flags``) receives g, S′, S″ of the points inside the upper
    body, the same values as the scalar evaluation's (:func:`sliding_flags`). ``top`` [µm]:
    an upper bound of f^l + f^u(ξ) over the runs' points (:func:`step_runs`), which bounds
    |g| over the closed ones: the filter's widenings are those of that bound, computed once
    (:func:`_gap_widening`)."""
    widening = _gap_widening(surf, top, d, reach)
    n_closed = 0
    o = 0
    if shift == math.floor(shift):  # every point on a knot (:func:`._culling._knot_flags`)
        for r in range(n_runs):
            length = run_len[r]
            n_closed += _flag_run(
                surf, run_start[r], length, shift, d, reach, widening, flags, values, o
            )
            o += length
        return n_closed
    done = surf.sphere_done
    for r in range(n_runs):  # the lower spheres first (a call in the loop below slows it)
        i0 = run_start[r]
        i1 = i0 + run_len[r]
        for blk in range(i0 >> _SPHERE_SHIFT, ((i1 - 1) >> _SPHERE_SHIFT) + 1):
            if not done[blk]:  # (a call costs more than the test)
                fill_spheres(surf, i0, i1)
                break
    e_d, e_9 = widening
    g_all, s1_all, s2_all = values
    for r in range(n_runs):
        i0 = run_start[r]
        length = run_len[r]
        p_lo, p_hi, k0 = _run_span(surf, i0, length, shift, flags, o)
        if p_hi > p_lo:
            a = i0 + p_lo
            b = k0 + p_lo
            e = i0 + p_hi
            q0 = o + p_lo
            q1 = o + p_hi
            n_closed += _run_flags(
                a, b, shift, d, reach, surf.placement, surf.kappa_max, surf.dx, surf.f_l[a:e],
                surf.kappa_l[a:e], surf.nl_x[a:e], surf.nl_z[a:e], surf.f_u[b : b + e - a + 1],
                surf.gamma_u[b : b + e - a + 1], flags[q0:q1],
                (g_all[q0:q1], s1_all[q0:q1], s2_all[q0:q1]), e_d, e_9,
            )  # fmt: skip
        o += length
    return n_closed
