"""The chunk loop of a streamed realization (:mod:`.streamed`): windowed spline fits, the
placement's candidates and the surface statistics, in buffers reused from chunk to chunk.

The spline margin: eq. 2's minimiser is a global banded solve whose response to a change of
one value decays like ρ^d at d points, ρ the largest root inside the unit circle of the
characteristic polynomial λ'r⁴ + (1/6 − 4λ')r³ + (2/3 + 6λ')r² + (1/6 − 4λ')r + λ' of the
system (λ' = λ/dx³). A window that extends :func:`margin_points` past each side of its chunk
fits the chunk as the whole profile's fit does, to round-off.
"""

from __future__ import annotations

import math
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Protocol

import numba
import numpy as np
from numpy.typing import NDArray

from ..generate import _BLOCK
from ..spline import _reinsch_uniform

__all__ = ["margin_points"]


class Heights(Protocol):
    """Heights [µm] of one body for grid indices [start, start + out.size)."""

    mean: float

    def fill(self, out: NDArray[np.float64], start: int) -> NDArray[np.float64]: ...


#: A fit on a window agrees with the global fit to this fraction of the data's scale.
_MARGIN_TOLERANCE = 2.0**-60

_FLAGS = {"reassoc", "nsz"}  # as contact.geometry._place_bodies


def _decay_rate(lam_grid: float) -> float:
    """ρ: the largest modulus < 1 of the roots of the spline system's characteristic polynomial."""
    a = 2.0 / 3.0 + 6.0 * lam_grid
    b = 1.0 / 6.0 - 4.0 * lam_grid
    roots = np.roots([lam_grid, b, a, b, lam_grid]) if lam_grid > 0 else np.roots([b, a, b])
    inside = [abs(r) for r in roots if abs(r) < 1.0]
    return float(max(inside))


def margin_points(lam_grid: float) -> int:
    """Points a spline window extends past its chunk for the fit to equal the global one.

    Parameters
    ----------
    lam_grid : float
        Smoothing weight in grid units λ/dx³ [1] (eqs. 2–3).

    Returns
    -------
    int
        The smallest m with ρ^m (1 + 16 λ') ≤ 2⁻⁶⁰ (ρ from :func:`_decay_rate`): a boundary
        condition's effect on γ decays like ρ^d, and f = z − λ'Qγ multiplies it by up to 16 λ'.
        At the paper's grid (λ' = 1000, ρ = 0.882) that is 382 points.
    """
    rho = _decay_rate(lam_grid)
    return max(8, math.ceil(math.log(_MARGIN_TOLERANCE / (1.0 + 16.0 * lam_grid)) / math.log(rho)))


def _rounded(points: int) -> int:
    return -(-points // _BLOCK) * _BLOCK


# --- one chunk --------------------------------------------------------------------------------


@numba.njit(cache=True, nogil=True, fastmath=_FLAGS)
def _body_sums(
    z: NDArray[np.float64],
    slope: NDArray[np.float64],
    lo: int,
    hi: int,
    first_diff: int,
    mean: float,
    dx: float,
    sums: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    """Add Σ|z − mean|, Σ(z − mean)², Σ((z_i − z_{i−1})/dx)² (i ≥ first_diff), Σ f′² over
    the window's points [lo, hi) to ``sums[0:4]``."""
    a = q = d = s = 0.0
    part = z[lo:hi]  # slices: indices known non-negative, so the loops vectorise
    part_slope = slope[lo:hi]
    for i in range(part.size):
        v = part[i] - mean
        a += abs(v)
        q += v * v
        s += part_slope[i] * part_slope[i]
    here = z[first_diff:hi]
    before = z[first_diff - 1 : hi - 1]
    for i in range(here.size):
        step = (here[i] - before[i]) / dx
        d += step * step
    sums[0] += a
    sums[1] += q
    sums[2] += d
    sums[3] += s


@numba.njit(cache=True, nogil=True, fastmath=_FLAGS)
def _pair_chunk(
    z_l: NDArray[np.float64],
    z_u: NDArray[np.float64],
    f_l: NDArray[np.float64],
    f_u: NDArray[np.float64],
    s_l: NDArray[np.float64],
    s_u: NDArray[np.float64],
    flat: bool,
    lo: int,
    hi: int,
    first_diff: int,
    dx: float,
    highest: float,
    limit: float,
    reference: float,
    sums: NDArray[np.float64],
    keep: NDArray[np.int64],
) -> tuple[float, int]:  # pragma: no cover - compiled
    """One chunk of the placement (points [lo, hi) of the window).

    Returns the highest f^u + f^l so far and the number of points written to ``keep`` (window
    indices) whose f^u + f^l is within ``limit`` (+ rounding) of it. Adds to ``sums``:
    Σ(f^u + f^l − reference), Σ((Δ(z^u + z^l))/dx)², Σ(f′^u + f′^l)².
    """
    lower = f_l[lo:hi]
    upper = lower if flat else f_u[lo:hi]
    total_sum = 0.0
    for i in range(lower.size):
        total = lower[i] if flat else upper[i] + lower[i]
        highest = max(highest, total)
        total_sum += total - reference
    sums[0] += total_sum
    bound = highest - limit - 1e-12 * (abs(highest) + limit)  # keeps every final candidate
    count = 0
    for i in range(lower.size):
        total = lower[i] if flat else upper[i] + lower[i]
        if total >= bound:
            keep[count] = lo + i
            count += 1
    if not flat:
        d = 0.0
        here_l, here_u = z_l[first_diff:hi], z_u[first_diff:hi]
        before_l, before_u = z_l[first_diff - 1 : hi - 1], z_u[first_diff - 1 : hi - 1]
        for i in range(here_l.size):
            step = ((here_l[i] + here_u[i]) - (before_l[i] + before_u[i])) / dx
            d += step * step
        q = 0.0
        slope_l, slope_u = s_l[lo:hi], s_u[lo:hi]
        for i in range(slope_l.size):
            v = slope_l[i] + slope_u[i]
            q += v * v
        sums[1] += d
        sums[2] += q
    return highest, count


@numba.njit(cache=True, nogil=True, fastmath=_FLAGS)
def _final_gaps(
    offset: float, f_l: NDArray[np.float64], f_u: NDArray[np.float64], flat: bool
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """offset − (f^u + f^l), as :func:`.geometry._place_bodies` forms the gap."""
    out = np.empty(f_l.size)
    for i in range(f_l.size):
        out[i] = offset - ((0.0 if flat else f_u[i]) + f_l[i])
    return out


class _Body:
    """Buffers of one body's window (heights, f, f′, f″), reused across chunks."""

    def __init__(self, heights: Heights, size: int) -> None:
        self.heights = heights
        self.z_buffer = np.empty(size)
        self.f = np.empty(size)
        self.slope = np.empty(size)
        self.second = np.empty(size)
        self.z = self.z_buffer
        self.sums = np.zeros(4)
        self.high, self.low = -math.inf, math.inf

    def fit(
        self, start: int, stop: int, lam_grid: float, dx: float, own: tuple[int, int, int]
    ) -> None:
        """Heights and fit of the window [start, stop); the sums of its own points
        ``own`` = (lo, hi, first_diff), window indices."""
        width = stop - start
        self.z = self.heights.fill(self.z_buffer[:width], start)
        _reinsch_uniform(
            self.z, lam_grid, dx, dx * dx, self.f[:width], self.slope[:width], self.second[:width]
        )
        self._reduce(*own, dx)

    def _reduce(self, lo: int, hi: int, first_diff: int, dx: float) -> None:
        _body_sums(self.z, self.slope, lo, hi, first_diff, self.heights.mean, dx, self.sums)
        part = self.z[lo:hi]
        self.high, self.low = max(self.high, float(part.max())), min(self.low, float(part.min()))


def _stream(
    lower: Heights,
    upper: Heights | None,
    n: int,
    dx: float,
    lam_grid: float,
    limit: float,
    chunk: int,
) -> tuple[dict[str, NDArray[Any]], float, float, dict[str, float]]:
    """Fit both bodies chunk by chunk; keep the points that may close.

    Returns the kept points' arrays (grid index, f^l, f^u, f′ and f″ of both bodies), the
    placement offset (highest f^u + f^l) [µm], the mean gap at δ_N = 0 [µm] and the surface
    statistics.
    """
    flat = upper is None
    margin = _rounded(margin_points(lam_grid))
    size = min(n, chunk + 2 * margin)
    bodies = [_Body(lower, size)] + ([] if upper is None else [_Body(upper, size)])
    keep = np.empty(chunk, dtype=np.int64)
    kept: list[tuple[NDArray[Any], ...]] = []
    pair_sums = np.zeros(3)
    highest = -math.inf
    reference = math.nan  # f^u + f^l at the first point: the sum of the totals is about it
    pool = ThreadPoolExecutor(max_workers=2) if len(bodies) == 2 and n >= 2 * chunk else None
    try:
        for start in range(0, n, chunk):
            stop = min(start + chunk, n)
            w0, w1 = max(0, start - margin), min(n, stop + margin)
            lo, hi = start - w0, stop - w0
            first_diff = lo if start > 0 else lo + 1
            own = (lo, hi, first_diff)
            if pool is None:
                for body in bodies:
                    body.fit(w0, w1, lam_grid, dx, own)
            else:  # the two bodies on two threads (the kernels release the GIL)
                for future in [pool.submit(b.fit, w0, w1, lam_grid, dx, own) for b in bodies]:
                    future.result()
            bl, bu = bodies[0], bodies[-1]
            if start == 0:
                reference = float(bl.f[0] if flat else bu.f[0] + bl.f[0])
            highest, count = _pair_chunk(
                bl.z, bu.z, bl.f, bu.f, bl.slope, bu.slope, flat, lo, hi, first_diff, dx,
                highest, limit, reference, pair_sums, keep,
            )  # fmt: skip
            at = keep[:count]
            kept.append(
                (at + w0, bl.f[at], bu.f[at], bl.slope[at], bl.second[at], bu.slope[at],
                 bu.second[at])
            )  # fmt: skip
    finally:
        if pool is not None:
            pool.shutdown()
    names = ("point", "f_l", "f_u", "slope_l", "second_l", "slope_u", "second_u")
    columns = {name: np.concatenate([k[i] for k in kept]) for i, name in enumerate(names)}
    mean_gap0 = (highest - reference) - pair_sums[0] / n
    return columns, highest, mean_gap0, _statistics(bodies, pair_sums, n, flat)


def _statistics(
    bodies: list[_Body], pair_sums: NDArray[np.float64], n: int, flat: bool
) -> dict[str, float]:
    """The scalars of :func:`splinecontact.profile.surface_statistics` from the chunk sums."""
    low = bodies[0]
    stats = {
        "ra_lower": float(low.sums[0] / n),
        "rq_lower": float(np.sqrt(low.sums[1] / n)),
        "peak_to_valley_lower": float(low.high - low.low),
        "rsq_lower": float(np.sqrt(low.sums[2] / (n - 1))),
        "rsq_lower_spline": float(np.sqrt(low.sums[3] / n)),
    }
    if flat:
        stats.update(ra_upper=0.0, rq_upper=0.0, rsq_upper=0.0, rsq_upper_spline=0.0)
        stats.update(rsq_gap=stats["rsq_lower"], rsq_gap_spline=stats["rsq_lower_spline"])
        return stats
    up = bodies[1]
    stats.update(
        ra_upper=float(up.sums[0] / n),
        rq_upper=float(np.sqrt(up.sums[1] / n)),
        rsq_upper=float(np.sqrt(up.sums[2] / (n - 1))),
        rsq_upper_spline=float(np.sqrt(up.sums[3] / n)),
        rsq_gap=float(np.sqrt(pair_sums[1] / (n - 1))),
        rsq_gap_spline=float(np.sqrt(pair_sums[2] / n)),
    )
    return stats
