"""Load paths: move the upper body along any sequence of normal and tangential displacements.

A path is a sequence of :class:`Segment`. It starts at zero minimum gap and no tangential shift
(δ_N = 0, u_T = 0, step 0); each segment moves linearly, in ``steps`` equal increments, from the
end of the previous one to its targets:

* ``Segment(normal=δ_N, tangential=u_T, steps=n)`` — displacement control [µm];
* ``Segment(normal_force=F_N, tangential=u_T, steps=n)`` — F_N [mN/µm] is held at every step of
  the segment while u_T moves; δ_N is solved at each step (relative tolerance 1e−9). Where eq. 9
  makes F_N(δ_N) jump across the target, the step's contact cells are fixed through the solve
  (:func:`_consistent_set`, ``docs/friction.md``); ``force_control`` codes the outcome.

``tangential`` omitted keeps the current shift. The upper body shifted by u_T is its spline
evaluated at x − u_T (no re-fit); the tangential springs of eqs. 11–13 follow each contact as
its centre migrates from cell to cell (rule in ``docs/conventions.md``, model in
``docs/friction.md``).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from ..errors import ForceControlError, LoadPathError, ParameterError
from ..profile import Profile
from ..results import ContactRecord, SimulationResult
from ..spline import SplineFit, fit_spline_pair
from . import _force_status as _fs
from . import path_kernel as _k
from ._culling import SPHERE_BLOCK
from ._path_run import run_steps
from .geometry import _place_bodies, displacement_steps
from .laws import ContactLaw, Hertz, check_law, kernel_material, law_record
from .segments import Segment, validate_path

__all__ = ["FORCE_RTOL", "run_path", "simulate_path"]

#: Relative tolerance to which a force-controlled step meets its target F_N.
FORCE_RTOL = 1e-9

#: Block size [points] of the candidate culling.
_BLOCK = 64

#: Sub-block size [points] of a sliding step's candidate runs (divides _BLOCK).
_SUB = 8

#: Blocks per super-block of the candidate culling.
_PER_SUPER = 16

#: Tangential travel [grid spacings] served by one candidate list.
_CHUNK_CELLS = 96


@dataclass(frozen=True, eq=False)
class _Geometry:
    surf: _k.Surfaces
    cull: _k.Culling
    scale: float
    surf_tuple: tuple[Any, ...]  # surf as a plain tuple (see path_kernel.path_step_from_python)


class _State:
    """Spring state (per grid cell), law state and scratch arrays of one path run."""

    def __init__(self, n: int, law: ContactLaw, e_star: float, g_star: float, mu0: float) -> None:
        self.springs = _k.Springs(
            acc=np.zeros(n, dtype=np.bool_),
            # by slot: only the n_committed first are read (no zeroing of 4n words)
            ft=np.empty(n),
            xc=np.empty(n),
            ex=np.empty(n),
            ez=np.empty(n),
            cells=np.empty(n, dtype=np.int64),
            n_committed=np.zeros(1, dtype=np.int64),
            claimed=np.zeros(n, dtype=np.bool_),
        )
        self.material = kernel_material(law, e_star=e_star, g_star=g_star, mu0=mu0, n_points=n)
        # plain-tuple views for the calls from Python (path_kernel.path_step_from_python)
        self.springs_tuple = tuple(self.springs)
        self.material_tuple = tuple(self.material)
        self.cand_idx = np.empty(n, dtype=np.int64)
        self.cand_bound = np.empty(n)
        self.capacity = 0
        self.scratch = _scratch(0)
        self.scratch_tuple: tuple[Any, ...] = ()
        self.ensure(16)

    def ensure(self, capacity: int) -> None:
        if capacity <= self.capacity:
            return
        self.capacity = capacity
        self.scratch = _scratch(capacity)
        self.scratch_tuple = tuple(self.scratch)


def _scratch(capacity: int) -> _k.Scratch:
    return _k.Scratch(
        idx=np.empty(capacity, dtype=np.int64),
        fn=np.empty(capacity),
        ex=np.empty(capacity),
        ez=np.empty(capacity),
        xc=np.empty(capacity),
        z=np.empty(capacity),
        delta=np.empty(capacity),
        reff=np.empty(capacity),
        ft=np.empty(capacity),
        slip=np.empty(capacity, dtype=np.bool_),
        src=np.empty(capacity, dtype=np.int64),
        width=np.empty(capacity),
        cl_i=np.empty(capacity, dtype=np.int64),
        cl_g=np.empty(capacity),
        cl_s1=np.empty(capacity),
        cl_s2=np.empty(capacity),
        cl_kl=np.empty(capacity),
        cl_nx=np.empty(capacity),
        cl_nz=np.empty(capacity),
        # (+16: also the bit-mask scratch of _decide.flag_list, capacity/8 + 8 bytes)
        cl_keep=np.empty(capacity + 16, dtype=np.bool_),
        # a whole number of 8-byte words (the sliding step reads its flags by the word)
        cl_flag=np.empty(capacity + (-capacity) % 8, dtype=np.uint8),
    )


class _Candidates:
    """Points that can touch at shift u_T = u and δ_N ≤ d_max, in grid order.

    Rebuilt at every step (block culling makes that O(n/64) plus the points near contact); the
    arrays are views of buffers shared by the run, valid until the next rebuild.
    """

    def __init__(self, geo: _Geometry, state: _State, u: float, d_max: float) -> None:
        self.u = u
        self.d_max = d_max
        centre = math.floor(-u / geo.surf.dx)
        count = _k.candidate_bounds(
            geo.surf, geo.cull, centre - 1, centre + 1,
            geo.surf.placement - d_max - state.material.reach, state.cand_idx, state.cand_bound,
        )  # fmt: skip
        self.idx = state.cand_idx[:count]
        self.bound = state.cand_bound[:count]


def _prepare(lower: Profile, fit_l: SplineFit, fit_u: SplineFit | None) -> _Geometry:
    dx = lower.dx
    r_min = 0.5 * dx
    n = fit_l.f.size
    flat = fit_u is None
    f_l = np.ascontiguousarray(fit_l.f, dtype=np.float64)
    if fit_u is None:
        f_u = np.zeros(2)
        gamma_u = np.zeros(2)
        slope_u = np.zeros(2)
        curv_u = np.zeros(2)
        # read-only like a fit's arrays, so that the compiled path loop has one specialisation
        # for rough and flat upper bodies (a second one costs ~40 s of compilation)
        for placeholder in (f_u, slope_u, curv_u):
            placeholder.setflags(write=False)
        placement = float(f_l.max())
        envelope = np.zeros(1)
        scale = float(np.abs(f_l).max()) + dx
        f_l_sub = _k.block_max(f_l, _SUB)
        envelope_sub = _k.block_max(envelope, _SUB)
    else:
        f_u = np.ascontiguousarray(fit_u.f, dtype=np.float64)
        slope_u = np.ascontiguousarray(fit_u.slope, dtype=np.float64)
        curv_u = np.ascontiguousarray(fit_u.second_derivative, dtype=np.float64)
        # γ = f″·dx², the interval envelope, the sub-block maxima, max(f^u + f^l) and the scale
        gamma_u, envelope, f_l_sub, envelope_sub, top, abs_sum = _k.upper_maxima(
            f_l, f_u, curv_u, dx, _SUB
        )
        placement = float(top)
        scale = float(abs_sum) + dx
    # maxima of blocks of _BLOCK // _SUB sub-blocks (the same values as over the points)
    f_l_block = _k.block_max(f_l_sub, _BLOCK // _SUB)
    envelope_block = _k.block_max(envelope_sub, _BLOCK // _SUB)
    surf = _k.Surfaces(
        f_l=f_l,
        kappa_l=np.empty(n),  # lazily evaluated (_culling.fill_spheres)
        nl_x=np.empty(n),
        nl_z=np.empty(n),
        f_u=f_u,
        gamma_u=gamma_u,
        slope_u=slope_u,
        curv_u=curv_u,
        flat=flat,
        placement=placement,
        dx=dx,
        kappa_max=1.0 / r_min,
        slope_l=np.ascontiguousarray(fit_l.slope, dtype=np.float64),
        curv_l=np.ascontiguousarray(fit_l.second_derivative, dtype=np.float64),
        sphere_done=np.zeros((n + SPHERE_BLOCK - 1) // SPHERE_BLOCK, dtype=np.uint8),
    )
    cull = _k.Culling(
        f_l_block=f_l_block,
        envelope=envelope,
        envelope_block=envelope_block,
        block=_BLOCK,
        f_l_super=_k.block_max(f_l_block, _PER_SUPER),
        envelope_super=_k.block_max(envelope_block, _PER_SUPER),
        per_super=_PER_SUPER,
        margin=1e-12 * scale,
        f_l_sub=f_l_sub,
        envelope_sub=envelope_sub,
        sub=_SUB,
    )
    return _Geometry(surf=surf, cull=cull, scale=scale, surf_tuple=tuple(surf))


def _step(
    geo: _Geometry,
    cands: _Candidates,
    state: _State,
    u: float,
    d: float,
    du: float,
    dd: float,
    commit: bool,
    fixed: NDArray[np.bool_] | None = None,
    migrate: int | None = None,
) -> _k.StepSums:
    state.ensure(cands.idx.size + 1)
    if migrate is None:
        migrate = _migrate_cells(geo, du, dd)
    return _k.StepSums(
        *_k.path_step_from_python(
            u, d, du, dd, commit, geo.surf_tuple, cands.idx, cands.bound, state.material_tuple,
            migrate, state.springs_tuple, state.scratch_tuple,
            state.springs.claimed if fixed is None else fixed, fixed is not None,
        )
    )  # fmt: skip


def _migrate_cells(geo: _Geometry, du: float, dd: float) -> int:
    """The migration window [cells] of a step (path_kernel.migrate_cells_of, run as Python)."""
    return int(_k.migrate_cells_of.py_func(du, dd, geo.surf.dx, geo.surf.f_l.size))


#: The per-step sums of :func:`.path_kernel.path_step`, in table column order.
_NAMES = _k.StepSums._fields


def _solve_force(
    target: float,
    evaluate: Any,
    d_start: float,
    scale: float,
) -> tuple[float, tuple[Any, ...], float, float]:
    """δ_N with F_N(δ_N) = target (bracketing, then Illinois regula falsi with bisection).

    Returns δ_N, the evaluation there, and the final bracket (lo, hi) with F_N(lo) < target ≤
    F_N(hi); lo = hi = δ_N when the target was met to ``FORCE_RTOL``.
    """
    f_start = evaluate(d_start)
    r_start = f_start[0] - target
    if abs(r_start) <= FORCE_RTOL * target:
        return d_start, f_start, d_start, d_start
    step = max(1e-6 * scale, 1e-3 * abs(d_start), 1e-12)
    direction = 1.0 if r_start < 0 else -1.0
    a, ra, fa = d_start, r_start, f_start
    limit = 2.0 * scale  # beyond this the bodies interpenetrate over their full height
    while True:
        b = a + direction * step
        if abs(b) > limit:
            b = math.copysign(limit, b)
        fb = evaluate(b)
        rb = fb[0] - target
        if (rb > 0) != (ra > 0) or rb == 0:
            break
        if abs(b) >= limit:
            raise ForceControlError(
                f"normal_force = {target!r} mN/µm cannot be reached: F_N is {fb[0]!r} mN/µm "
                f"at δ_N = {b!r} µm, where the bodies overlap over their full height; lower "
                "the target or check the profiles"
            )
        a, ra, fa = b, rb, fb
        step *= 2.0
    # Keep lo (F_N < target) and hi (F_N ≥ target).
    if ra < 0:
        lo, r_lo, f_lo, hi, r_hi, f_hi = a, ra, fa, b, rb, fb
    else:
        lo, r_lo, f_lo, hi, r_hi, f_hi = b, rb, fb, a, ra, fa
    side = 0
    for iteration in range(400):
        if abs(r_hi) <= FORCE_RTOL * target:
            return hi, f_hi, hi, hi
        if abs(r_lo) <= FORCE_RTOL * target:
            return lo, f_lo, lo, lo
        width = abs(hi - lo)
        if width <= 4.0 * np.spacing(max(abs(hi), abs(lo), 1e-300)):
            break
        if iteration % 3 == 2:
            mid = 0.5 * (lo + hi)
        else:
            w_lo = r_hi * (0.5 if side == 1 else 1.0)
            w_hi = r_lo * (0.5 if side == -1 else 1.0)
            mid = (lo * w_lo - hi * w_hi) / (w_lo - w_hi)
            if not min(lo, hi) < mid < max(lo, hi):
                mid = 0.5 * (lo + hi)
        fm = evaluate(mid)
        rm = fm[0] - target
        if rm < 0:
            lo, r_lo, f_lo = mid, rm, fm
            side = -1
        else:
            hi, r_hi, f_hi = mid, rm, fm
            side = 1
    # F_N jumps across the remaining bracket (a contact appears or vanishes within one ulp of
    # δ_N): no δ_N carries the target. Take the side closer to it; the miss stays visible as
    # normal_force − normal_force_target in the output.
    if abs(r_lo) < abs(r_hi):
        return lo, f_lo, lo, hi
    return hi, f_hi, lo, hi


def _accepted_cells(evaluate: Any, state: _State, d: float) -> NDArray[np.int64]:
    """The cells that eq. 9 accepts at δ_N = d (a trial evaluation)."""
    n_c = int(evaluate(d)[3])
    return state.scratch.idx[:n_c].copy()


def _consistent_set(
    target: float,
    evaluate: Any,
    state: _State,
    bracket: tuple[float, float],
    d_miss: float,
    scale: float,
    window_of: Any,
) -> tuple[float, NDArray[np.bool_] | None, int | None, int]:
    """δ_N holding F_N = target when the free F_N(δ_N) jumps across it (see docs/friction.md).

    With the contact cells and the migration window fixed, F_N(δ_N) is continuous (contacts
    appear at zero overlap) and the target is met. The cells that eq. 9 accepts on each side of
    the jump are tried in turn (the side below the target first), the window being the one of
    the step's solved Δδ_N (iterated to a fixed point); a set is consistent when eq. 9 accepts
    exactly it at the δ_N that carries the target with it, and the step is then the free model
    at that δ_N. If neither side is consistent, the target lies in a true jump of the model;
    the set of the side below the target is kept through the step, which holds F_N.

    Returns δ_N, the fixed cells, the window (``None``, ``None``: the free miss, kept) and the
    step's ``force_control`` code (:mod:`._force_status`: 1 consistent, 2 held, 3 missed).
    """
    n = state.springs.acc.size
    fallback: tuple[float, NDArray[np.bool_], int] | None = None
    for side in bracket:
        cells = _accepted_cells(evaluate, state, side)
        fixed = np.zeros(n, dtype=np.bool_)
        fixed[cells] = True
        next_window = window_of(side)
        solved = False
        d = side
        window = next_window
        for _ in range(4):
            window = next_window
            try:
                d, _, lo, hi = _solve_force(
                    target, lambda trial, _f=fixed, _w=window: evaluate(trial, _f, _w), side, scale
                )
            except ForceControlError:
                break
            solved = lo == hi
            next_window = window_of(d)
            if not solved or next_window == window:
                break
        if not solved:
            continue
        if np.array_equal(_accepted_cells(evaluate, state, d), cells):
            return d, fixed, window, _fs.HELD
        if fallback is None:
            fallback = (d, fixed, window)
    if fallback is not None:
        return (*fallback, _fs.HELD_FIXED_SET)
    return d_miss, None, None, _fs.MISSED


def run_path(
    lower: Profile,
    upper: Profile | Literal["flat"],
    path: Sequence[Segment],
    *,
    fits: tuple[SplineFit, SplineFit | None] | None = None,
    e_star: float,
    g_star: float,
    mu0: float,
    alpha: float,
    x0: float,
    record_steps: NDArray[np.int64] | None = None,
    law: ContactLaw | None = None,
) -> tuple[dict[str, NDArray[Any]], tuple[ContactRecord, ...]]:
    """Follow a load path (the engine of ``simulate(..., path=...)``).

    Parameters
    ----------
    lower, upper : Profile, Profile or "flat"
        The bodies (heights [µm] out of each body), sharing one grid.
    path : sequence of Segment
        The load path (validated by :func:`validate_path`).
    fits : (SplineFit, SplineFit or None), optional
        Spline fits already computed with the same α and x0.
    e_star, g_star : float
        E*, G* [GPa].
    mu0 : float
        μ0 [1].
    alpha, x0 : float
        Spline parameters α [1], x0 [µm].
    record_steps : array of int, optional
        Steps at which to keep the accepted contacts.
    law : ContactLaw, optional
        Local normal contact law (default :class:`.laws.Hertz`).

    Returns
    -------
    (curves, contacts)
        Per-step arrays (``STEP_VARIABLES`` and ``PATH_STEP_VARIABLES``) and recorded contacts.
    """
    segments = validate_path(path)
    law = Hertz() if law is None else check_law(law)
    if fits is None:
        fit_l, fit_u = fit_spline_pair(
            lower, None if isinstance(upper, str) else upper, alpha=alpha, x0=x0
        )
    else:
        fit_l, fit_u = fits
    geo = _prepare(lower, fit_l, fit_u)
    n = geo.surf.f_l.size
    total = 1 + sum(s.steps for s in segments)
    target = np.full(total, np.nan)
    codes = _fs.new_codes(total)
    record = np.zeros(total, dtype=np.bool_)
    if record_steps is not None and len(record_steps):
        record[record_steps] = True
    contacts: list[ContactRecord] = []
    state = _State(n, law, e_star, g_star, mu0)
    dx = geo.surf.dx

    # Per step: δ_N, u_T and the sums of path_kernel.path_step (see _NAMES).
    table = np.zeros((total, 2 + len(_NAMES)))

    def store_contacts(k: int, m: int) -> None:
        s = state.scratch
        idx = s.idx[:m].copy()
        contacts.append(
            ContactRecord(
                step=k,
                point=idx,
                x=lower.x[idx] + (s.xc[:m] - idx * dx),
                z=s.z[:m].copy(),
                overlap=s.delta[:m].copy(),
                effective_radius=s.reff[:m].copy(),
                normal_force=s.fn[:m].copy(),
                tangential_force=s.ft[:m].copy(),
                normal_x=s.ex[:m].copy(),
                normal_z=s.ez[:m].copy(),
                slipping=s.slip[:m].copy(),
            )
        )

    def store(k: int, d: float, u: float, values: _k.StepSums) -> None:
        table[k, 0] = d
        table[k, 1] = u
        table[k, 2:] = values
        if record[k]:
            store_contacts(k, int(values.n_contacts))

    # Step 0: zero minimum gap, no shift.
    first = _Candidates(geo, state, 0.0, 0.0)
    store(0, 0.0, 0.0, _step(geo, first, state, 0.0, 0.0, 0.0, 0.0, True))
    k = 0
    u_cur = 0.0
    d_cur = 0.0
    margin = 1e-3 * geo.scale  # extra δ_N range of a force-controlled step's candidates
    for seg in segments:
        u_a, d_a = u_cur, d_cur
        u_b = u_a if seg.tangential is None else float(seg.tangential)
        n_steps = seg.steps
        force = seg.normal_force
        d_target = d_a if seg.normal is None else float(seg.normal)
        if force is None:
            # Compiled runs between recorded steps; a recorded step runs alone so that its
            # contacts can be read from the scratch arrays.
            s = 1
            while s <= n_steps:
                rec = np.flatnonzero(record[k + s : k + n_steps + 1])
                if rec.size and rec[0] == 0:
                    s_last = s
                else:
                    s_last = n_steps if rec.size == 0 else s + int(rec[0]) - 1
                state.ensure(n)
                run_steps(
                    u_a, d_a, u_b, d_target, n_steps, s, s_last, u_cur, d_cur,
                    float(_CHUNK_CELLS), geo.surf, geo.cull, state.cand_idx, state.cand_bound,
                    state.material, state.springs, state.scratch, table, k + s,
                )  # fmt: skip
                if record[k + s_last]:
                    store_contacts(k + s_last, int(table[k + s_last, 5]))
                u_cur, d_cur = table[k + s_last, 1], table[k + s_last, 0]
                s = s_last + 1
            k += n_steps
            continue
        for s in range(1, n_steps + 1):
            u = u_b if s == n_steps else u_a + (u_b - u_a) * (s / n_steps)
            du = u - u_cur
            cands = _Candidates(geo, state, u, d_cur + margin)

            def evaluate(
                trial: float,
                fixed: NDArray[np.bool_] | None = None,
                migrate: int | None = None,
                _u: float = u,
                _du: float = du,
                _d0: float = d_cur,
            ) -> tuple[Any, ...]:
                nonlocal cands
                if trial > cands.d_max:
                    cands = _Candidates(geo, state, _u, trial + margin)
                return _step(geo, cands, state, _u, trial, _du, trial - _d0, False, fixed, migrate)

            d, _, lo, hi = _solve_force(force, evaluate, d_cur, geo.scale)
            fixed: NDArray[np.bool_] | None = None
            window: int | None = None
            code = _fs.HELD
            if lo != hi:
                # F_N jumps between lo and hi: eq. 9 drops a contact there (docs/friction.md).
                d, fixed, window, code = _consistent_set(
                    force, evaluate, state, (lo, hi), d, geo.scale,
                    lambda trial, _du=du, _d0=d_cur: _migrate_cells(geo, _du, trial - _d0),
                )  # fmt: skip
            if d > cands.d_max:
                cands = _Candidates(geo, state, u, d + margin)
            values = _step(geo, cands, state, u, d, du, d - d_cur, True, fixed, window)
            target[k + 1], codes[k + 1] = force, code
            k += 1
            store(k, d, u, values)
            u_cur, d_cur = u, d
    disp = table[:, 0].copy()
    tang = table[:, 1].copy()
    out = {
        name: table[:, 2 + j].astype(np.int64) if name.startswith("n_") else table[:, 2 + j].copy()
        for j, name in enumerate(_NAMES)
    }
    cause = "F_N(δ_N) jumps where a contact appears or vanishes (eq. 9) or a law jumps in or out"
    codes = _fs.finish(codes, out["normal_force"], target, cause=cause, stacklevel=4)
    curves: dict[str, NDArray[Any]] = {
        "displacement": disp,
        "tangential_displacement": tang,
        "normal_force": out["normal_force"],
        "tangential_force": out["tangential_force"],
        "contact_area": out["contact_area"],
        "n_contacts": out["n_contacts"],
        "n_slipping": out["n_slipping"],
        "dissipated_work": np.cumsum(out["step_work"]),
        "normal_force_target": target,
        "force_control": codes,
        "normal_force_normal_part": out["normal_force_normal_part"],
        "normal_force_tangential_part": out["normal_force_tangential_part"],
        "n_tilted_contacts": out["n_tilted_contacts"],
        "n_candidates": out["n_candidates"],
    }
    return curves, tuple(contacts)


def path_segments(
    path: Iterable[Segment], steps: int, final_displacement: float | None
) -> tuple[Segment, ...]:
    """The validated segments of ``path`` given to ``simulate``.

    ``steps`` [1] must keep its default 1000 and ``final_displacement`` [µm] must be ``None``:
    the segments set both, so any other value raises :class:`.LoadPathError`.
    """
    segments = validate_path(path)
    if final_displacement is not None:
        raise LoadPathError(
            f"final_displacement = {final_displacement!r} µm and path were both given: the path "
            "sets the displacements; drop final_displacement"
        )
    if steps != 1000:
        raise LoadPathError(
            f"steps = {steps!r} and path were both given: each Segment has its own steps; "
            "drop steps"
        )
    return segments


def simulate_path(
    lower: Profile,
    upper: Profile | Literal["flat"],
    path: Sequence[Segment],
    *,
    steps: int = 1000,
    final_displacement: float | None,
    e_star: float,
    g_star: float,
    mu0: float,
    alpha: float,
    x0: float,
    record_contacts: Iterable[int] | str | None,
    law: ContactLaw | None = None,
    fits: tuple[SplineFit, SplineFit | None] | None = None,
) -> SimulationResult:
    """``simulate(lower, upper, path=...)`` with validated material parameters.

    Parameters are those of :func:`splinecontact.simulate` (E*, G* [GPa], μ0 [1], α [1],
    x0 [µm], the contact law); ``steps`` must keep its default 1000 and
    ``final_displacement`` must be ``None`` (the path's segments set both).
    """
    from .simulation import _record_steps, build_result, spline_fits

    segments = path_segments(path, steps, final_displacement)
    flat = isinstance(upper, str)
    if flat and upper != "flat":
        raise ParameterError(f"upper = {upper!r}: give a Profile or the string 'flat'")
    extent = max(
        [abs(s.normal) for s in segments if s.normal is not None] + [lower.dx], default=lower.dx
    )
    fit_l, fit_u = spline_fits(lower, upper, alpha=alpha, x0=x0) if fits is None else fits
    displacement_steps(max(extent, lower.dx), 0.2, lower.peak_to_valley, 1)  # its limits
    # the mean gap at δ_N = 0 (that of contact_geometry; no candidates are needed: final −∞)
    f_u = fit_l.f if fit_u is None else fit_u.f
    mean_gap0 = float(_place_bodies(fit_l.f, f_u, fit_u is None, -np.inf)[2])
    total = sum(s.steps for s in segments)
    record_steps = _record_steps(record_contacts, total)
    curves, contacts = run_path(
        lower, upper, segments, fits=(fit_l, fit_u), e_star=e_star, g_star=g_star, mu0=mu0,
        alpha=alpha, x0=x0, record_steps=record_steps, law=law,
    )  # fmt: skip
    curves["mean_separation"] = mean_gap0 - curves["displacement"]
    path_record = [
        {"normal": s.normal, "normal_force": s.normal_force, "tangential": s.tangential,
         "steps": s.steps}
        for s in segments
    ]  # fmt: skip
    return build_result(
        lower, upper, (fit_l, fit_u), curves, contacts, steps=total,
        final_displacement_factor=0.2, e_star=e_star, g_star=g_star, mu0=mu0, alpha=alpha,
        x0=x0, extra={"path": path_record,
                      "path_segment_end": np.cumsum([s.steps for s in segments]).tolist(),
                      **law_record(Hertz() if law is None else law)},
    )  # fmt: skip
