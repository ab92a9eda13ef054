"""Compiled kernels of the load-path driver (:mod:`splinecontact.contact.loadpath`).

One call of :func:`path_step` evaluates one configuration (tangential shift u_T, normal
displacement δ_N) of the upper body: contact detection, Table 1, eq. 9 and eq. 10 on the shifted
geometry, the migration of the tangential springs (which previous contact each accepted contact
continues) and eqs. 11–13. With ``commit`` the new spring state replaces the old one; without it
the call is a trial (used by the force-controlled segments to solve for δ_N).

The upper body's smoothed height at lower grid point i and shift u is the natural cubic spline
evaluated at the fractional grid index ξ = i − u/dx, written from the spline's knot values f and
second differences γ = f″·dx² (a natural cubic spline is fully determined by them):

    S(ξ)  = (1−t) f_k + t f_{k+1} + [γ_k((1−t)³ − (1−t)) + γ_{k+1}(t³ − t)] / 6,
    S′(ξ) = f_{k+1} − f_k + [γ_{k+1}(3t² − 1) − γ_k(3(1−t)² − 1)] / 6,
    S″(ξ) = (1−t) γ_k + t γ_{k+1},

with k = ⌊ξ⌋, t = ξ − k (per grid unit; divided by dx and dx² for physical slopes). At t = 0
these are exactly the fitted f, f′ and f″ at the knots.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numba
import numpy as np
from numpy.typing import NDArray

from .geometry import add_contact_forces, contact_centre_height, sphere_contact
from .laws import Material, commit_law, normal_law, tangential_spring

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
    "run_steps",
]


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


class Springs(NamedTuple):
    """Spring state per lower grid cell (the committed contacts) and the migration flags."""

    acc: NDArray[np.bool_]  # cell holds a committed contact
    ft: NDArray[np.float64]  # its spring force [mN/µm]
    xc: NDArray[np.float64]  # its centre x [µm]
    ex: NDArray[np.float64]  # its repulsive direction [1]
    ez: NDArray[np.float64]
    cells: NDArray[np.int64]  # the committed cells
    n_committed: NDArray[np.int64]  # how many (one value)
    claimed: NDArray[np.bool_]  # scratch of the migration


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
    src: NDArray[np.int64]  # previous cell continued (−1: new contact)
    width: NDArray[np.float64]  # contact half-width [µm] (share of A_S)


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


@numba.njit(cache=True, nogil=True)
def _upper_surface(
    surf: Surfaces, i: int, shift: float
) -> tuple[bool, float, float, float]:  # pragma: no cover - compiled
    """(inside, h^u, S′/dx, S″/dx²) of the shifted upper spline at lower point i (module doc)."""
    if surf.flat:
        return True, 0.0, 0.0, 0.0
    f_u = surf.f_u
    n_up = f_u.size
    xi = i - shift
    if xi < 0.0 or xi > n_up - 1:
        return False, 0.0, 0.0, 0.0
    k = math.floor(xi)
    if k > n_up - 2:
        k = n_up - 2
    t = xi - k
    if t == 0.0:  # on a knot: the fitted values themselves
        return True, f_u[k], surf.slope_u[k], surf.curv_u[k]
    w = 1.0 - t
    g0 = surf.gamma_u[k]
    g1 = surf.gamma_u[k + 1]
    h_u = w * f_u[k] + t * f_u[k + 1] + (g0 * (w * w * w - w) + g1 * (t * t * t - t)) / 6.0
    inv_dx = 1.0 / surf.dx
    s1 = (
        f_u[k + 1] - f_u[k] + (g1 * (3.0 * t * t - 1.0) - g0 * (3.0 * w * w - 1.0)) / 6.0
    ) * inv_dx
    s2 = (w * g0 + t * g1) * (inv_dx * inv_dx)
    return True, h_u, s1, s2


@numba.njit(cache=True, nogil=True)
def _migrate(
    n: int, n_c: int, migrate_cells: int, springs: Springs, scratch: Scratch
) -> None:  # pragma: no cover - compiled
    """Which committed contact each accepted contact continues (``scratch.src``).

    The same cell continues its contact. Every other accepted contact may continue a vanished
    (not accepted again in its own cell) previous contact within ``migrate_cells`` cells; the
    pairs are assigned greedily by increasing distance between the previous and the new centre
    (independent of the visiting order, hence mirror symmetric).
    """
    st_acc = springs.acc
    claimed = springs.claimed
    c_idx = scratch.idx
    c_src = scratch.src
    n_pairs = 0
    for c in range(n_c):
        c_src[c] = -1
        i = c_idx[c]
        if st_acc[i]:
            c_src[c] = i
            claimed[i] = True
    for c in range(n_c):
        if c_src[c] >= 0:
            continue
        i = c_idx[c]
        for r in range(1, migrate_cells + 1):
            for sgn in (-1, 1):
                q = i + sgn * r
                if 0 <= q < n and st_acc[q] and not claimed[q]:
                    n_pairs += 1
    if n_pairs > 0:
        pair_c = np.empty(n_pairs, dtype=np.int64)
        pair_q = np.empty(n_pairs, dtype=np.int64)
        pair_d = np.empty(n_pairs)
        p = 0
        for c in range(n_c):
            if c_src[c] >= 0:
                continue
            i = c_idx[c]
            for r in range(1, migrate_cells + 1):
                for sgn in (-1, 1):
                    q = i + sgn * r
                    if 0 <= q < n and st_acc[q] and not claimed[q]:
                        pair_c[p] = c
                        pair_q[p] = q
                        pair_d[p] = abs(springs.xc[q] - scratch.xc[c])
                        p += 1
        order = np.argsort(pair_d, kind="mergesort")
        for o in order:
            c = pair_c[o]
            q = pair_q[o]
            if c_src[c] < 0 and not claimed[q]:
                c_src[c] = q
                claimed[q] = True
    for c in range(n_c):
        if c_src[c] >= 0:
            claimed[c_src[c]] = False


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
) -> StepSums:  # pragma: no cover - compiled
    """One configuration (u, δ_N) of the upper body; see the module docstring.

    Visits the candidates ``cand`` (with upper bounds ``bound`` of f^l + f^u; sorted by
    decreasing bound when ``descending``), accepts contacts (Table 1, eq. 9, eq. 10, the law of
    ``material``), migrates the springs (:func:`_migrate`) and applies eqs. 11–13. With
    ``commit`` the new spring and law state replace the old.
    """
    f_l = surf.f_l
    n = f_l.size
    placement = surf.placement
    reach = material.reach
    threshold = placement - d - reach
    shift = u / surf.dx
    half_dx = 0.5 * surf.dx
    kappa_max = surf.kappa_max
    code = material.law_code
    params = material.law_params
    law_state = material.law_state
    n_c = 0
    n_closed = 0
    for j in range(cand.size):
        if bound[j] < threshold:
            if descending:
                break
            continue
        i = cand[j]
        # The height first: the slope and curvature only where the gap has closed.
        inside, h_u, s1, s2 = _upper_surface(surf, i, shift)
        if not inside:
            continue
        g = (placement - (h_u + f_l[i])) - d
        if g > reach:
            continue
        n_closed += 1
        k_l = surf.kappa_l[i]
        norm_u = math.sqrt(1.0 + s1 * s1)
        k_u = -s2 / (norm_u * norm_u * norm_u)
        if k_u > kappa_max:
            k_u = kappa_max
        elif k_u < -kappa_max:
            k_u = -kappa_max
        m_z = 1.0 / norm_u
        n_z = surf.nl_z[i]
        accepted, delta, offset, e_x, e_z, y_norm = sphere_contact(
            g, k_l, k_u, s1 / norm_u, m_z, surf.nl_x[i], n_z, half_dx, -reach
        )
        if not accepted:
            continue
        reff = 2.0 / (k_l + k_u)
        f_n, width = normal_law(code, params, delta, reff, law_state, i)
        scratch.idx[n_c] = i
        scratch.fn[n_c] = f_n
        scratch.ex[n_c] = e_x
        scratch.ez[n_c] = e_z
        scratch.xc[n_c] = i * surf.dx + offset
        scratch.z[n_c] = f_l[i] + contact_centre_height(g, k_l, k_u, m_z, n_z, delta, y_norm)
        scratch.delta[n_c] = delta
        scratch.reff[n_c] = reff
        scratch.width[n_c] = width
        n_c += 1

    _migrate(n, n_c, migrate_cells, springs, scratch)

    g_star = material.g_star
    mu0 = material.mu0
    sums = (0.0, 0.0, 0.0, 0.0, 0.0, 0)
    work = 0.0
    n_slip = 0
    for c in range(n_c):
        f_n = scratch.fn[c]
        e_x = scratch.ex[c]
        e_z = scratch.ez[c]
        src = scratch.src[c]
        previous = 0.0
        increment = 0.0
        if src >= 0:
            # Eq. 11 with the upper body's increment (Δu_T, −Δδ_N) projected on the mean of the
            # old and new tangents t = (e_z, −e_x) (trapezoidal rule: reversible without slip).
            proj = 0.5 * (du * (springs.ez[src] + e_z) + dd * (springs.ex[src] + e_x))
            previous = springs.ft[src]
            increment = g_star * proj
        f_t, slipping, trial = tangential_spring(previous, increment, mu0, f_n)
        if slipping:
            n_slip += 1
            if g_star > 0.0:
                cap = mu0 * f_n
                work += cap * (abs(trial) - cap) / g_star
        scratch.ft[c] = f_t
        scratch.slip[c] = slipping
        sums = add_contact_forces(sums, f_n, f_t, e_x, e_z, scratch.width[c])
    if commit:
        for p in range(springs.n_committed[0]):
            springs.acc[springs.cells[p]] = False
        for c in range(n_c):
            i = scratch.idx[c]
            springs.acc[i] = True
            springs.ft[i] = scratch.ft[c]
            springs.xc[i] = scratch.xc[c]
            springs.ex[i] = scratch.ex[c]
            springs.ez[i] = scratch.ez[c]
            springs.cells[c] = i
            commit_law(code, params, scratch.delta[c], scratch.reff[c], law_state, i)
        springs.n_committed[0] = n_c
    return StepSums(
        sums[0], sums[1], sums[2], n_c, n_slip, work, sums[3], sums[4], sums[5], n_closed
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
) -> tuple[Any, ...]:  # pragma: no cover - compiled
    """:func:`path_step` (candidates in grid order) with its records given as plain tuples.

    For calls from Python (the force-controlled steps call it many times per step): numba
    types a plain tuple argument, and returns one, several times faster than a named tuple.
    The result is the fields of :class:`StepSums` in order.
    """
    s = path_step(
        u, d, du, dd, commit, Surfaces(*surf), cand, bound, False, Material(*material),
        migrate_cells, Springs(*springs), Scratch(*scratch),
    )  # fmt: skip
    return (s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7], s[8], s[9])


@numba.njit(cache=True, nogil=True)
def migrate_cells_of(du: float, dd: float, dx: float, n: int) -> int:  # pragma: no cover
    """Cells [1] within which a vanished contact may continue: 1 + ⌈2(|Δu_T| + |Δδ_N|)/dx⌉."""
    return 1 + int(min(math.ceil(2.0 * (abs(du) + abs(dd)) / dx), n))


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
            count = candidate_bounds(
                surf, cull, math.floor(-u_hi / dx) - 1, math.floor(-u_lo / dx) + 1,
                surf.placement - d_max - material.reach, buf_idx, buf_bound,
            )  # fmt: skip
            if moving:
                cand = buf_idx[:count]
                bound = buf_bound[:count]
            else:
                order = np.argsort(-buf_bound[:count], kind="mergesort")
                cand = buf_idx[:count][order]
                bound = buf_bound[:count][order]
            built_until = s_end
        u = u_b if s == n_steps else u_a + (u_b - u_a) * (s / n_steps)
        d = d_b if s == n_steps else d_a + (d_b - d_a) * (s / n_steps)
        du = u - u_cur
        dd = d - d_cur
        sums = path_step(
            u, d, du, dd, True, surf, cand, bound, not moving, material,
            migrate_cells_of(du, dd, dx, surf.f_l.size), springs, scratch,
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
