"""The Stockham stages of the compiled FFT: batches of short complex transforms.

Radix 2, 3, 4 and 5 (decimation in frequency, self-sorting). One stage (:func:`_stage`) walks
the sub-transforms and hands the views of their legs (:func:`_legs`) and their twiddle factors
(:func:`_twiddles`) to the unrolled butterfly of its radix, whose loop runs over the
contiguous batch index, so that every butterfly is a vector operation; :func:`_batched_fft`
chains the stages for lengths 2^a·3^b·5^c.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

__all__ = ["_batched_fft", "rotate"]

#: The views of the (up to) five legs of a butterfly, real or imaginary parts.
_Legs = tuple[
    NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64],
    NDArray[np.float64],
]  # fmt: skip
#: w1 … w4 of a butterfly as (re, im) pairs.
_Twiddles = tuple[float, float, float, float, float, float, float, float]

_H3 = 0.5 * math.sqrt(3.0)  # −Im exp(−2πi/3)
_C1 = math.cos(0.4 * math.pi)  # cos and sin of 2π/5 and 4π/5
_C2 = math.cos(0.8 * math.pi)
_S1 = math.sin(0.4 * math.pi)
_S2 = math.sin(0.8 * math.pi)


@numba.njit(cache=True, nogil=True, fastmath=True, inline="always")
def rotate(re: float, im: float, c: float, d: float) -> tuple[float, float]:  # pragma: no cover
    """(re + i·im)·(c + i·d): a value times a twiddle factor, as two reals."""
    return re * c - im * d, re * d + im * c


@numba.njit(cache=True, nogil=True, fastmath=True, inline="always")
def _legs(
    x: NDArray[np.float64], start: int, step: int, batch: int
) -> _Legs:  # pragma: no cover - compiled
    """The ``batch`` contiguous values at start + k·step for k = 0 … 4 (the legs of a
    butterfly; a stage of radix r < 5 leaves the last 5 − r unused, slices clamp at the end)."""
    return (
        x[start : start + batch],
        x[start + step : start + step + batch],
        x[start + 2 * step : start + 2 * step + batch],
        x[start + 3 * step : start + 3 * step + batch],
        x[start + 4 * step : start + 4 * step + batch],
    )


@numba.njit(cache=True, nogil=True, fastmath=True, inline="always")
def _twiddles(
    wr: NDArray[np.float64], wi: NDArray[np.float64], at: int, radix: int
) -> _Twiddles:  # pragma: no cover - compiled
    """w_k = w[k·at] for k = 1 … radix − 1 (w[0] = 1 for the unused k ≥ radix)."""
    k2 = 2 * at if radix > 2 else 0
    k3 = 3 * at if radix > 3 else 0
    k4 = 4 * at if radix > 4 else 0
    return wr[at], wi[at], wr[k2], wi[k2], wr[k3], wi[k3], wr[k4], wi[k4]


@numba.njit(cache=True, nogil=True, fastmath=True, inline="always")
def _butterfly2(
    xr: _Legs, xi: _Legs, yr: _Legs, yi: _Legs, w: _Twiddles, batch: int
) -> None:  # pragma: no cover - compiled
    """y0 = x0 + x1, y1 = (x0 − x1)·w1."""
    ar, br, _, _, _ = xr
    ai, bi, _, _, _ = xi
    sr, dr, _, _, _ = yr
    si, di, _, _, _ = yi
    c, d, _, _, _, _, _, _ = w
    for b in range(batch):
        sr[b] = ar[b] + br[b]
        si[b] = ai[b] + bi[b]
        dr[b], di[b] = rotate(ar[b] - br[b], ai[b] - bi[b], c, d)


@numba.njit(cache=True, nogil=True, fastmath=True, inline="always")
def _butterfly3(
    xr: _Legs, xi: _Legs, yr: _Legs, yi: _Legs, w: _Twiddles, batch: int
) -> None:  # pragma: no cover - compiled
    """y0 = a + b + c; y1, y2 = (a − (b + c)/2 ∓ i·h·(b − c))·w1, ·w2 (h = √3/2)."""
    ar, br, cr, _, _ = xr
    ai, bi, ci, _, _ = xi
    y0r, y1r, y2r, _, _ = yr
    y0i, y1i, y2i, _, _ = yi
    c1, d1, c2, d2, _, _, _, _ = w
    for b in range(batch):
        sr = br[b] + cr[b]
        si = bi[b] + ci[b]
        mr = ar[b] - 0.5 * sr
        mi = ai[b] - 0.5 * si
        er = _H3 * (bi[b] - ci[b])
        ei = _H3 * (br[b] - cr[b])
        y0r[b] = ar[b] + sr
        y0i[b] = ai[b] + si
        y1r[b], y1i[b] = rotate(mr + er, mi - ei, c1, d1)
        y2r[b], y2i[b] = rotate(mr - er, mi + ei, c2, d2)


@numba.njit(cache=True, nogil=True, fastmath=True, inline="always")
def _butterfly4(
    xr: _Legs, xi: _Legs, yr: _Legs, yi: _Legs, w: _Twiddles, batch: int
) -> None:  # pragma: no cover - compiled
    """y0 = (a + c) + (b + d), y2 = ((a + c) − (b + d))·w2, y1, y3 = ((a − c) ∓ i(b − d))·w1,
    ·w3."""
    ar, br, cr, dr, _ = xr
    ai, bi, ci, di, _ = xi
    y0r, y1r, y2r, y3r, _ = yr
    y0i, y1i, y2i, y3i, _ = yi
    c1, d1, c2, d2, c3, d3, _, _ = w
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
        y1r[b], y1i[b] = rotate(amcr + bmdi, amci - bmdr, c1, d1)
        y2r[b], y2i[b] = rotate(apcr - bpdr, apci - bpdi, c2, d2)
        y3r[b], y3i[b] = rotate(amcr - bmdi, amci + bmdr, c3, d3)


@numba.njit(cache=True, nogil=True, fastmath=True, inline="always")
def _butterfly5(
    xr: _Legs, xi: _Legs, yr: _Legs, yi: _Legs, w: _Twiddles, batch: int
) -> None:  # pragma: no cover - compiled
    """y0 = Σ x; y1, y4 = (a1 ∓ i·b1)·w1, ·w4 and y2, y3 = (a2 ∓ i·b2)·w2, ·w3."""
    x0r, x1r, x2r, x3r, x4r = xr
    x0i, x1i, x2i, x3i, x4i = xi
    y0r, y1r, y2r, y3r, y4r = yr
    y0i, y1i, y2i, y3i, y4i = yi
    w1r, w1i, w2r, w2i, w3r, w3i, w4r, w4i = w
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
        a1r = x0r[b] + _C1 * t1r + _C2 * t2r
        a1i = x0i[b] + _C1 * t1i + _C2 * t2i
        a2r = x0r[b] + _C2 * t1r + _C1 * t2r
        a2i = x0i[b] + _C2 * t1i + _C1 * t2i
        b1r = _S1 * t3r + _S2 * t4r
        b1i = _S1 * t3i + _S2 * t4i
        b2r = _S2 * t3r - _S1 * t4r
        b2i = _S2 * t3i - _S1 * t4i
        y1r[b], y1i[b] = rotate(a1r + b1i, a1i - b1r, w1r, w1i)
        y2r[b], y2i[b] = rotate(a2r + b2i, a2i - b2r, w2r, w2i)
        y3r[b], y3i[b] = rotate(a2r - b2i, a2i + b2r, w3r, w3i)
        y4r[b], y4i[b] = rotate(a1r - b1i, a1i + b1r, w4r, w4i)


@numba.njit(cache=True, nogil=True, fastmath=True, inline="always")
def _stage(
    radix: int,
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
    """One Stockham stage of radix 2, 3, 4 or 5: sub-transforms of radix·m points, stride s
    rows, from x into y. Called with a constant ``radix``, so each inlined copy keeps only the
    butterfly of its radix."""
    for p in range(m):
        w = _twiddles(wr, wi, p * s, radix)
        for q in range(s):
            i0 = (q + s * p) * stride
            o0 = (q + s * radix * p) * stride
            legs_xr = _legs(xr, i0, s * m * stride, batch)
            legs_xi = _legs(xi, i0, s * m * stride, batch)
            legs_yr = _legs(yr, o0, s * stride, batch)
            legs_yi = _legs(yi, o0, s * stride, batch)
            if radix == 5:
                _butterfly5(legs_xr, legs_xi, legs_yr, legs_yi, w, batch)
            elif radix == 3:
                _butterfly3(legs_xr, legs_xi, legs_yr, legs_yi, w, batch)
            elif radix == 4:
                _butterfly4(legs_xr, legs_xi, legs_yr, legs_yi, w, batch)
            else:
                _butterfly2(legs_xr, legs_xi, legs_yr, legs_yi, w, batch)


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
    # one call site of the stage (the buffers swapped by reference): the compiled stage is
    # inlined where it is called, and every copy costs compilation time
    n = length
    s = 1
    in_y = False
    while n > 1:
        src_r, src_i, dst_r, dst_i = (yr, yi, xr, xi) if in_y else (xr, xi, yr, yi)
        radix = 5 if n % 5 == 0 else 3 if n % 3 == 0 else 4 if n % 4 == 0 else 2
        m = n // radix
        if radix == 5:
            _stage(5, src_r, src_i, dst_r, dst_i, m, s, batch, stride, wr, wi)
        elif radix == 3:
            _stage(3, src_r, src_i, dst_r, dst_i, m, s, batch, stride, wr, wi)
        elif radix == 4:
            _stage(4, src_r, src_i, dst_r, dst_i, m, s, batch, stride, wr, wi)
        else:
            _stage(2, src_r, src_i, dst_r, dst_i, m, s, batch, stride, wr, wi)
        s *= radix
        in_y = not in_y
        n = m
    return in_y
