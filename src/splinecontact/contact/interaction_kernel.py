"""The interacting loading as one compiled loop over displacement steps.

Every step of :func:`splinecontact.contact.interaction.interacting_loading` — the eq. 9
acceptance, the warm start, the outer width loop, the particle–mesh operator (spreading, FFT
convolution on the mesh, near-field corrections), the constrained conjugate gradients of
Polonsky & Keer (Wear 231 (1999) 206–219) at contact level, the punch widths, the tangential
springs (eqs. 11–13) and the per-step sums (eq. 14) — runs here without returning to Python.

The mesh convolution is the package's compiled real-FFT circulant product
(``splinecontact._fft.circulant``); the mesh kernel and the transform's tables of every
mesh size are computed on first use and cached in a typed list. Steps with at most
``DENSE_CONTACTS`` contacts assemble the operator as a matrix (mesh coupling of every pair and
the exact near pairs) and convolve the mesh once, for the surface's rise.
"""

from __future__ import annotations

import math

import numba
import numpy as np
from numba.typed import List
from numpy.typing import NDArray

from .._fft import CirculantConvolution, circulant
from .halfplane import (
    CELLS_PER_SOURCE,
    NEAR_CELLS,
    NEAR_WIDTHS,
    _collect,
    _dense_coupling,
    _near_lists,
    _near_pairs,
    _pk_direction,
    _pk_update,
    _spread,
    mesh_kernel,
)
from .interaction import UPLIFT_FACTOR, _accept
from .interaction_laws import (
    _FD_STEP,
    _HALVINGS,
    _JUMP_AFTER,
    _MAX_NEWTON,
    LAW_TOL_FLOOR,
    commit_rows,
    law_bound,
    law_evaluate,
    law_widths,
    newton_rhs,
    newton_scale,
    release_dropped,
    release_unstable,
)
from .laws import HERTZ
from .punch import _profile_widths

__all__ = ["mesh_cache", "run_steps"]

_QUARTER_PI = 0.25 * math.pi

#: Conjugate-gradient iterations per solve.
_MAX_INNER = 10_000

#: Entries per mesh level in the kernel cache: the mesh kernel, then the arrays of the compiled
#: circulant product on the mesh (:attr:`splinecontact._fft.CirculantConvolution.arguments`,
#: its two integer sizes stored as one array).
_PER_LEVEL = 17

#: Smallest mesh: 2**_MIN_LEVEL cells.
_MIN_LEVEL = 6

#: Steps with at most this many accepted contacts apply the particle–mesh operator as a
#: matrix (the mesh coupling of every pair plus the near corrections, built once per width
#: update) instead of spreading and convolving at every conjugate-gradient iteration; the
#: mesh field is then convolved once, for the converged loads [1].
DENSE_CONTACTS = 512


def mesh_cache(max_cells: int) -> List:
    """An empty kernel cache for meshes of 64 … ``max_cells`` cells (filled on first use)."""
    levels = int(math.log2(max_cells)) + 1
    cache = List()
    for _ in range(levels * _PER_LEVEL):
        cache.append(np.zeros(0))
    return cache


def _mesh_level(
    cells: int, period: float, e_star: float
) -> tuple[NDArray[np.float64], NDArray[np.int64]]:
    """The arrays of one cache level, concatenated, and their offsets (``_PER_LEVEL`` + 1)."""
    green = mesh_kernel(cells, period, e_star)
    # the mesh kernel is real and even, so its spectrum is real
    product = CirculantConvolution(np.ascontiguousarray(np.fft.rfft(green).real), cells)
    parts = [green]
    for value in product.arguments:
        if isinstance(value, np.ndarray):
            parts.append(value)
        elif len(parts) == 8:  # n1 (n2 follows): one array of both
            parts.append(np.array([product.n1, product.n2], dtype=np.float64))
    offsets = np.zeros(len(parts) + 1, dtype=np.int64)
    offsets[1:] = np.cumsum([part.size for part in parts])
    return np.concatenate(parts).astype(np.float64), offsets


@numba.njit(cache=True)
def _level(cache, cells: int, period: float, e_star: float) -> int:  # pragma: no cover
    """Index of the mesh of ``cells`` cells in ``cache``, computing its kernels on first use.

    The mesh kernel is the periodic Green function at the cell offsets minus the mean
    smoothing h²/6 · G″ of linear spreading and reading (:func:`.halfplane.mesh_kernel`).
    """
    level = 0
    while (1 << level) < cells:
        level += 1
    base = level * _PER_LEVEL
    if cache[base].size == 0:
        with numba.objmode(flat="float64[::1]", offsets="int64[::1]"):
            flat, offsets = _mesh_level(cells, period, e_star)
        for k in range(_PER_LEVEL):
            cache[base + k] = flat[offsets[k] : offsets[k + 1]]
    return base


@numba.njit(cache=True)
def _convolve(
    cache, base: int, rho: NDArray[np.float64]
) -> NDArray[np.float64]:  # pragma: no cover
    """Periodic convolution of the mesh loads with the mesh kernel (compiled real FFT)."""
    phi = np.empty(rho.size)
    dims = cache[base + 8]
    circulant(
        rho, phi, cache[base + 1], cache[base + 2], cache[base + 3], cache[base + 4],
        cache[base + 5], cache[base + 6], cache[base + 7], int(dims[0]), int(dims[1]),
        cache[base + 9], cache[base + 10], cache[base + 11], cache[base + 12],
        cache[base + 13], cache[base + 14], cache[base + 15], cache[base + 16],
    )  # fmt: skip
    return phi


@numba.njit(cache=True)
def _apply(
    cache, base: int, load: NDArray[np.float64], local: float, ez: NDArray[np.float64], op: tuple
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:  # pragma: no cover - compiled
    """(local·P + e_z w(P) at the contacts, the mesh displacement).

    ``op`` = (source positions [µm], their contacts, their e_z, mesh spacing [µm], near-pair
    CSR start, sources and corrections) of the step.
    """
    pos, owner, ez_src, h, start, src, coef = op
    cells = cache[base].size
    q, rho = _spread(load, owner, ez_src, pos, cells, h)
    phi = _convolve(cache, base, rho)
    u = _collect(phi, pos, load.size, h, start, src, coef, q, load, ez, local)
    return u, phi


@numba.njit(cache=True)
def _operate(
    cache, base: int, load: NDArray[np.float64], local: float, ez: NDArray[np.float64], op: tuple
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:  # pragma: no cover - compiled
    """:func:`_apply`, or with the operator as a matrix (``op`` = (the operands of
    :func:`_apply`, Kᵀ of :func:`.halfplane._dense_coupling` or an empty matrix)) the same
    local·P + e_z Kᵀ P without the mesh displacement (empty)."""
    dense = op[7]
    if dense.shape[0] == 0:
        return _apply(cache, base, load, local, ez, op[:7])
    n = load.size
    w = np.zeros(n)
    for k in range(n):
        p = load[k]
        if p != 0.0:
            row = dense[k]
            for i in range(n):
                w[i] += row[i] * p
    for i in range(n):
        w[i] = local * load[i] + ez[i] * w[i]
    return w, np.zeros(0)


@numba.njit(cache=True)
def _pk_solve(
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
) -> tuple[NDArray[np.float64], int, float, NDArray[np.float64]]:  # pragma: no cover
    """Constrained conjugate gradients (Polonsky–Keer, displacement control) at contact level.

    Finds P ≥ 0 with h = C P − δ ≥ 0 and P·h = 0 (C at frozen widths). C P is updated
    incrementally while the loaded set does not change, and recomputed before convergence is
    declared (``op`` as :func:`_operate`). Returns (P, iterations, residual, mesh displacement
    of P); iterations −1 when the solve did not converge. A converged P was the last load the
    operator was applied to, so the mesh displacement of that application is the surface
    displacement of the step.
    """
    n = delta.size
    scale = delta.max()
    if scale <= 0.0:
        return np.zeros(n), 0, 0.0, np.zeros(0)
    p = np.maximum(load, 0.0)
    t = np.zeros(n)
    h = np.empty(n)
    g_norm_old = 0.0
    conjugate = False
    largest = -np.inf
    for i in range(n):
        self_part = max(c * (math.log(period / (math.pi * a[i])) - 1.5), 0.0)
        largest = max(largest, 2.0 * c + ez[i] ** 2 * self_part)
    fallback = 1.0 / largest
    local = 2.0 * c
    cp, phi = _operate(cache, base, p, local, ez, op)
    exact = True
    residual = np.inf
    for iteration in range(_MAX_INNER + 1):
        residual, any_loaded, g_norm = _pk_direction(
            p, cp, delta, h, t, conjugate, g_norm_old, scale
        )
        if residual <= tol:
            if exact:
                return p, iteration, residual, phi
            cp, phi = _operate(cache, base, p, local, ez, op)
            exact = True
            continue
        if not any_loaded:
            d = np.maximum(-h, 0.0)
            cd, _ = _operate(cache, base, d, local, ez, op)
            curvature = np.dot(d, cd)
            step = np.dot(d, d) / curvature if curvature > 0.0 else fallback
            p = step * d
            conjugate = False
            cp, phi = _operate(cache, base, p, local, ez, op)
            exact = True
            continue
        g_norm_old = g_norm
        r, _ = _operate(cache, base, t, local, ez, op)
        conjugate, linear = _pk_update(p, cp, r, t, h, fallback)
        if not linear:
            cp, phi = _operate(cache, base, p, local, ez, op)
        exact = not linear
    return p, -1, residual, phi


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
