"""The exact decision of the load-path kernels on the packed closed points (Table 1, eqs. 7–10).

:func:`decide_packed` runs the two-sphere contact of :func:`.geometry.sphere_contact` (with the
upper sphere of :func:`_upper_sphere`) on every packed point in one pass without branches, so
that it runs on vector units, then keeps the accepted points in order; :func:`apply_law` gives
them their normal force and width (eq. 10). The pass compiles the very source of
``sphere_contact`` and ``contact_centre_height`` inline (no copy of their arithmetic), without
fast-math: square roots and divisions are correctly rounded on vector and scalar units alike,
so the values are those of the scalar evaluation, to the bit (``tests/test_path_decide.py``).
"""

from __future__ import annotations

import math
from typing import Any

import numba
import numpy as np
from numba.cpython.unsafe.numbers import trailing_zeros as _cttz
from numpy.typing import NDArray

from .geometry import contact_centre_height, sphere_contact
from .laws import normal_law

__all__ = ["apply_law", "decide_packed", "flag_list", "packed_columns"]

# The same functions compiled into the caller (numba inlines their source), so that a loop
# calling them has no call in it and the vectoriser can take it.
_sphere_contact = numba.njit(inline="always")(sphere_contact.py_func)
_centre_height = numba.njit(inline="always")(contact_centre_height.py_func)
_normal_law = numba.njit(inline="always")(normal_law.py_func)


#: Trailing zero bits of an unsigned word (numba's intrinsic: one instruction; 64 for 0).
_trailing_zeros: Any = _cttz
_LOW_BITS = np.uint64(0x0101010101010101)  # bit 0 of each byte
_GATHER = np.uint64(0x0102040810204080)  # (low bits × this) >> 56: byte k's bit at bit k


@numba.njit(cache=True, nogil=True, inline="always")
def _bit_count(x: np.uint64) -> np.int64:  # pragma: no cover - compiled
    """The set bits of x (the compiler makes it one instruction where there is one)."""
    x = x - ((x >> np.uint64(1)) & np.uint64(0x5555555555555555))
    x = (x & np.uint64(0x3333333333333333)) + ((x >> np.uint64(2)) & np.uint64(0x3333333333333333))
    x = (x + (x >> np.uint64(4))) & np.uint64(0x0F0F0F0F0F0F0F0F)
    return np.int64((x * _LOW_BITS) >> np.uint64(56))


@numba.njit(cache=True, nogil=True)
def flag_list(
    flags: NDArray[np.uint8],
    total: int,
    hits: NDArray[np.int64],
    masks: NDArray[np.uint8],
) -> int:  # pragma: no cover - compiled
    """The positions j < ``total`` of the nonzero ``flags`` (each 0–3), ascending, into
    ``hits``; their count.

    Few flags are set, at random: a branch per flag or per word of flags would be mispredicted
    at many of them. So almost no branch depends on a flag: each eight flags, read as one
    word, give a byte of nonzero bits (``masks``, on vector units), each 64 flags a word of
    them, from which four positions are read off without a branch (a word with more set bits
    is rare: the others in a loop) and the count advanced by the set ones. ``hits`` must hold
    ``total`` entries, ``masks`` ``total``/8 + 8 bytes (scratch).
    """
    n_words = total >> 3
    words = flags[: 8 * n_words].view(np.uint64)
    one = np.uint64(1)
    for w in range(n_words):
        nonzero = (words[w] | (words[w] >> one)) & _LOW_BITS
        masks[w] = np.uint8((nonzero * _GATHER) >> np.uint64(56))
    tail = 0  # the last flags, fewer than eight
    for j in range(8 * n_words, total):
        tail |= (flags[j] != 0) << (j - 8 * n_words)
    n_chunks = (n_words >> 3) + 1
    masks[n_words] = tail
    masks[n_words + 1 : 8 * n_chunks] = 0
    bits = masks[: 8 * n_chunks].view(np.uint64)  # bit j of word c: flag 64c + j
    n_hits = 0
    room = hits.size - 4
    for c in range(n_chunks):
        m = bits[c]
        base = 64 * c
        count = int(_bit_count(m))
        if n_hits <= room:  # (always, but at the very end of a full list)
            for e in range(4):  # past the set bits: written, not counted
                hits[n_hits + e] = base + _trailing_zeros(m)
                m &= m - one
            first = 4
        else:
            first = 0
        for e in range(first, count):
            hits[n_hits + e] = base + _trailing_zeros(m)
            m &= m - one
        n_hits += count
    return n_hits


@numba.njit(cache=True, nogil=True, inline="always")
def _upper_sphere(
    s1: float, s2: float, kappa_max: float
) -> tuple[float, float, float]:  # pragma: no cover - compiled
    """(κ^u clamped to ±kappa_max [1/µm], m_x, m_z [1]) of the upper surface of slope s1 [1]
    and f″ s2 [1/µm] (eqs. 4–6: m = −n^u)."""
    norm_u = math.sqrt(1.0 + s1 * s1)
    k_u = -s2 / (norm_u * norm_u * norm_u)
    if k_u > kappa_max:
        k_u = kappa_max
    elif k_u < -kappa_max:
        k_u = -kappa_max
    return k_u, s1 / norm_u, 1.0 / norm_u


@numba.njit(cache=True, nogil=True, inline="always")
def packed_columns(
    scratch: Any,
) -> tuple[
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[np.float64],
    NDArray[np.bool_],
]:  # pragma: no cover - compiled
    """The packed points' columns g [µm], S′ [1], S″ [1/µm], κ^l [1/µm], n^l_x, n^l_z [1] and
    the kept flags (``scratch.cl_*``, :class:`.path_kernel.Scratch`)."""
    return (
        scratch.cl_g,
        scratch.cl_s1,
        scratch.cl_s2,
        scratch.cl_kl,
        scratch.cl_nx,
        scratch.cl_nz,
        scratch.cl_keep,
    )


@numba.njit(cache=True, nogil=True, error_model="numpy")
def decide_packed(
    n_packed: int,
    f_l: NDArray[np.float64],
    dx: float,
    kappa_max: float,
    cell_test: float,
    min_delta: float,
    scratch: Any,
) -> int:  # pragma: no cover - compiled
    """Decide the packed points (``scratch.cl_*``, q < ``n_packed``) exactly; their count kept.

    Parameters
    ----------
    n_packed : int
        Packed points [1]; those with ``cl_keep`` set are tested.
    f_l : ndarray
        Lower heights [µm] (the centre height z_c = f^l_i + eq. 8's rise).
    dx : float
        Grid spacing [µm] (the centre x_c = i·dx + offset).
    kappa_max : float
        Curvature clamp of the upper sphere [1/µm].
    cell_test : float
        Half-width [µm] of eq. 9's cell test (dx/2; ∞ when the contact cells are given).
    min_delta : float
        Smallest overlap accepted, exclusive [µm] (−reach of the law).
    scratch : Scratch
        The packed points in, the accepted contacts out (:class:`.path_kernel.Scratch`).

    Returns
    -------
    int
        The accepted contacts n_c [1]: entries c < n_c of ``idx``, ``ex``, ``ez``, ``xc``
        [µm], ``z`` [µm], ``delta`` [µm] and ``reff`` [µm], in the packed order (Table 1,
        eq. 9, δ > ``min_delta``, eqs. 7–8 and 10 by :func:`.geometry.sphere_contact`).
    """
    i_a = scratch.cl_i
    g_a, s1_a, s2_a, kl_a, nx_a, nz_a, keep = packed_columns(scratch)
    idx = scratch.idx
    ex = scratch.ex
    ez = scratch.ez
    xc = scratch.xc
    z = scratch.z
    delta_a = scratch.delta
    reff = scratch.reff
    # Every point, with no branch: a refused point's values are computed and dropped below.
    for q in range(n_packed):
        i = i_a[q]
        g = g_a[q]
        k_l = kl_a[q]
        n_z = nz_a[q]
        k_u, m_x, m_z = _upper_sphere(s1_a[q], s2_a[q], kappa_max)
        accepted, delta, offset, e_x, e_z, y_norm = _sphere_contact(
            g, k_l, k_u, m_x, m_z, nx_a[q], n_z, cell_test, min_delta
        )
        keep[q] = keep[q] & accepted
        idx[q] = i
        ex[q] = e_x
        ez[q] = e_z
        xc[q] = i * dx + offset
        z[q] = _centre_height(g, k_l, k_u, m_z, n_z, delta, y_norm)
        delta_a[q] = delta
        reff[q] = 2.0 / (k_l + k_u)
    # The accepted ones moved down in order (nearly all are: few moves).
    n_c = 0
    for q in range(n_packed):
        if not keep[q]:
            continue
        i = idx[q]
        if n_c < q:
            idx[n_c] = i
            ex[n_c] = ex[q]
            ez[n_c] = ez[q]
            xc[n_c] = xc[q]
            delta_a[n_c] = delta_a[q]
            reff[n_c] = reff[q]
        z[n_c] = f_l[i] + z[q]
        n_c += 1
    return n_c


@numba.njit(cache=True, nogil=True)
def apply_law(
    code: int,
    params: Any,
    law_state: NDArray[np.float64],
    n_c: int,
    scratch: Any,
) -> None:  # pragma: no cover - compiled
    """``scratch.fn`` [mN/µm] and ``scratch.width`` [µm] of the accepted contacts c < n_c
    (:func:`.laws.normal_law`, eq. 10, in their order; Hertz, typed alone, runs on vector
    units)."""
    for c in range(n_c):
        scratch.fn[c], scratch.width[c] = _normal_law(
            code, params, scratch.delta[c], scratch.reff[c], law_state, scratch.idx[c]
        )
