"""Interacting SAD along any load path: tangential sliding and force control.

The driver of ``simulate(..., path=..., interaction=True)`` when a segment moves the upper body
tangentially (``tangential=``) or holds a normal force (``normal_force=``). Every step is one
configuration (u_T, δ_N) of the upper body:

* **Geometry** as the non-interacting path (:mod:`.loadpath`): the upper body shifted by u_T is
  its spline at x − u_T (no re-fit); the candidates, surface spheres, local normals and
  curvatures (eqs. 4–8) are those of the shifted geometry.
* **Contacts and normal loads** from the interacting solve of :mod:`.interaction` (eq. 9,
  Table 1, eq. 10 with the elastic half-plane, interaction along the contact normals) on that
  geometry, one step continuing the state of the committed step (its loads, widths and mesh
  displacement, matched to the candidates at the current shift by grid point): the step is
  warm-started from the previous one and summits lifted by the surface's rise are tested
  against its displacement, as in the normal loading (the first step starts from contact-free
  at δ_N = 0). The contact widths get at least ``WIDTH_ITERATIONS`` updates per
  displacement-controlled step. A force-controlled step does not continue the state: every
  trial is a two-step loading at the current shift (the previous δ_N from contact-free, then
  the trial's) with the settings' own number of width updates; its first step does not
  depend on the trial and is solved once per shift (:meth:`_Driver._first_step`).
* **Tangential springs** (eqs. 11–13) with the migration rule of the non-interacting path
  (:func:`._migration.migrate`: a contact continues the nearest vanished contact within
  1 + ⌈2(|Δu_T| + |Δδ_N|)/dx⌉ cells), the increment (Δu_T, −Δδ_N) projected on the mean of the
  old and new tangents, and the Coulomb cap μ0 P_i with P_i the coupled normal load.
* **Force control**: δ_N is solved at every step so that the coupled F_N meets the target,
  each trial a full coupled solve at the step's shift with the springs not committed and the
  contact-level solve tightened to ``FORCE_SOLVE_TOL``. The free F_N(δ_N) jumps where eq. 9
  accepts or drops a contact, so, as the non-interacting path does, the step's contact set
  (and the springs' migration window) is held through the solve
  (:func:`.interaction_force._force_step`): eq. 9
  is not re-tested, a held contact whose effective approach falls to ≤ 0 still carries
  nothing; the first step of every trial does not depend on it), and F_N(δ_N) is
  continuous (secant steps, :func:`.interaction_force._solve_continuous`). The set is
  re-taken from the free model at the solved δ_N until the two agree (then the step is the
  free model's) or ``SET_ROUNDS`` sets were tried (the target lies in a jump of the free
  model; F_N is held with the last set). Where F_N still jumps across the target, the nearer
  side is taken and a ``RuntimeWarning`` says so (``normal_force − normal_force_target``).
  ``force_control`` codes each step's outcome (:mod:`._force_status`).
* **Contact laws**: history per lower grid point (it follows the lower body under a shift;
  the plastic memory is δ_max, met by any summit's R_eff); every evaluation continues the
  committed state on a copy, kept by the accepted step only. A_S: the sum of the laws' widths.
* **Validity**: a step whose contact-level solve leaves the model's validity (a contact too
  wide for the period) raises the :class:`~splinecontact.errors.ParameterError` of the normal
  path, naming the path's step; a force-controlled trial there counts as above the target.

The loop over steps runs in Python, each step one compiled coupled solve; what does not change
between the calls at one shift (the candidates and their surface spheres, their gap order,
slopes and quadratures, the mesh kernels) is built once (cost in ``docs/accuracy.md``).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from typing import Any, Literal

import numba
import numpy as np
from numpy.typing import NDArray

from ..errors import LoadPathError, NoConvergenceError, ParameterError
from ..profile import Profile
from ..results import ContactRecord
from ..spline import SplineFit
from . import _force_status as _fs
from ._culling import sphere_ready
from ._migration import migrate as _migrate
from .geometry import ContactGeometry
from .interaction import InteractionSettings, _check_finite, interacting_loading
from .interaction_force import MAX_FALLS as MAX_FALLS
from .interaction_force import SET_ROUNDS as SET_ROUNDS
from .interaction_force import Held, _force_step
from .interaction_force import _HeldSetFails as _HeldSetFails
from .interaction_force import _loaded as _loaded
from .interaction_force import _solve_continuous as _solve_continuous
from .interaction_operator import mesh_cache
from .laws import spring_sums
from .loadpath import _prepare
from .path_kernel import (
    Scratch,
    Springs,
    _rigid_gap,
    _upper_slopes,
    _upper_sphere,
    candidate_bounds,
    migrate_cells_of,
)
from .segments import Segment

__all__ = ["FORCE_SOLVE_TOL", "WIDTH_ITERATIONS", "run_interacting_path"]

#: Tolerance of the contact-level solve in force-controlled steps [1] (at most the settings').
FORCE_SOLVE_TOL = 1e-11

#: Width updates per step [1] (at least; they stop once the widths change by less than
#: ``width_tol``). Chosen when every step restarted the widths from the Hertz widths of the
#: previous δ_N (before the committed state was continued): on 2048-point profiles one update
#: left F_N 6–7 % off the converged widths, two 1 %, three 0.1–0.14 %; five or more made the
#: width loop diverge at some steps of a 10⁵-point rough pair (a step whose solve fails is
#: repeated with the settings' own number of updates).
WIDTH_ITERATIONS = 3

#: Relative miss of a force-controlled step above which a warning is given [1].
FORCE_HOLD_RTOL = 1e-6

_QUARTER_PI = 0.25 * math.pi

_LAW_HINT = "a contact law's force may jump there (adhesive jump-in or out): try more steps"


@numba.njit(cache=True, nogil=True)
def _shifted_columns(
    surf: Any, cand: NDArray[np.int64], shift: float, limit: float
) -> tuple[NDArray[np.float64], ...]:  # pragma: no cover - compiled
    """The candidates (grid order) whose rigid gap at δ_N = 0 is ≤ ``limit`` [µm] at the shift
    u_T = shift·dx, with their surface spheres (eqs. 4–6): point, gap, κ^l, κ^u, m_x, m_z,
    n^l_x, n^l_z (the values of :func:`.path_kernel.path_step` for the same configuration)."""
    m = cand.size
    out = np.empty((8, m))
    count = 0
    for j in range(m):
        i = cand[j]
        inside, g0, k, t = _rigid_gap(surf, i, shift)
        if not inside or g0 > limit:
            continue
        s1, s2 = _upper_slopes(surf, k, t)
        k_u, m_x, m_z = _upper_sphere(s1, s2, surf.kappa_max)
        sphere_ready(surf, i)  # the lower sphere, evaluated on first use
        out[0, count] = i
        out[1, count] = g0
        out[2, count] = surf.kappa_l[i]
        out[3, count] = k_u
        out[4, count] = m_x
        out[5, count] = m_z
        out[6, count] = surf.nl_x[i]
        out[7, count] = surf.nl_z[i]
        count += 1
    return (
        out[0, :count].copy(), out[1, :count].copy(), out[2, :count].copy(),
        out[3, :count].copy(), out[4, :count].copy(), out[5, :count].copy(),
        out[6, :count].copy(), out[7, :count].copy(),
    )  # fmt: skip


@numba.njit(cache=True, nogil=True)
def _spring_step(
    du: float,
    dd: float,
    n_c: int,
    migrate_cells: int,
    g_star: float,
    mu0: float,
    commit: bool,
    springs: Springs,
    scratch: Scratch,
) -> tuple[float, float, float, float, float, int, int, float]:  # pragma: no cover - compiled
    """Eqs. 11–13 on the ``n_c`` loaded contacts in ``scratch`` (grid order; ``fn`` the coupled
    loads, ``width`` the half-widths): the springs migrate as in the non-interacting path
    (:func:`._migration.migrate`), the Coulomb cap is μ0 times the coupled load. Returns the
    sums of :func:`.geometry.add_contact_forces`, the slipping contacts and the work
    dissipated in the step [mN·µm/µm]; with ``commit`` the springs are replaced."""
    _migrate(springs.acc.size, n_c, migrate_cells, springs, scratch)
    sums, n_slip, work, _ = spring_sums(du, dd, n_c, g_star, mu0, springs, scratch)
    if commit:
        for c in range(n_c):
            springs.cells[c] = scratch.idx[c]
            springs.ft[c] = scratch.ft[c]
            springs.xc[c] = scratch.xc[c]
            springs.ex[c] = scratch.ex[c]
            springs.ez[c] = scratch.ez[c]
        springs.n_committed[0] = n_c
    return sums[0], sums[1], sums[2], sums[3], sums[4], sums[5], n_slip, work


#: Per-step outputs of :func:`run_interacting_path` besides δ_N and u_T, in table order.
_NAMES = (
    "normal_force", "tangential_force", "contact_area", "normal_force_normal_part",
    "normal_force_tangential_part", "n_tilted_contacts", "n_slipping", "step_work",
    "n_contacts", "n_candidates", "coalesced_contact_length", "n_contact_patches",
    "interaction_iterations", "reach_exceeded",
)  # fmt: skip


class _Driver:
    """The state of one interacting path run: geometry, springs, the current configuration."""

    def __init__(
        self,
        lower: Profile,
        fits: tuple[SplineFit, SplineFit | None],
        settings: InteractionSettings,
        extent: float,
        *,
        e_star: float,
        g_star: float,
        mu0: float,
        law: Any = None,
    ) -> None:
        self.geo = _prepare(lower, fits[0], fits[1])
        self.n = lower.n_points
        self.dx = lower.dx
        self.given = settings
        self.settings = dataclasses.replace(
            settings, width_iterations=max(settings.width_iterations, WIDTH_ITERATIONS)
        )
        self.extent = extent
        self.e_star = e_star
        self.g_star = g_star
        self.mu0 = mu0
        n = self.n
        self.springs = Springs(
            acc=np.zeros(n, dtype=np.bool_), ft=np.zeros(n), xc=np.zeros(n), ex=np.zeros(n),
            ez=np.zeros(n), cells=np.zeros(n, dtype=np.int64),
            n_committed=np.zeros(1, dtype=np.int64), claimed=np.zeros(n, dtype=np.bool_),
        )  # fmt: skip
        self.cand_idx = np.empty(n, dtype=np.int64)
        self.cand_bound = np.empty(n)
        self.scratch = self._scratch(16)
        self.u = 0.0
        self.d = 0.0
        self._columns: tuple[float, float, tuple[NDArray[np.float64], ...]] | None = None
        # what the coupled solve keeps of the current candidates (interacting_loading's reuse)
        self.reuse: dict[str, Any] = {}
        # the first step of the force trials at one shift: (u, δ_N, tol), candidates, state
        self._first: tuple[tuple[float, float, float], dict[str, Any] | None] | None = None
        # the meshes of the coupled solve (same period and E* at every step), built once
        cells = max(64, 1 << math.ceil(math.log2(max(2 * n, 2))), settings.mesh_cells or 0)
        self.mesh = mesh_cache(cells)
        # the state of the committed step, continued by the next one
        self.carry: dict[str, Any] = {}
        # the last δ_N [µm] found beyond the model's validity (force control)
        self.beyond: float | None = None
        self.period = (1 if settings.periodic else 2) * self.n * self.dx
        self.law = law if law is not None and law.code != 0 else None
        self.law_state = None if self.law is None else np.zeros((self.n, self.law.n_state))
        self.law_reach = 0.0 if self.law is None else float(self.law.reach)

    @staticmethod
    def _scratch(capacity: int) -> Scratch:
        kinds = {"idx": np.int64, "src": np.int64, "cl_i": np.int64, "slip": np.bool_,
                 "cl_keep": np.bool_, "cl_flag": np.uint8}  # fmt: skip
        return Scratch(
            **{f: np.zeros(capacity, dtype=kinds.get(f, np.float64)) for f in Scratch._fields}
        )

    def columns(self, u: float, d: float) -> tuple[NDArray[np.float64], ...]:
        """The candidates at shift u whose gap can close by δ_N = d plus the reach."""
        limit = (1.0 + self.settings.reach_fraction) * max(d, self.extent) + self.law_reach
        cached = self._columns
        if cached is not None and cached[0] == u and cached[1] >= limit:
            return cached[2]
        surf = self.geo.surf
        centre = math.floor(-u / self.dx)
        count = candidate_bounds(
            surf, self.geo.cull, centre - 1, centre + 1, surf.placement - limit,
            self.cand_idx, self.cand_bound,
        )  # fmt: skip
        columns = _shifted_columns(surf, self.cand_idx[:count], u / self.dx, limit)
        self._columns = (u, limit, columns)
        return columns

    def _solve(
        self,
        geometry: ContactGeometry,
        settings: InteractionSettings,
        tol: float | None,
        held: NDArray[np.bool_] | None,
        carry: dict[str, Any],
        law_state: NDArray[np.float64] | None = None,
        recorded: int = 1,
    ) -> tuple[dict[str, NDArray[Any]], tuple[ContactRecord, ...]] | None:
        """The coupled step (:func:`.interaction.interacting_loading`) continuing ``carry``,
        repeated with the given settings' width updates if the width loop made it fail; ``None``
        where a contact grew too wide for the period (the model's validity, see
        :func:`.interaction._check_finite`); ``law_state`` the law's history (in and out)."""
        chosen = settings if tol is None else dataclasses.replace(settings, tol=tol)
        try:
            return interacting_loading(
                geometry, e_star=self.e_star, g_star=0.0, mu0=0.0, n_points=self.n,
                settings=chosen, record_steps=np.array([recorded]), contact_set=held,
                mesh=self.mesh, carry=carry, law=self.law, law_state=law_state, reuse=self.reuse,
            )  # fmt: skip
        except NoConvergenceError as error:
            if settings.width_iterations == self.given.width_iterations:
                hint = "" if self.law is None else f" (after u_T = {self.u:.6g} µm; {_LAW_HINT})"
                raise NoConvergenceError(f"{error}{hint}") from error
            if law_state is not None:  # the failed solve may have committed rows: start again
                law_state[:] = self.law_state
            return self._solve(geometry, self.given, tol, held, carry, law_state, recorded)
        except ParameterError as error:
            if "left its validity" not in str(error):
                raise
            return None

    def _first_step(self, u: float, geometry: ContactGeometry, tol: float) -> dict[str, Any] | None:
        """The state after the first step of a force trial's two-step loading (the committed
        δ_N at shift u [µm] from contact-free, on the trial's candidates ``geometry``), which
        does not depend on the trial's δ_N nor on the held set: solved once per shift and
        committed δ_N, and continued by every trial (bit-identical to solving it in each
        trial). ``None`` where it leaves the model's validity."""
        key = (u, self.d, tol)
        cached = self._first
        if cached is not None and cached[0] == key:
            # the same, or more candidates (a larger gap limit at the same shift): those added
            # have rigid gaps above the limit before, so above δ_N, and cannot touch in a first
            # step from contact-free (eq. 9 tests gaps up to δ_N there)
            return cached[1]
        carry: dict[str, Any] = {}
        start = dataclasses.replace(
            geometry, first_step_index=np.zeros(1, dtype=np.int64),
            displacement=np.array([self.d]),
        )  # fmt: skip
        solved = self._solve(start, self.given, tol, None, carry, recorded=0)
        first = None if solved is None else carry
        self._first = (key, first)
        return first

    def _valid(self, contacts: tuple[ContactRecord, ...]) -> bool:
        """Every loaded contact's Hertz half-width √(2 P R_eff/(πE*)) [µm] below L_p/π, the
        validity of the periodic half-plane model (where the normal path's loads, whose widths
        grow from step to step, become infinite)."""
        if not contacts:
            return True
        c = contacts[0]
        widest = float(np.max(2.0 * c.normal_force * c.effective_radius, initial=0.0))
        return math.sqrt(widest / (math.pi * self.e_star)) < self.period / math.pi

    def window(self, u: float, d: float) -> int:
        """Cells within which a vanished contact may continue (:func:`._migration.migrate`)
        from the current configuration to (u_T = u, δ_N = d) [µm]."""
        return int(migrate_cells_of(u - self.u, d - self.d, self.dx, self.n))

    def evaluate(
        self,
        u: float,
        d: float,
        commit: bool,
        tol: float | None = None,
        held: Held | None = None,
    ) -> tuple[tuple[float, ...], ContactRecord | None]:
        """The configuration (u_T = u, δ_N = d) after the current one: the per-step values of
        ``_NAMES`` and the loaded contacts (springs committed with ``commit``). With ``held``
        = (grid points, migration window [cells]) the contacts of the configuration are those
        points, eq. 9 not tested, and the springs migrate within that window."""
        point, gap0, k_l, k_u, m_x, m_z, n_x, n_z = self.columns(u, max(d, self.d))
        index = point.astype(np.int64)
        geometry = ContactGeometry(
            point=index, x=point * self.dx, gap0=gap0, height_lower=self.geo.surf.f_l[index],
            curvature_lower=k_l, curvature_upper=k_u, m_x=m_x, m_z=m_z, n_x=n_x, n_z=n_z,
            first_step_index=np.zeros(2, dtype=np.int64), displacement=np.array([self.d, d]),
            dx=self.dx, mean_gap0=0.0,
        )  # fmt: skip
        # force-controlled steps (tol given) keep the settings' width updates: with more, their
        # many trials cost several times as much and the width loop can fail to converge
        mask = None if held is None else np.isin(index, held[0])
        # a displacement step continues the committed state; a force-controlled step is a
        # two-step loading (the previous δ_N from contact-free, then d) whose first step does
        # not depend on d: with the widths carried, one update per trial left F_N(δ_N) with
        # the history of the widths (unloading in force needed more δ_N, not less)
        # with a law every evaluation continues the committed state (one commit per step)
        history = None if self.law_state is None else self.law_state.copy()
        solved: Any = None
        if tol is not None and self.law is None:
            first = self._first_step(u, geometry, tol)
            carry = {} if first is None else dict(first)
        else:
            carry = dict(self.carry)
        if carry or tol is None or self.law is not None:
            solved = self._solve(
                geometry, self.settings if tol is None else self.given, tol, mask, carry, history
            )
        if solved is None or not self._valid(solved[1]):
            # beyond validity: an infinite F_N (above any force target)
            self.beyond = d
            if commit:
                self.u, self.d = u, d
            return (math.inf, *(math.nan,) * 7, 0, 0, math.nan, 0, 0, 0), None
        curves, contacts = solved
        record = contacts[0] if contacts else None
        n_c = 0 if record is None else record.point.size
        if n_c > self.scratch.idx.size:
            self.scratch = self._scratch(2 * n_c)
        s = self.scratch
        if record is not None:
            order = np.argsort(record.point, kind="stable")
            s.idx[:n_c] = record.point[order]
            s.fn[:n_c] = record.normal_force[order]
            s.ex[:n_c] = record.normal_x[order]
            s.ez[:n_c] = record.normal_z[order]
            s.xc[:n_c] = record.x[order]
            s.width[:n_c] = np.sqrt(np.maximum(record.overlap * record.effective_radius, 0)[order])
        window = self.window(u, d) if held is None else held[1]
        f_n, f_t, area, fn_n, fn_t, tilted, slipping, work = _spring_step(
            u - self.u, d - self.d, n_c, window, self.g_star, self.mu0, commit, self.springs, s
        )
        values = (
            f_n, f_t, area, fn_n, fn_t, tilted, slipping, work, n_c,
            int(curves["n_candidates"][1]), float(curves["coalesced_contact_length"][1]),
            int(curves["n_contact_patches"][1]), int(curves["interaction_iterations"][1]),
            int(curves["reach_exceeded"][1]),
        )  # fmt: skip
        if self.law is not None:  # A_S: the sum of the laws' widths (as in the normal path)
            values = (*values[:2], float(curves["contact_area"][1]), *values[3:])
        if commit:
            self.u, self.d = u, d
            self.carry = carry
            if history is not None:
                self.law_state = history
        return values, record


def run_interacting_path(
    lower: Profile,
    upper: Profile | Literal["flat"],
    segments: Sequence[Segment],
    fits: tuple[SplineFit, SplineFit | None],
    settings: InteractionSettings,
    *,
    e_star: float,
    g_star: float,
    mu0: float,
    record_steps: NDArray[np.int64] | None = None,
    law: Any = None,
) -> tuple[dict[str, NDArray[Any]], tuple[ContactRecord, ...]]:
    """Follow a load path with interacting contacts (the module docstring).

    Parameters
    ----------
    lower, upper : Profile, Profile or "flat"
        The bodies (heights [µm]), sharing one grid.
    segments : sequence of Segment
        The validated load path (δ_N [µm], F_N [mN/µm], u_T [µm], steps [1]).
    fits : (SplineFit, SplineFit or None)
        The spline fits (eqs. 2–3) of the bodies.
    settings : InteractionSettings
        Options of the coupled solve (``stop_force`` must be ``None``).
    e_star, g_star : float
        E*, G* [GPa].
    mu0 : float
        μ0 [1] (eqs. 12–13).
    record_steps : array of int, optional
        Steps at which to keep the loaded contacts.
    law : ContactLaw, optional
        The normal law, bound (:func:`splinecontact.contact.laws.bind_law`); ``None``: eq. 10.

    Returns
    -------
    (curves, contacts)
        The per-step arrays of the non-interacting path (δ_N, u_T, F_N, F_T, A_S, contacts,
        slipping contacts, dissipated work, F_N target, …) plus ``coalesced_contact_length``
        [µm], ``n_contact_patches``, ``interaction_iterations`` and ``reach_exceeded`` [1].
    """
    if settings.stop_force is not None:
        raise LoadPathError(
            f"stop_force = {settings.stop_force!r} mN/µm with a tangential or force-controlled "
            "path: stop_force ends a normal loading only; use a normal_force segment instead"
        )
    extent = max([abs(s.normal) for s in segments if s.normal is not None] + [lower.dx])
    driver = _Driver(lower, fits, settings, extent, e_star=e_star, g_star=g_star, mu0=mu0, law=law)
    total = 1 + sum(s.steps for s in segments)
    table = np.zeros((total, 2 + len(_NAMES)))
    target = np.full(total, np.nan)
    codes = _fs.new_codes(total)
    record = np.zeros(total, dtype=np.bool_)
    if record_steps is not None and len(record_steps):
        record[np.asarray(record_steps)] = True
    contacts: list[ContactRecord] = []
    force_tol = min(settings.tol, FORCE_SOLVE_TOL)

    def store(k: int, values: tuple[float, ...], rec: ContactRecord | None) -> None:
        table[k, 0] = driver.d
        table[k, 1] = driver.u
        table[k, 2:] = values
        if record[k] and rec is not None and rec.point.size:
            s = driver.scratch
            m = rec.point.size
            order = np.argsort(rec.point, kind="stable")
            contacts.append(
                dataclasses.replace(
                    rec,
                    step=k,
                    point=s.idx[:m].copy(),
                    x=rec.x[order] + lower.x[0],
                    z=rec.z[order],
                    overlap=rec.overlap[order],
                    effective_radius=rec.effective_radius[order],
                    normal_force=s.fn[:m].copy(),
                    tangential_force=s.ft[:m].copy(),
                    normal_x=s.ex[:m].copy(),
                    normal_z=s.ez[:m].copy(),
                    slipping=s.slip[:m].copy(),
                )
            )

    period = driver.period

    def check(k: int) -> None:
        """The ParameterError of the normal path where step k left the model's validity."""
        _check_finite(table[:, 2:7].T, k, k + 1, table[:, 0], period)

    store(0, *driver.evaluate(0.0, 0.0, True))
    check(0)
    k = 0
    for seg in segments:
        u_a, d_a = driver.u, driver.d
        u_b = u_a if seg.tangential is None else float(seg.tangential)
        d_b = d_a if seg.normal is None else float(seg.normal)
        for s in range(1, seg.steps + 1):
            u = u_b if s == seg.steps else u_a + (u_b - u_a) * (s / seg.steps)
            k += 1
            force = seg.normal_force
            if force is None:
                d = d_b if s == seg.steps else d_a + (d_b - d_a) * (s / seg.steps)
                store(k, *driver.evaluate(u, d, True))
                check(k)
                continue

            driver.beyond = None
            d, held, codes[k] = _force_step(driver, u, force, force_tol)
            target[k] = force
            store(k, *driver.evaluate(u, d, True, force_tol, held))
            if driver.beyond is not None and abs(table[k, 2] - force) > FORCE_HOLD_RTOL * force:
                table[k, 0], table[k, 2] = driver.beyond, math.inf  # reachable only beyond
            check(k)
    curves: dict[str, NDArray[Any]] = {
        "displacement": table[:, 0].copy(),
        "tangential_displacement": table[:, 1].copy(),
    }
    for j, name in enumerate(_NAMES):
        column = table[:, 2 + j]
        curves[name] = column.astype(np.int64) if name.startswith("n_") else column.copy()
    for name in ("interaction_iterations", "reach_exceeded"):
        curves[name] = curves[name].astype(np.int64)
    curves["dissipated_work"] = np.cumsum(curves.pop("step_work"))
    curves["normal_force_target"] = target
    cause = (
        "F_N(δ_N) jumped across the target even with the step's contacts held (a law's jump, "
        "the width loop stopping after a different number of updates, or the target reachable "
        "only beyond the model's validity)"
    )
    curves["force_control"] = _fs.finish(
        codes, curves["normal_force"], target, cause=cause, stacklevel=4
    )
    return curves, tuple(contacts)
