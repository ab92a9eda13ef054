"""A compiled circulant convolution by real FFT: u = irfft(λ · rfft(v)) for any length n.

The boundary element solver applies its elastic operator once or twice per iteration, so this
transform pair is its inner loop. numpy's and scipy's FFTs (pocketfft) run one transform at a
time with scalar butterflies; this one is laid out for SIMD instead:

* the n real values are read as N = n/2 complex ones (even samples real part, odd samples
  imaginary part), held as separate real and imaginary arrays;
* the complex FFT of length N = N1·N2 is done in four steps (Bailey): N2 transforms of length N1
  down the columns of the N1 × N2 matrix, a twiddle factor, a transpose, and N1 transforms of
  length N2 (N1 divides N2). Each batch of short transforms is a Stockham sweep (radix 5 and 3
  for those factors, then radix 4 and 2) whose innermost loop runs over the contiguous batch
  index, so every butterfly is a vector operation;
* one pass separates the even and odd spectra, multiplies by the real response λ and builds the
  half-length spectrum of the inverse; the inverse is the same forward transform of the
  conjugate.

This serves every even n ≥ ``MIN_SIZE`` with n/2 = 2^a·3^b·5^c (:func:`fast_size`: powers of
two, 3·2^k, 10^k, …). Any other length n (odd, another prime factor, or shorter than
``MIN_SIZE``) is embedded in the smallest such length M ≥ 2n − 1 (:func:`transform_size`).
The circulant product of n points is u_i = Σ_j a_{(i−j) mod n} v_j with a the response to a
unit load at node 0 (real and even, as λ is real). Padding v with zeros to M points and
wrapping a onto M points (a'_k = a_k for k < n, a'_{M−k} = a_k for 0 < k < n, zero between)
gives a circulant product of M points whose first n values are u, because every difference
i − j of two nodes lies in (−n, n). a' is real and even, so its response λ' = rfft(a') is real
and the transform pair above serves unchanged. This is the convolution step of Bluestein's
algorithm without its chirps: one real transform pair of length M per product (2n ≤ M < 2.25n
above 128 points).

Rounding differs from pocketfft's at the level of 1e−16 relative (both are O(ε log N)).
"""

from __future__ import annotations

import math
from typing import Any

import numba
import numpy as np
from numpy.typing import NDArray

from ..errors import BEMError
from ._stages import _batched_fft, rotate

__all__ = ["CirculantConvolution", "circulant", "fast_size", "transform_size"]

#: Shortest transform; shorter grids are embedded in a transform of at least this length.
MIN_SIZE = 256

#: Padding [values] of every row of the work matrices (one cache line).
_PAD = 8


def _smooth(n: int) -> bool:
    """True when n > 0 has no prime factor other than 2, 3 and 5."""
    for factor in (3, 5):
        while n > 0 and n % factor == 0:
            n //= factor
    return n > 0 and n & (n - 1) == 0


def fast_size(n: int) -> bool:
    """True when ``n`` ≥ ``MIN_SIZE`` is even and n/2 = 2^a·3^b·5^c (transformed directly)."""
    return n >= MIN_SIZE and n % 2 == 0 and _smooth(n // 2)


def transform_size(n: int) -> int:
    """Length M of the transform pair that serves a circulant product of n points.

    ``n`` itself when :func:`fast_size`, otherwise the smallest fast size ≥ max(2n − 1,
    ``MIN_SIZE``) (the zero-padded embedding described in the module docstring).
    """
    if fast_size(n):
        return n
    target = max(2 * n - 1, MIN_SIZE)
    best = 4 * target
    five = 1
    while 2 * five < best:  # each 2·5^c·3^b·2^a: the smallest one ≥ target for every b, c
        odd = five
        while 2 * odd < best:
            size = 2 * odd
            while size < target:
                size *= 2
            best = min(best, size)
            odd *= 3
        five *= 5
    return best


def _split(big: int) -> int:
    """n1 of the four-step split big = n1·n2: the largest n1 ≤ √big that divides n2.

    :func:`_middle` writes runs of n1 consecutive values into rows of n2, so n1 | n2; for
    big = 2^a·3^b·5^c that is n1 = 2^⌊a/2⌋·3^⌊b/2⌋·5^⌊c/2⌋.
    """
    return max(d for d in range(1, math.isqrt(big) + 1) if big % (d * d) == 0)


@numba.njit(cache=True, nogil=True, fastmath=True)
def _complex_fft(
    ar: NDArray[np.float64],
    ai: NDArray[np.float64],
    br: NDArray[np.float64],
    bi: NDArray[np.float64],
    n1: int,
    n2: int,
    w1r: NDArray[np.float64],
    w1i: NDArray[np.float64],
    w2r: NDArray[np.float64],
    w2i: NDArray[np.float64],
    tr: NDArray[np.float64],
    ti: NDArray[np.float64],
) -> bool:  # pragma: no cover - compiled
    """Forward FFT of N = n1·n2 complex values (four steps); returns True if the result is in b.

    Input in a: value j = r·n2 + c at r·(n2 + PAD) + c. Output: value k = k1 + n1·k2 at
    k2·(n1 + PAD) + k1, in a or b. Padded rows keep the strided accesses of the transpose off
    the same cache sets. ``t`` holds the twiddles exp(−2πi k1 c/N) at c·n1 + k1.
    """
    s1 = n2 + _PAD
    s2 = n1 + _PAD
    if _batched_fft(ar, ai, br, bi, n1, n2, s1, w1r, w1i):
        sr, si, dr, di = br, bi, ar, ai
    else:
        sr, si, dr, di = ar, ai, br, bi
    # d[c][k1] = s[k1][c] · t[c][k1]: contiguous writes, strided (padded) reads
    for c in range(n2):
        row = c * s2
        tw = c * n1
        for k1 in range(n1):
            src = k1 * s1 + c
            dr[row + k1], di[row + k1] = rotate(sr[src], si[src], tr[tw + k1], ti[tw + k1])
    # result in d unless the second batch ends in s
    return _batched_fft(dr, di, sr, si, n2, n1, s2, w2r, w2i) == (dr is ar)


@numba.njit(cache=True, nogil=True, fastmath=True)
def _load(
    values: NDArray[np.float64], ar: NDArray[np.float64], ai: NDArray[np.float64], n1: int, n2: int
) -> None:  # pragma: no cover - compiled
    """Even samples to a's real part, odd ones to its imaginary part (padded rows)."""
    s1 = n2 + _PAD
    for r in range(n1):
        row_in = values[2 * r * n2 : 2 * (r + 1) * n2]
        row_r = ar[r * s1 : r * s1 + n2]
        row_i = ai[r * s1 : r * s1 + n2]
        for c in range(n2):
            row_r[c] = row_in[2 * c]
            row_i[c] = row_in[2 * c + 1]


@numba.njit(cache=True, nogil=True, fastmath=True)
def _store(
    fr: NDArray[np.float64], fi: NDArray[np.float64], out: NDArray[np.float64], n1: int, n2: int
) -> None:  # pragma: no cover - compiled
    """out[2k] = Re F_k, out[2k + 1] = −Im F_k (F in the transposed, padded layout)."""
    s2 = n1 + _PAD
    for k2 in range(n2):
        row_r = fr[k2 * s2 : k2 * s2 + n1]
        row_i = fi[k2 * s2 : k2 * s2 + n1]
        row_out = out[2 * k2 * n1 : 2 * (k2 + 1) * n1]
        for k1 in range(n1):
            row_out[2 * k1] = row_r[k1]
            row_out[2 * k1 + 1] = -row_i[k1]


@numba.njit(cache=True, nogil=True, fastmath=True, inline="always")
def _spectrum_step(
    zkr: float, zki: float, zcr: float, zci: float, cr: float, ci: float, lk: float, lc: float
) -> tuple[float, float]:  # pragma: no cover - compiled
    """conj(V_k) from Z_k, Z_{N−k}, h_k = cr + i·ci, λ_k and λ_{N−k} (scaled)."""
    pr = zcr  # conj(Z_{N−k}) = (pr, pi)
    pi_ = -zci
    # X_k = (Z_k + conj Z_{N−k}) − i h_k (Z_k − conj Z_{N−k}), up to the factor 1/2
    sr = zkr + pr
    si = zki + pi_
    er = zkr - pr
    ei = zki - pi_
    # −i·h·e = −i(cr + i ci)(er + i ei) = (ci er + cr ei) + i(ci ei − cr er)
    mr = ci * er + cr * ei
    mi = ci * ei - cr * er
    # X_{N−k} = conj(E) + h_{N−k} conj(O) with h_{N−k} = −conj(h_k); Y = λ X
    ykr = lk * (sr + mr)
    yki = lk * (si + mi)
    ycr = lc * (sr - mr)
    yci = lc * (mi - si)
    # V_k = (Y_k + conj Y_{N−k}) + i conj(h_k) (Y_k − conj Y_{N−k})
    gr = ykr + ycr
    gi = yki - yci
    fr = ykr - ycr
    fi = yki + yci
    # i·conj(h)·f = i(cr − i ci)(fr + i fi) = (ci fr − cr fi) + i(cr fr + ci fi)
    return gr + (ci * fr - cr * fi), -(gi + (cr * fr + ci * fi))


@numba.njit(cache=True, nogil=True, fastmath=True)
def _middle(
    zr: NDArray[np.float64],
    zi: NDArray[np.float64],
    vr: NDArray[np.float64],
    vi: NDArray[np.float64],
    scaled: NDArray[np.float64],
    hr: NDArray[np.float64],
    hi: NDArray[np.float64],
    n1: int,
    n2: int,
) -> None:  # pragma: no cover - compiled
    """Z → Y = λ X (the real spectrum) → conj(V), the half-length spectrum of the inverse.

    Z is read in the output layout of :func:`_complex_fft` (k = k1 + n1·k2 at k2·(n1 + PAD)
    + k1), conj(V) written in its input layout (k = r·n2 + c at r·(n2 + PAD) + c), so that the
    inverse is the same forward transform. Each k is computed on its own from Z_k and Z_{N−k}
    (every pair twice), so that the loop over k1 is a vector loop.
    """
    big = n1 * n2
    s1 = n2 + _PAD
    s2 = n1 + _PAD
    for k2 in range(n2):
        start = n1 * k2
        at_out = (start // n2) * s1 + start % n2
        row_r = zr[k2 * s2 : k2 * s2 + n1]
        row_i = zi[k2 * s2 : k2 * s2 + n1]
        # N − k for k1 ≥ 1 lies in row n2 − 1 − k2 at column n1 − k1
        mirror = (n2 - 1 - k2) * s2
        mir_r = zr[mirror : mirror + n1 + 1]
        mir_i = zi[mirror : mirror + n1 + 1]
        lam = scaled[start : start + n1]
        lam_c = scaled[big - start - n1 + 1 : big - start + 1]  # λ_{N−k} = lam_c[n1 − k1]
        h_r = hr[start : start + n1]
        h_i = hi[start : start + n1]
        out_r = vr[at_out : at_out + n1]
        out_i = vi[at_out : at_out + n1]
        for k1 in range(1, n1):
            j = n1 - k1
            out_r[k1], out_i[k1] = _spectrum_step(
                row_r[k1], row_i[k1], mir_r[j], mir_i[j], h_r[k1], h_i[k1], lam[k1],
                lam_c[j - 1],
            )  # fmt: skip
        # k1 = 0: N − k = n1·(n2 − k2), row (n2 − k2) mod n2, column 0
        at_c = ((n2 - k2) % n2) * s2
        out_r[0], out_i[0] = _spectrum_step(
            row_r[0], row_i[0], zr[at_c], zi[at_c], h_r[0], h_i[0], lam[0], scaled[big - start]
        )


@numba.njit(cache=True, nogil=True, fastmath=True)
def _convolve(
    values: NDArray[np.float64],
    out: NDArray[np.float64],
    scaled: NDArray[np.float64],
    ar: NDArray[np.float64],
    ai: NDArray[np.float64],
    br: NDArray[np.float64],
    bi: NDArray[np.float64],
    n1: int,
    n2: int,
    w1r: NDArray[np.float64],
    w1i: NDArray[np.float64],
    w2r: NDArray[np.float64],
    w2i: NDArray[np.float64],
    tr: NDArray[np.float64],
    ti: NDArray[np.float64],
    hr: NDArray[np.float64],
    hi: NDArray[np.float64],
) -> None:  # pragma: no cover - compiled
    """out = irfft(λ · rfft(values)); ``scaled`` = λ/(2n) (n/2 + 1 entries), h = exp(−2πik/n)."""
    _load(values, ar, ai, n1, n2)
    # forward: Z in a or b; conj(V) into the other one; inverse from there
    in_b = _complex_fft(ar, ai, br, bi, n1, n2, w1r, w1i, w2r, w2i, tr, ti)
    zr, zi, vr, vi = (br, bi, ar, ai) if in_b else (ar, ai, br, bi)
    _middle(zr, zi, vr, vi, scaled, hr, hi, n1, n2)
    in_z = _complex_fft(vr, vi, zr, zi, n1, n2, w1r, w1i, w2r, w2i, tr, ti)
    fr, fi = (zr, zi) if in_z else (vr, vi)
    _store(fr, fi, out, n1, n2)


@numba.njit(cache=True, nogil=True)
def circulant(
    values: NDArray[np.float64],
    out: NDArray[np.float64],
    padded_in: NDArray[np.float64],
    padded_out: NDArray[np.float64],
    *transform: Any,
) -> None:  # pragma: no cover - compiled
    """out = the circulant product of ``values`` (n points) for any n.

    With empty ``padded_*`` buffers (n a fast size) the transform pair works on ``values``
    directly; otherwise ``values`` goes into the first n entries of ``padded_in`` (the rest
    stays zero), the product of M points into ``padded_out``, and its first n entries are u.
    ``transform`` are the arguments of :func:`_convolve` after (values, out); all arguments
    after (values, out) are :attr:`CirculantConvolution.arguments`.
    """
    if padded_in.size == 0:
        _convolve(values, out, *transform)
        return
    n = values.size
    padded_in[:n] = values
    _convolve(padded_in, padded_out, *transform)
    out[:] = padded_out[:n]


def _embedded_response(response: NDArray[np.float64], n: int, size: int) -> NDArray[np.float64]:
    """λ' of the M-point product whose first n values are the n-point one (module docstring)."""
    column = np.fft.irfft(response, n)  # a: the response to a unit load at node 0 (even)
    wrapped = np.zeros(size)
    wrapped[:n] = column
    wrapped[size - n + 1 :] = column[1:]
    return np.ascontiguousarray(np.fft.rfft(wrapped).real)


def _unit_circle(
    numerator: NDArray[np.int64], denominator: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """cos and −sin of 2π·numerator/denominator, the angle reduced exactly first."""
    angle = 2.0 * np.pi * (numerator % denominator) / denominator
    return np.cos(angle), -np.sin(angle)


class CirculantConvolution:
    """u = irfft(λ · rfft(v), n) for a fixed real response λ and any length n ≥ 2.

    Parameters
    ----------
    response : ndarray
        λ_k for k = 0 … n//2 [any unit].
    n : int
        Real length; a :func:`fast_size` is transformed directly, any other length through
        the embedding in a longer fast size (:func:`transform_size`).
    """

    def __init__(self, response: NDArray[np.float64], n: int) -> None:
        if n < 2 or response.shape != (n // 2 + 1,):
            raise BEMError(
                f"the circulant product needs n ≥ 2 points and n//2 + 1 response modes, got {n} "
                f"points and {response.shape} modes; pass the rfft response of the n-point grid"
            )
        self.n = n
        size = transform_size(n)
        self.size = size
        if size == n:
            self.padded_in = self.padded_out = np.empty(0)
            spectrum = np.ascontiguousarray(response, dtype=np.float64)
        else:
            self.padded_in = np.zeros(size)
            self.padded_out = np.empty(size)
            spectrum = _embedded_response(np.asarray(response, dtype=np.float64), n, size)
        big = size // 2
        n1 = _split(big)
        n2 = big // n1
        self.n1 = n1
        self.n2 = n2
        self.scaled = spectrum * (0.5 / size)
        self.w1r, self.w1i = _unit_circle(np.arange(n1), n1)
        self.w2r, self.w2i = _unit_circle(np.arange(n2), n2)
        c = np.arange(n2)[:, None]
        k1 = np.arange(n1)[None, :]
        self.tr, self.ti = (np.ascontiguousarray(a.ravel()) for a in _unit_circle(k1 * c, big))
        self.hr, self.hi = _unit_circle(np.arange(big), size)
        work = max(n1 * (n2 + _PAD), n2 * (n1 + _PAD))
        self.ar, self.ai, self.br, self.bi = (np.empty(work) for _ in range(4))

    @property
    def arguments(self) -> tuple[Any, ...]:
        """The arguments of :func:`circulant` after (values, out), for compiled callers."""
        return (
            self.padded_in, self.padded_out, self.scaled, self.ar, self.ai, self.br, self.bi,
            self.n1, self.n2, self.w1r, self.w1i, self.w2r, self.w2i, self.tr, self.ti, self.hr,
            self.hi,
        )  # fmt: skip

    def __call__(self, values: NDArray[np.float64], out: NDArray[np.float64]) -> None:
        """Write irfft(λ · rfft(values), n) into ``out`` (length n, float64, contiguous)."""
        circulant(values, out, *self.arguments)
