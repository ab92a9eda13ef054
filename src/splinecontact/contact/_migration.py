"""The migration of the tangential springs of a load-path step (eq. 11, ``docs/conventions.md``).

:func:`migrate` decides which committed contact (spring) each accepted contact of a step
continues: the one in its own cell, else a vanished one nearby, nearest first. Used by
:func:`.path_kernel.path_step` and the sliding step.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numba
import numpy as np
from numpy.typing import NDArray

from ._culling import first_at_least

if TYPE_CHECKING:
    from .path_kernel import Scratch, Springs

__all__ = ["migrate"]


@numba.njit(cache=True, nogil=True)
def migrate(
    n: int, n_c: int, migrate_cells: int, springs: Springs, scratch: Scratch, reuse: bool = False
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
    n_old = springs.n_committed[0]
    if reuse and n_old <= scratch.cl_i.size:  # (n_c ≤ that size: the accepted points)
        vanished = scratch.cl_i
        slot = scratch.cl_kl.view(np.int64)
        pair_c = scratch.cl_g.view(np.int64)
        pair_q = scratch.cl_s1.view(np.int64)
        pair_d = scratch.cl_s2
        order = scratch.cl_nx.view(np.int64)
    else:
        vanished = np.empty(n_old, dtype=np.int64)
        slot = np.empty(n_old, dtype=np.int64)
        pair_c = np.empty(4 * n_c + 16, dtype=np.int64)
        pair_q = np.empty(4 * n_c + 16, dtype=np.int64)
        pair_d = np.empty(4 * n_c + 16)
        order = np.empty(_SMALL, dtype=np.int64)
    c_idx = scratch.idx
    c_src = scratch.src
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
    n_v = 0
    for p in range(n_old):
        if not claimed[p]:
            vanished[n_v] = cells[p]
            slot[n_v] = p
            n_v += 1
    vanished = vanished[:n_v]
    # One sweep generates each contact's candidate pairs and assigns each group (contacts
    # whose candidate ranges chain; one group unless ascending) once the next contact's
    # candidates lie beyond it.
    capacity = pair_d.size
    n_pairs = 0
    group = 0  # first pair of the open group
    single = True  # the open group holds one contact
    reach_end = -1  # one past the last vanished index the open group reaches
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
        if hi == lo:
            continue  # no candidate
        if n_pairs == 0 or (ascending and lo >= reach_end):
            _assign(group, n_pairs, single, pair_c, pair_q, pair_d, order, c_src, claimed)
            group = n_pairs
            single = True
        else:
            single = False
        if n_pairs + (hi - lo) > capacity:
            capacity = 2 * (n_pairs + (hi - lo))
            pair_c = _grown(pair_c, n_pairs, capacity)
            pair_q = _grown(pair_q, n_pairs, capacity)
            pair_d = _grown(pair_d, n_pairs, capacity)
        # the candidates by |q − i|, the left one first on a tie (vanished[mid − 1] < i ≤ …)
        left = mid - 1
        right = mid
        x = scratch.xc[c]
        while True:
            has_left = left >= lo
            has_right = right < hi
            if has_left and (not has_right or i - vanished[left] <= vanished[right] - i):
                q = slot[left]
                left -= 1
            elif has_right:
                q = slot[right]
                right += 1
            else:
                break
            pair_c[n_pairs] = c
            pair_q[n_pairs] = q
            pair_d[n_pairs] = abs(springs.xc[q] - x)
            n_pairs += 1
        reach_end = max(reach_end, hi)
    _assign(group, n_pairs, single, pair_c, pair_q, pair_d, order, c_src, claimed)
    for c in range(n_c):
        if c_src[c] >= 0:
            claimed[c_src[c]] = False


#: Groups of at most this many pairs are ordered by insertion (no allocation).
_SMALL = 32


@numba.njit(cache=True, nogil=True, inline="always")
def _assign(
    g0: int,
    g1: int,
    single: bool,
    pair_c: NDArray[np.int64],
    pair_q: NDArray[np.int64],
    pair_d: NDArray[np.float64],
    order: NDArray[np.int64],
    c_src: NDArray[np.int64],
    claimed: NDArray[np.bool_],
) -> None:  # pragma: no cover - compiled
    """Assign the pairs g0 … g1 − 1 of one group greedily by increasing distance.

    The pairs are taken in the stable order of their distances (``order``: scratch of at
    least ``_SMALL`` entries; a larger group is ordered by numpy's stable sort, the same).
    """
    m = g1 - g0
    if m == 0:
        return
    if single:
        # one contact: the first nearest candidate (all are unclaimed)
        best = g0
        for p in range(g0 + 1, g1):
            if pair_d[p] < pair_d[best]:
                best = p
        c_src[pair_c[best]] = pair_q[best]
        claimed[pair_q[best]] = True
        return
    if m > min(_SMALL, order.size):
        ranks = np.argsort(pair_d[g0:g1], kind="mergesort")
    else:
        ranks = order[:m]
        for a in range(m):  # stable insertion (a NaN last, as numpy's sort)
            key = pair_d[g0 + a]
            b = a
            while b > 0 and _after(pair_d[g0 + ranks[b - 1]], key):
                ranks[b] = ranks[b - 1]
                b -= 1
            ranks[b] = a
    for o in ranks:
        c = pair_c[g0 + o]
        q = pair_q[g0 + o]
        if c_src[c] < 0 and not claimed[q]:
            c_src[c] = q
            claimed[q] = True


@numba.njit(cache=True, nogil=True, inline="always")
def _after(a: float, b: float) -> bool:  # pragma: no cover - compiled
    """Whether a sorts strictly after b in numpy's order (NaN last)."""
    return a > b or (a != a and b == b)


@numba.njit(cache=True, nogil=True)
def _grown(values: NDArray[Any], used: int, size: int) -> NDArray[Any]:  # pragma: no cover
    """A copy of ``values`` of length ``size`` holding its first ``used`` entries."""
    out = np.empty(size, dtype=values.dtype)
    out[:used] = values[:used]
    return out
