"""The elastic half-plane at contact level: Green function, pair coefficients, fast operator.

The periodic plane-strain Green function of a line load (the kernel of :mod:`splinecontact.bem`
summed in closed form), the coupling coefficients of Hertzian contacts (flat-punch averages,
Barber's reciprocal argument), the pieces of the particle–mesh operator C P = 2c P + e_z w(P)
(mesh kernel, spreading, near pairs, reading back) and the steps of the constrained conjugate
gradients (Polonsky & Keer, Wear 231 (1999) 206–219) that solve the unilateral contact problem
at contact level. Used by the compiled loop of :mod:`.interaction_kernel`.
"""

from __future__ import annotations

import math
from typing import Any

import numba
import numpy as np
from numpy.typing import NDArray

__all__ = [
    "CELLS_PER_SOURCE",
    "NEAR_CELLS",
    "NEAR_WIDTHS",
    "pair_coefficient",
    "periodic_green",
    "self_coefficient",
]

#: Mesh cells per load (contact or image) when the mesh size follows the contacts [1].
CELLS_PER_SOURCE = 8

#: Pairs of contacts closer than this many mesh cells get the exact coupling coefficient.
NEAR_CELLS = 4

#: Pairs closer than this many times the largest contact half-width are also near pairs (their
#: displacement gradients shape each other's contact) [1].
NEAR_WIDTHS = 6.0

#: Gauss–Chebyshev (second kind) nodes over the Hertz distribution of a neighbour.
_QUAD_NODES = 16


# --- closed forms ---------------------------------------------------------------------------


def periodic_green(r: NDArray[np.float64] | float, period: float, e_star: float) -> Any:
    """Zero-mean periodic plane-strain displacement of a unit line load [µm per mN/µm].

    u(r) = −(2/(πE*)) ln|2 sin(πr/L_p)|, the Fourier series 2/(E*|q|) of
    :mod:`splinecontact.bem` summed in closed form.

    Parameters
    ----------
    r : float or ndarray
        Distance from the load [µm] (not a multiple of the period).
    period : float
        Period L_p [µm].
    e_star : float
        Effective modulus E* [GPa].
    """
    return -(2.0 / (math.pi * e_star)) * np.log(
        np.abs(2.0 * np.sin(np.pi * np.asarray(r) / period))
    )


def self_coefficient(a: float, period: float, e_star: float) -> float:
    """Periodic Hertz central displacement per unit load minus SAD's local compliance [µm/(mN/µm)].

    c (ln(L_p/(π a)) + 1/2) − 2c with c = 2/(πE*): the part of a Hertzian line contact's own
    displacement (half-width ``a`` [µm], period ``period`` [µm]) that eq. 10's
    F = (π/4)E*δ does not contain.
    """
    c = 2.0 / (math.pi * e_star)
    return c * (math.log(period / (math.pi * a)) - 1.5)


@numba.njit(cache=True, nogil=True)
def _punch_log(rho: float, a: float) -> float:  # pragma: no cover - compiled
    """Flat-punch average of ln|x − y| over |x| ≤ a for a source at y = ρ."""
    t = abs(rho)
    if t <= a:
        return math.log(0.5 * a) if a > 0.0 else -1e300
    return math.log(0.5 * (t + math.sqrt(t * t - a * a)))


@numba.njit(cache=True, nogil=True)
def _pair(
    r: float,
    a_t: float,
    a_s: float,
    period: float,
    c: float,
    nodes: NDArray[np.float64],
    weights: NDArray[np.float64],
) -> float:  # pragma: no cover - compiled
    """Symmetrised coupling coefficient between contacts at distance r with half-widths a_t, a_s.

    Beyond three times the sum of the widths the averages are ln|r| − (3/16)(a_t² + a_s²)/r²
    to O((a/r)⁴) (the second moments of the punch and Hertz weights); closer by quadrature.
    """
    t = abs(r)
    if t > 3.0 * (a_t + a_s):
        # ln t + ln(2π/L) + ln|sinc(πr/L)| = ln|2 sin(πr/L)|
        far = math.log(abs(2.0 * math.sin(math.pi * r / period)))
        return -c * (far - 0.1875 * (a_t * a_t + a_s * a_s) / (t * t))
    else:
        total = 0.0
        for k in range(nodes.size):
            total += weights[k] * (
                _punch_log(r - a_s * nodes[k], a_t) + _punch_log(r - a_t * nodes[k], a_s)
            )
        mean_log = 0.5 * total
    x = math.pi * r / period
    sinc = math.sin(x) / x if x != 0.0 else 1.0
    return -c * (mean_log + math.log(2.0 * math.pi / period) + math.log(abs(sinc)))


def _quadrature() -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Nodes t_k and weights of (2/π)∫√(1−t²) f(t) dt ≈ Σ w_k f(t_k) (weights sum to 1)."""
    m = _QUAD_NODES
    k = np.arange(1, m + 1)
    theta = k * np.pi / (m + 1)
    return np.cos(theta), (2.0 / (m + 1)) * np.sin(theta) ** 2


def pair_coefficient(
    r: float, a_target: float, a_source: float, period: float, e_star: float
) -> float:
    """Vertical displacement at one contact per unit load on another [µm/(mN/µm)].

    The source's Hertz field (half-width ``a_source`` [µm]) averaged over the target contact
    (half-width ``a_target`` [µm]) with the flat-punch weight, symmetrised in the two widths,
    in a period ``period`` [µm] at distance ``r`` [µm] (zero-mean periodic displacement).
    """
    nodes, weights = _quadrature()
    return float(
        _pair(
            float(r),
            float(a_target),
            float(a_source),
            float(period),
            2.0 / (math.pi * e_star),
            nodes,
            weights,
        )
    )


# --- the elastic operator -------------------------------------------------------------------


@numba.njit(cache=True, nogil=True)
def _near_lists(
    pos: NDArray[np.float64], n_targets: int, period: float, near: float
) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:  # pragma: no cover
    """CSR list of the (target, source) pairs within ``near`` [µm] (periodic): start, sources and
    the period shift of each entry. Targets are sources 0 … n_targets − 1 (the contacts)."""
    order = np.argsort(pos)
    sorted_pos = pos[order]
    start = np.zeros(n_targets + 1, dtype=np.int64)
    shifts = (-period, 0.0, period)
    for i in range(n_targets):
        cnt = 0
        for shift in shifts:
            if not -near <= pos[i] + shift <= period + near:
                continue  # (positions lie in [0, period): nothing within reach)
            lo = np.searchsorted(sorted_pos, pos[i] + shift - near, side="left")
            hi = np.searchsorted(sorted_pos, pos[i] + shift + near, side="right")
            cnt += hi - lo
        start[i + 1] = start[i] + cnt
    nnz = start[n_targets]
    src = np.empty(nnz, dtype=np.int64)
    shift_of = np.empty(nnz)
    for i in range(n_targets):
        k = start[i]
        for shift in shifts:
            if not -near <= pos[i] + shift <= period + near:
                continue
            lo = np.searchsorted(sorted_pos, pos[i] + shift - near, side="left")
            hi = np.searchsorted(sorted_pos, pos[i] + shift + near, side="right")
            for q in range(lo, hi):
                src[k] = order[q]
                shift_of[k] = shift
                k += 1
    return start, src, shift_of


@numba.njit(cache=True, nogil=True)
def _mesh_coupling(
    ia: int, fi: float, sa: int, fs: float, mesh_green: NDArray[np.float64]
) -> float:  # pragma: no cover - compiled
    """Mesh coupling of a target in cell ``ia`` (fraction ``fi``) and a source in cell ``sa``
    (fraction ``fs``): linear weights at both ends."""
    cells = mesh_green.size
    mesh = 0.0
    for da in range(2):
        wa = fi if da == 1 else 1.0 - fi
        for db in range(2):
            wb = fs if db == 1 else 1.0 - fs
            mesh += wa * wb * mesh_green[(ia + da - sa - db) % cells]
    return mesh


@numba.njit(cache=True, nogil=True)
def _exact_pair(
    i: int,
    s: int,
    r: float,
    pos_a: NDArray[np.float64],
    owner: NDArray[np.int64],
    period: float,
    c: float,
    nodes: NDArray[np.float64],
    weights: NDArray[np.float64],
) -> float:  # pragma: no cover - compiled
    """Exact coupling of target i and source s at distance r [µm] (``pos_a``: half-widths)."""
    if s == i:
        return c * (math.log(period / (math.pi * pos_a[i])) - 1.5)
    if owner[s] == i:  # own mirror image
        return _pair(r, pos_a[i], pos_a[i], period, c, nodes, weights)
    return _pair(r, pos_a[i], pos_a[s], period, c, nodes, weights)


@numba.njit(cache=True, nogil=True)
def _near_pairs(
    pos: NDArray[np.float64],
    a: NDArray[np.float64],
    n_targets: int,
    owner: NDArray[np.int64],
    period: float,
    cells: int,
    near: float,
    mesh_green: NDArray[np.float64],
    c: float,
    nodes: NDArray[np.float64],
    weights: NDArray[np.float64],
) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:  # pragma: no cover
    """CSR list of (target, source) pairs within ``near`` and their correction coefficients.

    Targets are sources 0 … n_targets − 1 (the contacts); the correction replaces the mesh's
    coupling of the pair by the exact one (the self pair by the self coefficient).
    """
    h = period / cells
    start, src, shift_of = _near_lists(pos, n_targets, period, near)
    coef = np.empty(src.size)
    for i in range(n_targets):
        xi = pos[i]
        ci = xi / h
        ia = math.floor(ci)
        fi = ci - ia
        for k in range(start[i], start[i + 1]):
            s = src[k]
            cs = pos[s] / h
            sa = math.floor(cs)
            mesh = _mesh_coupling(ia, fi, sa, cs - sa, mesh_green)
            r = xi - (pos[s] - shift_of[k])
            coef[k] = _exact_pair(i, s, r, a, owner, period, c, nodes, weights) - mesh
    return start, src, coef


@numba.njit(cache=True, nogil=True)
def _mesh_pair(
    d: int, fi: float, fs: float, mesh_green: NDArray[np.float64], mask: int
) -> float:  # pragma: no cover - compiled
    """:func:`_mesh_coupling` for cells ``d`` apart on a mesh of ``mask`` + 1 (a power of two)
    cells."""
    g0 = mesh_green[d & mask]
    gm = mesh_green[(d - 1) & mask]
    gp = mesh_green[(d + 1) & mask]
    return (1.0 - fi) * ((1.0 - fs) * g0 + fs * gm) + fi * ((1.0 - fs) * gp + fs * g0)


@numba.njit(cache=True, nogil=True)
def _dense_coupling(
    pos: NDArray[np.float64],
    a: NDArray[np.float64],
    owner: NDArray[np.int64],
    ez_src: NDArray[np.float64],
    n_targets: int,
    period: float,
    mesh_green: NDArray[np.float64],
    lists: tuple,
    c: float,
    nodes: NDArray[np.float64],
    weights: NDArray[np.float64],
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """The particle–mesh operator of :func:`_near_pairs` as a matrix, transposed.

    K[j, i] = Σ over the sources s of contact j of e_z,s × (mesh coupling of i and s, or the
    exact coupling for the near pairs of ``lists`` = :func:`_near_lists`), so that the mesh field
    of loads P read back with the near corrections (:func:`_gather`) equals Kᵀ P, without the
    FFT (for few contacts). The exact coupling of two contacts is computed once per pair (it is
    symmetric: the punch and Hertz weights are even).
    """
    start, src, shift_of = lists
    cells = mesh_green.size
    h = period / cells
    mask = cells - 1  # cells is a power of two
    n_src = pos.size
    sa = np.empty(n_src, dtype=np.int64)
    fs = np.empty(n_src)
    for s in range(n_src):
        cs = pos[s] / h
        sa[s] = math.floor(cs)
        fs[s] = cs - sa[s]
    out = np.zeros((n_targets, n_targets))
    for s in range(n_src):
        row = out[owner[s]]
        for i in range(n_targets):
            row[i] += ez_src[s] * _mesh_pair(sa[i] - sa[s], fs[i], fs[s], mesh_green, mask)
    pairs = np.full((n_targets, n_targets), np.nan)
    for i in range(n_targets):
        for k in range(start[i], start[i + 1]):
            s = src[k]
            exact = pairs[s, i] if s < n_targets else np.nan
            if math.isnan(exact):
                r = pos[i] - (pos[s] - shift_of[k])
                exact = _exact_pair(i, s, r, a, owner, period, c, nodes, weights)
                if s < n_targets:
                    pairs[i, s] = exact
            mesh = _mesh_pair(sa[i] - sa[s], fs[i], fs[s], mesh_green, mask)
            out[owner[s], i] += ez_src[s] * (exact - mesh)
    return out


@numba.njit(cache=True, nogil=True)
def _deposit(
    pos: NDArray[np.float64], q: NDArray[np.float64], cells: int, h: float
) -> NDArray[np.float64]:  # pragma: no cover
    rho = np.zeros(cells)
    for s in range(pos.size):
        cs = pos[s] / h
        sa = math.floor(cs)
        fs = cs - sa
        rho[sa % cells] += (1.0 - fs) * q[s]
        rho[(sa + 1) % cells] += fs * q[s]
    return rho


@numba.njit(cache=True, nogil=True)
def _gather(
    phi: NDArray[np.float64],
    pos: NDArray[np.float64],
    n_targets: int,
    h: float,
    start: NDArray[np.int64],
    src: NDArray[np.int64],
    coef: NDArray[np.float64],
    q: NDArray[np.float64],
) -> NDArray[np.float64]:  # pragma: no cover
    cells = phi.size
    u = np.empty(n_targets)
    for i in range(n_targets):
        ci = pos[i] / h
        ia = math.floor(ci)
        fi = ci - ia
        value = (1.0 - fi) * phi[ia % cells] + fi * phi[(ia + 1) % cells]
        for k in range(start[i], start[i + 1]):
            value += coef[k] * q[src[k]]
        u[i] = value
    return u


def mesh_kernel(cells: int, period: float, e_star: float) -> NDArray[np.float64]:
    """Mesh Green function [µm per mN/µm] at the offsets of ``cells`` cells over ``period`` [µm].

    The periodic Green function at the cell offsets, minus the mean smoothing h²/6 · G″ of
    linear spreading and reading (each smooths the kernel by h²/12 · G″ on average over the
    positions in a cell); the self cell takes any finite value (near pairs are corrected).
    """
    h = period / cells
    m = np.arange(cells, dtype=np.float64)
    m[0] = 0.5
    green = np.asarray(periodic_green(m * h, period, e_star), dtype=np.float64)
    c = 2.0 / (math.pi * e_star)
    curvature = c * (math.pi / period) ** 2 / np.sin(math.pi * m * h / period) ** 2
    return np.asarray(green - (h**2 / 6.0) * curvature, dtype=np.float64)


@numba.njit(cache=True, nogil=True)
def _spread(
    load: NDArray[np.float64],
    owner: NDArray[np.int64],
    ez_src: NDArray[np.float64],
    pos: NDArray[np.float64],
    cells: int,
    h: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:  # pragma: no cover - compiled
    """Vertical source loads q = e_z P (contacts and images) and their linear mesh spreading."""
    q = np.empty(pos.size)
    for s in range(pos.size):
        q[s] = ez_src[s] * load[owner[s]]
    return q, _deposit(pos, q, cells, h)


@numba.njit(cache=True, nogil=True)
def _collect(
    phi: NDArray[np.float64],
    pos: NDArray[np.float64],
    n: int,
    h: float,
    start: NDArray[np.int64],
    src: NDArray[np.int64],
    coef: NDArray[np.float64],
    q: NDArray[np.float64],
    load: NDArray[np.float64],
    ez: NDArray[np.float64],
    local: float,
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """local·P + e_z (mesh field read back + exact near corrections) at the contacts."""
    u = _gather(phi, pos, n, h, start, src, coef, q)
    for i in range(n):
        u[i] = local * load[i] + ez[i] * u[i]
    return u


@numba.njit(cache=True, nogil=True)
def _pk_direction(
    p: NDArray[np.float64],
    cp: NDArray[np.float64],
    delta: NDArray[np.float64],
    h: NDArray[np.float64],
    t: NDArray[np.float64],
    conjugate: bool,
    g_norm_old: float,
    scale: float,
) -> tuple[float, bool, float]:  # pragma: no cover - compiled
    """Gap h = C P − δ, the largest complementarity violation / scale, and the CG direction t."""
    residual = 0.0
    g_norm = 0.0
    any_loaded = False
    for i in range(p.size):
        h[i] = cp[i] - delta[i]
        if p[i] > 0.0:
            any_loaded = True
            residual = max(residual, abs(h[i]))
            g_norm += h[i] * h[i]
        else:
            residual = max(residual, -h[i])
    beta = g_norm / g_norm_old if conjugate and g_norm_old > 0.0 else 0.0
    for i in range(p.size):
        t[i] = h[i] + beta * t[i] if p[i] > 0.0 else 0.0
    return residual / scale, any_loaded, g_norm


@numba.njit(cache=True, nogil=True)
def _pk_update(
    p: NDArray[np.float64],
    cp: NDArray[np.float64],
    r: NDArray[np.float64],
    t: NDArray[np.float64],
    h: NDArray[np.float64],
    fallback: float,
) -> tuple[bool, bool]:  # pragma: no cover - compiled
    """Step P ← max(P − τ t, 0) (overlapping unloaded contacts get −τ h); returns (conjugate,
    linear) where linear means C P was updated exactly as C P − τ C t."""
    num = 0.0
    den = 0.0
    for i in range(p.size):
        if p[i] > 0.0:
            num += h[i] * t[i]
            den += r[i] * t[i]
    tau = num / den if den > 0.0 else fallback
    conjugate = True
    linear = True
    for i in range(p.size):
        was = p[i] > 0.0
        value = p[i] - tau * t[i]
        if was and value < 0.0:
            value = 0.0
            linear = False
        if not was and h[i] < 0.0:
            value = -tau * h[i]
            conjugate = False
            linear = False
        p[i] = value
    if linear:
        for i in range(p.size):
            cp[i] -= tau * r[i]
    return conjugate, linear
