"""Compiled kernels of the load-path driver (:mod:`splinecontact.loadpath`).

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
from typing import Any

import numba
import numpy as np
from numpy.typing import NDArray

_QUARTER_PI = 0.25 * math.pi


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
    f_l: NDArray[np.float64],
    f_l_block: NDArray[np.float64],
    envelope: NDArray[np.float64],
    envelope_block: NDArray[np.float64],
    block: int,
    f_l_super: NDArray[np.float64],
    envelope_super: NDArray[np.float64],
    per_super: int,
    flat: bool,
    offset_lo: int,
    offset_hi: int,
    threshold: float,
    margin: float,
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
def path_step(
    u: float,
    d: float,
    du: float,
    dd: float,
    commit: bool,
    f_l: NDArray[np.float64],
    kappa_l: NDArray[np.float64],
    nl_x: NDArray[np.float64],
    nl_z: NDArray[np.float64],
    f_u: NDArray[np.float64],
    gamma_u: NDArray[np.float64],
    slope_u: NDArray[np.float64],
    curv_u: NDArray[np.float64],
    flat: bool,
    placement: float,
    dx: float,
    kappa_max: float,
    cand: NDArray[np.int64],
    bound: NDArray[np.float64],
    descending: bool,
    e_star: float,
    g_star: float,
    mu0: float,
    reach: int,
    st_acc: NDArray[np.bool_],
    st_ft: NDArray[np.float64],
    st_xc: NDArray[np.float64],
    st_ex: NDArray[np.float64],
    st_ez: NDArray[np.float64],
    st_list: NDArray[np.int64],
    st_count: NDArray[np.int64],
    claimed: NDArray[np.bool_],
    c_idx: NDArray[np.int64],
    c_fn: NDArray[np.float64],
    c_ex: NDArray[np.float64],
    c_ez: NDArray[np.float64],
    c_xc: NDArray[np.float64],
    c_z: NDArray[np.float64],
    c_delta: NDArray[np.float64],
    c_reff: NDArray[np.float64],
    c_ft: NDArray[np.float64],
    c_slip: NDArray[np.bool_],
    c_src: NDArray[np.int64],
) -> tuple[Any, ...]:  # pragma: no cover - compiled
    """One configuration (u, δ_N) of the upper body; see the module docstring.

    Returns (F_N, F_T, A_S, n_contacts, n_slipping, dissipated work of this step,
    F_N normal part, F_N tangential part, n_tilted, n_closed).
    """
    n = f_l.size
    n_up = f_u.size
    threshold = placement - d
    shift = u / dx
    inv_dx = 1.0 / dx
    inv_dx2 = inv_dx * inv_dx
    half_dx = 0.5 * dx
    n_c = 0
    n_closed = 0
    for j in range(cand.size):
        if bound[j] < threshold:
            if descending:
                break
            continue
        i = cand[j]
        # The height first: the slope and curvature only where the gap has closed.
        if flat:
            h_u = 0.0
            s1 = 0.0
            s2 = 0.0
            g = (placement - (h_u + f_l[i])) - d
            if g > 0.0:
                continue
        else:
            xi = i - shift
            if xi < 0.0 or xi > n_up - 1:
                continue
            k = math.floor(xi)
            if k > n_up - 2:
                k = n_up - 2
            t = xi - k
            if t == 0.0:  # on a knot: the fitted values themselves
                h_u = f_u[k]
                g = (placement - (h_u + f_l[i])) - d
                if g > 0.0:
                    continue
                s1 = slope_u[k]
                s2 = curv_u[k]
            else:
                w = 1.0 - t
                g0 = gamma_u[k]
                g1 = gamma_u[k + 1]
                h_u = (
                    w * f_u[k]
                    + t * f_u[k + 1]
                    + (g0 * (w * w * w - w) + g1 * (t * t * t - t)) / 6.0
                )
                g = (placement - (h_u + f_l[i])) - d
                if g > 0.0:
                    continue
                s1 = (
                    f_u[k + 1]
                    - f_u[k]
                    + (g1 * (3.0 * t * t - 1.0) - g0 * (3.0 * w * w - 1.0)) / 6.0
                ) * inv_dx
                s2 = (w * g0 + t * g1) * inv_dx2
        n_closed += 1
        k_l = kappa_l[i]
        norm_u = math.sqrt(1.0 + s1 * s1)
        k_u = -s2 / (norm_u * norm_u * norm_u)
        if k_u > kappa_max:
            k_u = kappa_max
        elif k_u < -kappa_max:
            k_u = -kappa_max
        k_sum = k_l + k_u
        if not k_sum > 0.0:  # Table 1
            continue
        m_x = s1 / norm_u
        m_z = 1.0 / norm_u
        n_x = nl_x[i]
        n_z = nl_z[i]
        k_prod = k_u * k_l
        y_x = k_l * m_x + k_u * n_x
        y_z = k_prod * g + k_l * m_z + k_u * n_z
        y_norm = math.sqrt(y_x * y_x + y_z * y_z)
        if not y_norm > 0.0:
            continue
        dmx = m_x - n_x
        dmz = m_z - n_z
        delta = (dmx * dmx + dmz * dmz - k_prod * g * g - 2.0 * g * (k_l * m_z + k_u * n_z)) / (
            y_norm + k_sum
        )
        if not delta > 0.0:
            continue
        offset = (2.0 * dmx + delta * (k_u * n_x - k_l * m_x)) / (2.0 * y_norm)
        if not (-half_dx <= offset < half_dx):  # eq. 9
            continue
        c_idx[n_c] = i
        c_fn[n_c] = _QUARTER_PI * e_star * delta
        c_ex[n_c] = y_x / y_norm
        c_ez[n_c] = y_z / y_norm
        c_xc[n_c] = i * dx + offset
        c_z[n_c] = f_l[i] + (
            2.0 * dmz + delta * (k_u * n_z - k_l * m_z) + g * k_u * (2.0 - k_l * delta)
        ) / (2.0 * y_norm)
        c_delta[n_c] = delta
        c_reff[n_c] = 2.0 / k_sum
        n_c += 1

    # Spring migration: the same cell continues its contact. Every other accepted contact may
    # continue a vanished (not accepted again in its own cell) previous contact within `reach`
    # cells; the pairs are assigned greedily by increasing distance between the previous and the
    # new centre (independent of the visiting order, hence mirror symmetric).
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
        for r in range(1, reach + 1):
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
            for r in range(1, reach + 1):
                for sgn in (-1, 1):
                    q = i + sgn * r
                    if 0 <= q < n and st_acc[q] and not claimed[q]:
                        pair_c[p] = c
                        pair_q[p] = q
                        pair_d[p] = abs(st_xc[q] - c_xc[c])
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

    sum_fn = 0.0
    sum_ft = 0.0
    sum_area = 0.0
    sum_fn_normal = 0.0
    sum_fn_tangential = 0.0
    work = 0.0
    n_slip = 0
    tilted = 0
    for c in range(n_c):
        f_n = c_fn[c]
        e_x = c_ex[c]
        e_z = c_ez[c]
        src = c_src[c]
        if src >= 0:
            # Eq. 11 with the upper body's increment (Δu_T, −Δδ_N) projected on the mean of the
            # old and new tangents t = (e_z, −e_x) (trapezoidal rule: reversible without slip).
            proj = 0.5 * (du * (st_ez[src] + e_z) + dd * (st_ex[src] + e_x))
            trial = st_ft[src] - g_star * proj
        else:
            trial = 0.0
        cap = mu0 * f_n
        slipping = False
        f_t = trial
        if trial > cap:
            f_t = cap
            slipping = True
        elif trial < -cap:
            f_t = -cap
            slipping = True
        if slipping:
            n_slip += 1
            if g_star > 0.0:
                work += cap * (abs(trial) - cap) / g_star
        c_ft[c] = f_t
        c_slip[c] = slipping
        fn_part = f_n * e_z
        ft_part = -f_t * e_x
        sum_fn_normal += fn_part
        sum_fn_tangential += ft_part
        sum_fn += fn_part + ft_part
        sum_ft += f_n * e_x + f_t * e_z
        sum_area += math.sqrt(c_delta[c] * c_reff[c])
        if e_z < 0.0:
            tilted += 1
    if commit:
        for p in range(st_count[0]):
            st_acc[st_list[p]] = False
        for c in range(n_c):
            i = c_idx[c]
            st_acc[i] = True
            st_ft[i] = c_ft[c]
            st_xc[i] = c_xc[c]
            st_ex[i] = c_ex[c]
            st_ez[i] = c_ez[c]
            st_list[c] = i
        st_count[0] = n_c
    return (
        sum_fn,
        sum_ft,
        sum_area,
        n_c,
        n_slip,
        work,
        sum_fn_normal,
        sum_fn_tangential,
        tilted,
        n_closed,
    )


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
    f_l: NDArray[np.float64],
    kappa_l: NDArray[np.float64],
    nl_x: NDArray[np.float64],
    nl_z: NDArray[np.float64],
    f_u: NDArray[np.float64],
    gamma_u: NDArray[np.float64],
    slope_u: NDArray[np.float64],
    curv_u: NDArray[np.float64],
    flat: bool,
    placement: float,
    dx: float,
    kappa_max: float,
    f_l_block: NDArray[np.float64],
    envelope: NDArray[np.float64],
    envelope_block: NDArray[np.float64],
    block: int,
    f_l_super: NDArray[np.float64],
    envelope_super: NDArray[np.float64],
    per_super: int,
    margin: float,
    buf_idx: NDArray[np.int64],
    buf_bound: NDArray[np.float64],
    e_star: float,
    g_star: float,
    mu0: float,
    st_acc: NDArray[np.bool_],
    st_ft: NDArray[np.float64],
    st_xc: NDArray[np.float64],
    st_ex: NDArray[np.float64],
    st_ez: NDArray[np.float64],
    st_list: NDArray[np.int64],
    st_count: NDArray[np.int64],
    claimed: NDArray[np.bool_],
    c_idx: NDArray[np.int64],
    c_fn: NDArray[np.float64],
    c_ex: NDArray[np.float64],
    c_ez: NDArray[np.float64],
    c_xc: NDArray[np.float64],
    c_z: NDArray[np.float64],
    c_delta: NDArray[np.float64],
    c_reff: NDArray[np.float64],
    c_ft: NDArray[np.float64],
    c_slip: NDArray[np.bool_],
    c_src: NDArray[np.int64],
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
                f_l, f_l_block, envelope, envelope_block, block, f_l_super, envelope_super,
                per_super, flat, math.floor(-u_hi / dx) - 1, math.floor(-u_lo / dx) + 1,
                placement - d_max, margin, buf_idx, buf_bound,
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
        reach = 1 + int(min(math.ceil(2.0 * (abs(du) + abs(dd)) / dx), f_l.size))
        sums = path_step(
            u, d, du, dd, True, f_l, kappa_l, nl_x, nl_z, f_u, gamma_u, slope_u, curv_u, flat,
            placement, dx, kappa_max, cand, bound, not moving, e_star, g_star, mu0, reach,
            st_acc, st_ft, st_xc, st_ex, st_ez, st_list, st_count, claimed,
            c_idx, c_fn, c_ex, c_ez, c_xc, c_z, c_delta, c_reff, c_ft, c_slip, c_src,
        )  # fmt: skip
        row = k0 + s - s_first
        out[row, 0] = d
        out[row, 1] = u
        out[row, 2] = sums[0]
        out[row, 3] = sums[1]
        out[row, 4] = sums[2]
        out[row, 5] = sums[3]
        out[row, 6] = sums[4]
        out[row, 7] = sums[5]
        out[row, 8] = sums[6]
        out[row, 9] = sums[7]
        out[row, 10] = sums[8]
        out[row, 11] = sums[9]
        u_cur = u
        d_cur = d
