"""The 2D Maugis–Dugdale branch in closed form and its fold (Baney & Hui 1997; Johnson &
Greenwood 2008).

The contact branch parametrized by t = √(c² − b²)/b (approach, force and half-width with
their derivatives in ln t), the branch without contact and the fold of the contact branch
(the minimum of δ). The per-contact evaluation along a path, with its state and its root
finding, is :mod:`.maugis_dugdale`. Conventions as in :mod:`.adhesion`.
"""

from __future__ import annotations

import math

import numba

_PI = math.pi

# --- 2D Maugis–Dugdale (Baney & Hui 1997; Johnson & Greenwood 2008) ---------------------------
#
# Contact |x| < b, Dugdale tension σ0 on b < |x| < c, t = √(c² − b²)/b, m = c/b = √(1 + t²).
# With a_k = 4σ0/(π E*) and R = R_eff/2:
#   (MD-P) P = π E* b²/(4R) − 2σ0 b t
#   (MD-h) h0 = b² (m t − asinh t)/(2R) + a_k b (t asinh t − m ln m)      (gap at x = c)
#   (MD-δ) δ = b²/R + a_k b (m asinh t − t (5/2 + ln m))
# Out of contact (adhesive zone |x| < c, no contact): δ = c²/(2R) − α c − h0 with
# α = a_k (5/2 − 2 ln 2), P = −2σ0 c, valid while δ < −a_k c (5/2 − ln 2) (gap at x = 0 > 0).


@numba.njit(cache=True, nogil=True)
def _mt_minus_asinh(t: float) -> float:
    if t < 1e-3:
        t2 = t * t
        return t * t2 * (2.0 / 3.0 - t2 / 5.0 + 3.0 * t2 * t2 / 28.0)
    return math.sqrt(1.0 + t * t) * t - math.asinh(t)


@numba.njit(cache=True, nogil=True)
def _mt_minus_asinh_of(t: float, m: float, asinh_t: float) -> float:
    # _mt_minus_asinh(t) given m = √(1 + t²) and asinh t, computed as it computes them (the
    # same operations: bit-identical), so that the branch evaluations call each once.
    if t < 1e-3:
        t2 = t * t
        return t * t2 * (2.0 / 3.0 - t2 / 5.0 + 3.0 * t2 * t2 / 28.0)
    return m * t - asinh_t


@numba.njit(cache=True, nogil=True)
def md_gap_residual(
    b: float, t: float, r_eff: float, e_star: float, w: float, sigma0: float
) -> float:
    """(MD-h) minus h0 [µm]: zero when the gap at the end of the Dugdale zone equals h0 = w/σ0.

    ``b`` half-width [µm], ``t`` = √(c² − b²)/b [1], ``w`` [mN/µm], ``sigma0`` [GPa].
    """
    r = 0.5 * r_eff
    a_k = 4.0 * sigma0 / (_PI * e_star)
    m = math.sqrt(1.0 + t * t)
    return (
        b * b * _mt_minus_asinh(t) / (2.0 * r)
        + a_k * b * (t * math.asinh(t) - m * 0.5 * math.log1p(t * t))
        - w / sigma0
    )


@numba.njit(cache=True, nogil=True)
def _md_t(b: float, r_eff: float, e_star: float, w: float, sigma0: float) -> float:
    # (MD-h) is increasing in t from −h0 at t = 0: safeguarded Newton on a bracket.
    r = 0.5 * r_eff
    a_k = 4.0 * sigma0 / (_PI * e_star)
    lo = 0.0
    # Start near the root: the smaller of the roots of the two terms' leading orders
    # (a_k b t²/2 = h0 and b² t³/(3R) = h0), then double until the residual is ≥ 0.
    h0 = w / sigma0
    hi = min(math.sqrt(2.0 * h0 / (a_k * b)), (3.0 * r * h0 / (b * b)) ** (1.0 / 3.0))
    if not hi > 0.0:
        hi = 1.0
    for _ in range(2000):
        if md_gap_residual(b, hi, r_eff, e_star, w, sigma0) >= 0.0:
            break
        lo = hi
        hi *= 2.0
    t = hi
    for _ in range(200):
        g = md_gap_residual(b, t, r_eff, e_star, w, sigma0)
        if g > 0.0:
            hi = t
        else:
            lo = t
        m = math.sqrt(1.0 + t * t)
        dg = b * b * t * t / (r * m) + a_k * b * (math.asinh(t) - t / m * 0.5 * math.log1p(t * t))
        t_new = t - g / dg if dg > 0.0 else 0.5 * (lo + hi)
        if not lo < t_new < hi:
            t_new = 0.5 * (lo + hi)
        if abs(t_new - t) <= 1e-15 * t or hi - lo <= 1e-15 * hi:
            return t_new
        t = t_new
    return t


@numba.njit(cache=True, nogil=True)
def md_branch(
    b: float, r_eff: float, e_star: float, w: float, sigma0: float
) -> tuple[float, float, float]:
    """The Maugis–Dugdale contact of half-width b: (δ [µm], P [mN/µm], c [µm]) by (MD-h),
    (MD-δ), (MD-P)."""
    t = _md_t(b, r_eff, e_star, w, sigma0)
    r = 0.5 * r_eff
    a_k = 4.0 * sigma0 / (_PI * e_star)
    m = math.sqrt(1.0 + t * t)
    delta = b * b / r + a_k * b * (m * math.asinh(t) - t * (2.5 + 0.5 * math.log1p(t * t)))
    force = 0.25 * _PI * e_star * b * b / r - 2.0 * sigma0 * b * t
    return delta, force, b * m


def md_force(half_width: float, outer: float, r_eff: float, e_star: float, sigma0: float) -> float:
    """(MD-P) P = π E* b²/(4R) − 2σ0 √(c² − b²) [mN/µm] for contact half-width b and Dugdale
    zone half-width c [µm]."""
    r = 0.5 * r_eff
    return float(
        0.25 * _PI * e_star * half_width**2 / r
        - 2.0 * sigma0 * math.sqrt(max(outer * outer - half_width * half_width, 0.0))
    )


def md_approach(
    half_width: float, outer: float, r_eff: float, e_star: float, sigma0: float
) -> float:
    """(MD-δ) δ = b²/R + (4σ0/(πE*)) [c·acosh(c/b) − √(c²−b²)(5/2 + ln(c/b))] [µm]."""
    r = 0.5 * r_eff
    k = math.sqrt(max(outer * outer - half_width * half_width, 0.0))
    return float(
        half_width**2 / r
        + 4.0
        * sigma0
        / (_PI * e_star)
        * (outer * math.acosh(outer / half_width) - k * (2.5 + math.log(outer / half_width)))
    )


@numba.njit(cache=True, nogil=True)
def md_noncontact(
    delta: float, r_eff: float, e_star: float, w: float, sigma0: float
) -> tuple[float, float, bool]:
    """Adhesive zone without contact at overlap δ < 0: (P [mN/µm], c [µm], exists).

    The stable root c = αR + √(α²R² + 2R(h0 + δ)) of δ = c²/(2R) − αc − h0; ``exists`` is
    False below the fold δ = −h0 − α²R/2. Whether the surfaces already touch is left to the
    caller (δ ≥ −a_k c (5/2 − ln 2)).
    """
    r = 0.5 * r_eff
    alpha = 4.0 * sigma0 / (_PI * e_star) * (2.5 - 2.0 * math.log(2.0))
    disc = alpha * alpha * r * r + 2.0 * r * (w / sigma0 + delta)
    if disc < 0.0:
        return 0.0, 0.0, False
    c = alpha * r + math.sqrt(disc)
    return -2.0 * sigma0 * c, c, True


@numba.njit(cache=True, nogil=True)
def _md_branch_point(
    t: float, r_eff: float, e_star: float, w: float, sigma0: float
) -> tuple[float, float, float, float, float, float, float, float, float, float]:
    # The contact branch parametrized by t = √(c² − b²)/b: (MD-h) is a quadratic in b, so
    # b(t), δ(t) and P(t) are closed forms (no nested solve). b decreases as t grows.
    # Returns (b, δ, P) and what the derivative reuses: 1/R, a_k, t/m, ln m, asinh t,
    # √(B² + 4A h0) and g = m asinh t − t (5/2 + ln m) (δ = b²/R + a_k b g). asinh t is
    # log1p(t + t²/(1 + m)) with m = √(1 + t²) at hand; 1/R multiplies (R = R_eff/2).
    inv_r = 2.0 / r_eff
    a_k = 4.0 * sigma0 / (_PI * e_star)
    h0 = w / sigma0
    tt = t * t
    m = math.sqrt(1.0 + tt)
    log_m = 0.5 * math.log1p(tt)
    asinh_t = math.log1p(t + tt / (1.0 + m))
    big_a = _mt_minus_asinh_of(t, m, asinh_t) / r_eff
    big_b = a_k * (t * asinh_t - m * log_m)
    root = math.sqrt(big_b * big_b + 4.0 * big_a * h0)
    b = 2.0 * h0 / (big_b + root)
    g = m * asinh_t - t * (2.5 + log_m)
    bb_r = b * b * inv_r
    delta = bb_r + a_k * b * g
    force = 0.25 * _PI * e_star * bb_r - 2.0 * sigma0 * b * t
    return b, delta, force, inv_r, a_k, t / m, log_m, asinh_t, root, g


@numba.njit(cache=True, nogil=True)
def _md_of_t(
    t: float, r_eff: float, e_star: float, w: float, sigma0: float
) -> tuple[float, float, float]:
    # (b, δ, P) on the contact branch at t.
    point = _md_branch_point(t, r_eff, e_star, w, sigma0)
    return point[0], point[1], point[2]


@numba.njit(cache=True, nogil=True)
def _md_of_t_d(
    t: float, r_eff: float, e_star: float, w: float, sigma0: float
) -> tuple[float, float, float, float, float]:
    # (b, δ, P, dδ/d ln t, db/d ln t) on the contact branch: _md_of_t with the analytic derivative
    # (same transcendental functions). With A = (m t − asinh t)/(2R), B = a_k (t asinh t − m ln m),
    # A b² + B b = h0 gives b' = −(A' b² + B' b)/(2A b + B), A' = t²/(m R),
    # B' = a_k (asinh t − (t/m) ln m); g = m asinh t − t (5/2 + ln m) has
    # g' = (t/m) asinh t − 3/2 − ln m − t²/m², and δ = b²/R + a_k b g.
    b, delta, force, inv_r, a_k, t_m, log_m, asinh_t, root, g = _md_branch_point(
        t, r_eff, e_star, w, sigma0
    )
    d_a = t * t_m * inv_r
    d_b = a_k * (asinh_t - t_m * log_m)
    d_bt = -(d_a * b * b + d_b * b) / root  # 2A b + B = √(B² + 4A h0) at the root
    d_g = t_m * asinh_t - 1.5 - log_m - t_m * t_m
    d_delta = (2.0 * b * inv_r + a_k * g) * d_bt + a_k * b * d_g
    return b, delta, force, t * d_delta, t * d_bt


_LOG_T_MIN = math.log(1e-9)
_LOG_T_MAX = math.log(1e9)


@numba.njit(cache=True, nogil=True)
def _md_fold_flat(
    x0: float, x1: float, r_eff: float, e_star: float, w: float, sigma0: float
) -> tuple[float, float]:
    # dδ/d ln t was ≤ 0 at every bracket point up to the largest t: δ falls all the way to
    # b → 0 (DMT-like), or its fold is so shallow (λ just below ≈ 0.5: δ rises by ~1e-11 |δ|
    # after it, over a few e-folds) that the expanding bracket stepped over it. The smallest δ
    # on a grid of 1/4 in x = ln t over [x0, x1], then golden-section search between its grid
    # neighbours (δ is unimodal there), to 1e-6 in ln t: δ is flat at its minimum, so δ_f is
    # then its minimum to rounding.
    n = max(math.ceil((x1 - x0) / 0.25), 2)
    h = (x1 - x0) / n
    best = n
    d_best = _md_of_t(math.exp(x1), r_eff, e_star, w, sigma0)[1]
    for i in range(n):
        d = _md_of_t(math.exp(x0 + i * h), r_eff, e_star, w, sigma0)[1]
        if d < d_best:
            best = i
            d_best = d
    if best == n:
        return math.exp(x1), d_best
    a = x0 + max(best - 1, 0) * h
    c = x0 + (best + 1) * h
    ratio = 0.5 * (math.sqrt(5.0) - 1.0)
    p = c - ratio * (c - a)
    q = a + ratio * (c - a)
    d_p = _md_of_t(math.exp(p), r_eff, e_star, w, sigma0)[1]
    d_q = _md_of_t(math.exp(q), r_eff, e_star, w, sigma0)[1]
    for _ in range(80):
        if c - a < 1e-6:
            break
        if d_p <= d_q:
            c = q
            q = p
            d_q = d_p
            p = c - ratio * (c - a)
            d_p = _md_of_t(math.exp(p), r_eff, e_star, w, sigma0)[1]
        else:
            a = p
            p = q
            d_p = d_q
            q = a + ratio * (c - a)
            d_q = _md_of_t(math.exp(q), r_eff, e_star, w, sigma0)[1]
    if d_p <= d_q:
        return math.exp(p), d_p
    return math.exp(q), d_q


@numba.njit(cache=True, nogil=True)
def _md_fold_t(r_eff: float, e_star: float, w: float, sigma0: float) -> tuple[float, float]:
    # (t_f, δ_f): the minimum of δ(t), where dδ/d ln t changes sign from − to + (δ falls then
    # rises). The fold's t depends on Maugis' λ alone, t_f ≈ 2.03/λ for λ ≫ 1: the sign
    # change is bracketed around that guess and found by Illinois on the analytic derivative.
    # A monotone (DMT-like) branch, still falling at the largest t searched (b → 0), has it
    # there, where it meets the branch without contact.
    lo = _LOG_T_MIN
    hi = _LOG_T_MAX
    lam = 2.0 * sigma0 * (0.5 * r_eff / (_PI * w * e_star * e_star)) ** (1.0 / 3.0)
    # t_f λ → 2.03 as λ → ∞ and diverges as λ falls to ≈ 0.47 (the fold disappears): a rough
    # fit of the two ends, only the centre of the first bracket.
    excess = lam - 0.47
    guess = 2.03 / lam + (1.5 / (excess * excess) if excess > 0.05 else 600.0)
    centre = min(max(math.log(guess), lo), hi)
    width = 0.25
    a = max(centre - width, lo)
    fa = _md_of_t_d(math.exp(a), r_eff, e_star, w, sigma0)[3]
    c = min(centre + width, hi)
    fc = _md_of_t_d(math.exp(c), r_eff, e_star, w, sigma0)[3]
    for _ in range(100):
        if fa < 0.0 and fc > 0.0:
            break
        width *= 4.0
        if fa >= 0.0:  # the fold is left of a
            if a <= lo:
                t_lo = math.exp(lo)
                return t_lo, _md_of_t(t_lo, r_eff, e_star, w, sigma0)[1]
            c = a
            fc = fa
            a = max(centre - width, lo)
            fa = _md_of_t_d(math.exp(a), r_eff, e_star, w, sigma0)[3]
        else:  # fc ≤ 0: the fold is right of c
            if c >= hi:
                return _md_fold_flat(a, hi, r_eff, e_star, w, sigma0)
            a = c
            fa = fc
            c = min(centre + width, hi)
            fc = _md_of_t_d(math.exp(c), r_eff, e_star, w, sigma0)[3]
    side = 0
    x = 0.5 * (a + c)
    for _ in range(200):
        x = (a * fc - c * fa) / (fc - fa)
        if not a < x < c:
            x = 0.5 * (a + c)
        _, d, _, f, _ = _md_of_t_d(math.exp(x), r_eff, e_star, w, sigma0)
        if abs(f) <= 1e-13 * abs(d):  # flat to rounding: δ is its minimum to ~1e-26 relative
            break
        if f < 0.0:
            a = x
            fa = f
            if side == 1:
                fc *= 0.5
            side = 1
        else:
            c = x
            fc = f
            if side == -1:
                fa *= 0.5
            side = -1
        if c - a < 1e-12:
            break
    t_f = math.exp(x)
    return t_f, _md_of_t(t_f, r_eff, e_star, w, sigma0)[1]


@numba.njit(cache=True, nogil=True)
def md_fold(r_eff: float, e_star: float, w: float, sigma0: float) -> tuple[float, float]:
    """Fold of the contact branch, (b_f [µm], δ_f [µm]): the minimum of δ(b). A monotone branch
    (DMT-like) gives b_f ≈ 0 and δ_f = δ(0⁺), where it meets the branch without contact."""
    t_f, d_f = _md_fold_t(r_eff, e_star, w, sigma0)
    return _md_of_t(t_f, r_eff, e_star, w, sigma0)[0], d_f
