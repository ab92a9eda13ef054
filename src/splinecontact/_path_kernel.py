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
def candidate_bounds(
    f_l: NDArray[np.float64],
    envelope: NDArray[np.float64],
    flat: bool,
    offset_lo: int,
    offset_hi: int,
    threshold: float,
    margin: float,
) -> tuple[NDArray[np.int64], NDArray[np.float64]]:  # pragma: no cover - compiled
    """Points whose rigid gap can close, and an upper bound of f^l_i + f^u(ξ) for each.

    For lower point i the upper spline is evaluated on the knot intervals
    k ∈ [i + offset_lo, i + offset_hi] (clipped to the upper body); the bound is f^l_i plus the
    largest interval envelope there (a sliding-window maximum, O(n)). Only points with
    bound ≥ ``threshold`` (= C − largest δ_N) are returned.
    """
    n = f_l.size
    bound = np.empty(n)
    if flat:
        for i in range(n):
            bound[i] = f_l[i] + margin
    else:
        m = envelope.size
        # Monotone deque of interval indices with decreasing envelope values.
        dq = np.empty(m, dtype=np.int64)
        head = 0
        tail = 0
        next_k = 0
        for i in range(n):
            lo = i + offset_lo
            hi = i + offset_hi
            if lo < 0:
                lo = 0
            if hi > m - 1:
                hi = m - 1
            if hi < lo:
                bound[i] = -np.inf
                continue
            while next_k <= hi:
                while tail > head and envelope[dq[tail - 1]] <= envelope[next_k]:
                    tail -= 1
                dq[tail] = next_k
                tail += 1
                next_k += 1
            while head < tail and dq[head] < lo:
                head += 1
            bound[i] = f_l[i] + envelope[dq[head]] + margin
    count = 0
    for i in range(n):
        if bound[i] >= threshold:
            count += 1
    idx = np.empty(count, dtype=np.int64)
    val = np.empty(count)
    c = 0
    for i in range(n):
        if bound[i] >= threshold:
            idx[c] = i
            val[c] = bound[i]
            c += 1
    return idx, val


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
            break
        i = cand[j]
        if flat:
            h_u = 0.0
            s1 = 0.0
            s2 = 0.0
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
                s1 = (
                    f_u[k + 1]
                    - f_u[k]
                    + (g1 * (3.0 * t * t - 1.0) - g0 * (3.0 * w * w - 1.0)) / 6.0
                ) * inv_dx
                s2 = (w * g0 + t * g1) * inv_dx2
        g = (placement - (h_u + f_l[i])) - d
        if g > 0.0:
            continue
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

    # Spring migration: the same cell continues its contact; otherwise the nearest vanished,
    # unclaimed previous contact within `reach` cells (nearest previous centre) is continued.
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
        best = -1
        best_dist = np.inf
        for r in range(1, reach + 1):
            for sgn in (-1, 1):
                q = i + sgn * r
                if 0 <= q < n and st_acc[q] and not claimed[q]:
                    dist = abs(st_xc[q] - c_xc[c])
                    if dist < best_dist:
                        best_dist = dist
                        best = q
        if best >= 0:
            c_src[c] = best
            claimed[best] = True
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
