"""Compiled kernels of the load-path driver (:mod:`splinecontact.contact.loadpath`).

One call of :func:`path_step` evaluates one configuration (tangential shift u_T, normal
displacement δ_N) of the upper body: contact detection, Table 1, eq. 9 and eq. 10 on the shifted
geometry, the migration of the tangential springs (which previous contact each accepted contact
continues) and eqs. 11–13. With ``commit`` the new spring state replaces the old one; without it
the call is a trial (used by the force-controlled segments to solve for δ_N).

The upper body's smoothed height at lower grid point i and shift u is its natural cubic spline
at ξ = i − u/dx, from the knot values f and second differences γ = f″·dx² (which determine it):

    S(ξ)  = (1−t) f_k + t f_{k+1} + [γ_k((1−t)³ − (1−t)) + γ_{k+1}(t³ − t)] / 6,
    S′(ξ) = f_{k+1} − f_k + [γ_{k+1}(3t² − 1) − γ_k(3(1−t)² − 1)] / 6,
    S″(ξ) = (1−t) γ_k + t γ_{k+1},

with k = ⌊ξ⌋, t = ξ − k (per grid unit; ÷ dx, dx² for physical slopes); at t = 0 the fit's values.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numba
import numpy as np
from numpy.typing import NDArray

from ._culling import (
    Culling,
    Surfaces,
    _interval_top,
    block_max,
    candidate_bounds,
    interval_envelope,
    sliding_flags,
    sphere_ready,
)
from ._decide import _upper_sphere as _upper_sphere
from ._decide import apply_law, decide_packed, flag_list, packed_columns
from ._filter import _may_touch
from ._migration import migrate as _migrate
from .laws import Material, commit_law, release_law, spring_sums

__all__ = [
    "Culling",
    "Scratch",
    "Springs",
    "StepSums",
    "Surfaces",
    "block_max",
    "candidate_bounds",
    "interval_envelope",
    "path_step",
    "path_step_from_python",
    "run_steps",  # noqa: F822 - from ._path_run, through __getattr__
]


class Springs(NamedTuple):
    """The committed contacts (slot p < n_committed, in grid order) and the migration flags.

    Stored compactly by slot, not by grid cell, so that a step touches only a few cache lines.
    """

    acc: NDArray[np.bool_]  # unused (kept for the record layout; its size is the grid's)
    ft: NDArray[np.float64]  # spring force of slot p [mN/µm]
    xc: NDArray[np.float64]  # its centre x [µm]
    ex: NDArray[np.float64]  # its repulsive direction [1]
    ez: NDArray[np.float64]
    cells: NDArray[np.int64]  # its cell (ascending)
    n_committed: NDArray[np.int64]  # how many (one value)
    claimed: NDArray[np.bool_]  # scratch of the migration (by slot)


class Scratch(NamedTuple):
    """The accepted contacts of one configuration (valid until the next call)."""

    idx: NDArray[np.int64]  # lower grid index
    fn: NDArray[np.float64]  # normal force [mN/µm]
    ex: NDArray[np.float64]  # repulsive direction [1]
    ez: NDArray[np.float64]
    xc: NDArray[np.float64]  # centre x [µm]
    z: NDArray[np.float64]  # centre z [µm]
    delta: NDArray[np.float64]  # overlap [µm]
    reff: NDArray[np.float64]  # effective radius [µm]
    ft: NDArray[np.float64]  # tangential force [mN/µm]
    slip: NDArray[np.bool_]  # slipping
    src: NDArray[np.int64]  # previous contact (slot) continued (−1: new contact)
    width: NDArray[np.float64]  # contact half-width [µm] (share of A_S)
    # the closed points of the configuration (gap ≤ reach), packed for the acceptance filter
    cl_i: NDArray[np.int64]  # lower grid index
    cl_g: NDArray[np.float64]  # gap [µm]
    cl_s1: NDArray[np.float64]  # upper slope S′ [1]
    cl_s2: NDArray[np.float64]  # upper S″ [1/µm]
    cl_kl: NDArray[np.float64]  # lower curvature [1/µm]
    cl_nx: NDArray[np.float64]  # lower normal [1]
    cl_nz: NDArray[np.float64]
    cl_keep: NDArray[np.bool_]  # may pass Table 1, eq. 9 and δ > −reach (conservative)
    cl_flag: NDArray[np.uint8]  # per candidate: 1 closed and kept, 2 undecided (sliding)


class StepSums(NamedTuple):
    """Global sums of one configuration (eq. 14 and the path outputs)."""

    normal_force: float
    tangential_force: float
    contact_area: float
    n_contacts: int
    n_slipping: int
    step_work: float
    normal_force_normal_part: float
    normal_force_tangential_part: float
    n_tilted_contacts: int
    n_candidates: int


@numba.njit(cache=True, nogil=True, inline="always")
def _upper_height(
    surf: Surfaces, i: int, shift: float
) -> tuple[bool, float, int, float]:  # pragma: no cover - compiled
    """(inside, h^u, k, t) of the shifted upper spline at lower point i (module doc)."""
    if surf.flat:
        return True, 0.0, 0, 0.0
    f_u = surf.f_u
    n_up = f_u.size
    xi = i - shift
    if xi < 0.0 or xi > n_up - 1:
        return False, 0.0, 0, 0.0
    k = math.floor(xi)
    if k > n_up - 2:
        k = n_up - 2
    t = xi - k
    if t == 0.0:  # on a knot: the fitted value itself
        return True, f_u[k], k, t
    w = 1.0 - t
    h_u = (
        w * f_u[k]
        + t * f_u[k + 1]
        + (surf.gamma_u[k] * (w * w * w - w) + surf.gamma_u[k + 1] * (t * t * t - t)) / 6.0
    )
    return True, h_u, k, t


@numba.njit(cache=True, nogil=True, inline="always")
def _upper_slopes(
    surf: Surfaces, k: int, t: float
) -> tuple[float, float]:  # pragma: no cover - compiled
    """(S′/dx, S″/dx²) of the upper spline at knot interval k, fraction t (module doc)."""
    if surf.flat:
        return 0.0, 0.0
    if t == 0.0:  # on a knot: the fitted values themselves
        return surf.slope_u[k], surf.curv_u[k]
    f_u = surf.f_u
    w = 1.0 - t
    g0 = surf.gamma_u[k]
    g1 = surf.gamma_u[k + 1]
    inv_dx = 1.0 / surf.dx
    s1 = (
        f_u[k + 1] - f_u[k] + (g1 * (3.0 * t * t - 1.0) - g0 * (3.0 * w * w - 1.0)) / 6.0
    ) * inv_dx
    s2 = (w * g0 + t * g1) * (inv_dx * inv_dx)
    return s1, s2


@numba.njit(cache=True, nogil=True, inline="always")
def _pack(
    scratch: Scratch, q: int, surf: Surfaces, i: int, g: float, s1: float, s2: float
) -> None:  # pragma: no cover - compiled
    """Store closed point i (gap g, upper S′ s1 and S″ s2) as packed entry q.

    Its lower sphere must have been evaluated (:func:`._culling.sphere_ready`): not tested
    here, where a call, even one not taken, would slow the sliding step's packing threefold.
    """
    scratch.cl_i[q] = i
    scratch.cl_g[q] = g
    scratch.cl_s1[q] = s1
    scratch.cl_s2[q] = s2
    _lower_sphere(scratch, q, surf, i)


@numba.njit(cache=True, nogil=True, inline="always")
def _lower_sphere(scratch: Scratch, q: int, surf: Surfaces, i: int) -> None:  # pragma: no cover
    """Store the lower sphere (κ^l, n^l) of point i as packed entry q (evaluated: :func:`_pack`)."""
    scratch.cl_kl[q] = surf.kappa_l[i]
    scratch.cl_nx[q] = surf.nl_x[i]
    scratch.cl_nz[q] = surf.nl_z[i]


@numba.njit(cache=True, nogil=True)
def _pack_lower(scratch: Scratch, surf: Surfaces, n_packed: int) -> None:  # pragma: no cover
    """:func:`_lower_sphere` of the packed points q < n_packed (their index ``cl_i[q]``)."""
    for q in range(n_packed):
        _lower_sphere(scratch, q, surf, scratch.cl_i[q])


@numba.njit(cache=True, nogil=True, inline="always")
def _rigid_gap(
    surf: Surfaces, i: int, shift: float
) -> tuple[bool, float, int, float]:  # pragma: no cover - compiled
    """(inside, C − (h^u + f^l), k, t) at lower point i: the gap before the approach δ_N."""
    inside, h_u, k, t = _upper_height(surf, i, shift)
    return inside, surf.placement - (h_u + surf.f_l[i]), k, t


@numba.njit(cache=True, nogil=True, inline="always")
def _pack_flagged(
    scratch: Scratch,
    q: int,
    surf: Surfaces,
    i: int,
    shift: float,
    d: float,
    reach: float,
    flag: int,
) -> tuple[int, int]:  # pragma: no cover - compiled
    """Evaluate point i flagged by :func:`._culling.sliding_flags` alone; pack it as entry q.

    A point flagged 1 is packed (``cl_keep`` set) when it is inside the upper body; one
    flagged 2 (undecided) only when its gap is also ≤ ``reach`` [µm], and it then counts as
    closed. Returns (the next free entry, the closed points added).
    """
    inside, g0, k, t = _rigid_gap(surf, i, shift)
    if not inside:
        return q, 0
    g = g0 - d
    closed = 0
    if flag == 2:
        if g > reach:
            return q, 0
        closed = 1
    s1, s2 = _upper_slopes(surf, k, t)
    _pack(scratch, q, surf, i, g, s1, s2)
    scratch.cl_keep[q] = True
    return q + 1, closed


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _filter_closed(
    n_cl: int, kappa_max: float, half_dx: float, min_delta: float, scratch: Scratch
) -> None:  # pragma: no cover - compiled
    """Flag the closed points that may pass Table 1, δ > min_delta and eq. 9 (``cl_keep``).

    :func:`._filter._may_touch` on the packed closed points, without branches so that it runs
    on vector units: its tests are widened by a bound of the rounding errors, so that no point
    the exact test accepts is dropped. The kept points are decided exactly afterwards.
    """
    g_a, s1_a, s2_a, kl_a, nx_a, nz_a, keep = packed_columns(scratch)
    dx = 2.0 * half_dx
    for q in range(n_cl):
        keep[q] = _may_touch(
            g_a[q], s1_a[q], s2_a[q], kl_a[q], nx_a[q], nz_a[q], kappa_max, dx, -min_delta
        )


@numba.njit(cache=True, nogil=True)
def path_step(
    u: float,
    d: float,
    du: float,
    dd: float,
    commit: bool,
    surf: Surfaces,
    cand: NDArray[np.int64],
    bound: NDArray[np.float64],
    descending: bool,
    material: Material,
    migrate_cells: int,
    springs: Springs,
    scratch: Scratch,
    fixed: NDArray[np.bool_],
    use_fixed: bool,
    pre: NDArray[np.float64],
) -> StepSums:  # pragma: no cover - compiled
    """One configuration (u, δ_N) of the upper body; see the module docstring.

    Visits the candidates ``cand`` (with upper bounds ``bound`` of f^l + f^u; sorted by
    decreasing bound when ``descending``), accepts contacts (Table 1, eq. 9, eq. 10, the law of
    ``material``), migrates the springs (:func:`_migrate`) and applies eqs. 11–13. With
    ``commit`` the new spring and law state replace the old.

    With ``use_fixed`` the contact cells are given: the cells i with ``fixed[i]`` are the ones
    that may carry a contact (Table 1 and δ > −reach still tested, eq. 9 and the detection
    gap ≤ reach not), the others carry none. The result is then continuous in δ_N (a contact
    appears at zero overlap), and for cells that eq. 9 accepts anyway it is bit-identical to the
    free evaluation.
    """
    placement = surf.placement
    reach = material.reach
    threshold = placement - d - reach
    shift = u / surf.dx
    half_dx = 0.5 * surf.dx
    kappa_max = surf.kappa_max
    # 1. The closed points (gap ≤ reach) that may be accepted are packed (cl_*, cl_keep).
    n_closed = 0
    n_packed = 0
    if use_fixed or surf.flat:
        # The gap of every candidate; the closed points are packed, then filtered.
        for j in range(cand.size):
            if bound[j] < threshold:
                if descending:
                    break
                continue
            i = cand[j]
            # The height first: the slope and curvature only where the gap has closed.
            inside, g0, k, t = _rigid_gap(surf, i, shift)
            if not inside:
                continue
            g = g0 - d
            if g > reach and not (use_fixed and fixed[i]):
                continue
            s1, s2 = _upper_slopes(surf, k, t)
            sphere_ready(surf, i)
            _pack(scratch, n_closed, surf, i, g, s1, s2)
            n_closed += 1
        n_packed = n_closed
        if not use_fixed:
            _filter_closed(n_packed, kappa_max, half_dx, -reach, scratch)
    elif pre.shape[1] > 0 or descending:
        # A fixed shift: the upper body's values at the candidates were computed once.
        if pre.shape[1] == 0:  # (or not: a reference evaluation, see path_step's doc)
            pre = _fixed_shift_values(surf, cand, shift)
        stop = cand.size
        if descending:  # the candidates with bound ≥ threshold are a prefix: bisection
            lo = 0
            while lo < stop:
                mid = (lo + stop) >> 1
                if bound[mid] < threshold:
                    stop = mid
                else:
                    lo = mid + 1
        # one branch-free pass flags the closed points that may be accepted; only those are
        # packed (in the candidates' order: the order the exact tests see them in)
        flags = scratch.cl_flag
        n_closed = _fixed_flags(
            pre[0, :stop], pre[1, :stop], pre[2, :stop], pre[3, :stop], pre[4, :stop],
            pre[5, :stop], bound[:stop], threshold, d, reach, kappa_max, surf.dx, flags[:stop],
        )  # fmt: skip
        hits = scratch.idx  # (free until the exact decision)
        for h in range(flag_list(flags, stop, hits, scratch.cl_keep.view(np.uint8))):
            j = hits[h]
            scratch.cl_i[n_packed] = cand[j]
            scratch.cl_g[n_packed] = pre[0, j] - d
            scratch.cl_s1[n_packed] = pre[1, j]
            scratch.cl_s2[n_packed] = pre[2, j]
            scratch.cl_kl[n_packed] = pre[3, j]
            scratch.cl_nx[n_packed] = pre[4, j]
            scratch.cl_nz[n_packed] = pre[5, j]
            scratch.cl_keep[n_packed] = True
            n_packed += 1
    else:
        # Sliding: one branch-free pass flags the few closed points the filter keeps; only
        # those (and the few it could not decide) are evaluated again, alone, and packed.
        flags = scratch.cl_flag
        n_closed = sliding_flags(
            surf, cand, bound, shift, d, threshold, reach, flags,
            (scratch.cl_g, scratch.cl_s1, scratch.cl_s2),
        )  # fmt: skip
        for j in range(cand.size):
            flag = flags[j]
            if flag == 0:
                continue
            if flag == 2 and bound[j] < threshold:
                continue
            n_packed, closed = _pack_flagged(
                scratch, n_packed, surf, cand[j], shift, d, reach, flag
            )
            n_closed += closed

    return _settle(
        u, d, du, dd, commit, surf, material, migrate_cells, springs, scratch, fixed, use_fixed,
        n_packed, n_closed,
    )  # fmt: skip


@numba.njit(cache=True, nogil=True)
def _settle(
    u: float,
    d: float,
    du: float,
    dd: float,
    commit: bool,
    surf: Surfaces,
    material: Material,
    migrate_cells: int,
    springs: Springs,
    scratch: Scratch,
    fixed: NDArray[np.bool_],
    use_fixed: bool,
    n_packed: int,
    n_closed: int,
) -> StepSums:  # pragma: no cover - compiled
    """The packed closed points of a configuration decided exactly, the springs moved (eqs.
    9–13); see :func:`path_step`. ``n_closed`` is reported as ``n_candidates``."""
    n = surf.f_l.size
    code = material.law_code
    params = material.law_params
    law_state = material.law_state
    # 3. The exact tests (Table 1, eq. 9, eq. 10) on the kept points, in grid order.
    if use_fixed:  # eq. 9 given: the offset test always passes; the given cells only
        for q in range(n_packed):
            scratch.cl_keep[q] = fixed[scratch.cl_i[q]]
        cell_test = np.inf
    else:
        cell_test = 0.5 * surf.dx
    n_c = decide_packed(
        n_packed, surf.f_l, surf.dx, surf.kappa_max, cell_test, -material.reach, scratch
    )
    apply_law(code, params, law_state, n_c, scratch)

    _migrate(n, n_c, migrate_cells, springs, scratch, True)  # (cl_* are free: scratch)

    sums, n_slip, work, n_touch = spring_sums(
        du, dd, n_c, material.g_star, material.mu0, springs, scratch
    )
    if commit:
        # The committed contacts are kept in grid order (slot p: cell springs.cells[p]).
        idx = scratch.idx[:n_c]
        ordered = True
        for c in range(1, n_c):
            if idx[c] < idx[c - 1]:
                ordered = False
                break
        order = scratch.src  # (read no more) the commit order: grid order
        if ordered:
            for c in range(n_c):
                order[c] = c
        else:
            order[:n_c] = np.argsort(idx, kind="mergesort")
        # A contact of the previous step that is not accepted now has let go (laws with a
        # branch state: JKR, Maugis–Dugdale); its plastic history stays.
        # A law without history state (Hertz, DMT) has nothing to release or commit.
        history = law_state.shape[1] > 0
        n_old = springs.n_committed[0]
        r = 0
        for p in range(n_old if history else 0):
            q = springs.cells[p]
            while r < n_c and idx[order[r]] < q:
                r += 1
            if r == n_c or idx[order[r]] != q:
                release_law(code, law_state, q)
        for r in range(n_c):
            c = order[r]
            springs.cells[r] = idx[c]
            springs.ft[r] = scratch.ft[c]
            springs.xc[r] = scratch.xc[c]
            springs.ex[r] = scratch.ex[c]
            springs.ez[r] = scratch.ez[c]
        if history:
            for r in range(n_c):
                c = order[r]
                commit_law(code, params, scratch.delta[c], scratch.reff[c], law_state, idx[c])
        springs.n_committed[0] = n_c
    return StepSums(
        sums[0], sums[1], sums[2], n_touch, n_slip, work, sums[3], sums[4], sums[5], n_closed
    )


@numba.njit(cache=True, nogil=True)
def path_step_from_python(
    u: float,
    d: float,
    du: float,
    dd: float,
    commit: bool,
    surf: tuple[Any, ...],
    cand: NDArray[np.int64],
    bound: NDArray[np.float64],
    material: tuple[Any, ...],
    migrate_cells: int,
    springs: tuple[Any, ...],
    scratch: tuple[Any, ...],
    fixed: NDArray[np.bool_],
    use_fixed: bool,
) -> tuple[Any, ...]:  # pragma: no cover - compiled
    """:func:`path_step` (candidates in grid order) with its records given as plain tuples.

    For calls from Python (the force-controlled steps call it many times per step): numba
    types a plain tuple argument, and returns one, several times faster than a named tuple.
    The result is the fields of :class:`StepSums` in order. (No precomputed values: a new
    empty array, not the global ``_NONE``, which numba would type read-only and so compile
    :func:`path_step` once more than for :func:`.run_steps`.)
    """
    s = path_step(
        u, d, du, dd, commit, Surfaces(*surf), cand, bound, False, Material(*material),
        migrate_cells, Springs(*springs), Scratch(*scratch), fixed, use_fixed, np.empty((6, 0)),
    )  # fmt: skip
    return (s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7], s[8], s[9])


#: No precomputed values (:func:`path_step` then evaluates the upper body itself).
_NONE = np.empty((6, 0))


@numba.njit(cache=True, nogil=True)
def _fixed_shift_values(
    surf: Surfaces, cand: NDArray[np.int64], shift: float
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Per candidate, for a fixed shift: C − (h^u + f^l), S′, S″, κ^l, n^l_x, n^l_z (rows).

    The upper values by the same scalar evaluation as :func:`path_step`'s (so the gap
    C − (h^u + f^l) − δ_N is the same to the bit); a candidate outside the upper body gets an
    infinite gap (never closed). One column per candidate, in the candidates' order, so that
    the steps read each value contiguously (on vector units).
    """
    m = cand.size
    out = np.empty((6, m))
    for j in range(m):
        i = cand[j]
        inside, g0, k, t = _rigid_gap(surf, i, shift)
        s1, s2 = _upper_slopes(surf, k, t) if inside else (0.0, 0.0)
        out[0, j] = g0 if inside else np.inf
        out[1, j] = s1
        out[2, j] = s2
        sphere_ready(surf, i)
        out[3, j] = surf.kappa_l[i]
        out[4, j] = surf.nl_x[i]
        out[5, j] = surf.nl_z[i]
    return out


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _fixed_flags(
    g0: NDArray[np.float64],
    s1: NDArray[np.float64],
    s2: NDArray[np.float64],
    k_l: NDArray[np.float64],
    n_x: NDArray[np.float64],
    n_z: NDArray[np.float64],
    bound: NDArray[np.float64],
    threshold: float,
    d: float,
    reach: float,
    kappa_max: float,
    dx: float,
    flags: NDArray[np.uint8],
) -> int:  # pragma: no cover - compiled
    """Flags of a fixed-shift step's candidates (the columns of :func:`_fixed_shift_values`).

    A candidate is closed when ``bound`` ≥ ``threshold`` and its gap g0 − δ_N ≤ ``reach``;
    ``flags`` is 1 where it is closed and passes the conservative filter of
    :func:`._filter._may_touch`, else 0. Returns the number of closed candidates.
    """
    n_closed = 0
    for j in range(flags.size):
        g = g0[j] - d
        closed = (bound[j] >= threshold) & (not g > reach)
        n_closed += closed
        keep = closed & _may_touch(g, s1[j], s2[j], k_l[j], n_x[j], n_z[j], kappa_max, dx, reach)
        flags[j] = np.uint8(keep)
    return n_closed


@numba.njit(cache=True, nogil=True, fastmath={"nnan", "ninf", "nsz"})
def upper_maxima(
    f_l: NDArray[np.float64],
    f_u: NDArray[np.float64],
    curv_u: NDArray[np.float64],
    dx: float,
    sub: int,
) -> tuple[
    NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], float, float
]:  # pragma: no cover - compiled
    """For a rough pair on one grid: the upper spline's γ = f″·dx², its
    :func:`interval_envelope`, the :func:`block_max` of f^l and of the envelope over ``sub``
    points, max(f^u + f^l) and max|f^l| + max|f^u| [µm].

    The same values as those functions and numpy's (each is one product per point or a
    maximum, exact in any order; the flags let the maxima run on vector units: finite values).
    """
    n = f_l.size
    gamma = np.empty(n)
    for i in range(n):
        gamma[i] = curv_u[i] * dx * dx
    envelope = np.empty(n - 1)
    for k in range(n - 1):
        envelope[k] = _interval_top(f_u[k], f_u[k + 1], gamma[k], gamma[k + 1])
    top = -np.inf
    abs_l = 0.0
    abs_u = 0.0
    for i in range(n):
        top = max(top, f_u[i] + f_l[i])
        abs_l = max(abs_l, abs(f_l[i]))
        abs_u = max(abs_u, abs(f_u[i]))
    return gamma, envelope, _sub_max(f_l, sub), _sub_max(envelope, sub), top, abs_l + abs_u


@numba.njit(cache=True, nogil=True, inline="always", fastmath={"nnan", "ninf", "nsz"})
def _sub_max(values: NDArray[np.float64], sub: int) -> NDArray[np.float64]:  # pragma: no cover
    """:func:`block_max` of finite values (on vector units)."""
    n = values.size
    out = np.empty((n + sub - 1) // sub)
    for q in range(out.size):
        hi = values[q * sub]
        for i in range(q * sub + 1, min(n, q * sub + sub)):
            hi = max(hi, values[i])
        out[q] = hi
    return out


@numba.njit(cache=True, nogil=True)
def migrate_cells_of(du: float, dd: float, dx: float, n: int) -> int:  # pragma: no cover
    """Cells [1] within which a vanished contact may continue: 1 + ⌈2(|Δu_T| + |Δδ_N|)/dx⌉."""
    return 1 + int(min(math.ceil(2.0 * (abs(du) + abs(dd)) / dx), n))


def __getattr__(name: str) -> Any:
    """``run_steps`` (and ``slide_step``) live in :mod:`._path_run`; kept importable here."""
    if name in ("run_steps", "slide_step"):
        from . import _path_run

        return getattr(_path_run, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
