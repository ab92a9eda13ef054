"""The compiled loop of a displacement-controlled load-path segment.

:func:`run_steps` moves the upper body through the steps of a segment, committing each one.
A fixed-shift segment (no tangential motion) visits one candidate list sorted by a bound,
with the upper body evaluated at the candidates once (:func:`.path_kernel.path_step`). A
sliding step of a rough upper body (:func:`slide_step`) visits only the runs of sub-blocks
whose bound says they may touch at that shift (:func:`._sliding.step_runs`, within a block
list rebuilt every ``chunk_cells`` of travel), flags them in one vector pass and decides the
few flagged points exactly; its results are the same, to the bit, as the scalar evaluation
of every point (``tests/test_path_culling.py``).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

from ._culling import Culling, Surfaces, candidate_bounds
from ._decide import flag_list
from ._sliding import candidate_blocks, run_flags, step_runs
from .laws import Material
from .path_kernel import (
    Scratch,
    Springs,
    StepSums,
    _fixed_shift_values,
    _pack_lower,
    _settle,
    _upper_height,
    _upper_slopes,
    migrate_cells_of,
    path_step,
)

__all__ = ["run_steps", "slide_step"]


@numba.njit(cache=True, nogil=True)
def slide_step(
    u: float,
    d: float,
    du: float,
    dd: float,
    surf: Surfaces,
    run_start: NDArray[np.int64],
    run_len: NDArray[np.int64],
    n_runs: int,
    top: float,
    material: Material,
    migrate_cells: int,
    springs: Springs,
    scratch: Scratch,
) -> StepSums:  # pragma: no cover - compiled
    """:func:`path_step` (committed, free) of a rough upper body on runs of candidate points.

    The runs (:func:`.step_runs`, grid order) must hold every point whose gap can close; the
    result is then the same, to the bit, as :func:`path_step` on any candidate list in grid
    order holding them: one vector pass (:func:`.run_flags`) flags the few closed points the
    conservative filter keeps (:func:`._filter._may_touch`) and writes every point's g, S′
    and S″ (the scalar evaluation's values); only the flagged points are packed, with those
    values (the few the pass could not decide evaluated again, alone), and decided exactly in
    grid order.
    """
    f_l = surf.f_l
    placement = surf.placement
    reach = material.reach
    shift = u / surf.dx
    flags = scratch.cl_flag
    values = (scratch.cl_g, scratch.cl_s1, scratch.cl_s2)
    n_closed = run_flags(surf, run_start, run_len, n_runs, shift, d, reach, top, flags, values)
    total = 0
    for r in range(n_runs):
        total += run_len[r]
    # The positions of the set flags (``scratch.idx`` is free until the exact decision, and
    # ``cl_keep`` until the packing).
    hits = scratch.idx
    n_hits = flag_list(flags, total, hits, scratch.cl_keep.view(np.uint8))
    # Flagged point h packed as entry h (in place: h ≤ its position); one the pass could not
    # decide is evaluated again alone, and kept (``cl_keep``) only if its gap has closed.
    r = 0  # the next run, …
    end = 0  # … starting at this position
    off = 0  # grid index − position in the current run
    for h in range(n_hits):
        pos = hits[h]
        while pos >= end:
            off = run_start[r] - end
            end += run_len[r]
            r += 1
        i = pos + off
        g = scratch.cl_g[pos]  # the values of the vector pass (the same)
        s1 = scratch.cl_s1[pos]
        s2 = scratch.cl_s2[pos]
        keep = True
        if flags[pos] != 1:
            inside, h_u, k, t = _upper_height(surf, i, shift)
            g = (placement - (h_u + f_l[i])) - d
            if inside and not g > reach:
                n_closed += 1
                s1, s2 = _upper_slopes(surf, k, t)
            else:
                keep = False
        scratch.cl_i[h] = i
        scratch.cl_g[h] = g
        scratch.cl_s1[h] = s1
        scratch.cl_s2[h] = s2
        scratch.cl_keep[h] = keep
    # The lower spheres (evaluated by the pass) in a loop of their own: its loads, with no
    # branch between them, are in flight together.
    _pack_lower(scratch, surf, n_hits)
    return _settle(
        u, d, du, dd, True, surf, material, migrate_cells, springs, scratch, springs.claimed,
        False, n_hits, n_closed,
    )  # fmt: skip


@numba.njit(cache=True, nogil=True)
def run_steps(
    u_a: float,
    d_a: float,
    u_b: float,
    d_b: float,
    n_steps: int,
    s_first: int,
    s_last: int,
    u_prev: float,
    d_prev: float,
    chunk_cells: float,
    surf: Surfaces,
    cull: Culling,
    buf_idx: NDArray[np.int64],
    buf_bound: NDArray[np.float64],
    material: Material,
    springs: Springs,
    scratch: Scratch,
    out: NDArray[np.float64],
    k0: int,
) -> None:  # pragma: no cover - compiled
    """Steps ``s_first … s_last`` of a displacement-controlled segment, committed in order.

    Step s is at u = u_a + (u_b − u_a)·s/n_steps and δ_N = d_a + (d_b − d_a)·s/n_steps (exactly
    u_b, d_b at s = n_steps). Without tangential motion one candidate list, sorted by decreasing
    bound, serves all steps (each step visits the points whose gap can have closed); otherwise
    the list is rebuilt, in grid order, every ``chunk_cells`` grid spacings of travel. ``out``
    receives, per step (row k0 + s − s_first), δ_N, u_T and the 10 sums of :func:`path_step`.
    """
    dx = surf.dx
    moving = u_b != u_a
    sliding = moving and not surf.flat
    if moving:
        per_chunk = int(chunk_cells * n_steps / (abs(u_b - u_a) / dx))
        if per_chunk < 1:
            per_chunk = 1
    else:
        per_chunk = n_steps + 1
    count = 0
    built_until = -1
    cand = buf_idx[:0]
    bound = buf_bound[:0]
    pre = np.empty((6, 0))
    n_sub = cull.f_l_sub.size if sliding else 0
    blocks = np.empty(cull.f_l_block.size if sliding else 0, dtype=np.int64)
    run_start = np.empty(n_sub, dtype=np.int64)
    run_len = np.empty(n_sub, dtype=np.int64)
    u_cur = u_prev
    d_cur = d_prev
    for s in range(s_first, s_last + 1):
        if s > built_until:
            s_end = min(n_steps, s + per_chunk - 1)
            u_s = u_a + (u_b - u_a) * ((s - 1) / n_steps)
            u_e = u_b if s_end == n_steps else u_a + (u_b - u_a) * (s_end / n_steps)
            d_s = d_a + (d_b - d_a) * ((s - 1) / n_steps)
            d_e = d_b if s_end == n_steps else d_a + (d_b - d_a) * (s_end / n_steps)
            u_lo = min(u_s, u_e, u_cur)
            u_hi = max(u_s, u_e, u_cur)
            d_max = max(d_s, d_e)
            lo = math.floor(-u_hi / dx) - 1
            hi = math.floor(-u_lo / dx) + 1
            thr = surf.placement - d_max - material.reach
            if sliding:
                count = candidate_blocks(surf, cull, lo, hi, thr, blocks)
            else:
                count = candidate_bounds(surf, cull, lo, hi, thr, buf_idx, buf_bound)
            if sliding:
                pass
            elif moving:
                cand = buf_idx[:count]
                bound = buf_bound[:count]
            else:
                order = np.argsort(-buf_bound[:count], kind="mergesort")
                cand = buf_idx[:count][order]
                bound = buf_bound[:count][order]
                if not surf.flat:
                    pre = _fixed_shift_values(surf, cand, u_a / dx)
            built_until = s_end
        u = u_b if s == n_steps else u_a + (u_b - u_a) * (s / n_steps)
        d = d_b if s == n_steps else d_a + (d_b - d_a) * (s / n_steps)
        du = u - u_cur
        dd = d - d_cur
        window = migrate_cells_of(du, dd, dx, surf.f_l.size)
        if sliding:
            n_runs, top = step_runs(
                surf, cull, blocks[:count], u / dx, surf.placement - d - material.reach,
                run_start, run_len,
            )  # fmt: skip
            sums = slide_step(
                u, d, du, dd, surf, run_start, run_len, n_runs, top, material, window, springs,
                scratch,
            )  # fmt: skip
        else:
            sums = path_step(
                u, d, du, dd, True, surf, cand, bound, not moving, material, window, springs,
                scratch, springs.claimed, False, pre,
            )  # fmt: skip
        row = k0 + s - s_first
        out[row, 0] = d
        out[row, 1] = u
        out[row, 2] = sums.normal_force
        out[row, 3] = sums.tangential_force
        out[row, 4] = sums.contact_area
        out[row, 5] = sums.n_contacts
        out[row, 6] = sums.n_slipping
        out[row, 7] = sums.step_work
        out[row, 8] = sums.normal_force_normal_part
        out[row, 9] = sums.normal_force_tangential_part
        out[row, 10] = sums.n_tilted_contacts
        out[row, 11] = sums.n_candidates
        u_cur = u
        d_cur = d
