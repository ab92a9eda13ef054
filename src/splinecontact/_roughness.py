"""Compiled single-pass sums behind the roughness parameters of :mod:`splinecontact.profile`.

One pass per quantity instead of numpy's chain of temporaries (z − mean, its absolute value or
square, the mean; a difference array, divided, squared, averaged). Sums run in blocks of
``_BLOCK`` values (vectorised partial sums inside a block, then block sums added in order), so
their rounding is of numpy's pairwise-summation kind, O(ε·(block + n/block)).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

import numba
import numpy as np
from numpy.typing import NDArray

__all__ = ["deviation_sums", "difference_square_sum", "mean_abs_about", "square_sum", "total"]

_BLOCK = 1024
_FLAGS = {"reassoc", "nsz"}


@numba.njit(cache=True, nogil=True, fastmath=_FLAGS)
def total(z: NDArray[np.float64]) -> float:  # pragma: no cover - compiled
    """Σ z."""
    result = 0.0
    for start in range(0, z.size, _BLOCK):
        part = z[start : start + _BLOCK]
        block = 0.0
        for i in range(part.size):
            block += part[i]
        result += block
    return result


@numba.njit(cache=True, nogil=True, fastmath=_FLAGS)
def deviation_sums(z: NDArray[np.float64], mean: float) -> tuple[float, float]:  # pragma: no cover
    """Σ |z − mean| and Σ (z − mean)²."""
    absolute = 0.0
    squared = 0.0
    for start in range(0, z.size, _BLOCK):
        part = z[start : start + _BLOCK]
        block_abs = 0.0
        block_sq = 0.0
        for i in range(part.size):
            d = part[i] - mean
            block_abs += abs(d)
            block_sq += d * d
        absolute += block_abs
        squared += block_sq
    return absolute, squared


@numba.njit(cache=True, nogil=True, fastmath=_FLAGS)
def difference_square_sum(
    a: NDArray[np.float64], b: NDArray[np.float64], use_b: bool, dx: float
) -> float:  # pragma: no cover - compiled
    """Σ_i (((a + b)_i − (a + b)_{i−1}) / dx)² over i ≥ 1 (b ignored unless ``use_b``)."""
    result = 0.0
    n = a.size
    for start in range(1, n, _BLOCK):
        stop = min(start + _BLOCK, n)
        here_a = a[start:stop]
        before_a = a[start - 1 : stop - 1]
        here_b = b[start:stop] if use_b else here_a
        before_b = b[start - 1 : stop - 1] if use_b else before_a
        block = 0.0
        if use_b:
            for i in range(here_a.size):
                step = ((here_a[i] + here_b[i]) - (before_a[i] + before_b[i])) / dx
                block += step * step
        else:
            for i in range(here_a.size):
                step = (here_a[i] - before_a[i]) / dx
                block += step * step
        result += block
    return result


@numba.njit(cache=True, nogil=True, fastmath=_FLAGS)
def square_sum(
    a: NDArray[np.float64], b: NDArray[np.float64], use_b: bool
) -> float:  # pragma: no cover - compiled
    """Σ (a + b)² (b ignored unless ``use_b``)."""
    result = 0.0
    for start in range(0, a.size, _BLOCK):
        part_a = a[start : start + _BLOCK]
        part_b = b[start : start + _BLOCK] if use_b else part_a
        block = 0.0
        if use_b:
            for i in range(part_a.size):
                s = part_a[i] + part_b[i]
                block += s * s
        else:
            for i in range(part_a.size):
                block += part_a[i] * part_a[i]
        result += block
    return result


#: Largest |r| / mean |z| for which mean |z| stands for mean |z − r| (they differ by ≤ |r|).
_RESIDUAL_TOLERANCE = 1e-13


def mean_abs_about(
    mean_abs: float,
    residual_mean: float,
    chunks: Callable[[], Iterable[NDArray[np.float64]]],
) -> float:
    """mean |z − r| [µm] of heights whose mean |z| [µm] and residual mean r [µm] are known.

    The generator's closed-form mean of eq. 1 leaves a residual r of rounding size, so mean |z|
    is R_A's mean |z − r| to |r|. Where every term is much longer than the profile (nearly
    constant heights) r is not negligible against mean |z|: then the heights, given chunk by
    chunk by ``chunks()``, are summed again about r.
    """
    if abs(residual_mean) <= _RESIDUAL_TOLERANCE * mean_abs:
        return mean_abs
    total_abs = 0.0
    count = 0
    for part in chunks():
        total_abs += float(deviation_sums(part, residual_mean)[0])
        count += part.size
    return total_abs / count
