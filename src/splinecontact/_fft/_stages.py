"""The Stockham stages of the compiled FFT: batches of short complex transforms.

Radix 2, 3, 4 and 5 (decimation in frequency, self-sorting), each an unrolled butterfly whose
innermost loop runs over the contiguous batch index, so that every butterfly is a vector
operation; :func:`_batched_fft` chains them for lengths 2^a·3^b·5^c.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

__all__ = ["_batched_fft"]


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
            i1 = (q + s * (p + m)) * stride
            o0 = (q + s * 2 * p) * stride
            o1 = o0 + s * stride
            ar = xr[i0 : i0 + batch]
            ai = xi[i0 : i0 + batch]
            br = xr[i1 : i1 + batch]
            bi = xi[i1 : i1 + batch]
            sr = yr[o0 : o0 + batch]
            si = yi[o0 : o0 + batch]
            dr = yr[o1 : o1 + batch]
            di = yi[o1 : o1 + batch]
            for b in range(batch):
                er = ar[b] - br[b]
                ei = ai[b] - bi[b]
                sr[b] = ar[b] + br[b]
                si[b] = ai[b] + bi[b]
                dr[b] = er * c - ei * d
                di[b] = er * d + ei * c


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
            step_in = s * m * stride
            o0 = (q + s * 4 * p) * stride
            step_out = s * stride
            ar = xr[i0 : i0 + batch]
            ai = xi[i0 : i0 + batch]
            br = xr[i0 + step_in : i0 + step_in + batch]
            bi = xi[i0 + step_in : i0 + step_in + batch]
            cr = xr[i0 + 2 * step_in : i0 + 2 * step_in + batch]
            ci = xi[i0 + 2 * step_in : i0 + 2 * step_in + batch]
            dr = xr[i0 + 3 * step_in : i0 + 3 * step_in + batch]
            di = xi[i0 + 3 * step_in : i0 + 3 * step_in + batch]
            y0r = yr[o0 : o0 + batch]
            y0i = yi[o0 : o0 + batch]
            y1r = yr[o0 + step_out : o0 + step_out + batch]
            y1i = yi[o0 + step_out : o0 + step_out + batch]
            y2r = yr[o0 + 2 * step_out : o0 + 2 * step_out + batch]
            y2i = yi[o0 + 2 * step_out : o0 + 2 * step_out + batch]
            y3r = yr[o0 + 3 * step_out : o0 + 3 * step_out + batch]
            y3i = yi[o0 + 3 * step_out : o0 + 3 * step_out + batch]
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
                # (a − c) − i(b − d)
                tr = amcr + bmdi
                ti = amci - bmdr
                y1r[b] = tr * c1 - ti * d1
                y1i[b] = tr * d1 + ti * c1
                tr = apcr - bpdr
                ti = apci - bpdi
                y2r[b] = tr * c2 - ti * d2
                y2i[b] = tr * d2 + ti * c2
                # (a − c) + i(b − d)
                tr = amcr - bmdi
                ti = amci + bmdr
                y3r[b] = tr * c3 - ti * d3
                y3i[b] = tr * d3 + ti * c3


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
    step_in = s * m * stride
    step_out = s * stride
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
            x0r = xr[i0 : i0 + batch]
            x0i = xi[i0 : i0 + batch]
            x1r = xr[i0 + step_in : i0 + step_in + batch]
            x1i = xi[i0 + step_in : i0 + step_in + batch]
            x2r = xr[i0 + 2 * step_in : i0 + 2 * step_in + batch]
            x2i = xi[i0 + 2 * step_in : i0 + 2 * step_in + batch]
            x3r = xr[i0 + 3 * step_in : i0 + 3 * step_in + batch]
            x3i = xi[i0 + 3 * step_in : i0 + 3 * step_in + batch]
            x4r = xr[i0 + 4 * step_in : i0 + 4 * step_in + batch]
            x4i = xi[i0 + 4 * step_in : i0 + 4 * step_in + batch]
            y0r = yr[o0 : o0 + batch]
            y0i = yi[o0 : o0 + batch]
            y1r = yr[o0 + step_out : o0 + step_out + batch]
            y1i = yi[o0 + step_out : o0 + step_out + batch]
            y2r = yr[o0 + 2 * step_out : o0 + 2 * step_out + batch]
            y2i = yi[o0 + 2 * step_out : o0 + 2 * step_out + batch]
            y3r = yr[o0 + 3 * step_out : o0 + 3 * step_out + batch]
            y3i = yi[o0 + 3 * step_out : o0 + 3 * step_out + batch]
            y4r = yr[o0 + 4 * step_out : o0 + 4 * step_out + batch]
            y4i = yi[o0 + 4 * step_out : o0 + 4 * step_out + batch]
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
                tr = a1r + b1i
                ti = a1i - b1r
                y1r[b] = tr * w1r - ti * w1i
                y1i[b] = tr * w1i + ti * w1r
                tr = a2r + b2i
                ti = a2i - b2r
                y2r[b] = tr * w2r - ti * w2i
                y2i[b] = tr * w2i + ti * w2r
                tr = a2r - b2i
                ti = a2i + b2r
                y3r[b] = tr * w3r - ti * w3i
                y3i[b] = tr * w3i + ti * w3r
                tr = a1r - b1i
                ti = a1i + b1r
                y4r[b] = tr * w4r - ti * w4i
                y4i[b] = tr * w4i + ti * w4r


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
            step_in = s * m * stride
            o0 = (q + s * 3 * p) * stride
            step_out = s * stride
            ar = xr[i0 : i0 + batch]
            ai = xi[i0 : i0 + batch]
            br = xr[i0 + step_in : i0 + step_in + batch]
            bi = xi[i0 + step_in : i0 + step_in + batch]
            cr = xr[i0 + 2 * step_in : i0 + 2 * step_in + batch]
            ci = xi[i0 + 2 * step_in : i0 + 2 * step_in + batch]
            y0r = yr[o0 : o0 + batch]
            y0i = yi[o0 : o0 + batch]
            y1r = yr[o0 + step_out : o0 + step_out + batch]
            y1i = yi[o0 + step_out : o0 + step_out + batch]
            y2r = yr[o0 + 2 * step_out : o0 + 2 * step_out + batch]
            y2i = yi[o0 + 2 * step_out : o0 + 2 * step_out + batch]
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
                tr = mr + er
                ti = mi - ei
                y1r[b] = tr * c1 - ti * d1
                y1i[b] = tr * d1 + ti * c1
                tr = mr - er
                ti = mi + ei
                y2r[b] = tr * c2 - ti * d2
                y2i[b] = tr * d2 + ti * c2


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
