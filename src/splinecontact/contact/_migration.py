"""The migration of the tangential springs of a load-path step (eq. 11, ``docs/conventions.md``).

:func:`migrate` decides which committed contact (spring) each accepted contact of a step
continues: the one in its own cell, else a vanished one nearby, nearest first. Used by
:func:`.path_kernel.path_step` and the sliding step.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numba
import numpy as np

from ._culling import first_at_least

if TYPE_CHECKING:
    from .path_kernel import Scratch, Springs

__all__ = ["migrate"]


@numba.njit(cache=True, nogil=True)
def migrate(
    n: int, n_c: int, migrate_cells: int, springs: Springs, scratch: Scratch
) -> None:  # pragma: no cover - compiled
    """Which committed contact each accepted contact continues (``scratch.src``).

    The same cell continues its contact. Every other accepted contact may continue a vanished
    (not accepted again in its own cell) previous contact within ``migrate_cells`` cells; the
    pairs are assigned greedily by increasing distance between the previous and the new centre
    (ties: in the order the pairs are generated; independent of the visiting order, hence
    mirror symmetric).

    With the accepted contacts in grid order (a sliding step), the searches are merged sweeps
    and the greedy assignment runs per group of contacts that share a candidate (a group
    claims only its own, so the result is that of one global pass); a contact alone in its
    group takes its nearest candidate without sorting.
    """
    claimed = springs.claimed
    c_idx = scratch.idx
    c_src = scratch.src
    n_old = springs.n_committed[0]
    cells = springs.cells[:n_old]  # ascending
    ascending = True
    for c in range(1, n_c):
        if c_idx[c] < c_idx[c - 1]:
            ascending = False
            break
    p = 0
    for c in range(n_c):
        c_src[c] = -1
        i = c_idx[c]
        if ascending:
            while p < n_old and cells[p] < i:
                p += 1
        else:
            p = first_at_least(cells, n_old, i)
        if p < n_old and cells[p] == i:
            c_src[c] = p
            claimed[p] = True
    # The vanished previous contacts (not continued in their own cell), in grid order: the
    # candidates of a contact are found by search instead of visiting its 2·migrate_cells
    # neighbours, and generated in the same order (by |q − i|, then the left one first).
    vanished = np.empty(n_old, dtype=np.int64)  # their cells
    slot = np.empty(n_old, dtype=np.int64)
    n_v = 0
    for p in range(n_old):
        if not claimed[p]:
            vanished[n_v] = cells[p]
            slot[n_v] = p
            n_v += 1
    vanished = vanished[:n_v]
    first = np.empty(n_c, dtype=np.int64)  # first vanished cell ≥ i − migrate_cells
    middle = np.empty(n_c, dtype=np.int64)  # first vanished cell ≥ i
    n_pairs = 0
    lo = hi = mid = 0
    for c in range(n_c):
        if c_src[c] >= 0:
            continue
        i = c_idx[c]
        if ascending:
            while lo < n_v and vanished[lo] < i - migrate_cells:
                lo += 1
            while mid < n_v and vanished[mid] < i:
                mid += 1
            while hi < n_v and vanished[hi] <= i + migrate_cells:
                hi += 1
        else:
            lo = first_at_least(vanished, n_v, i - migrate_cells)
            mid = first_at_least(vanished, n_v, i)
            hi = first_at_least(vanished, n_v, i + migrate_cells + 1)
        first[c] = lo
        middle[c] = mid
        n_pairs += hi - lo
    if n_pairs > 0:
        pair_c = np.empty(n_pairs, dtype=np.int64)
        pair_q = np.empty(n_pairs, dtype=np.int64)
        pair_d = np.empty(n_pairs)
        # group g: pairs group_start[g] … group_start[g + 1] − 1 (one group unless ascending)
        group_start = np.empty(n_c + 1, dtype=np.int64)
        group_single = np.empty(n_c, dtype=np.bool_)
        n_groups = 0
        reach_end = -1  # one past the last vanished index the current group reaches
        p = 0
        for c in range(n_c):
            if c_src[c] >= 0:
                continue
            i = c_idx[c]
            left = middle[c] - 1  # vanished[left] < i ≤ vanished[left + 1]
            right = middle[c]
            lo = first[c]
            p_start = p
            while True:
                has_left = left >= lo
                has_right = right < n_v and vanished[right] - i <= migrate_cells
                if has_left and (not has_right or i - vanished[left] <= vanished[right] - i):
                    q = slot[left]
                    left -= 1
                elif has_right:
                    q = slot[right]
                    right += 1
                else:
                    break
                pair_c[p] = c
                pair_q[p] = q
                pair_d[p] = abs(springs.xc[q] - scratch.xc[c])
                p += 1
            if p == p_start:
                continue
            if n_groups == 0 or (ascending and lo >= reach_end):
                group_start[n_groups] = p_start
                group_single[n_groups] = True
                n_groups += 1
            else:
                group_single[n_groups - 1] = False
            reach_end = max(reach_end, right)
        group_start[n_groups] = n_pairs
        for grp in range(n_groups):
            g0 = group_start[grp]
            g1 = group_start[grp + 1]
            if group_single[grp]:
                # one contact: the first nearest candidate (all are unclaimed)
                best = g0
                for p in range(g0 + 1, g1):
                    if pair_d[p] < pair_d[best]:
                        best = p
                c_src[pair_c[best]] = pair_q[best]
                claimed[pair_q[best]] = True
                continue
            order = np.argsort(pair_d[g0:g1], kind="mergesort")
            for o in order:
                c = pair_c[g0 + o]
                q = pair_q[g0 + o]
                if c_src[c] < 0 and not claimed[q]:
                    c_src[c] = q
                    claimed[q] = True
    for c in range(n_c):
        if c_src[c] >= 0:
            claimed[c_src[c]] = False
