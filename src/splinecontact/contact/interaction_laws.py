"""Every contact law with interacting contacts: the nonlinear contact-level solve.

With SAD's Hertz law (eq. 10) the coupled contacts of :mod:`.interaction` are a linear
complementarity problem, solved by the constrained conjugate gradients of Polonsky & Keer
(Wear 231 (1999) 206–219). With another law (:mod:`splinecontact.contact.laws`: JKR, DMT,
Maugis–Dugdale, the elastic–plastic law) every contact's load is its law's force at its
effective approach,

    P_i = f_i(δ_i^eff; state_i),   δ^eff = δ − e_z (C P),

with C the coupling operator of :mod:`.interaction` without eq. 10's local compliance (the
other contacts, the images and the self term c P_i (ln(L_p/(π a_i)) − 3/2)). This module holds
the solve (``_law_solve``, called by :mod:`.interaction_kernel`'s step loop, with the operator
and constrained solve of :mod:`.interaction_operator`):

* **Newton with the law's tangent.** At the loads P^m: δ^eff = δ − C P^m, f_i and the tangent
  stiffness k_i = f_i′ (forward difference of the trial law, :func:`law_evaluate`). The law is
  linearised, f ≈ f^m + k̃ (δ^eff − δ^eff,m), and the linear problem
  (diag(1/k̃) + C) P = diag(1/k̃) f^m + C P^m, P ≥ L, is solved by the same constrained
  conjugate gradients as the Hertz problem: the diagonal is made uniform by scaling contact i
  by s_i = √(k̃_i/k_H) (k_H = (π/4)E*), i.e. C's vertical components e_z by s_i. The stiffness
  is clipped, k̃ = min(max(k, ε k_H), k_H), so the matrix stays positive definite; where k ≤ 0
  (the adhesive laws' softening branches, DMT's attraction at a gap) the iteration is a damped
  fixed point, which converges wherever the coupled equilibrium is stable (1 + S_i k_i > 0 for
  one contact of self compliance S_i). The residual is always the exact law, so the converged
  loads satisfy it to the tolerance whatever k̃.
* **Bounds.** L = 0 for laws without tension (Hertz, elastic–plastic: a contact opens, as in the
  Hertz problem); for the adhesive laws L_i = 2 min(P_i, f_i, 0) + (the JKR and DMT pull-offs
  of the contact's radius), a safeguard below the step's loads that keeps the linear problem's
  shift, hence its scale, near the loads themselves.
* **Damping.** Each Newton step is halved (up to ``_HALVINGS`` times) until ‖P − f‖₂ decreases
  (the full step when no halving does: the law may jump between the iterates).
* **Branches.** A contact is evaluated on the branch its committed state gives (the laws'
  displacement-control rules: stay on a branch while it exists, jump at its fold). Coupling adds
  compliance, so an adhesive contact can lose its stable equilibrium before its law's own fold
  (the coupled fold, 1 + S_i k_i = 0, S_i its self coefficient along e_z), and neighbours can
  push a contact past the end of its branch where its law jumps (no equilibrium is left on the
  branch: the iterates alternate across the jump). Rule: when the solve has not converged
  after ``_JUMP_AFTER`` Newton steps, the tensile contacts past the coupled fold
  (1 + S_i k_i ≤ 0) jump out: their trial state lets go (:func:`.laws.release_law`) and they
  are held apart for the rest of the step (the next step evaluates them afresh on the branch
  they then have); if there is none, the tensile contact of largest misfit |P_i − f_i| does;
  repeated until the solve converges. (A stable equilibrium that the damped iteration does not
  reach in ``_JUMP_AFTER`` steps, 1 + S_i k_i > 0 but small, is treated the same way.) The
  histories of the step are committed only once the step has converged
  (:func:`commit_rows`), as without interaction.
* **Widths.** Each contact's half-width in the neighbour and self relations is its law's own
  (b = width/√2), at least √(2|P| R_eff/(πE*)) (the Hertz width of its load: an adhesive contact
  attracting at a gap has no contact width, but its tension is spread over its cohesive zone)
  and the floor of :mod:`.punch`. Its pressure is taken Hertzian in shape for the far field
  (the pair coefficients of :mod:`.halfplane`), an approximation for JKR's edge singularity and
  the cohesive tractions, whose far fields differ at order (a/ρ)².
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

from .interaction_operator import _MAX_INNER, _operate, _pk_solve
from .laws import HERTZ, commit_law, normal_law, release_law

__all__ = [
    "LAW_TOL_FLOOR",
    "STIFFNESS_FLOOR",
    "commit_rows",
    "law_bound",
    "law_evaluate",
    "law_widths",
    "newton_rhs",
    "newton_scale",
    "release_dropped",
    "release_unstable",
]

_QUARTER_PI = 0.25 * math.pi

#: Lower clip of the tangent stiffness in the Newton matrix, × k_H [1].
STIFFNESS_FLOOR = 1e-2

#: Residual [1] (|P − f|/k_H over the approach scale) below which a law solve that stops
#: improving (by less than half in a Newton step) is accepted although above the tolerance:
#: roundoff of the coupled sums and the laws' own roots (JKR's quartic, Maugis–Dugdale's
#: Newton) stall the residual near 1e−12…1e−10 on rough pairs.
LAW_TOL_FLOOR = 1e-9

#: Newton steps without convergence after which the coupled fold rule lets contacts jump out.
_JUMP_AFTER = 25

#: Most halvings of a Newton step.
_HALVINGS = 6

#: Most Newton steps of one contact-level solve.
_MAX_NEWTON = 400

#: Forward-difference step of the tangent, × the largest |δ| of the step [1].
_FD_STEP = 1e-7

_JKR = 1
_DMT = 2
_MD = 3


@numba.njit(cache=True, nogil=True)
def law_bound(
    code: int, params: NDArray[np.float64], r_eff: NDArray[np.float64]
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Reserve below the loads [mN/µm]: 0 without tension, else −4 × (the 2D JKR and DMT
    pull-offs of R = R_eff/2), below every force the adhesive law gives."""
    out = np.zeros(r_eff.size)
    if code != _JKR and code != _DMT and code != _MD:
        return out
    e_star = params[0]
    w = params[1]
    sigma0 = params[2] if params.size > 2 else 0.0
    for i in range(r_eff.size):
        r = 0.5 * r_eff[i]
        jkr = 3.0 * (math.pi * e_star * r * w * w / 16.0) ** (1.0 / 3.0)
        dmt = 2.0 * math.sqrt(r_eff[i] * w * sigma0)
        out[i] = -4.0 * (jkr + dmt) - 1e-300
    return out


@numba.njit(cache=True, nogil=True)
def law_evaluate(
    code: int,
    params: NDArray[np.float64],
    x: NDArray[np.float64],
    r_eff: NDArray[np.float64],
    rows: NDArray[np.float64],
    step: float,
    force: NDArray[np.float64],
    width: NDArray[np.float64],
    stiffness: NDArray[np.float64],
    held: NDArray[np.bool_],
) -> None:  # pragma: no cover - compiled
    """Trial force [mN/µm], width √2·b [µm] and tangent dF/dδ [GPa] of every contact at the
    effective approaches ``x`` [µm] (``rows``: the contacts' history rows, row i for contact
    i; only memos are written), the tangent by a forward difference of ``step`` [µm]; a contact
    ``held`` apart by the jump rule carries nothing."""
    for i in range(x.size):
        if held[i]:
            force[i] = 0.0
            width[i] = 0.0
            stiffness[i] = 0.0
            continue
        f, b = normal_law(code, params, x[i], r_eff[i], rows, i)
        g, _ = normal_law(code, params, x[i] + step, r_eff[i], rows, i)
        force[i] = f
        width[i] = b
        stiffness[i] = (g - f) / step


@numba.njit(cache=True, nogil=True)
def newton_scale(
    stiffness: NDArray[np.float64], e_star: float
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """s_i = √(k̃_i/k_H), k̃ the tangent clipped to [ε k_H, k_H] (``STIFFNESS_FLOOR`` ε)."""
    k_h = _QUARTER_PI * e_star
    out = np.empty(stiffness.size)
    for i in range(stiffness.size):
        out[i] = math.sqrt(min(max(stiffness[i] / k_h, STIFFNESS_FLOOR), 1.0))
    return out


@numba.njit(cache=True, nogil=True)
def newton_rhs(
    s: NDArray[np.float64],
    force: NDArray[np.float64],
    lower: NDArray[np.float64],
    coupled: NDArray[np.float64],
    coupled_lower: NDArray[np.float64],
    c: float,
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Right-hand side of the scaled Newton problem in Q = (P − L)/s ≥ 0 [mN/µm]:
    s (diag(1/k̃)(f − L) + C P^m − C L), with 1/k̃ = 2c/s² (c = 2/(πE*); ``coupled`` = C P^m,
    ``coupled_lower`` = C L [µm])."""
    out = np.empty(s.size)
    for i in range(s.size):
        out[i] = 2.0 * c * (force[i] - lower[i]) / s[i] + s[i] * (coupled[i] - coupled_lower[i])
    return out


@numba.njit(cache=True, nogil=True)
def release_unstable(
    code: int,
    rows: NDArray[np.float64],
    load: NDArray[np.float64],
    force: NDArray[np.float64],
    stiffness: NDArray[np.float64],
    ez: NDArray[np.float64],
    a: NDArray[np.float64],
    period: float,
    c: float,
    held: NDArray[np.bool_],
) -> int:  # pragma: no cover - compiled
    """The jump rule of a solve that does not converge: the tensile contacts past the coupled
    fold (1 + S_i k_i ≤ 0, S_i = e_z² c (ln(L_p/(π a_i)) − 3/2) [µm per mN/µm]), or if there is
    none the tensile contact of largest misfit |P_i − f_i| (one at a jump of its law, where no
    equilibrium is left on either side), let go (their trial rows, :func:`.laws.release_law`)
    and are held apart for the rest of the step (``held``). Returns the number released (0:
    none tensile)."""
    released = 0
    worst = -1
    largest = -1.0
    for i in range(force.size):
        if held[i] or (force[i] >= 0.0 and load[i] >= 0.0):
            continue
        self_part = max(c * (math.log(period / (math.pi * a[i])) - 1.5), 0.0)
        if 1.0 + ez[i] * ez[i] * self_part * stiffness[i] <= 0.0:
            release_law(code, rows, i)
            held[i] = True  # (DMT has no branch to let go: held apart all the same)
            released += 1
        elif abs(load[i] - force[i]) > largest:
            largest = abs(load[i] - force[i])
            worst = i
    if released == 0 and worst >= 0:
        release_law(code, rows, worst)
        held[worst] = True
        released = 1
    return released


@numba.njit(cache=True, nogil=True)
def law_widths(
    width: NDArray[np.float64],
    load: NDArray[np.float64],
    r_eff: NDArray[np.float64],
    e_star: float,
    floor: float,
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Half-widths [µm] for the coupling: max(b, √(2|P| R_eff/(πE*)), floor), b = width/√2."""
    out = np.empty(width.size)
    for i in range(width.size):
        hertz = math.sqrt(2.0 * abs(load[i]) * r_eff[i] / (math.pi * e_star))
        out[i] = max(width[i] / math.sqrt(2.0), hertz, floor)
    return out


@numba.njit(cache=True, nogil=True)
def commit_rows(
    code: int,
    params: NDArray[np.float64],
    x: NDArray[np.float64],
    r_eff: NDArray[np.float64],
    rows: NDArray[np.float64],
    law_state: NDArray[np.float64],
    points: NDArray[np.int64],
    held: NDArray[np.bool_],
) -> None:  # pragma: no cover - compiled
    """Commit the converged step: each contact's history at its effective approach ``x`` [µm]
    (:func:`.laws.commit_law` on its trial row; a contact ``held`` apart keeps its released
    row), copied to its grid point's row."""
    if rows.shape[1] == 0 or code == HERTZ:
        return
    for i in range(x.size):
        if not held[i]:
            commit_law(code, params, x[i], r_eff[i], rows, i)
        law_state[points[i]] = rows[i]


@numba.njit(cache=True, nogil=True)
def release_dropped(
    code: int,
    law_state: NDArray[np.float64],
    cand_point: NDArray[np.int64],
    last: NDArray[np.int64],
    current: NDArray[np.int64],
) -> None:  # pragma: no cover - compiled
    """Contacts of the previous step (candidate indices ``last``) not accepted now
    (``current``) let go (:func:`.laws.release_law`; a plastic history is kept)."""
    if law_state.shape[1] == 0 or last.size == 0:
        return
    now = np.sort(current)
    for k in range(last.size):
        q = last[k]
        at = np.searchsorted(now, q)
        if at == now.size or now[at] != q:
            release_law(code, law_state, cand_point[q])


@numba.njit(cache=True)
def _law_solve(
    cache,
    base: int,
    delta: NDArray[np.float64],
    load: NDArray[np.float64],
    tol: float,
    ez: NDArray[np.float64],
    a: NDArray[np.float64],
    period: float,
    c: float,
    op: tuple,
    law: tuple,
    rows: NDArray[np.float64],
    r_eff: NDArray[np.float64],
    held: NDArray[np.bool_],
) -> tuple:  # pragma: no cover - compiled
    """P_i = f_i(δ − e_z w(P)) for a law other than Hertz (:mod:`.interaction_laws`): Newton
    steps, each a constrained CG solve (:func:`_pk_solve`, contacts scaled by √(k̃/k_H)).

    ``law`` = (code, kernel parameters, E* [GPa]); ``rows`` the contacts' trial history rows,
    ``held`` the contacts the jump rule holds apart for the step (updated).
    Returns (the law's forces at the converged δ^eff, CG iterations or −1, residual, mesh
    displacement, δ^eff [µm], the law's widths √2·b [µm]).
    """
    code, params, e_star = law
    n = delta.size
    k_h = _QUARTER_PI * e_star
    reserve = law_bound(code, params, r_eff)
    adhesive = reserve.min() < 0.0
    # approach scale: the largest overlap, or the pull-off's approach (δ ≈ 0 at touching)
    scale = max(np.abs(delta).max(), 0.25 * np.abs(reserve).max() / k_h, 1e-300)
    fd = _FD_STEP * scale
    lower = np.zeros(n)
    coupled_lower = np.zeros(n)
    pos, owner, ez_src, h, start, src, coef, dense = op
    p = load.copy()
    force, width, stiffness = np.empty(n), np.empty(n), np.empty(n)
    u, phi = _operate(cache, base, p, 0.0, ez, op)
    law_evaluate(code, params, delta - u, r_eff, rows, fd, force, width, stiffness, held)
    total = 0
    since = 0
    last = np.inf
    for _ in range(_MAX_NEWTON):
        misfit = p - force
        residual = np.abs(misfit).max() / (k_h * scale)
        # converged at tol, or stalled (at roundoff or the laws' own root accuracy) below the
        # floor
        if residual <= tol or (residual <= LAW_TOL_FLOOR and residual > 0.5 * last):
            return force.copy(), total, residual, phi, delta - u, width
        last = residual
        if since >= _JUMP_AFTER:
            if release_unstable(code, rows, p, force, stiffness, ez, a, period, c, held) == 0:
                break
            since = 0
            law_evaluate(code, params, delta - u, r_eff, rows, fd, force, width, stiffness, held)
            continue
        if adhesive:
            # a bound below the loads of the step, never far below them (the shift by the
            # bound sets the scale of the linear solve): twice the most tensile of P and f,
            # and a quarter of the pull-off bound
            lower = 2.0 * np.minimum(np.minimum(p, force), 0.0) + 0.25 * reserve
            coupled_lower, _ = _operate(cache, base, lower, 0.0, ez, op)
        s = newton_scale(stiffness, e_star)
        rhs = newton_rhs(s, force, lower, u, coupled_lower, c)
        # contact i scaled by s_i: sources by s of their contact, the matrix's rows likewise
        # (Kᵀ[j, i] carries source j's e_z), the gathering by ez·s below
        scaled_dense = dense * np.expand_dims(s, 1) if dense.shape[0] else dense
        scaled = (pos, owner, ez_src * s[owner], h, start, src, coef, scaled_dense)
        # inexact Newton: the linear solve to a tenth of the residual (not below 1e−12), its
        # tolerance relative to its right-hand side (a solve stopped at its iteration limit
        # still improves P: the residual is the exact law's)
        wanted = max(min(0.1 * residual, tol), 1e-12) * scale
        inner = min(max(wanted / max(np.abs(rhs).max(), 1e-300), 1e-14), 0.1)
        q, iterations, _, _ = _pk_solve(
            cache, base, rhs, np.maximum(p - lower, 0.0) / s, inner, ez * s, a, period, c, scaled
        )
        total += iterations if iterations >= 0 else _MAX_INNER
        step = lower + s * q - p
        merit = np.dot(misfit, misfit)
        start_p = p
        for halving in range(_HALVINGS + 2):
            # the full step again when no halving lowers ‖P − f‖ (a law's jump between the
            # iterates: the merit is not continuous there)
            lam = 1.0 if halving > _HALVINGS else 0.5**halving
            p = start_p + lam * step
            u, phi = _operate(cache, base, p, 0.0, ez, op)
            law_evaluate(code, params, delta - u, r_eff, rows, fd, force, width, stiffness, held)
            if np.dot(p - force, p - force) < merit or halving > _HALVINGS:
                break
        since += 1
    return force.copy(), -1, np.abs(p - force).max() / (k_h * scale), phi, delta - u, width
