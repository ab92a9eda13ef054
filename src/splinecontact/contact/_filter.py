"""The conservative pre-filter of the load-path kernels (Table 1, δ > −reach, eq. 9).

:func:`_may_touch` decides, with cheap branch-free arithmetic, whether a closed point may be
accepted by the exact test :func:`.geometry.sphere_contact`; it never refuses one the exact
test accepts (its tests are widened by a bound of the rounding errors of both computations),
so the points it keeps, decided exactly afterwards, give the same results to the bit
(:func:`._decide.flag_list` lists the points a pass has flagged).
"""

from __future__ import annotations

import math

import numba

__all__ = ["FILTER_SLACK", "widenings"]


#: Relative width of the filter's widened tests (:func:`_may_touch`), far above the rounding
#: error of both its arithmetic and that of :func:`.geometry.sphere_contact` (< 10⁻¹³, a few
#: hundred units in the last place of float64, of the same magnitudes).
FILTER_SLACK = 1e-12


@numba.njit(cache=True, nogil=True, error_model="numpy", fastmath={"contract"})
def widenings(
    q: float, kappa_max: float, dx: float, reach: float
) -> tuple[float, float]:  # pragma: no cover - compiled
    """The widenings E_δ and E₉ of :func:`_may_touch` at q = K·|g| (K = ``kappa_max``) [1].

    Polynomials in q with non-negative coefficients, evaluated with non-negative operands:
    rounding is monotonic, so a larger q never gives a smaller widening. With q computed from
    an upper bound G ≥ |g| (fl(K·G) ≥ fl(K·|g|)), the widened tests of :func:`_touches` refuse
    no more points than those of :func:`_may_touch`: the filter stays conservative.
    """
    big = kappa_max
    e_d = FILTER_SLACK * ((4.0 + 5.0 * reach * big) + q * ((4.0 + reach * big) + q))
    dk2 = dx * big * big
    e_9 = FILTER_SLACK * (
        (28.0 * big + 15.0 * dk2) + q * ((12.0 * big + 8.0 * dk2) + q * (2.0 * big + dk2))
    )
    return e_d, e_9


@numba.njit(cache=True, nogil=True, error_model="numpy", fastmath={"contract"})
def _touches(
    g: float,
    s1: float,
    s2: float,
    k_l: float,
    n_x: float,
    n_z: float,
    kappa_max: float,
    dx: float,
    reach: float,
    e_d: float,
    e_9: float,
) -> bool:  # pragma: no cover - compiled
    """:func:`_may_touch` with given widenings E_δ, E₉ (:func:`widenings` at q ≥ K·|g|).

    The sliding pass gives the widenings of an upper bound of |g| over all its closed points,
    the same for every point (:func:`._sliding.run_flags`); :func:`_may_touch` those of the
    point's own |g|.
    """
    r = 1.0 / math.sqrt(1.0 + s1 * s1)
    k_u = min(max(-s2 * (r * (r * r)), -kappa_max), kappa_max)
    m_x = s1 * r
    k_sum = k_l + k_u
    k_prod = k_u * k_l
    a = k_l * r + k_u * n_z
    y_x = k_l * m_x + k_u * n_x
    y_z = k_prod * g + a
    y_norm = math.sqrt(y_x * y_x + y_z * y_z)
    dmx = m_x - n_x
    dmz = r - n_z
    num = dmx * dmx + dmz * dmz - g * (y_z + a)
    den = y_norm + k_sum
    z = 2.0 * dmx * den + num * (k_u * n_x - k_l * m_x)
    refused = (
        (k_sum < -FILTER_SLACK * 2.0 * kappa_max)
        | (num + reach * den < -e_d)
        | (abs(z) > dx * y_norm * den + e_9)
    )
    return not refused


@numba.njit(cache=True, nogil=True, error_model="numpy", fastmath={"contract"})
def _may_touch(
    g: float,
    s1: float,
    s2: float,
    k_l: float,
    n_x: float,
    n_z: float,
    kappa_max: float,
    dx: float,
    reach: float,
) -> bool:  # pragma: no cover - compiled
    """Whether a closed point may pass Table 1, δ > −reach and eq. 9 (a conservative filter).

    Never false where :func:`.geometry.sphere_contact` (with the kernel's upper sphere of
    slope s1 and f″ s2) accepts; the points it keeps are decided by that exact test. It uses
    cheaper arithmetic: one reciprocal r = 1/√(1 + s1²), m = (s1·r, r), κ^u = −s2·r³
    (clamped), and no division in the tests, which are those of eq. 10 and eq. 9 multiplied
    through by their positive denominators D = |Y| + κ^l + κ^u and 2|Y|:

    * Table 1: κ^l + κ^u > −E₀;
    * δ > −reach: N + reach·D > −E_δ (N the numerator of δ = N/D);
    * eq. 9: |2(m_x − n_x)·D + N·W| ≤ dx·|Y|·D + E₉ (W = κ^u n_x − κ^l m_x: the numerator
      of the offset times D).

    Each widening E is ``FILTER_SLACK`` = 10⁻¹² times a bound of the sum of the magnitudes of
    the terms of its test (the test with every term replaced by its absolute value): with
    |m|, |n| ≤ 1, |κ^l|, |κ^u| ≤ K = ``kappa_max`` (both are clamped) and q = K·|g|,
    |N| ≤ 4 + q(q + 4), |Y| ≤ K(3 + q), D ≤ K(5 + q), |W| ≤ 2K and |m_x − n_x| ≤ 2, so
    E₀ = 10⁻¹²·2K, E_δ = 10⁻¹²·(4 + q(q + 4) + reach·K(5 + q)) and
    E₉ = 10⁻¹²·(4K(5 + q) + 2K(4 + q(q + 4)) + dx·K²(3 + q)(5 + q)). Both this arithmetic and
    the exact test's differ from the real-number values of the same quantities by less than
    10⁻¹³ of those magnitudes (a forward error bound of each term: factors with relative
    errors of at most 8 units of 2⁻⁵³ — the square roots, the reciprocal, r³ — through at most
    some 30 roundings); and rounding is monotonic, so an accepted δ = fl(N/D) > −reach means
    N > −reach·D for the exact test's own N and D (D > 0 there), and an accepted offset
    |fl(O/2|Y|)| ≤ dx/2 means |O| ≤ dx·|Y|·(1 + 2⁻⁵³). So the widened tests keep every point
    the exact test accepts, also where κ^l + κ^u, |Y| or N nearly vanish (the widening then
    decides: the point is kept). A NaN keeps the point (each test is written as "refused when
    clearly outside").
    """
    e_d, e_9 = widenings(kappa_max * abs(g), kappa_max, dx, reach)
    return _touches(g, s1, s2, k_l, n_x, n_z, kappa_max, dx, reach, e_d, e_9)
