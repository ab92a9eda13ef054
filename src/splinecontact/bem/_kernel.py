"""The compiled Polonsky–Keer load-control loop of the BEM and its fused passes.

One loop for every grid size: the operator u = A p is the package's compiled circulant product
(:func:`splinecontact._fft.circulant`: grids with n/2 = 2^a·3^b·5^c directly, any other
grid embedded in such a length), called from inside the loop.
"""

from __future__ import annotations

import math
from typing import Any

import numba
import numpy as np
from numpy.typing import NDArray

from .._fft import circulant

# --- fused kernels of the load-control loop ---------------------------------------------------
#
# Each kernel is one pass over the nodes. The fast-math flags let the reductions be vectorised
# (their order of summation differs from numpy's pairwise sums by rounding only); they leave
# out "nnan"/"ninf", so NaN and Inf keep their meaning and a broken input cannot hide behind
# the flags, and "contract", so an expression evaluated in two loops rounds the same in both.

_FAST = {"nsz", "arcp", "afn", "reassoc"}


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_loaded_sum(
    p: NDArray[np.float64], u: NDArray[np.float64], z: NDArray[np.float64]
) -> tuple[float, int]:  # pragma: no cover - compiled
    """Σ over loaded nodes (p > 0) of u − z, and their count."""
    total = 0.0
    count = 0
    for i in range(p.size):
        loaded = p[i] > 0.0
        total += u[i] - z[i] if loaded else 0.0
        count += 1 if loaded else 0
    return total, count


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_gap(
    p: NDArray[np.float64],
    u: NDArray[np.float64],
    z: NDArray[np.float64],
    separation: float,
    g: NDArray[np.float64],
    scale: float,
    tol: float,
) -> tuple[int, float]:  # pragma: no cover - compiled
    """g = u − z + s; return the number of nodes violating complementarity by more than
    tol·scale (|g| on loaded nodes, the overlap −g on free ones; NaN counts) and Σ_loaded g².

    Counting rather than taking the largest violation keeps the loop a vector loop (float
    max-reductions are not vectorised); the residual itself is :func:`_k_residual`.
    """
    bad = 0
    norm = 0.0
    for i in range(p.size):
        value = (u[i] - z[i]) + separation
        g[i] = value
        loaded = p[i] > 0.0
        violation = abs(value) if loaded else -value
        bad += 0 if violation / scale <= tol else 1
        norm += value * value if loaded else 0.0
    return bad, norm


@numba.njit(cache=True, nogil=True)
def _k_residual(
    p: NDArray[np.float64], g: NDArray[np.float64], scale: float
) -> float:  # pragma: no cover - compiled
    """Largest complementarity violation / scale: max |g| on loaded nodes, max −g on free ones."""
    worst_loaded = 0.0
    worst_free = 0.0
    for i in range(p.size):
        loaded = p[i] > 0.0
        worst_loaded = max(worst_loaded, abs(g[i]) if loaded else 0.0)
        worst_free = max(worst_free, 0.0 if loaded else -g[i])
    return max(worst_loaded, worst_free) / scale


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_direction(
    p: NDArray[np.float64],
    g: NDArray[np.float64],
    t: NDArray[np.float64],
    beta: float,
    conjugate: bool,
) -> tuple[float, float]:  # pragma: no cover - compiled
    """t = (β t + g) on loaded nodes, 0 elsewhere (β = 0 restarts); return Σ t and Σ g·t."""
    total = 0.0
    gt = 0.0
    for i in range(p.size):
        value = (t[i] * beta + g[i] if conjugate else g[i]) if p[i] > 0.0 else 0.0
        t[i] = value
        total += value
        gt += g[i] * value
    return total, gt


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_curvature(
    p: NDArray[np.float64], r: NDArray[np.float64], t: NDArray[np.float64]
) -> tuple[float, float]:  # pragma: no cover - compiled
    """Σ r·t and Σ over loaded nodes of r."""
    rt = 0.0
    r_loaded = 0.0
    for i in range(p.size):
        rt += r[i] * t[i]
        r_loaded += r[i] if p[i] > 0.0 else 0.0
    return rt, r_loaded


#: Nodes per chunk of :func:`_k_step`: a chunk where no node is clamped or newly loaded is one
#: vector loop; the others take the scalar loop that records the changes.
_STEP_CHUNK = 128


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_step(
    p: NDArray[np.float64],
    t: NDArray[np.float64],
    g: NDArray[np.float64],
    tau: float,
    changed: NDArray[np.int64],
    delta: NDArray[np.float64],
) -> tuple[float, int, bool]:  # pragma: no cover - compiled
    """p ← max(p − τ t, 0), then p = −τ g where p = 0 and g < 0 (new contact).

    Records the nodes where the result differs from p − τ t (and by how much) in ``changed`` and
    ``delta`` while they fit; returns Σ p, the number of such nodes and whether any node overlapped.
    """
    total = 0.0
    n_changed = 0
    overlap = False
    capacity = changed.size
    for start in range(0, p.size, _STEP_CHUNK):
        # slices: indices from range(size) are known non-negative, so the loops vectorise
        pc = p[start : start + _STEP_CHUNK]
        tc = t[start : start + _STEP_CHUNK]
        gc = g[start : start + _STEP_CHUNK]
        flagged = 0
        for i in range(pc.size):
            linear = pc[i] - tau * tc[i]
            value = linear if linear > 0.0 else 0.0
            value = -tau * gc[i] if value == 0.0 and gc[i] < 0.0 else value
            flagged += 0 if value == linear else 1
        if flagged == 0:
            for i in range(pc.size):
                value = pc[i] - tau * tc[i]
                pc[i] = value
                total += value
            continue
        for i in range(pc.size):
            linear = pc[i] - tau * tc[i]
            value = linear if linear > 0.0 else 0.0
            if value == 0.0 and gc[i] < 0.0:
                value = -tau * gc[i]
                overlap = True
            if value != linear:
                if n_changed < capacity:
                    changed[n_changed] = start + i
                    delta[n_changed] = value - linear
                n_changed += 1
            pc[i] = value
            total += value
    return total, n_changed, overlap


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_add_columns(
    u: NDArray[np.float64],
    column2: NDArray[np.float64],
    changed: NDArray[np.int64],
    delta: NDArray[np.float64],
    n_changed: int,
) -> None:  # pragma: no cover - compiled
    """u += Σ_k δ_k a(· − j_k): the response to a few point loads.

    ``column2`` is the response a to a unit load at node 0, stored twice (length 2n), so that
    a((i − j) mod n) = column2[n − j + i] is one contiguous run for every i.
    """
    n = u.size
    k = 0
    while k + 4 <= n_changed:  # four columns per pass over u (same order of additions)
        d0 = delta[k]
        d1 = delta[k + 1]
        d2 = delta[k + 2]
        d3 = delta[k + 3]
        r0 = column2[n - changed[k] : 2 * n - changed[k]]
        r1 = column2[n - changed[k + 1] : 2 * n - changed[k + 1]]
        r2 = column2[n - changed[k + 2] : 2 * n - changed[k + 2]]
        r3 = column2[n - changed[k + 3] : 2 * n - changed[k + 3]]
        for i in range(n):
            u[i] = (((u[i] + d0 * r0[i]) + d1 * r1[i]) + d2 * r2[i]) + d3 * r3[i]
        k += 4
    while k < n_changed:
        start = n - changed[k]
        d = delta[k]
        run = column2[start : start + n]
        for i in range(n):
            u[i] += d * run[i]
        k += 1


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_rescale(
    p: NDArray[np.float64],
    u: NDArray[np.float64],
    r: NDArray[np.float64],
    z: NDArray[np.float64],
    tau: float,
    factor: float,
    update_u: bool,
) -> tuple[float, int]:  # pragma: no cover - compiled
    """p ← c p, and u ← c (u − τ r) if asked; return Σ_loaded (u − z) and the loaded count."""
    total = 0.0
    count = 0
    for i in range(p.size):
        value = p[i] * factor
        p[i] = value
        if update_u:
            u[i] = (u[i] - tau * r[i]) * factor
        if value > 0.0:
            total += u[i] - z[i]
            count += 1
    return total, count


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_gap_and_direction(
    p: NDArray[np.float64],
    u: NDArray[np.float64],
    z: NDArray[np.float64],
    g: NDArray[np.float64],
    t: NDArray[np.float64],
    separation: float,
    scale: float,
    tol: float,
    conjugate: bool,
    g_norm_old: float,
    may_step: bool,
) -> tuple[float, float, float, float]:  # pragma: no cover - compiled
    """The gap and residual; unless converged (or ``may_step`` is False), the new direction t.

    Returns the residual (exact when ≤ tol or when no direction is made, otherwise only known
    to be > tol and returned as inf), Σ_loaded g², Σ t and Σ g·t (the last two 0 when no
    direction).
    """
    bad, g_norm = _k_gap(p, u, z, separation, g, scale, tol)
    if bad == 0 or not may_step:
        return _k_residual(p, g, scale), g_norm, 0.0, 0.0
    use_beta = conjugate and g_norm_old > 0.0
    beta = g_norm / g_norm_old if use_beta else 0.0
    t_sum, gt = _k_direction(p, g, t, beta, use_beta)
    return np.inf, g_norm, t_sum, gt


@numba.njit(cache=True, nogil=True, fastmath=_FAST)
def _k_advance(
    p: NDArray[np.float64],
    u: NDArray[np.float64],
    r: NDArray[np.float64],
    t: NDArray[np.float64],
    g: NDArray[np.float64],
    z: NDArray[np.float64],
    count: int,
    t_sum: float,
    gt: float,
    tau_fallback: float,
    mean_pressure: float,
    column2: NDArray[np.float64],
    changed: NDArray[np.int64],
    delta: NDArray[np.float64],
    limit: int,
) -> tuple[float, int, bool, bool]:  # pragma: no cover - compiled
    """Line search along t (r = A t), projected step, rescale to the mean pressure.

    u follows p incrementally when few nodes changed (then returns Σ_loaded (u − z) and the
    loaded count for the next iteration, and ``incremental`` True); otherwise u is left for the
    caller to recompute. Also returns whether a node overlapped (conjugacy is then lost).
    """
    rt, r_loaded = _k_curvature(p, r, t)
    denominator = rt - r_loaded / count * t_sum
    tau = gt / denominator if denominator > 0.0 else tau_fallback
    total, n_changed, overlap = _k_step(p, t, g, tau, changed, delta)
    restart = total <= 0.0
    if restart:  # every node was released: restart at the deepest overlap
        p[np.argmin(g)] = 1.0
        total = 1.0
        overlap = True
    factor = mean_pressure * p.size / total
    incremental = not restart and n_changed <= limit
    if incremental:
        _k_add_columns(u, column2, changed, delta, n_changed)
    loaded_sum, new_count = _k_rescale(p, u, r, z, tau, factor, incremental)
    return loaded_sum, new_count, overlap, incremental


#: Point loads changed in one iteration up to which their response is added column by column
#: (k·n multiply-adds) instead of re-applying the operator with an FFT pair; per grid size
#: (a negative limit re-applies the operator after every iteration).
def _sparse_limit(n: int) -> int:
    return 3 * max(4, int(math.log2(max(n, 2))))


@numba.njit(cache=True, nogil=True)
def _k_pk_loop(
    z: NDArray[np.float64],
    p: NDArray[np.float64],
    t: NDArray[np.float64],
    g: NDArray[np.float64],
    r: NDArray[np.float64],
    u: NDArray[np.float64],
    column2: NDArray[np.float64],
    changed: NDArray[np.int64],
    delta: NDArray[np.float64],
    limit: int,
    scale: float,
    tol: float,
    tau_fallback: float,
    mean_pressure: float,
    max_iterations: int,
    op: tuple[Any, ...],
) -> tuple[bool, int, float, float]:  # pragma: no cover - compiled
    """Polonsky–Keer constrained conjugate gradients at fixed mean pressure, compiled whole.

    ``op`` is the argument tuple of :func:`splinecontact._fft.circulant` after its first two
    (values, out): u = A p for the grid of ``z``, whatever its size. The displacement u = A p is
    carried from one iteration to the next: after the step p ← c (p − τ t + δ),
    u ← c (u − τ r + A δ) with r = A t already known and δ the few nodes that were released or
    newly loaded, whose response is added column by column (:func:`_k_add_columns`, at most
    ``limit`` of them). Only when more nodes change is u recomputed with the operator, and
    always before convergence is declared, so the gap ``g`` left behind is that of ``p``.
    ``p`` and ``g`` hold the solution on return; returns (converged, iterations, residual,
    separation).
    """
    circulant(p, u, *op)
    exact = True
    loaded_sum, count = _k_loaded_sum(p, u, z)
    g_norm_old = 0.0
    conjugate = False
    residual = np.inf
    iteration = 0
    while True:
        separation = -loaded_sum / count
        residual, g_norm, t_sum, gt = _k_gap_and_direction(
            p, u, z, g, t, separation, scale, tol, conjugate, g_norm_old,
            iteration < max_iterations,
        )  # fmt: skip
        if residual <= tol:
            if exact:
                return True, iteration, residual, separation
            circulant(p, u, *op)
            exact = True
            loaded_sum, count = _k_loaded_sum(p, u, z)
            continue
        if iteration == max_iterations:
            break
        iteration += 1
        g_norm_old = g_norm
        circulant(t, r, *op)
        loaded_sum, new_count, overlap, incremental = _k_advance(
            p, u, r, t, g, z, count, t_sum, gt, tau_fallback, mean_pressure, column2, changed,
            delta, limit,
        )  # fmt: skip
        conjugate = not overlap
        count = new_count
        if not incremental:
            circulant(p, u, *op)
            loaded_sum, count = _k_loaded_sum(p, u, z)
        exact = not incremental
    return False, iteration, residual, 0.0
