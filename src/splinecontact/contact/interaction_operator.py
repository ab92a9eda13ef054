"""The contact-level operator of interacting SAD and its constrained solve.

The particle–mesh operator (spreading of each contact's load onto a periodic mesh, FFT
convolution with the mesh kernel, near-field corrections; or, for few contacts, the same
operator as a matrix) and the constrained conjugate gradients of Polonsky & Keer (Wear 231
(1999) 206–219) at contact level, used by the compiled step loop
(:mod:`.interaction_kernel`) and by the contact laws' Newton solve
(:mod:`.interaction_laws`). The mesh convolution is the package's compiled real-FFT
circulant product (``splinecontact._fft.circulant``); the mesh kernel and the transform's
tables of every mesh size are computed on first use and cached in a typed list.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba.typed import List
from numpy.typing import NDArray

from .._fft import CirculantConvolution, circulant
from .halfplane import _collect, _pk_direction, _pk_update, _spread, mesh_kernel

__all__ = ["mesh_cache"]

#: Conjugate-gradient iterations per solve.
_MAX_INNER = 10_000

#: Entries per mesh level in the kernel cache: the mesh kernel, then the arrays of the compiled
#: circulant product on the mesh (:attr:`splinecontact._fft.CirculantConvolution.arguments`,
#: its two integer sizes stored as one array).
_PER_LEVEL = 17

#: Smallest mesh: 2**_MIN_LEVEL cells.
_MIN_LEVEL = 6


def mesh_cache(max_cells: int) -> List:
    """An empty kernel cache for meshes of 64 … ``max_cells`` cells (filled on first use)."""
    levels = int(math.log2(max_cells)) + 1
    cache = List()
    for _ in range(levels * _PER_LEVEL):
        cache.append(np.zeros(0))
    return cache


def _mesh_level(
    cells: int, period: float, e_star: float
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """The arrays of one cache level, concatenated, and their offsets (``_PER_LEVEL`` + 1)."""
    green = mesh_kernel(cells, period, e_star)
    # the mesh kernel is real and even, so its spectrum is real
    product = CirculantConvolution(np.ascontiguousarray(np.fft.rfft(green).real), cells)
    parts = [green]
    for value in product.arguments:
        if isinstance(value, np.ndarray):
            parts.append(value)
        elif len(parts) == 8:  # n1 (n2 follows): one array of both
            parts.append(np.array([product.n1, product.n2], dtype=np.float64))
    offsets = np.zeros(len(parts) + 1, dtype=np.int64)
    offsets[1:] = np.cumsum([part.size for part in parts])
    return np.concatenate(parts).astype(np.float64), offsets


@numba.njit(cache=True)
def _level(cache, cells: int, period: float, e_star: float) -> int:  # pragma: no cover
    """Index of the mesh of ``cells`` cells in ``cache``, computing its kernels on first use.

    The mesh kernel is the periodic Green function at the cell offsets minus the mean
    smoothing h²/6 · G″ of linear spreading and reading (:func:`.halfplane.mesh_kernel`).
    """
    level = 0
    while (1 << level) < cells:
        level += 1
    base = level * _PER_LEVEL
    if cache[base].size == 0:
        with numba.objmode(flat="float64[::1]", offsets="int64[::1]"):
            flat, offsets = _mesh_level(cells, period, e_star)
        for k in range(_PER_LEVEL):
            cache[base + k] = flat[offsets[k] : offsets[k + 1]]
    return base


@numba.njit(cache=True)
def _convolve(
    cache, base: int, rho: NDArray[np.float64]
) -> NDArray[np.float64]:  # pragma: no cover
    """Periodic convolution of the mesh loads with the mesh kernel (compiled real FFT)."""
    phi = np.empty(rho.size)
    dims = cache[base + 8]
    circulant(
        rho, phi, cache[base + 1], cache[base + 2], cache[base + 3], cache[base + 4],
        cache[base + 5], cache[base + 6], cache[base + 7], int(dims[0]), int(dims[1]),
        cache[base + 9], cache[base + 10], cache[base + 11], cache[base + 12],
        cache[base + 13], cache[base + 14], cache[base + 15], cache[base + 16],
    )  # fmt: skip
    return phi


@numba.njit(cache=True)
def _apply(
    cache, base: int, load: NDArray[np.float64], local: float, ez: NDArray[np.float64], op: tuple
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:  # pragma: no cover - compiled
    """(local·P + e_z w(P) at the contacts, the mesh displacement).

    ``op`` = (source positions [µm], their contacts, their e_z, mesh spacing [µm], near-pair
    CSR start, sources and corrections) of the step.
    """
    pos, owner, ez_src, h, start, src, coef = op
    cells = cache[base].size
    q, rho = _spread(load, owner, ez_src, pos, cells, h)
    phi = _convolve(cache, base, rho)
    u = _collect(phi, pos, load.size, h, start, src, coef, q, load, ez, local)
    return u, phi


@numba.njit(cache=True)
def _operate(
    cache, base: int, load: NDArray[np.float64], local: float, ez: NDArray[np.float64], op: tuple
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:  # pragma: no cover - compiled
    """:func:`_apply`, or with the operator as a matrix (``op`` = (the operands of
    :func:`_apply`, Kᵀ of :func:`.halfplane._dense_coupling` or an empty matrix)) the same
    local·P + e_z Kᵀ P without the mesh displacement (empty)."""
    dense = op[7]
    if dense.shape[0] == 0:
        return _apply(cache, base, load, local, ez, op[:7])
    n = load.size
    w = np.zeros(n)
    for k in range(n):
        p = load[k]
        if p != 0.0:
            row = dense[k]
            for i in range(n):
                w[i] += row[i] * p
    for i in range(n):
        w[i] = local * load[i] + ez[i] * w[i]
    return w, np.zeros(0)


@numba.njit(cache=True)
def _pk_solve(
    cache,
    base: int,
    delta: NDArray[np.float64],
    load: NDArray[np.float64],
    tol: float,
    ez: NDArray[np.float64],
    a: NDArray[np.float64],
    period: float,
    c: float,
    op: tuple,
) -> tuple[NDArray[np.float64], int, float, NDArray[np.float64]]:  # pragma: no cover
    """Constrained conjugate gradients (Polonsky–Keer, displacement control) at contact level.

    Finds P ≥ 0 with h = C P − δ ≥ 0 and P·h = 0 (C at frozen widths). C P is updated
    incrementally while the loaded set does not change, and recomputed before convergence is
    declared (``op`` as :func:`_operate`). Returns (P, iterations, residual, mesh displacement
    of P); iterations −1 when the solve did not converge. A converged P was the last load the
    operator was applied to, so the mesh displacement of that application is the surface
    displacement of the step.
    """
    n = delta.size
    scale = delta.max()
    if scale <= 0.0:
        return np.zeros(n), 0, 0.0, np.zeros(0)
    p = np.maximum(load, 0.0)
    t = np.zeros(n)
    h = np.empty(n)
    g_norm_old = 0.0
    conjugate = False
    largest = -np.inf
    for i in range(n):
        self_part = max(c * (math.log(period / (math.pi * a[i])) - 1.5), 0.0)
        largest = max(largest, 2.0 * c + ez[i] ** 2 * self_part)
    fallback = 1.0 / largest
    local = 2.0 * c
    cp, phi = _operate(cache, base, p, local, ez, op)
    exact = True
    residual = np.inf
    for iteration in range(_MAX_INNER + 1):
        residual, any_loaded, g_norm = _pk_direction(
            p, cp, delta, h, t, conjugate, g_norm_old, scale
        )
        if residual <= tol:
            if exact:
                return p, iteration, residual, phi
            cp, phi = _operate(cache, base, p, local, ez, op)
            exact = True
            continue
        if not any_loaded:
            d = np.maximum(-h, 0.0)
            cd, _ = _operate(cache, base, d, local, ez, op)
            curvature = np.dot(d, cd)
            step = np.dot(d, d) / curvature if curvature > 0.0 else fallback
            p = step * d
            conjugate = False
            cp, phi = _operate(cache, base, p, local, ez, op)
            exact = True
            continue
        g_norm_old = g_norm
        r, _ = _operate(cache, base, t, local, ez, op)
        conjugate, linear = _pk_update(p, cp, r, t, h, fallback)
        if not linear:
            cp, phi = _operate(cache, base, p, local, ez, op)
        exact = not linear
    return p, -1, residual, phi
