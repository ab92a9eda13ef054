"""The interacting loading as one compiled loop over displacement steps.

Every step of :func:`splinecontact.contact.interaction.interacting_loading` — the eq. 9
acceptance, the warm start, the outer width loop, the particle–mesh operator (spreading, FFT
convolution on the mesh, near-field corrections), the constrained conjugate gradients of
Polonsky & Keer (Wear 231 (1999) 206–219) at contact level, the punch widths, the tangential
springs (eqs. 11–13) and the per-step sums (eq. 14) — runs here without returning to Python.

The operator and the constrained solve live in :mod:`.interaction_operator`, the contact
laws' Newton solve in :mod:`.interaction_laws`. Steps with at most ``DENSE_CONTACTS``
contacts assemble the operator as a matrix (mesh coupling of every pair and the exact near
pairs) and convolve the mesh once, for the surface's rise.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numpy.typing import NDArray

from .halfplane import (
    CELLS_PER_SOURCE,
    NEAR_CELLS,
    NEAR_WIDTHS,
    _dense_coupling,
    _near_lists,
    _near_pairs,
    _spread,
)
from .interaction import UPLIFT_FACTOR, _accept
from .interaction_laws import _law_solve, commit_rows, law_widths, release_dropped
from .interaction_operator import _convolve, _level, _pk_solve, mesh_cache
from .laws import HERTZ
from .punch import _profile_widths

__all__ = ["mesh_cache", "run_steps"]

_QUARTER_PI = 0.25 * math.pi

#: Steps with at most this many accepted contacts apply the particle–mesh operator as a
#: matrix (the mesh coupling of every pair plus the near corrections, built once per width
#: update) instead of spreading and convolving at every conjugate-gradient iteration; the
#: mesh field is then convolved once, for the converged loads [1].
DENSE_CONTACTS = 512


@numba.njit(cache=True, nogil=True)
def _hertz_width(
    load: NDArray[np.float64], reff: NDArray[np.float64], e_star: float, floor: float
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """Hertz half-width √(2 P R_eff/(πE*)) [µm], at least ``floor`` (as :mod:`.punch`)."""
    out = np.empty(load.size)
    for i in range(load.size):
        out[i] = max(math.sqrt(2.0 * max(load[i], 0.0) * reff[i] / (math.pi * e_star)), floor)
    return out


@numba.njit(cache=True, nogil=True)
def _union_length(
    lo: NDArray[np.float64], hi: NDArray[np.float64]
) -> tuple[float, int]:  # pragma: no cover - compiled
    """Length of the union of intervals [lo, hi] and the number of its connected pieces."""
    if lo.size == 0:
        return 0.0, 0
    order = np.argsort(lo, kind="mergesort")
    length = 0.0
    pieces = 0
    first = lo[order[0]]
    reach = hi[order[0]]
    for k in range(1, lo.size):
        o = order[k]
        if lo[o] > reach:
            length += reach - first
            pieces += 1
            first = lo[o]
        reach = max(reach, hi[o])
    length += reach - first
    return length, pieces + 1


@numba.njit(cache=True)
def run_steps(
    first: int,
    stop: int,
    displacement: NDArray[np.float64],
    closing_gap: NDArray[np.float64],
    reach: float,
    point_x: NDArray[np.float64],
    gap0: NDArray[np.float64],
    kl: NDArray[np.float64],
    ku: NDArray[np.float64],
    mx: NDArray[np.float64],
    mz: NDArray[np.float64],
    nx: NDArray[np.float64],
    nz: NDArray[np.float64],
    dx: float,
    length: float,
    e_star: float,
    g_star: float,
    mu0: float,
    tol: float,
    width_tol: float,
    stop_force: float,
    outer: int,
    mirror: bool,
    mirror_axis: float,
    period: float,
    fixed_cells: int,
    max_cells: int,
    profile_width: bool,
    slope: NDArray[np.float64],
    curvature: NDArray[np.float64],
    sines: NDArray[np.float64],
    weights: NDArray[np.float64],
    nodes: NDArray[np.float64],
    qweights: NDArray[np.float64],
    floor: float,
    cache,
    state: NDArray[np.float64],
    field: NDArray[np.float64],
    load_all: NDArray[np.float64],
    older_all: NDArray[np.float64],
    tangential: NDArray[np.float64],
    width_all: NDArray[np.float64],
    shift_all: NDArray[np.float64],
    last_j: NDArray[np.int64],
    idx: NDArray[np.int64],
    delta: NDArray[np.float64],
    ex: NDArray[np.float64],
    ez: NDArray[np.float64],
    reff: NDArray[np.float64],
    offset: NDArray[np.float64],
    offset_z: NDArray[np.float64],
    out_x: NDArray[np.float64],
    out_load: NDArray[np.float64],
    out_ft: NDArray[np.float64],
    curves: NDArray[np.float64],
    counts: NDArray[np.int64],
    law: tuple,
    law_state: NDArray[np.float64],
    law_reach: float,
    cand_point: NDArray[np.int64],
    hold: NDArray[np.bool_] | None = None,
) -> tuple[int, int, float, int]:  # pragma: no cover - compiled
    """Steps ``first`` … ``stop`` − 1 of the interacting loading (SAD eqs. 7–14, coupled).

    ``state`` holds (last increment, uplift margin, mesh spacing of ``field``, cells of
    ``field``, contacts of the last step); the per-contact arrays are the state of
    :func:`.interaction.interacting_loading`. ``curves`` rows: normal force, tangential force,
    contact area, normal-force normal and tangential parts, coalesced length; ``counts`` rows:
    contacts, tilted contacts, patches, CG iterations, reach exceeded. The loop ends after the
    first step whose normal force reaches ``stop_force`` [mN/µm] (> 0; 0: never). Returns
    (count of the last step's accepted contacts, step that failed to converge or −1, its
    residual, the step at which ``stop_force`` was reached or −1). ``curvature`` is not read
    (the punch widths differentiate the interpolated ``slope``); it keeps the argument list.
    ``law`` = (code, kernel parameters, E*): a law other than Hertz takes the nonlinear solve of
    :mod:`.interaction_laws` (its history ``law_state`` per lower grid point, ``cand_point`` the
    candidates' grid points, its reach [µm]); Hertz takes the linear one, unchanged.
    ``hold`` (a mask over the candidates, gap order): every step after step 0 takes the masked
    candidates as its contacts, eq. 9 not tested (the unilateral condition still unloads those
    whose effective approach is ≤ 0), so that the loads are continuous in δ_N.
    """
    c0 = 2.0 / (math.pi * e_star)
    count = 0
    for step in range(first, stop):
        last_increment = state[0]
        margin = state[1]
        field_cell = state[2]
        field_n = int(state[3])
        last_n = int(state[4])
        d = displacement[step]
        increment = d - displacement[step - 1] if step > 0 else 0.0
        lawful = law[0] != HERTZ
        threshold = d + max(margin, law_reach)
        if threshold > reach:
            counts[4, step] = 1
        n_active = np.searchsorted(closing_gap, threshold, side="right")
        if hold is not None and step > 0:  # the held set, whatever eq. 9 says
            n_active = closing_gap.size
        count = _accept(
            d, -max(margin, law_reach), field[:field_n], field_cell, point_x, n_active,
            (gap0, kl, ku, mx, mz, nx, nz), dx, (idx, delta, ex, ez, reff, offset, offset_z),
            hold if step > 0 else None,
            law_reach,
        )  # fmt: skip
        j = idx[:count].copy()
        if lawful:
            release_dropped(law[0], law_state, cand_point, last_j[:last_n].copy(), j)
        previous = np.empty(count)
        older = np.empty(count)
        keep_t = np.empty(count)
        b_start = np.empty(count)
        c_start = np.empty(count)
        for k in range(count):
            previous[k] = load_all[j[k]]
            older[k] = older_all[j[k]]
            keep_t[k] = tangential[j[k]]
            b_start[k] = width_all[j[k]]
            c_start[k] = shift_all[j[k]]
        for k in range(last_n):
            older_all[last_j[k]] = 0.0
        for k in range(count):
            older_all[j[k]] = previous[k]
        for k in range(last_n):
            s = last_j[k]
            load_all[s] = 0.0
            tangential[s] = 0.0
            width_all[s] = 0.0
            shift_all[s] = 0.0
        last_j[:count] = j
        state[4] = count
        if count == 0:
            continue
        x = np.empty(count)
        for k in range(count):
            x[k] = point_x[j[k]] + offset[k]
        ratio = increment / last_increment if last_increment > 0.0 else 0.0
        guess = np.empty(count)
        for k in range(count):
            if previous[k] > 0.0 and older[k] > 0.0:
                guess[k] = previous[k] + ratio * (previous[k] - older[k])
            else:
                guess[k] = previous[k]
            if previous[k] > 0.0 and guess[k] > 0.0:
                b_start[k] = b_start[k] * math.sqrt(guess[k] / previous[k])
        state[0] = increment
        # --- the contact-level solve with the outer width loop (interaction.solve_contacts)
        dl = delta[:count].copy()
        e_z = ez[:count].copy()
        r_eff = reff[:count].copy()
        load = guess.copy() if lawful else np.maximum(guess, 0.0)
        rows = law_state[cand_point[j]] if lawful else law_state[:0]
        widths = np.zeros(count)
        effective = np.zeros(count)
        held = np.zeros(count, dtype=np.bool_)
        a_fresh = _hertz_width(_QUARTER_PI * e_star * np.maximum(dl, 0.0), r_eff, e_star, floor)
        a = np.empty(count)
        cc = np.empty(count)
        for k in range(count):
            fresh = b_start[k] <= 0.0
            a[k] = a_fresh[k] if fresh else b_start[k]
            cc[k] = 0.0 if fresh else c_start[k]
        total = 0
        phi = np.zeros(0)
        sources = 2 * count if mirror else count
        cells = fixed_cells
        if fixed_cells <= 0:
            wanted = 1 << math.ceil(math.log2(max(CELLS_PER_SOURCE * sources, 64)))
            cells = min(wanted, max_cells)
        base = _level(cache, cells, period, e_star)
        h_mesh = period / cells
        pos = np.empty(sources)
        a_src = np.empty(sources)
        owner = np.empty(sources, dtype=np.int64)
        ez_src = np.empty(sources)
        start = np.zeros(1, dtype=np.int64)
        src = np.zeros(0, dtype=np.int64)
        coef = np.zeros(0)
        for it in range(outer):
            xc = x + cc
            for k in range(count):
                pos[k] = xc[k]
                a_src[k] = a[k]
                owner[k] = k
                ez_src[k] = e_z[k]
                if mirror:
                    pos[count + k] = mirror_axis - xc[k]
                    a_src[count + k] = a[k]
                    owner[count + k] = k
                    ez_src[count + k] = e_z[k]
            pos = np.mod(pos, period)
            largest = a.max()
            near = min(max(NEAR_CELLS * h_mesh, NEAR_WIDTHS * largest), 0.25 * period)
            if count <= DENSE_CONTACTS:
                lists = _near_lists(pos, count, period, near)
                start, src, _ = lists
                coef = np.zeros(0)
                dense = _dense_coupling(
                    pos, a_src, owner, ez_src, count, period, cache[base], lists, c0, nodes,
                    qweights,
                )  # fmt: skip
            else:
                start, src, coef = _near_pairs(
                    pos, a_src, count, owner, period, cells, near, cache[base], c0, nodes,
                    qweights,
                )  # fmt: skip
                dense = np.zeros((0, 0))
            op = (pos, owner, ez_src, h_mesh, start, src, coef, dense)
            if lawful:
                load, iterations, residual, phi, effective, widths = _law_solve(
                    cache, base, dl, load, tol, e_z, a, period, c0, op, law, rows, r_eff, held
                )
            else:
                load, iterations, residual, phi = _pk_solve(
                    cache, base, dl, load, tol, e_z, a, period, c0, op
                )
            if iterations < 0:
                return count, step, residual, -1
            total += iterations
            a_new = _hertz_width(load, r_eff, e_star, floor)
            c_new = np.zeros(count)
            if lawful:
                a_new = law_widths(widths, load, r_eff, e_star, floor)
            elif profile_width:
                src_q = np.empty(sources)
                for s in range(sources):
                    src_q[s] = ez_src[s] * load[owner[s]]
                b, c_new = _profile_widths(
                    load, a_new, x, a, cc, slope, dx, e_star, sines, weights,
                    start, src, pos, a_src, src_q, period, width_tol,
                )  # fmt: skip
                a_new = np.maximum(b, floor)
            done = True
            anyload = False
            for k in range(count):
                if load[k] > 0.0 or (lawful and load[k] != 0.0):
                    anyload = True
                if abs(a_new[k] - a[k]) + abs(c_new[k] - cc[k]) > width_tol * max(a[k], floor):
                    done = False
            a = a_new
            cc = c_new
            if not anyload or done or it == outer - 1:
                break
        counts[3, step] = total
        on = load > 0.0
        if lawful:
            on = (load != 0.0) | (widths > 0.0)
            commit_rows(law[0], law[1], effective, r_eff, rows, law_state, cand_point[j], held)
            delta[:count] = effective  # the contacts record δ^eff
        for k in range(count):
            width_all[j[k]] = a[k] if on[k] else 0.0
            shift_all[j[k]] = cc[k] if on[k] else 0.0
            x[k] += cc[k]
        if np.any(on):
            # the mesh displacement of the converged loads (the solve's last application; with
            # the operator as a matrix, convolved here)
            if phi.size == 0:
                phi = _convolve(cache, base, _spread(load, owner, ez_src, pos, cells, h_mesh)[1])
            field[: phi.size] = phi
            state[2] = h_mesh
            state[3] = phi.size
            state[1] = UPLIFT_FACTOR * max(0.0, -phi.min())
        # tangential springs (eqs. 11–13) on loaded contacts, reset where unloaded
        fn_n = 0.0
        fn_t = 0.0
        f_norm = 0.0
        f_tan = 0.0
        area = 0.0
        n_on = 0
        n_in = 0
        n_tilted = 0
        lo = np.empty(count)
        hi = np.empty(count)
        for k in range(count):
            f_n = load[k]
            e_x = ex[k]
            f_t = keep_t[k] - g_star * increment * e_x if previous[k] > 0.0 else 0.0
            cap = mu0 * max(f_n, 0.0)  # an adhesive (tensile) contact carries no friction
            f_t = min(max(f_t, -cap), cap)
            if not on[k]:
                f_t = 0.0
            load_all[j[k]] = f_n
            tangential[j[k]] = f_t
            out_x[k] = x[k]
            out_load[k] = f_n
            out_ft[k] = f_t
            if on[k]:
                fn_n += f_n * e_z[k]
                fn_t += -f_t * e_x
                f_norm += f_n * e_z[k] + -f_t * e_x
                f_tan += f_n * e_x + f_t * e_z[k]
                half = a[k]
                if lawful:
                    area += widths[k]
                    half = widths[k] / math.sqrt(2.0)
                else:
                    area += math.sqrt(f_n / (_QUARTER_PI * e_star) * r_eff[k])
                if half > 0.0:
                    lo[n_in] = min(max(x[k] - half, 0.0), length)
                    hi[n_in] = min(max(x[k] + half, 0.0), length)
                    n_in += 1
                n_on += 1
                if e_z[k] < 0.0:
                    n_tilted += 1
        curves[0, step] = f_norm
        curves[1, step] = f_tan
        curves[2, step] = area
        curves[3, step] = fn_n
        curves[4, step] = fn_t
        union, pieces = _union_length(lo[:n_in], hi[:n_in])
        curves[5, step] = union
        counts[0, step] = n_on
        counts[1, step] = n_tilted
        counts[2, step] = pieces
        if stop_force > 0.0 and f_norm >= stop_force:
            return count, -1, 0.0, step
    return count, -1, 0.0, -1
