"""The boundary element solver's load-control loop as it was before the fused kernels.

Kept verbatim (plain numpy, an FFT pair per operator application) as the reference that
``tests/test_bem.py`` compares the production solver against: same iteration counts, contact
sets and mean gaps.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft
from numpy.typing import NDArray

from splinecontact.bem import ContactProblem, _initial_guess
from splinecontact.errors import NoConvergenceError


def _apply(response: NDArray[np.float64], values: NDArray[np.float64]) -> NDArray[np.float64]:
    return np.asarray(sfft.irfft(response * sfft.rfft(values), values.size), dtype=np.float64)


def _diagonal(response: NDArray[np.float64], n: int) -> float:
    """Diagonal element of the (circulant) influence matrix [µm/GPa]."""
    full = 2.0 * response[1:].sum()
    if n % 2 == 0:
        full -= response[-1]
    return float(full / n)


@dataclass
class _Solution:
    pressure: NDArray[np.float64]
    gap: NDArray[np.float64]
    separation: float
    iterations: int
    residual: float


def _dot(a: NDArray[np.float64], b: NDArray[np.float64]) -> float:
    """Scalar product without BLAS (threaded BLAS costs milliseconds per call on busy cores)."""
    return float(np.multiply(a, b).sum())


def pk_load(
    problem: ContactProblem,
    mean_pressure: float,
    initial: NDArray[np.float64],
    tol: float,
    max_iterations: int,
) -> _Solution:
    """Polonsky–Keer constrained conjugate gradients at fixed mean pressure."""
    z = problem.heights
    lam = problem.response
    n = z.size
    scale = problem.rms_height
    tau_fallback = 1.0 / _diagonal(lam, n)
    p = initial * (mean_pressure / initial.mean())
    t = np.zeros(n)
    g_norm_old = 0.0
    conjugate = False
    residual = np.inf
    for iteration in range(max_iterations + 1):
        g = _apply(lam, p)
        g -= z
        loaded = p > 0.0
        mask = loaded.astype(np.float64)
        count = float(mask.sum())
        separation = -_dot(g, mask) / count
        g += separation
        g_loaded = g * mask
        free_overlap = -min(float(np.where(loaded, 0.0, g).min()), 0.0)
        residual = max(float(np.abs(g_loaded).max()), free_overlap) / scale
        if residual <= tol:
            return _Solution(p, g, separation, iteration, residual)
        if iteration == max_iterations:
            break
        g_norm = _dot(g_loaded, g_loaded)
        if conjugate and g_norm_old > 0.0:
            t *= g_norm / g_norm_old
            t += g_loaded
            t *= mask
        else:
            t = g_loaded.copy()
        g_norm_old = g_norm
        r = _apply(lam, t)
        # Σ_loaded (r − mean_loaded r)·t, with t = 0 off the contact
        denominator = _dot(r, t) - _dot(r, mask) / count * float(t.sum())
        tau = _dot(g_loaded, t) / denominator if denominator > 0.0 else tau_fallback
        p -= tau * t
        np.maximum(p, 0.0, out=p)
        overlap = (p == 0.0) & (g < 0.0)
        if overlap.any():
            conjugate = False
            p[overlap] = -tau * g[overlap]
        else:
            conjugate = True
        total = float(p.sum())
        if total <= 0.0:  # every node was released: restart at the deepest overlap
            p[np.argmin(g)] = 1.0
            total = 1.0
            conjugate = False
        p *= mean_pressure * n / total
    raise NoConvergenceError(
        f"load control at mean pressure {mean_pressure:.6g} GPa did not converge in "
        f"{max_iterations} iterations (residual {residual:.3g} > tol {tol:.3g}); raise "
        "max_iterations or tol, or approach this load in smaller steps (load_path)"
    )


def legacy_load_path(
    problem: ContactProblem, loads: NDArray[np.float64], tol: float
) -> list[_Solution]:
    """``bem.load_path`` with the legacy loop: each step warm-started from the previous one."""
    solutions: list[_Solution] = []
    previous: NDArray[np.float64] | None = None
    for load in loads:
        guess = previous
        if guess is None or not np.any(guess > 0.0):
            guess = _initial_guess(problem, float(load))
        else:
            guess = np.clip(guess, 0.0, None)
        sol = pk_load(problem, float(load), guess, tol, 100_000)
        previous = sol.pressure
        solutions.append(sol)
    return solutions
