"""2D Maugis–Dugdale adhesive line contact (Baney & Hui 1997; Johnson & Greenwood 2008).

Conventions as in :mod:`.adhesion` (R = R_eff/2, width √2·b, the 2D approach referred to β
times the half-width of the zone each part of the pressure loads, ``docs/contact-laws.md``).
The branch in closed form and its fold are :mod:`._md_branch`'s; this module evaluates a
contact along a path (state, root, prediction) and defines the law.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numba
import numpy as np
from numpy.typing import NDArray

from ._md_branch import (
    _md_fold_t,
    _md_of_t,
    _md_of_t_d,
    md_approach,
    md_branch,
    md_fold,
    md_force,
    md_gap_residual,
    md_noncontact,
)
from .adhesion import CohesiveZoneLaw

__all__ = [
    "MaugisDugdale",
    "md_approach",
    "md_branch",
    "md_evaluate",
    "md_fold",
    "md_force",
    "md_gap_residual",
    "md_noncontact",
    "tabor_parameter",
]

_PI = math.pi

#: State columns: branch (0 apart, 1 adhesive zone without contact, 2 contact), t of the last
#: step, the fold memo (R_eff [µm], t_f, δ_f [µm]), the memo of the last evaluation (δ [µm],
#: R_eff [µm], branch, t, dδ/d ln t [µm], ln t, d²δ/d(ln t)² [µm], db/d ln t [µm],
#: d²b/d(ln t)² [µm]) and what those second derivatives are estimated from (the last step in
#: ln t, the divided differences of dδ/d ln t and db/d ln t over it [µm], d³δ/d(ln t)³ [µm];
#: 0: not known): the commit reuses the trial, the next step predicts (:func:`_md_predicted`).
N_STATE = 18


@numba.njit(cache=True, nogil=True)
def _md_contact_root(
    delta: float,
    t_f: float,
    d_f: float,
    r_eff: float,
    e_star: float,
    w: float,
    sigma0: float,
    guess: float,
    previous: float,
) -> tuple[float, float, float, float]:
    # δ(t) decreases on (0, t_f]: (t, dδ/d ln t) with δ(t) = δ, by Newton in x = ln t with the
    # analytic derivative, safeguarded by the bracket lo < x < hi it has seen (δ − δ(lo) ≤ 0 ≤
    # δ − δ(hi); hi starts at the fold): a step that leaves it, a non-negative slope (near the
    # fold) or a step of more than 2 bisects or, with no lower end yet, moves 2 left.
    # ``guess`` is the previous step's t or a point predicted from the last evaluation's tangent
    # (``previous`` is then that prediction's length in ln t, 0 when it is no Newton step: the
    # convergence test then waits for one), 0 when cold. Returns t, the
    # slope and db/d ln t of the last evaluation, and ln t.
    x_f = math.log(t_f)
    f_f = d_f - delta
    if f_f >= 0.0:
        return t_f, 0.0, x_f, 0.0
    x = math.log(guess) if 0.0 < guess < t_f else x_f - 1.0
    lo = -700.0
    lo_known = False
    hi = x_f
    slope = 0.0
    d_b = 0.0
    for _ in range(300):
        _, d, _, slope, d_b = _md_of_t_d(math.exp(x), r_eff, e_star, w, sigma0)
        f = d - delta
        # converged: δ met to rounding, and the Newton step that remains is negligible too
        # (near the fold |dδ/d ln t| can be ~1e-8 |δ|, where a residual of 1e-14 |δ| is still
        # a step of 1e-6 in ln t)
        if abs(f) <= 1e-14 * abs(delta) and (slope < 0.0 and abs(f) <= 1e-12 * -slope):
            return math.exp(x), slope, x, d_b
        if f > 0.0:
            lo = x
            lo_known = True
        else:
            hi = x
        if hi - lo <= 1e-13:
            return math.exp(x), slope, x, d_b
        x_new = x - f / slope if slope < 0.0 else x
        step = abs(x_new - x)
        if not (lo < x_new < hi and 0.0 < step <= 2.0):
            x_new = 0.5 * (lo + hi) if lo_known else max(x, hi) - 2.0
            previous = 0.0  # not a Newton step
            x = x_new
            continue
        # Quadratic convergence: the next step would be ≈ step³/previous² (C = step/prev²);
        # below 1e-14 the new point is converged and needs no evaluation of its own.
        if step <= 1e-13 or (step < 1e-2 * previous and step**3 <= 1e-14 * previous**2):
            return math.exp(x_new), slope, x_new, d_b
        previous = step
        x = x_new
    return math.exp(x), slope, x, d_b


@numba.njit(cache=True, nogil=True)
def md_evaluate(
    delta: float,
    r_eff: float,
    e_star: float,
    w: float,
    sigma0: float,
    state: NDArray[np.float64],
) -> tuple[float, float, float, float, float, float, float]:
    """One Maugis–Dugdale contact under displacement control.

    Parameters
    ----------
    delta : float
        Overlap of the undeformed surface spheres δ [µm] (eq. 10; < 0 at a gap).
    r_eff, e_star, w, sigma0 : float
        R_eff [µm], E* [GPa], work of adhesion [mN/µm], Dugdale stress [GPa].
    state : ndarray
        The contact's :data:`N_STATE` values. Only memos are written here (the fold, a function
        of R_eff alone, and this evaluation's inputs and result); the caller stores the returned
        branch and t when the step is committed.

    Returns
    -------
    (force, width, branch, t, r_cached, t_fold, delta_fold)
        Force [mN/µm], width √2·b [µm], and the new state values of the first five columns.
    """
    out = _md_evaluate(delta, r_eff, e_star, w, sigma0, state)
    if state.size >= N_STATE:
        state[5] = delta
        state[6] = r_eff
        state[7] = out[2]
        state[8] = out[3]
        state[9] = out[7]
        state[10] = out[8]
        state[12] = out[9]
        if not out[10]:  # no new estimates of the derivatives (_md_predicted): not known
            state[11] = 0.0
            state[13:N_STATE] = 0.0
    return out[0], out[1], out[2], out[3], out[4], out[5], out[6]


@numba.njit(cache=True, nogil=True)
def _md_evaluate(
    delta: float,
    r_eff: float,
    e_star: float,
    w: float,
    sigma0: float,
    state: NDArray[np.float64],
) -> tuple[float, float, float, float, float, float, float, float, float, float, bool]:
    """:func:`md_evaluate` without its memo of this evaluation: writes only the fold memo
    (state columns 2–4, a function of R_eff alone) and :func:`_md_predicted`'s estimates, and
    returns, after md_evaluate's seven values, dδ/d ln t [µm] at t, ln t and db/d ln t [µm]
    (0 when not known), and whether the estimates were written (else they are stale)."""
    if w == 0.0:
        f, width = (
            (0.25 * _PI * e_star * delta, math.sqrt(delta * r_eff)) if delta > 0.0 else (0.0, 0.0)
        )
        return f, width, 2.0 if delta > 0.0 else 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, False
    branch = state[0]
    h0 = w / sigma0
    if branch == 0.0 and delta < -h0:  # apart and out of range: nothing to compute
        return 0.0, 0.0, 0.0, 0.0, state[2], state[3], state[4], 0.0, 0.0, 0.0, False
    if state[2] == r_eff and r_eff > 0.0:
        t_f = state[3]
        d_f = state[4]
    else:
        t_f, d_f = _md_fold_t(r_eff, e_star, w, sigma0)
        # Memo of a pure function of R_eff (not history): a trial evaluation may keep it.
        state[2] = r_eff
        state[3] = t_f
        state[4] = d_f
    in_contact = branch == 2.0 and delta >= d_f
    if not in_contact:
        a_k = 4.0 * sigma0 / (_PI * e_star)
        force, c, exists = md_noncontact(delta, r_eff, e_star, w, sigma0)
        if exists and delta < -a_k * c * (2.5 - math.log(2.0)):
            # adhesive zone, gap at x = 0 open
            return force, 0.0, 1.0, 0.0, r_eff, t_f, d_f, 0.0, 0.0, 0.0, False
        if delta < d_f:
            # no zone without contact (below its fold, or it would close the gap) and the contact
            # branch does not reach this δ: apart (a jump-out if it was attached)
            return 0.0, 0.0, 0.0, 0.0, r_eff, t_f, d_f, 0.0, 0.0, 0.0, False
    guess = state[1] if branch == 2.0 else 0.0
    previous = 0.0
    predicted = False
    if (
        branch == 2.0
        and state.size >= N_STATE
        and state[7] == 2.0
        and state[6] == r_eff
        and state[8] > 0.0
        and state[9] < 0.0
    ):
        # The last evaluation was on this contact branch: predict the root from it.
        done, t, b, force, slope, x, d_b = _md_predicted(
            delta, t_f, r_eff, e_star, w, sigma0, state
        )
        if done:
            return force, math.sqrt(2.0) * b, 2.0, t, r_eff, t_f, d_f, slope, x, d_b, True
        # Not converged: Newton goes on from the prediction (a Newton step from a known point,
        # so the root's convergence test can use its length).
        if t > 0.0:
            guess = t
            previous = x
        predicted = slope < 0.0  # it evaluated: its estimates of the derivatives are new
    t, slope, x, d_b = _md_contact_root(delta, t_f, d_f, r_eff, e_star, w, sigma0, guess, previous)
    b, _, force = _md_of_t(t, r_eff, e_star, w, sigma0)
    return force, math.sqrt(2.0) * b, 2.0, t, r_eff, t_f, d_f, slope, x, d_b, predicted


#: Largest predicted step in ln t [1] that :func:`_md_predicted` finishes in one evaluation.
_PREDICTED_STEP_MAX = 0.05
#: Bound on the error (in ln t, relative in b) of the root :func:`_md_predicted` accepts.
_PREDICTED_TOL = 1e-14


@numba.njit(cache=True, nogil=True)
def _md_predicted(
    delta: float,
    t_f: float,
    r_eff: float,
    e_star: float,
    w: float,
    sigma0: float,
    state: NDArray[np.float64],
) -> tuple[bool, float, float, float, float, float, float]:
    # The root of δ(x) = δ (x = ln t) on the contact branch in ONE evaluation, from the memo
    # of the last one (δ_k, x_k, δ'_k, b'_k and the estimates below; primes: d/dx):
    # * a cubic prediction x_g = x_k + Δx, δ'_k Δx + δ''_k Δx²/2 + δ'''_k Δx³/6 = δ − δ_k;
    # * one evaluation there (δ_g, δ'_g, b_g, b'_g). Divided differences of δ', b' since x_k
    #   (h = x_g − x_k) and of those since the last step give δ''', b''' and δ'', b'' at x_g
    #   (corrected from the midpoint by h/2 × the third derivative; error ε: that correction's
    #   size plus h² × the sizes of the lower derivatives, power laws in t bounding the 4th);
    # * the root of the quadratic Taylor polynomial of δ at x_g, x* = x_g + Δ with
    #   Δ = −s − δ''s²/(2δ'), s = (δ_g − δ)/δ'_g, and b* = b_g + b'Δ + b''Δ²/2; accepted when
    #   the terms neglected, ≈ ε_δ'' s²/|δ'| + |s|³ (1 + (δ''/δ')² + |δ'''/δ'|) in x and
    #   ε_b'' Δ² + |Δ|³ (|b'| + |b''| + |b'''|) in b (times 10), are below _PREDICTED_TOL
    #   (relative in b), else tried once more from x*; P* is then (MD-P) at b*, t* = e^{x*}.
    # Writes the estimates (state columns 11, 13–17) when it evaluates. Returns (done, t*, b*,
    # P*, δ'_g, x*, b'_g), or where Newton goes on from: (False, t or 0 (none), 0, 0, δ'_g, the
    # length in x of the Newton step to t (0: no Newton step), b'_g).
    slope_k = state[9]
    x_k = state[10]
    curvature_k = state[11]
    third_k = state[17]
    inv_slope_k = 1.0 / slope_k
    p = (delta - state[5]) * inv_slope_k
    dx = p - p * p * (0.5 * curvature_k + third_k * p / 6.0) * inv_slope_k
    dx = p - dx * dx * (0.5 * curvature_k + third_k * dx / 6.0) * inv_slope_k
    x_g = x_k + dx
    t_g = math.exp(x_g)
    if not (abs(dx) <= _PREDICTED_STEP_MAX and t_g < t_f and dx != 0.0):
        # too far for one evaluation: Newton starts from the tangent, if not too far either
        if abs(p) < 0.5:
            return False, state[8] * math.exp(p), 0.0, 0.0, 0.0, abs(p), 0.0
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    b, d, _, slope, d_b = _md_of_t_d(t_g, r_eff, e_star, w, sigma0)
    if not slope < 0.0:
        return False, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    inv_slope = 1.0 / slope
    s = (d - delta) * inv_slope
    h = dx
    h_k = state[14]
    inv_h = 1.0 / h
    curvature_mid = (slope - slope_k) * inv_h
    d2_b_mid = (d_b - state[12]) * inv_h
    if h_k != 0.0 and h + h_k != 0.0:  # (a step back by exactly the last: no difference)
        inv_mid = 2.0 / (h + h_k)
        third = (curvature_mid - state[15]) * inv_mid
        third_b = (d2_b_mid - state[16]) * inv_mid
        # the correction from the midpoint, not trusted beyond its size, and the fourth
        # derivatives bounded by the sizes of the lower ones (power laws in t)
        error_curvature = abs(h) * (0.5 * abs(third) + abs(h) * (abs(curvature_mid) - slope))
        error_d2_b = abs(h) * (0.5 * abs(third_b) + abs(h) * (abs(d2_b_mid) + abs(d_b)))
    else:  # no second difference yet: δ'' and b'' known to their size only
        third = 0.0
        third_b = 0.0
        error_curvature = abs(curvature_mid)
        error_d2_b = abs(d2_b_mid)
    curvature = curvature_mid + 0.5 * h * third
    d2_b = d2_b_mid + 0.5 * h * third_b
    state[11] = curvature
    state[13] = d2_b
    state[14] = h
    state[15] = curvature_mid
    state[16] = d2_b_mid
    state[17] = third
    x = x_g
    t = t_g
    a_step = 0.0
    for attempt in range(2):
        if attempt == 1:  # once more from x* (its error, err_x, is small): the same finish
            b, d, _, slope, d_b = _md_of_t_d(t_g, r_eff, e_star, w, sigma0)
            if not slope < 0.0:
                break
            inv_slope = 1.0 / slope
            s = (d - delta) * inv_slope
        ratio = curvature * inv_slope
        step = -s - 0.5 * ratio * s * s
        x = x_g + step
        s2 = s * s
        a_step = abs(step)
        err_x = -error_curvature * s2 * inv_slope + abs(s) * s2 * (
            1.0 + ratio * ratio + abs(third * inv_slope)
        )
        err_b = error_d2_b * step * step + a_step**3 * (abs(d_b) + abs(d2_b) + abs(third_b))
        # t* = t_g e^Δ (the series to Δ³ where the rest is below rounding)
        if a_step < 1e-4:
            t = t_g * (1.0 + step * (1.0 + step * (0.5 + step / 6.0)))
        else:
            t = math.exp(x)
        if not t < t_f:
            break
        if 10.0 * err_x <= _PREDICTED_TOL and 10.0 * err_b <= _PREDICTED_TOL * b:
            b = b + step * (d_b + 0.5 * d2_b * step)
            force = 0.25 * _PI * e_star * b * b * (2.0 / r_eff) - 2.0 * sigma0 * b * t
            return True, t, b, force, slope, x, d_b
        if err_x > 1e-6 or err_b > 1e-6 * b:
            break  # far: Newton's own safeguards
        x_g = x
        t_g = t
    # (its step is no Newton step: the iteration's convergence test waits for one, length 0)
    return False, t if t < t_f else 0.0, 0.0, 0.0, slope, 0.0, d_b


def tabor_parameter(r_eff: float, e_star: float, w: float, sigma0: float) -> float:
    """Maugis' parameter λ = 2σ0 (R/(π w E*²))^{1/3} with R = R_eff/2 [1]: JKR as λ → ∞,
    DMT as λ → 0. ``w`` in mN/µm, ``sigma0`` in GPa."""
    r = 0.5 * r_eff
    return float(2.0 * sigma0 * (r / (_PI * w * e_star * e_star)) ** (1.0 / 3.0))


@dataclass(frozen=True)
class MaugisDugdale(CohesiveZoneLaw):
    """2D Maugis–Dugdale line contact (Baney & Hui 1997; Johnson & Greenwood 2008).

    A Dugdale stress σ0 acts where the gap is below h0 = w/σ0, inside the contact's adhesive zone
    b < |x| < c; before contact the zone |x| < c attracts alone. Spans JKR (λ → ∞) and DMT
    (λ → 0) through :func:`tabor_parameter`.

    Parameters
    ----------
    work_of_adhesion : float
        Work of adhesion w [J/m²] (≥ 0; 0 gives Hertz exactly).
    cohesive_stress : float
        Dugdale stress σ0 [GPa] (> 0).
    """

    code: ClassVar[int] = 3
    name: ClassVar[str] = "maugis-dugdale"
    n_state: ClassVar[int] = N_STATE
    #: The reach depends on the largest R_eff (``bind`` needs it).
    needs_radius: ClassVar[bool] = True

    def reach_for(self, e_star: float, r_eff_max: float) -> float:
        """Deepest separation [µm] at which a contact of R_eff ≤ ``r_eff_max`` still attracts."""
        if self.w == 0.0:
            return 0.0
        sigma0 = float(self.cohesive_stress)
        a_k = 4.0 * sigma0 / (_PI * e_star)
        alpha = a_k * (2.5 - 2.0 * math.log(2.0))
        # The zone without contact has its fold at c = αR, a state with the gap at x = 0 open
        # only for R < h0/(α²/2 + a_k α ln 2); its deepest fold is −h0 − α²R/2 at that R.
        r_open = self.range / (0.5 * alpha * alpha + a_k * alpha * math.log(2.0))
        free_fold = self.range + 0.5 * alpha * alpha * min(0.5 * r_eff_max, r_open)
        _, d_f = md_fold(r_eff_max, e_star, self.w, sigma0)
        return max(free_fold, -float(d_f), 0.0)
