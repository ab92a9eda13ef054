"""The elastic half-plane at contact level: Green function, pair coefficients, fast operator.

The periodic plane-strain Green function of a line load (the kernel of :mod:`splinecontact.bem`
summed in closed form), the coupling coefficients of Hertzian contacts (flat-punch averages,
Barber's reciprocal argument), the particle–mesh operator C P = 2c P + e_z w(P) and the
constrained conjugate gradients (Polonsky & Keer, Wear 231 (1999) 206–219) that solve the
unilateral contact problem at contact level. Used by :mod:`.interaction`.
"""

from __future__ import annotations

import math
from typing import Any

import numba
import numpy as np
import scipy.fft as sfft
from numpy.typing import NDArray

from ..errors import NoConvergenceError

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

#: Conjugate-gradient iterations per solve.
_MAX_INNER = 10_000


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
        mean_log = math.log(t) - 0.1875 * (a_t * a_t + a_s * a_s) / (t * t)
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
    order = np.argsort(pos)
    sorted_pos = pos[order]
    h = period / cells
    start = np.zeros(n_targets + 1, dtype=np.int64)
    # first pass: count
    for i in range(n_targets):
        cnt = 0
        for shift in (-period, 0.0, period):
            lo = np.searchsorted(sorted_pos, pos[i] + shift - near, side="left")
            hi = np.searchsorted(sorted_pos, pos[i] + shift + near, side="right")
            cnt += hi - lo
        start[i + 1] = start[i] + cnt
    nnz = start[n_targets]
    src = np.empty(nnz, dtype=np.int64)
    coef = np.empty(nnz)
    for i in range(n_targets):
        k = start[i]
        xi = pos[i]
        ci = xi / h
        ia = math.floor(ci)
        fi = ci - ia
        for shift in (-period, 0.0, period):
            lo = np.searchsorted(sorted_pos, xi + shift - near, side="left")
            hi = np.searchsorted(sorted_pos, xi + shift + near, side="right")
            for q in range(lo, hi):
                s = order[q]
                src[k] = s
                # mesh coupling of the pair (linear weights at both ends)
                cs = pos[s] / h
                sa = math.floor(cs)
                fs = cs - sa
                mesh = 0.0
                for da in range(2):
                    wa = fi if da == 1 else 1.0 - fi
                    for db in range(2):
                        wb = fs if db == 1 else 1.0 - fs
                        mesh += wa * wb * mesh_green[(ia + da - sa - db) % cells]
                if s == i:
                    exact = c * (math.log(period / (math.pi * a[i])) - 1.5)
                else:
                    r = xi - (pos[s] - shift)
                    if owner[s] == i:  # own mirror image
                        exact = _pair(r, a[i], a[i], period, c, nodes, weights)
                    else:
                        exact = _pair(r, a[i], a[s], period, c, nodes, weights)
                coef[k] = exact - mesh
                k += 1
    return start, src, coef


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


class _Operator:
    """Displacement at the contacts caused by contact loads: mesh far field + exact near field."""

    def __init__(
        self,
        period: float,
        cells: int | None,
        e_star: float,
        mirror: bool,
        length_nodes: int,
        dx: float,
    ) -> None:
        self.period = period
        self.fixed_cells = cells
        self.e_star = e_star
        self.c = 2.0 / (math.pi * e_star)
        self.mirror = mirror
        self.mirror_axis = (2 * length_nodes - 1) * dx
        self.max_cells = max(64, 1 << math.ceil(math.log2(max(2 * length_nodes, 2))))
        self.nodes, self.weights = _quadrature()
        self._meshes: dict[int, tuple[NDArray[np.float64], NDArray[np.complex128]]] = {}
        self._use(cells if cells is not None else 64)

    def _use(self, cells: int) -> None:
        """Switch to a mesh of ``cells`` cells (kernels cached per size)."""
        if cells not in self._meshes:
            mesh_green = mesh_kernel(cells, self.period, self.e_star)
            self._meshes[cells] = (mesh_green, sfft.rfft(mesh_green))
        self.cells = cells
        self.h = self.period / cells
        self.mesh_green, self.spectrum = self._meshes[cells]

    def prepare(
        self, x: NDArray[np.float64], a: NDArray[np.float64], ez: NDArray[np.float64]
    ) -> None:
        n = x.size
        self.n = n
        if self.fixed_cells is None:
            # about CELLS_PER_SOURCE cells per load (contacts and images): the mesh follows the
            # number of contacts, not the number of grid points
            sources = 2 * n if self.mirror else n
            wanted = 1 << math.ceil(math.log2(max(CELLS_PER_SOURCE * sources, 64)))
            self._use(min(wanted, self.max_cells))
        if self.mirror:
            self.pos = np.concatenate([x, self.mirror_axis - x])
            self.a = np.concatenate([a, a])
            self.owner = np.concatenate([np.arange(n), np.arange(n)]).astype(np.int64)
            self.ez_src = np.concatenate([ez, ez])
        else:
            self.pos = x.copy()
            self.a = a.copy()
            self.owner = np.arange(n, dtype=np.int64)
            self.ez_src = ez.copy()
        self.pos = np.mod(self.pos, self.period)
        self.ez = ez
        largest = float(a.max()) if a.size else 0.0
        near = min(max(NEAR_CELLS * self.h, NEAR_WIDTHS * largest), 0.25 * self.period)
        self.start, self.src, self.coef = _near_pairs(
            self.pos,
            self.a,
            n,
            self.owner,
            self.period,
            self.cells,
            near,
            self.mesh_green,
            self.c,
            self.nodes,
            self.weights,
        )

    def displacement(self, load: NDArray[np.float64]) -> NDArray[np.float64]:
        """w_i: vertical displacement at every contact (own far part included) from loads P."""
        return self._apply(load, 0.0, np.ones(self.n))

    def apply(self, load: NDArray[np.float64]) -> NDArray[np.float64]:
        """Total compliance C P = 2c P + e_z w(P) (SAD's local law plus the coupling)."""
        return self._apply(load, 2.0 * self.c, self.ez)

    def _apply(
        self, load: NDArray[np.float64], local: float, ez: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        q, rho = _spread(load, self.owner, self.ez_src, self.pos, self.cells, self.h)
        phi = np.asarray(sfft.irfft(self.spectrum * sfft.rfft(rho), self.cells), dtype=np.float64)
        self.phi = phi
        return _collect(
            phi, self.pos, self.n, self.h, self.start, self.src, self.coef, q, load, ez, local
        )


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


def _pk_solve(
    op: _Operator, delta: NDArray[np.float64], load: NDArray[np.float64], tol: float
) -> tuple[NDArray[np.float64], int]:
    """Constrained conjugate gradients (Polonsky–Keer, displacement control) at contact level.

    Finds P ≥ 0 with h = C P − δ ≥ 0 and P·h = 0 (C at frozen widths). C P is updated
    incrementally while the loaded set does not change, and recomputed before convergence is
    declared.
    """
    scale = float(delta.max())
    if scale <= 0.0:
        return np.zeros_like(delta), 0
    p = np.clip(load, 0.0, None)
    t = np.zeros_like(p)
    h = np.empty_like(p)
    g_norm_old = 0.0
    conjugate = False
    self_part = np.maximum(op.c * (np.log(op.period / (np.pi * op.a[: op.n])) - 1.5), 0.0)
    fallback = float(1.0 / np.max(2.0 * op.c + op.ez**2 * self_part))
    cp = op.apply(p)
    exact = True
    residual = math.inf
    for iteration in range(_MAX_INNER + 1):
        residual, any_loaded, g_norm = _pk_direction(
            p, cp, delta, h, t, conjugate, g_norm_old, scale
        )
        if residual <= tol:
            if exact:
                return p, iteration
            cp = op.apply(p)
            exact = True
            continue
        if not any_loaded:
            # nothing loaded: exact line search along the overlap −h
            d = np.clip(-h, 0.0, None)
            cd = op.apply(d)
            curvature = float(d @ cd)
            step = float(d @ d) / curvature if curvature > 0.0 else fallback
            p = step * d
            conjugate = False
            cp = op.apply(p)
            exact = True
            continue
        g_norm_old = g_norm
        r = op.apply(t)
        conjugate, linear = _pk_update(p, cp, r, t, h, fallback)
        if not linear:
            cp = op.apply(p)
        exact = not linear
    raise NoConvergenceError(
        f"the interacting contact solve did not converge in {_MAX_INNER} iterations (residual "
        f"{residual:.3g} > tol {tol:.3g}); raise tol or use more steps"
    )
