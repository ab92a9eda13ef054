"""The Stockham stages of the compiled FFT: batches of short complex transforms.

Radix 2, 3, 4 and 5 (decimation in frequency, self-sorting), each an unrolled butterfly whose
innermost loop runs over the contiguous batch index, so that every butterfly is a vector
operation; :func:`_batched_fft` chains them for lengths 2^a·3^b·5^c. The stages share the
views of their legs (:func:`_legs`) and the twiddle product (:func:`rotate`).
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

__all__ = ["_batched_fft", "rotate"]

_Views = tuple[
    NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
    NDArray[np.float64],
]  # fmt: skip


@numba.njit(cache=True, nogil=True, fastmath=True, inline="always")
def rotate(re: float, im: float, c: float, d: float) -> tuple[float, float]:  # pragma: no cover
    """(re + i·im)·(c + i·d): a value times a twiddle factor, as two reals."""
    return re * c - im * d, re * d + im * c


@numba.njit(cache=True, nogil=True, fastmath=True, inline="always")
def _legs(
    x: NDArray[np.float64], start: int, step: int, batch: int
) -> _Views:  # pragma: no cover - compiled
    """The ``batch`` contiguous values at start + k·step for k = 0 … 4 (the legs of a
    butterfly; a stage of radix r < 5 leaves the last 5 − r unused, slices clamp at the end)."""
    return (
        x[start : start + batch],
        x[start + step : start + step + batch],
        x[start + 2 * step : start + 2 * step + batch],
        x[start + 3 * step : start + 3 * step + batch],
        x[start + 4 * step : start + 4 * step + batch],
    )


@numba.njit(cache=True, nogil=True, fastmath=True)
def _stage(
    xr: NDArray[np.float64],
    xi: NDArray[np.float64],
    yr: NDArray[np.float64],
    yi: NDArray[np.float64],
    m: int,
    s: int,
    batch: int,
    stride: int,
    wr: NDArray[np.float64],
    wi: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    """One radix-2 Stockham stage: sub-transforms of 2m points, stride s rows, into y."""
    for p in range(m):
        c = wr[p * s]
        d = wi[p * s]
        for q in range(s):
            i0 = (q + s * p) * stride
            o0 = (q + s * 2 * p) * stride
            ar, br, _, _, _ = _legs(xr, i0, s * m * stride, batch)
            ai, bi, _, _, _ = _legs(xi, i0, s * m * stride, batch)
            sr, dr, _, _, _ = _legs(yr, o0, s * stride, batch)
            si, di, _, _, _ = _legs(yi, o0, s * stride, batch)
            for b in range(batch):
                sr[b] = ar[b] + br[b]
                si[b] = ai[b] + bi[b]
                dr[b], di[b] = rotate(ar[b] - br[b], ai[b] - bi[b], c, d)


@numba.njit(cache=True, nogil=True, fastmath=True)
def _stage4(
    xr: NDArray[np.float64],
    xi: NDArray[np.float64],
    yr: NDArray[np.float64],
    yi: NDArray[np.float64],
    m: int,
    s: int,
    batch: int,
    stride: int,
    wr: NDArray[np.float64],
    wi: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    """One radix-4 Stockham stage: sub-transforms of 4m points, stride s rows, into y."""
    for p in range(m):
        c1 = wr[p * s]
        d1 = wi[p * s]
        c2 = wr[2 * p * s]
        d2 = wi[2 * p * s]
        c3 = wr[3 * p * s]
        d3 = wi[3 * p * s]
        for q in range(s):
            i0 = (q + s * p) * stride
            o0 = (q + s * 4 * p) * stride
            ar, br, cr, dr, _ = _legs(xr, i0, s * m * stride, batch)
            ai, bi, ci, di, _ = _legs(xi, i0, s * m * stride, batch)
            y0r, y1r, y2r, y3r, _ = _legs(yr, o0, s * stride, batch)
            y0i, y1i, y2i, y3i, _ = _legs(yi, o0, s * stride, batch)
            for b in range(batch):
                apcr = ar[b] + cr[b]
                apci = ai[b] + ci[b]
                amcr = ar[b] - cr[b]
                amci = ai[b] - ci[b]
                bpdr = br[b] + dr[b]
                bpdi = bi[b] + di[b]
                bmdr = br[b] - dr[b]
                bmdi = bi[b] - di[b]
                y0r[b] = apcr + bpdr
                y0i[b] = apci + bpdi
                # (a − c) ∓ i(b − d)
                y1r[b], y1i[b] = rotate(amcr + bmdi, amci - bmdr, c1, d1)
                y2r[b], y2i[b] = rotate(apcr - bpdr, apci - bpdi, c2, d2)
                y3r[b], y3i[b] = rotate(amcr - bmdi, amci + bmdr, c3, d3)


@numba.njit(cache=True, nogil=True, fastmath=True)
def _stage5(
    xr: NDArray[np.float64],
    xi: NDArray[np.float64],
    yr: NDArray[np.float64],
    yi: NDArray[np.float64],
    m: int,
    s: int,
    batch: int,
    stride: int,
    wr: NDArray[np.float64],
    wi: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    """One radix-5 Stockham stage: sub-transforms of 5m points, stride s rows, into y."""
    c1 = math.cos(0.4 * math.pi)
    c2 = math.cos(0.8 * math.pi)
    s1 = math.sin(0.4 * math.pi)
    s2 = math.sin(0.8 * math.pi)
    for p in range(m):
        w1r = wr[p * s]
        w1i = wi[p * s]
        w2r = wr[2 * p * s]
        w2i = wi[2 * p * s]
        w3r = wr[3 * p * s]
        w3i = wi[3 * p * s]
        w4r = wr[4 * p * s]
        w4i = wi[4 * p * s]
        for q in range(s):
            i0 = (q + s * p) * stride
            o0 = (q + s * 5 * p) * stride
            x0r, x1r, x2r, x3r, x4r = _legs(xr, i0, s * m * stride, batch)
            x0i, x1i, x2i, x3i, x4i = _legs(xi, i0, s * m * stride, batch)
            y0r, y1r, y2r, y3r, y4r = _legs(yr, o0, s * stride, batch)
            y0i, y1i, y2i, y3i, y4i = _legs(yi, o0, s * stride, batch)
            for b in range(batch):
                # t1 = x1 + x4, t2 = x2 + x3, t3 = x1 − x4, t4 = x2 − x3
                t1r = x1r[b] + x4r[b]
                t1i = x1i[b] + x4i[b]
                t2r = x2r[b] + x3r[b]
                t2i = x2i[b] + x3i[b]
                t3r = x1r[b] - x4r[b]
                t3i = x1i[b] - x4i[b]
                t4r = x2r[b] - x3r[b]
                t4i = x2i[b] - x3i[b]
                y0r[b] = x0r[b] + t1r + t2r
                y0i[b] = x0i[b] + t1i + t2i
                # y1, y4 = a1 ∓ i·b1 and y2, y3 = a2 ∓ i·b2
                a1r = x0r[b] + c1 * t1r + c2 * t2r
                a1i = x0i[b] + c1 * t1i + c2 * t2i
                a2r = x0r[b] + c2 * t1r + c1 * t2r
                a2i = x0i[b] + c2 * t1i + c1 * t2i
                b1r = s1 * t3r + s2 * t4r
                b1i = s1 * t3i + s2 * t4i
                b2r = s2 * t3r - s1 * t4r
                b2i = s2 * t3i - s1 * t4i
                y1r[b], y1i[b] = rotate(a1r + b1i, a1i - b1r, w1r, w1i)
                y2r[b], y2i[b] = rotate(a2r + b2i, a2i - b2r, w2r, w2i)
                y3r[b], y3i[b] = rotate(a2r - b2i, a2i + b2r, w3r, w3i)
                y4r[b], y4i[b] = rotate(a1r - b1i, a1i + b1r, w4r, w4i)


@numba.njit(cache=True, nogil=True, fastmath=True)
def _stage3(
    xr: NDArray[np.float64],
    xi: NDArray[np.float64],
    yr: NDArray[np.float64],
    yi: NDArray[np.float64],
    m: int,
    s: int,
    batch: int,
    stride: int,
    wr: NDArray[np.float64],
    wi: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    """One radix-3 Stockham stage: sub-transforms of 3m points, stride s rows, into y."""
    h = 0.5 * math.sqrt(3.0)  # −Im exp(−2πi/3)
    for p in range(m):
        c1 = wr[p * s]
        d1 = wi[p * s]
        c2 = wr[2 * p * s]
        d2 = wi[2 * p * s]
        for q in range(s):
            i0 = (q + s * p) * stride
            o0 = (q + s * 3 * p) * stride
            ar, br, cr, _, _ = _legs(xr, i0, s * m * stride, batch)
            ai, bi, ci, _, _ = _legs(xi, i0, s * m * stride, batch)
            y0r, y1r, y2r, _, _ = _legs(yr, o0, s * stride, batch)
            y0i, y1i, y2i, _, _ = _legs(yi, o0, s * stride, batch)
            for b in range(batch):
                sr = br[b] + cr[b]
                si = bi[b] + ci[b]
                # a − (b + c)/2 ∓ i·h·(b − c)
                mr = ar[b] - 0.5 * sr
                mi = ai[b] - 0.5 * si
                er = h * (bi[b] - ci[b])
                ei = h * (br[b] - cr[b])
                y0r[b] = ar[b] + sr
                y0i[b] = ai[b] + si
                y1r[b], y1i[b] = rotate(mr + er, mi - ei, c1, d1)
                y2r[b], y2i[b] = rotate(mr - er, mi + ei, c2, d2)


@numba.njit(cache=True, nogil=True, fastmath=True)
def _batched_fft(
    xr: NDArray[np.float64],
    xi: NDArray[np.float64],
    yr: NDArray[np.float64],
    yi: NDArray[np.float64],
    length: int,
    batch: int,
    stride: int,
    wr: NDArray[np.float64],
    wi: NDArray[np.float64],
) -> bool:  # pragma: no cover - compiled
    """``batch`` forward FFTs of ``length`` points, element (row r, column b) at r·stride + b.

    Stockham radix-5 and radix-3 stages for those factors of ``length`` (2^a·3^b·5^c), then
    radix 4 (and one radix-2 stage for an odd power of two; decimation in frequency,
    self-sorting), ping-pong between x and y; ``w`` holds exp(−2πik/length) for k < length.
    Returns True when the result is in y.
    """
    # one call site per stage kind (the buffers swapped by reference): the compiled stages are
    # inlined where they are called, and every copy costs compilation time
    n = length
    s = 1
    in_y = False
    while n > 1:
        src_r, src_i, dst_r, dst_i = (yr, yi, xr, xi) if in_y else (xr, xi, yr, yi)
        if n % 5 == 0:
            m = n // 5
            _stage5(src_r, src_i, dst_r, dst_i, m, s, batch, stride, wr, wi)
            s *= 5
        elif n % 3 == 0:
            m = n // 3
            _stage3(src_r, src_i, dst_r, dst_i, m, s, batch, stride, wr, wi)
            s *= 3
        elif n % 4 == 0:
            m = n // 4
            _stage4(src_r, src_i, dst_r, dst_i, m, s, batch, stride, wr, wi)
            s *= 4
        else:
            m = n // 2
            _stage(src_r, src_i, dst_r, dst_i, m, s, batch, stride, wr, wi)
            s *= 2
        in_y = not in_y
        n = m
    return in_y
