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

#: Beyond every cell (a list that is used up reads as this).
_END = 1 << 62
#: The low half of a packed (previous, new) contact position.
_LOW = (1 << 32) - 1


@numba.njit(cache=True, nogil=True)
def migrate(
    n: int, n_c: int, migrate_cells: int, springs: Springs, scratch: Scratch, reuse: bool = False
) -> None:  # pragma: no cover - compiled
    """Which committed contact each accepted contact continues (``scratch.src``).

    The same cell continues its contact. Every other accepted contact may continue a vanished
    (not accepted again in its own cell) previous contact within ``migrate_cells`` cells; the
    pairs are assigned greedily by increasing distance between the previous and the new centre
    (ties: in the order the pairs are generated — contacts in their order, each one's
    candidates by distance in cells, the left one first; independent of the visiting order,
    hence mirror symmetric).

    With the accepted contacts in grid order (a sliding step) :func:`_migrate_sorted` merges
    the two sorted lists (allocating nothing, so that no reference counting enters its
    loops; a cluster with more pairs than its arrays hold is settled here); otherwise
    :func:`_migrate_any` bisects and assigns in one global pass. ``reuse``: the work arrays
    are the free ``cl_*`` columns of ``scratch``.
    """
    n_old = springs.n_committed[0]
    if reuse and n_old < scratch.cl_i.size:  # (n_c ≤ that size: the accepted points)
        first = scratch.cl_i
        second = scratch.cl_kl.view(np.int64)
        third = scratch.cl_nx.view(np.int64)
        pair_c = scratch.cl_g.view(np.int64)
        pair_q = scratch.cl_s1.view(np.int64)
        pair_d = scratch.cl_s2
        pair_g = scratch.cl_nz.view(np.int64)
    else:
        size = max(4 * n_c, n_old) + n_c + 16  # (every column the same size, as the scratch's)
        first = np.empty(size, dtype=np.int64)
        second = np.empty(size, dtype=np.int64)
        third = np.empty(size, dtype=np.int64)
        pair_c = np.empty(size, dtype=np.int64)
        pair_q = np.empty(size, dtype=np.int64)
        pair_d = np.empty(size)
        pair_g = np.empty(size, dtype=np.int64)
    cells = springs.cells
    old_x = springs.xc
    claimed = springs.claimed
    c_idx = scratch.idx
    c_x = scratch.xc
    c_src = scratch.src
    descents = 0  # (no early exit: one vector pass)
    for c in range(1, n_c):
        descents += c_idx[c] < c_idx[c - 1]
    if descents:
        _migrate_any(n_c, migrate_cells, springs, scratch, first, second, pair_c, pair_q, pair_d)
        return
    n_left = _migrate_sorted(
        n_old, n_c, migrate_cells, cells, old_x, claimed, c_idx, c_x, c_src,
        first, second, third, pair_c, pair_q, pair_d, pair_g, pair_d.view(np.int64),
    )  # fmt: skip
    for k in range(n_left):  # clusters with more pairs than the arrays hold
        while not _settle_cluster(
            first[k] >> 32, second[k] >> 32, first[k] & _LOW, second[k] & _LOW, migrate_cells,
            cells, old_x, claimed, c_idx, c_x, c_src, third, pair_g, pair_c, pair_q, pair_d,
        ):  # fmt: skip
            pair_c = np.empty(2 * pair_d.size, dtype=np.int64)
            pair_q = np.empty(2 * pair_d.size, dtype=np.int64)
            pair_d = np.empty(2 * pair_d.size)


@numba.njit(cache=True, nogil=True)
def _migrate_sorted(
    n_old: int,
    n_c: int,
    window: int,
    cells: NDArray[np.int64],
    old_x: NDArray[np.float64],
    claimed: NDArray[np.bool_],
    c_idx: NDArray[np.int64],
    c_x: NDArray[np.float64],
    c_src: NDArray[np.int64],
    starts: NDArray[np.int64],
    ends: NDArray[np.int64],
    ones: NDArray[np.int64],
    pair_c: NDArray[np.int64],
    pair_q: NDArray[np.int64],
    pair_d: NDArray[np.float64],
    pair_g: NDArray[np.int64],
    pair_bits: NDArray[np.int64],
) -> int:  # pragma: no cover - compiled
    """:func:`migrate` with the accepted contacts in grid order (no allocation).

    One branch-free merge of the previous cells ``cells[:n_old]`` and the new ones
    ``c_idx[:n_c]`` (both ascending) sets the same-cell continuations and cuts the merged
    sequence into clusters wherever two consecutive cells lie more than ``window`` apart: no
    pair crosses a cut, so the greedy pass runs per cluster with the result of one global
    pass. A cluster of one kind has no pair; the clusters of both kinds are listed, then
    sorted by kind (branch-free) and each kind settled in its own loop: one previous and one
    new contact (the new one continues the previous one, in its cell or within the window:
    most of them), two and one, one and two (branch-free), larger ones by
    :func:`_settle_small` (fewer than 63 of each kind) or :func:`_settle_cluster`. Positions
    are packed as (previous << 32) | new. Returns how many clusters had more pairs than the
    pair arrays hold: they are left, unsettled, in ``starts`` and ``ends``.
    """
    if n_c == 0:
        return 0
    p = c = 0
    open_p = open_c = 0  # where the open cluster starts
    last = -_END  # the last cell taken
    last_old = -_END  # the last previous cell taken
    n_mixed = 0  # clusters of both kinds
    while p < n_old and c < n_c:
        a = cells[p]
        b = c_idx[c]
        take_old = a <= b
        m = min(a, b)
        cut = m - last > window
        starts[n_mixed] = (open_p << 32) | open_c
        ends[n_mixed] = (p << 32) | c
        n_mixed += cut & (p > open_p) & (c > open_c)
        open_p = p if cut else open_p
        open_c = c if cut else open_c
        c_src[c] = p - 1 if last_old == b else -1  # (final when the new one is taken)
        last_old = a if take_old else last_old
        last = m
        p += take_old
        c += not take_old
    # one list is used up: the open cluster takes what is left within reach, then closes
    while p < n_old and cells[p] - last <= window:
        last = cells[p]
        p += 1
    while c < n_c and c_idx[c] - last <= window:
        c_src[c] = p - 1 if last_old == c_idx[c] else -1
        last = c_idx[c]
        c += 1
    starts[n_mixed] = (open_p << 32) | open_c
    ends[n_mixed] = (p << 32) | c
    n_mixed += (p > open_p) & (c > open_c)
    for rest in range(c, n_c):
        c_src[rest] = -1
    # the clusters by kind: 1 + 1 (ones), 2 + 1 (pair_c), 1 + 2 (pair_q), larger (kept in place)
    n_one = n_21 = n_12 = n_open = 0
    for k in range(n_mixed):
        at = starts[k]
        end = ends[k]
        n_o = (end >> 32) - (at >> 32)
        n_n = (end & _LOW) - (at & _LOW)
        ones[n_one] = at
        n_one += (n_o == 1) & (n_n == 1)
        pair_c[n_21] = at
        n_21 += (n_o == 2) & (n_n == 1)
        pair_q[n_12] = at
        n_12 += (n_o == 1) & (n_n == 2)
        starts[n_open] = at
        ends[n_open] = end
        n_open += n_o + n_n > 3
    for k in range(n_one):
        c_src[ones[k] & _LOW] = ones[k] >> 32
    reach = 2 * window + 1  # (rank = 2|q − i| + [q > i] ≤ reach: within the window)
    for k in range(n_21):  # the new one takes the first of its candidates (distance, rank)
        q = pair_c[k] >> 32
        c = pair_c[k] & _LOW
        i = c_idx[c]
        d0 = abs(old_x[q] - c_x[c])
        d1 = abs(old_x[q + 1] - c_x[c])
        r0 = 2 * abs(cells[q] - i) + (cells[q] > i)
        r1 = 2 * abs(cells[q + 1] - i) + (cells[q + 1] > i)
        second = (r1 <= reach) & ((r0 > reach) | _first(d1, r1, d0, r0))
        pick = q + 1 if second else q
        pick = pick if (r0 <= reach) | (r1 <= reach) else -1
        own = c_src[c]
        c_src[c] = own if own >= 0 else pick
    for k in range(n_12):  # the first pair (distance, then the left new one) is taken
        q = pair_q[k] >> 32
        c = pair_q[k] & _LOW
        d0 = abs(old_x[q] - c_x[c])
        d1 = abs(old_x[q] - c_x[c + 1])
        in0 = abs(cells[q] - c_idx[c]) <= window
        in1 = abs(cells[q] - c_idx[c + 1]) <= window
        own0 = c_src[c]
        own1 = c_src[c + 1]
        free = (own0 < 0) & (own1 < 0)
        second = in1 & ((not in0) | _first(d1, 1, d0, 0))
        c_src[c] = q if free & in0 & (not second) else own0
        c_src[c + 1] = q if free & second else own1
    n_left = 0
    for k in range(n_open):
        p0 = starts[k] >> 32
        p1 = ends[k] >> 32
        c0 = starts[k] & _LOW
        c1 = ends[k] & _LOW
        if p1 - p0 < 63 and c1 - c0 < 63 and (p1 - p0) * (c1 - c0) < pair_d.size:
            _settle_small(
                p0, p1, c0, c1, window, cells, old_x, c_idx, c_x, c_src, pair_c, pair_q, pair_d,
                pair_g, pair_bits, ones,
            )  # fmt: skip
        elif not _settle_cluster(
            p0, p1, c0, c1, window, cells, old_x, claimed, c_idx, c_x, c_src, ones, pair_g,
            pair_c, pair_q, pair_d,
        ):  # fmt: skip
            starts[n_left] = starts[k]
            ends[n_left] = ends[k]
            n_left += 1
    return n_left


@numba.njit(cache=True, nogil=True, inline="always")
def _settle_small(
    p0: int,
    p1: int,
    c0: int,
    c1: int,
    window: int,
    cells: NDArray[np.int64],
    old_x: NDArray[np.float64],
    c_idx: NDArray[np.int64],
    c_x: NDArray[np.float64],
    c_src: NDArray[np.int64],
    pair_c: NDArray[np.int64],
    pair_q: NDArray[np.int64],
    pair_d: NDArray[np.float64],
    pair_g: NDArray[np.int64],
    pair_bits: NDArray[np.int64],
    order: NDArray[np.int64],
) -> None:  # pragma: no cover - compiled
    """:func:`_settle_cluster` of fewer than 63 previous and 63 new contacts, branch-free.

    The continued previous contacts and the assigned new ones are bits of two words. Every
    (new, previous) pair is listed, flagged as a candidate or not, with its rank in the
    generation order (new contact, then 2|q − i| + [q > i]: by distance in cells, the left one
    first); the candidates are placed in (distance, rank) order by counting (a NaN distance
    last, as numpy's sort) and taken in that order where both sides are still free.
    """
    taken_q = 0
    for c in range(c0, c1):
        q = c_src[c]
        taken_q |= (1 << (q - p0)) if q >= 0 else 0
    n_pairs = 0
    reach = 2 * window + 1
    for c in range(c0, c1):
        free = c_src[c] < 0
        i = c_idx[c]
        x = c_x[c]
        for q in range(p0, p1):
            cell = cells[q]
            rank = 2 * abs(cell - i) + (cell > i)
            d = abs(old_x[q] - x)
            pair_c[n_pairs] = c
            pair_q[n_pairs] = q
            pair_d[n_pairs] = d if d == d else np.nan  # (one NaN: its bits sort last)
            pair_g[n_pairs] = ((c - c0) << 32) | rank
            n_pairs += free & (rank <= reach) & (((taken_q >> (q - p0)) & 1) == 0)
    # the place of each pair in (distance, rank) order: the distances (≥ 0) compared as bits
    for k in range(n_pairs):
        place = 0
        key = pair_bits[k]
        g = pair_g[k]
        for j in range(n_pairs):
            place += (pair_bits[j] < key) | ((pair_bits[j] == key) & (pair_g[j] < g))
        order[place] = k
    taken_c = 0
    for o in range(n_pairs):
        k = order[o]
        c = pair_c[k]
        q = pair_q[k]
        free = (((taken_c >> (c - c0)) | (taken_q >> (q - p0))) & 1) == 0
        own = c_src[c]
        c_src[c] = q if free else own
        taken_c |= (1 << (c - c0)) if free else 0
        taken_q |= (1 << (q - p0)) if free else 0


@numba.njit(cache=True, nogil=True, inline="always")
def _settle_cluster(
    p0: int,
    p1: int,
    c0: int,
    c1: int,
    window: int,
    cells: NDArray[np.int64],
    old_x: NDArray[np.float64],
    claimed: NDArray[np.bool_],
    c_idx: NDArray[np.int64],
    c_x: NDArray[np.float64],
    c_src: NDArray[np.int64],
    vanished: NDArray[np.int64],
    slot: NDArray[np.int64],
    pair_c: NDArray[np.int64],
    pair_q: NDArray[np.int64],
    pair_d: NDArray[np.float64],
) -> bool:  # pragma: no cover - compiled
    """The greedy pass over the previous contacts p0 … p1 − 1 and the new ones c0 … c1 − 1.

    The previous contacts not continued in their cell are listed (``vanished``: cells,
    ``slot``), every other new contact's candidates among them (within ``window`` cells, found
    by sweeps) generated by :func:`_candidates` and the pairs assigned by :func:`_assign`.
    Returns False, having changed nothing, if the pair arrays are too small.
    """
    for c in range(c0, c1):
        if c_src[c] >= 0:
            claimed[c_src[c]] = True
    n_v = 0
    for p in range(p0, p1):
        if not claimed[p]:
            vanished[n_v] = cells[p]
            slot[n_v] = p
            n_v += 1
        claimed[p] = False
    n_pairs = lo = mid = hi = 0
    for c in range(c0, c1):
        if c_src[c] >= 0:
            continue
        i = c_idx[c]
        while lo < n_v and vanished[lo] < i - window:
            lo += 1
        while mid < n_v and vanished[mid] < i:
            mid += 1
        while hi < n_v and vanished[hi] <= i + window:
            hi += 1
        if n_pairs + hi - lo > pair_d.size:
            return False
        n_pairs = _candidates(
            c, i, c_x[c], lo, mid, hi, vanished, slot, old_x, pair_c, pair_q, pair_d, n_pairs
        )
    _assign(n_pairs, pair_c, pair_q, pair_d, c_src, claimed)
    for o in range(n_pairs):
        claimed[pair_q[o]] = False
    return True


@numba.njit(cache=True, nogil=True, inline="always")
def _candidates(
    c: int,
    i: int,
    x: float,
    lo: int,
    right: int,
    hi: int,
    vanished: NDArray[np.int64],
    slot: NDArray[np.int64],
    old_x: NDArray[np.float64],
    pair_c: NDArray[np.int64],
    pair_q: NDArray[np.int64],
    pair_d: NDArray[np.float64],
    n_pairs: int,
) -> int:  # pragma: no cover - compiled
    """Append the pairs of new contact c (cell i, centre x) with its candidates.

    The candidates are the vanished contacts vanished[lo:hi] (cells, ascending; slots
    ``slot``), generated by |q − i|, the left one first on a tie (vanished[right − 1] < i ≤
    vanished[right]). Returns the new count of pairs.
    """
    left = right - 1
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
        pair_d[n_pairs] = abs(old_x[q] - x)
        n_pairs += 1
    return n_pairs


@numba.njit(cache=True, nogil=True)
def _migrate_any(
    n_c: int,
    window: int,
    springs: Springs,
    scratch: Scratch,
    vanished: NDArray[np.int64],
    slot: NDArray[np.int64],
    pair_c: NDArray[np.int64],
    pair_q: NDArray[np.int64],
    pair_d: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    """:func:`migrate` with the accepted contacts in any order: bisections, one global pass.

    The candidates of a contact are found by bisection in the vanished contacts (in grid
    order) instead of visiting its 2·window neighbours, and generated in the same order.
    """
    claimed = springs.claimed
    n_old = springs.n_committed[0]
    cells = springs.cells
    c_idx = scratch.idx
    c_x = scratch.xc
    c_src = scratch.src
    for c in range(n_c):
        p = first_at_least(cells, n_old, c_idx[c])
        c_src[c] = -1
        if p < n_old and cells[p] == c_idx[c]:
            c_src[c] = p
            claimed[p] = True
    n_v = 0
    for p in range(n_old):
        if not claimed[p]:
            vanished[n_v] = cells[p]
            slot[n_v] = p
            n_v += 1
    n_pairs = 0
    for c in range(n_c):
        if c_src[c] >= 0:
            continue
        i = c_idx[c]
        x = c_x[c]
        lo = first_at_least(vanished, n_v, i - window)
        hi = first_at_least(vanished, n_v, i + window + 1)
        if n_pairs + hi - lo > pair_d.size:
            capacity = 2 * (n_pairs + hi - lo)
            pair_c = _grown(pair_c, n_pairs, capacity)
            pair_q = _grown(pair_q, n_pairs, capacity)
            pair_d = _grown(pair_d, n_pairs, capacity)
        right = first_at_least(vanished, n_v, i)
        n_pairs = _candidates(
            c, i, x, lo, right, hi, vanished, slot, springs.xc, pair_c, pair_q, pair_d, n_pairs
        )
    _assign(n_pairs, pair_c, pair_q, pair_d, c_src, claimed)
    for c in range(n_c):
        if c_src[c] >= 0:
            claimed[c_src[c]] = False


#: Up to this many pairs are ordered by insertion (in place, no allocation).
_SMALL = 32


@numba.njit(cache=True, nogil=True, inline="always")
def _assign(
    n_pairs: int,
    pair_c: NDArray[np.int64],
    pair_q: NDArray[np.int64],
    pair_d: NDArray[np.float64],
    c_src: NDArray[np.int64],
    claimed: NDArray[np.bool_],
) -> None:  # pragma: no cover - compiled
    """Assign the pairs greedily by increasing distance (``claimed``: the taken candidates).

    The pairs are taken in the stable order of their distances (a few are reordered in place
    by insertion, more by numpy's stable sort: the same order, a NaN last).
    """
    if n_pairs > _SMALL:
        _assign_many(n_pairs, pair_c, pair_q, pair_d, c_src, claimed)
        return
    for a in range(1, n_pairs):
        key = pair_d[a]
        c = pair_c[a]
        q = pair_q[a]
        b = a
        while b > 0 and _after(pair_d[b - 1], key):
            pair_d[b] = pair_d[b - 1]
            pair_c[b] = pair_c[b - 1]
            pair_q[b] = pair_q[b - 1]
            b -= 1
        pair_d[b] = key
        pair_c[b] = c
        pair_q[b] = q
    for o in range(n_pairs):
        _take(o, pair_c, pair_q, c_src, claimed)


@numba.njit(cache=True, nogil=True)
def _assign_many(
    n_pairs: int,
    pair_c: NDArray[np.int64],
    pair_q: NDArray[np.int64],
    pair_d: NDArray[np.float64],
    c_src: NDArray[np.int64],
    claimed: NDArray[np.bool_],
) -> None:  # pragma: no cover - compiled
    """:func:`_assign` of many pairs: in the order of numpy's stable sort of the distances."""
    for o in np.argsort(pair_d[:n_pairs], kind="mergesort"):
        _take(o, pair_c, pair_q, c_src, claimed)


@numba.njit(cache=True, nogil=True, inline="always")
def _take(
    o: int,
    pair_c: NDArray[np.int64],
    pair_q: NDArray[np.int64],
    c_src: NDArray[np.int64],
    claimed: NDArray[np.bool_],
) -> None:  # pragma: no cover - compiled
    """Pair o is assigned unless its contact or its candidate already is."""
    c = pair_c[o]
    q = pair_q[o]
    if c_src[c] < 0 and not claimed[q]:
        c_src[c] = q
        claimed[q] = True


@numba.njit(cache=True, nogil=True, inline="always")
def _first(d: float, rank: int, other_d: float, other_rank: int) -> bool:  # pragma: no cover
    """Whether the pair (d, rank) comes before (other_d, other_rank): by distance (NaN last),
    then by rank (branch-free)."""
    return (
        (d < other_d)
        | ((d == other_d) & (rank < other_rank))
        | ((other_d != other_d) & ((d == d) | (rank < other_rank)))
    )


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
