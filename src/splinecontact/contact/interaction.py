"""Interacting SAD: accepted contacts coupled through the elastic half-plane.

SAD (paper eq. 10) gives every accepted contact an independent Hertzian line-contact force
F_i = (π/4) E* δ_i. In plane strain the surface displacement under a loaded contact decays only
logarithmically, so every contact lowers all the others and the body as a whole. This module
keeps SAD's geometry (eqs. 2–9: spline, spheres, detection, Table 1, eq. 9 acceptance, local
normals, R_eff), SAD's local law and its tangential springs (eqs. 11–13), and adds the elastic
coupling (the "interacting Hertzian asperities" of multi-asperity models: Ciavarella, Greenwood
& Paggi, Wear 265 (2008) 729–734; Afferrante, Carbone & Demelio, Wear 278–279 (2012) 28–33).

Model (rigid displacement δ_N prescribed at every step, as in SAD)
-------------------------------------------------------------------
* The elastic body is the profile's segment of length L between two frictionless symmetry walls
  (equivalently: period L_p = 2L with the mirror image of every contact), the same boundary
  conditions as the exact reference of ``splinecontact compare``; ``periodic=True`` uses period
  L_p = L without images. Displacements have zero mean over the period, so the mean gap is the
  rigid one and the mean-plane lift is carried by the forces (as in :mod:`splinecontact.bem`).
* Periodic plane-strain Green function of a line load P (the kernel of :mod:`splinecontact.bem`
  summed in closed form): u(x) = −(2P/(πE*)) ln|2 sin(πx/L_p)|.
* Contact j carries the Hertzian pressure of half-width a_j, a_j² = δ_j^eff R_eff,j / 2
  (R_eff = 2/(κ^u + κ^l) as in eq. 10, so a_j² = 4 P_j R/(πE*) with R = R_eff/2), and load
  P_j = (π/4) E* δ_j^eff (SAD's eq. 10 law, unchanged) along its repulsive direction e_j.
* Effective approach: δ_i^eff = δ_i − e_z,i w_i, with δ_i SAD's sphere overlap (eq. 10) and w_i
  the vertical surface displacement at contact i caused by the vertical load components
  e_z,j P_j of all other contacts and images, plus the part of contact i's own periodic Hertz
  displacement that SAD's local law leaves out: c P_i (ln(L_p/(π a_i)) − 3/2), c = 2/(πE*)
  (the periodic Hertz central displacement is c P (ln(L_p/(π a)) + 1/2); SAD's law supplies
  2 c P of it). Interaction acts along the contact normals; tangential springs are unchanged.
* Coupling between neighbours: the displacement field of contact j is averaged over contact i
  with the flat-punch weight 1/(π√(a_i² − (x − x_i)²)), which is the first-order load change of a
  Hertzian contact under an imposed surface displacement (reciprocal theorem; Barber, *Contact
  Mechanics*, Springer 2018, §5.2). For a line load at distance ρ the average is closed form,
  ln((|ρ| + √(ρ² − a_i²))/2) (ln(a_i/2) for |ρ| ≤ a_i), and the Hertz distribution of j is
  integrated over by Gauss–Chebyshev quadrature; the pair coefficient is symmetrised.
* Unilateral condition: P_i ≥ 0, δ_i^eff ≥ 0 wherever P_i > 0, and a contact whose effective
  approach would be ≤ 0 carries nothing (a linear complementarity problem at frozen widths,
  solved by the constrained conjugate gradients of Polonsky & Keer, Wear 231 (1999) 206–219,
  at contact level; the widths a_i are updated in an outer fixed-point loop). Every step is
  warm-started from the previous step's loads.
* Coalescence: contacts whose Hertz intervals [x_i − a_i, x_i + a_i] overlap form one contact
  patch. The contact length is the length of the union of the intervals (within the segment)
  and ``n_patches`` counts its connected pieces, in the spirit of the equivalent-spot rule of
  Afferrante et al. (2012) (conservation of the contact area); their mutual coupling is still
  the punch-averaged Hertz field above (saturating at ln(a_i/2) inside an overlap).
* Cost: the far field is a particle–mesh sum — loads spread to a coarse periodic mesh with
  linear (cloud-in-cell) weights, convolved with the Green function by FFT, read back with the
  same weights — and pairs closer than ``NEAR_CELLS`` mesh cells are corrected to the exact
  coefficient. One operator application costs O(N + M log M + near pairs) for N contacts on
  M cells, independent of the number of grid points; steps with few contacts assemble the same
  operator as an N × N matrix (:mod:`.interaction_kernel`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import numba
import numpy as np
from numpy.typing import NDArray

from ..errors import NoConvergenceError, ParameterError
from ..profile import Profile
from ..results import ContactRecord
from ..spline import SplineFit
from .geometry import ContactGeometry, contact_geometry
from .halfplane import (
    NEAR_CELLS,
    _quadrature,
    pair_coefficient,
    periodic_green,
    self_coefficient,
)
from .punch import _punch_quadrature

__all__ = [
    "DEFAULT_INTERACTION_TOLERANCE",
    "NEAR_CELLS",
    "InteractionSettings",
    "extended_geometry",
    "interacting_loading",
    "pair_coefficient",
    "periodic_green",
    "self_coefficient",
]
_QUARTER_PI = 0.25 * math.pi

#: Default tolerance of the contact-level solve: largest complementarity violation / largest
#: rigid overlap δ_i of the step [1].
DEFAULT_INTERACTION_TOLERANCE = 1e-6

#: Default reach of the candidate set beyond the final displacement, as a fraction of it [1].
DEFAULT_REACH = 1.0

#: Safety factor on the largest uplift of the surface (the most negative mesh displacement) of
#: the previous step: summits whose rigid gap is below it are tested for contact [1].
UPLIFT_FACTOR = 1.5

#: Relative change of the contact widths and centres at which the outer loop stops [1]
#: (widths enter the coupling through logarithms only).
WIDTH_TOLERANCE = 1e-3


@dataclass(frozen=True)
class InteractionSettings:
    """Options of the interacting solve.

    Attributes
    ----------
    periodic : bool
        False (default): the segment lies between two frictionless symmetry walls (period 2L with
        mirror images, as ``splinecontact compare``); True: the profile is one period L.
    tol : float
        Largest complementarity violation / largest overlap of the step [1].
    mesh_cells : int or None
        Cells of the far-field mesh per period [1] (power of two); ``None`` chooses about
        ``CELLS_PER_SOURCE`` cells per contact and image at every step (at least 64).
    width : {"profile", "hertz"}
        Contact half-widths from the local punch problem of the smoothed profile (default) or
        from the Hertz relation a² = δ^eff R_eff/2 of the tip curvature (eq. 10).
    reach_fraction : float
        Candidates are the points whose gap closes by (1 + reach_fraction) × the final
        displacement [1] (summits lifted by the surface's rise can touch).
    width_iterations : int
        Most width updates per step [1] (fewer once the widths change by less than
        ``width_tol``); 1 lets the widths lag one step behind the loads.
    width_tol : float
        Relative change of the widths and centres at which the width updates of a step
        stop [1] (default ``WIDTH_TOLERANCE``).
    stop_force : float or None
        End the loading at the first step whose normal force reaches this [mN/µm]; the
        curves end at that step (``None``: run every step).
    """

    periodic: bool = False
    tol: float = DEFAULT_INTERACTION_TOLERANCE
    mesh_cells: int | None = None
    width: str = "profile"
    width_iterations: int = 1
    reach_fraction: float = DEFAULT_REACH
    width_tol: float = WIDTH_TOLERANCE
    stop_force: float | None = None


# --- the per-step geometric pass (SAD eqs. 7–10, Table 1, eq. 9) ----------------------------


@numba.njit(cache=True, nogil=True)
def _accept(
    d: float,
    delta_min: float,
    uplift: NDArray[np.float64],
    cell: float,
    point_x: NDArray[np.float64],
    n_active: int,
    columns: tuple,
    dx: float,
    out: tuple,
    held: NDArray[np.bool_] | None = None,
    reach: float = 0.0,
) -> int:  # pragma: no cover - compiled
    """SAD's acceptance (Table 1, eqs. 7–10, eq. 9) of the first ``n_active`` candidates at
    displacement ``d`` [µm], down to the overlap ``delta_min`` [µm] where the surface has risen
    (the mesh displacement ``uplift`` [µm] of the previous step, cells of ``cell`` [µm]).
    ``columns`` = (gap0, κ^l, κ^u, m_x, m_z, n_x, n_z) of the candidates; the accepted ones go
    to ``out`` = (index, δ, e_x, e_z, R_eff, offset, centre height); returns their number.
    A law acting at a gap (``reach`` [µm] > 0) keeps every candidate with δ > −reach.
    With ``held`` (a mask over the candidates) the masked candidates are taken whatever their
    overlap and centre (eq. 9 not tested; Table 1 at ``d``).
    """
    gap0, kl, ku, mx, mz, nx, nz = columns
    out_index, out_delta, out_ex, out_ez, out_reff, out_offset, out_offset_z = out
    half_dx = 0.5 * dx
    count = 0
    for j in range(n_active):
        if held is not None and not held[j]:
            continue
        k_l = kl[j]
        k_u = ku[j]
        k_sum = k_l + k_u
        if k_sum <= 0.0:
            continue
        g = gap0[j] - d
        m_x = mx[j]
        m_z = mz[j]
        n_x = nx[j]
        n_z = nz[j]
        k_prod = k_u * k_l
        y_x = k_l * m_x + k_u * n_x
        y_z = k_prod * g + k_l * m_z + k_u * n_z
        y_norm = math.sqrt(y_x * y_x + y_z * y_z)
        if y_norm <= 0.0:
            continue
        dmx = m_x - n_x
        dmz = m_z - n_z
        delta = (dmx * dmx + dmz * dmz - k_prod * g * g - 2.0 * g * (k_l * m_z + k_u * n_z)) / (
            y_norm + k_sum
        )
        if held is None and delta <= delta_min:
            continue
        offset = (2.0 * dmx + delta * (k_u * n_x - k_l * m_x)) / (2.0 * y_norm)
        if held is None and not (-half_dx <= offset < half_dx):
            continue  # (most candidates: points beside their summit; tested before the rise)
        if held is None and delta <= 0.0 and delta <= -reach:
            # an open summit can only touch where the surface has risen towards it: the mesh
            # displacement of the previous step (smooth, so it underestimates the rise next to
            # loaded contacts only where the surface is pushed down anyway)
            t = point_x[j] / cell
            i0 = math.floor(t)
            frac = t - i0
            cells = uplift.size
            rise = -(uplift[i0 % cells] * (1.0 - frac) + uplift[(i0 + 1) % cells] * frac)
            if delta <= -UPLIFT_FACTOR * rise:
                continue
        out_index[count] = j
        out_delta[count] = delta
        out_ex[count] = y_x / y_norm
        out_ez[count] = y_z / y_norm
        out_reff[count] = 2.0 / k_sum
        out_offset[count] = offset
        out_offset_z[count] = (
            2.0 * dmz + delta * (k_u * n_z - k_l * m_z) + g * k_u * (2.0 - k_l * delta)
        ) / (2.0 * y_norm)
        count += 1
    return count


@numba.njit(cache=True, nogil=True)
def _can_centre_in_cell(
    gap0: NDArray[np.float64],
    d_low: float,
    d_high: float,
    columns: tuple,
    dx: float,
) -> NDArray[np.bool_]:  # pragma: no cover - compiled
    """Candidates whose contact centre can fall in their own cell (eq. 9) at some displacement.

    A rigorous bound over the gaps g ∈ [gap0 − ``d_high``, gap0 − ``d_low``] [µm] a candidate
    passes through: |offset| ≥ (2|Δm_x| − max|δ| |κ^u n_x − κ^l m_x|) / (2 max|Y|), with
    |δ| ≤ max|N(g)|/(κ^l + κ^u) (N the numerator of δ, quadratic in g; |Y| ≥ 0) and |Y| largest
    at an end (Y_z linear in g). Candidates that Table 1 always refuses (κ^l + κ^u ≤ 0) or
    whose bound exceeds half the grid spacing ``dx`` [µm] are never accepted by
    :func:`_accept`; the others are kept (most candidates are points beside their summit).
    ``columns`` = (κ^l, κ^u, m_x, m_z, n_x, n_z).
    """
    kl, ku, mx, mz, nx, nz = columns
    keep = np.zeros(gap0.size, dtype=np.bool_)
    for j in range(gap0.size):
        k_sum = kl[j] + ku[j]
        if not k_sum > 0.0:
            continue
        k_prod = kl[j] * ku[j]
        b = kl[j] * mz[j] + ku[j] * nz[j]
        dmx = mx[j] - nx[j]
        dmz = mz[j] - nz[j]
        a = dmx * dmx + dmz * dmz
        g_lo = gap0[j] - d_high
        g_hi = gap0[j] - d_low
        n_max = max(
            abs(a - k_prod * g_lo * g_lo - 2.0 * g_lo * b),
            abs(a - k_prod * g_hi * g_hi - 2.0 * g_hi * b),
        )
        if k_prod != 0.0:
            turn = -b / k_prod
            if g_lo < turn < g_hi:
                n_max = max(n_max, abs(a - k_prod * turn * turn - 2.0 * turn * b))
        y_x = kl[j] * mx[j] + ku[j] * nx[j]
        y_z = max(abs(k_prod * g_lo + b), abs(k_prod * g_hi + b))
        y_max = math.sqrt(y_x * y_x + y_z * y_z)
        bound = (2.0 * abs(dmx) - n_max / k_sum * abs(ku[j] * nx[j] - kl[j] * mx[j])) / (
            2.0 * y_max
        )
        keep[j] = not bound > 0.5 * dx * (1.0 + 1e-6)
    return keep


def extended_geometry(
    lower: Profile,
    upper: Profile | Literal["flat"],
    *,
    steps: int,
    final_displacement: float | None,
    final_displacement_factor: float,
    alpha: float,
    x0: float,
    fits: tuple[SplineFit, SplineFit | None] | None = None,
    reach_fraction: float = DEFAULT_REACH,
) -> ContactGeometry:
    """SAD geometry whose candidate set reaches beyond the last displacement.

    In the coupled body the surface between loaded contacts rises (the displacement has zero
    mean), so summits whose rigid gap is still open can touch. The candidates are those whose gap
    closes by (1 + ``reach_fraction``) × the final displacement; the displacement steps are
    SAD's, δ_N = final · k / steps. Parameters as
    :func:`splinecontact.contact.contact_geometry`; ``reach_fraction`` [1] ≥ 0.
    """
    if isinstance(reach_fraction, bool) or not (
        isinstance(reach_fraction, (int, float))
        and math.isfinite(reach_fraction)
        and reach_fraction >= 0.0
    ):
        raise ParameterError(
            f"reach_fraction must be a finite number ≥ 0 [1], got {reach_fraction!r}"
        )
    final = (
        final_displacement_factor * lower.peak_to_valley
        if final_displacement is None
        else float(final_displacement)
    )
    return contact_geometry(
        lower,
        upper,
        steps=steps,
        final_displacement=final_displacement,
        final_displacement_factor=final_displacement_factor,
        alpha=alpha,
        x0=x0,
        fits=fits,
        reach=final * reach_fraction,
    )


def _check_finite(
    sums: NDArray[np.float64],
    first: int,
    stop: int,
    displacement: NDArray[np.float64],
    period: float,
) -> None:
    """Raise :class:`ParameterError` at the first step whose sums are not finite.

    The model's self coefficient c P (ln(L_p/(π a)) − 3/2) and the periodic Green function
    hold only while every contact is narrow next to the period L_p [µm]; a contact as wide as
    the period leaves the model and its loads become infinite or undefined.
    """
    bad = ~np.all(np.isfinite(sums[:, first:stop]), axis=0)
    if not bad.any():
        return
    step = first + int(np.argmax(bad))
    raise ParameterError(
        f"the interacting model left its validity at step {step} (displacement "
        f"{float(displacement[step]):.4g} µm): a contact grew too wide for the period "
        f"L_p = {period:.4g} µm of the half-plane model (its half-width must stay well below "
        f"L_p/π = {period / math.pi:.4g} µm), so its load is not finite; use a longer profile "
        "(more points at the same spacing) or a smaller final displacement"
    )


def _fixed_parts(geometry: Any, n: int, width: str) -> tuple[Any, ...]:
    """What :func:`interacting_loading` needs of the candidates whatever the displacements:
    the slope of the rigid gap at the nodes (``width`` = "profile", else ``None``), the sorted
    gaps [µm], the columns, the gaps, a slot for the stable gap order of every candidate (set
    by :func:`interacting_loading` when ``reuse`` meets the same candidates again) and the
    quadratures of the punch widths and the pair coefficients."""
    slope = None
    if width == "profile":
        # slope of the rigid gap from the spline slopes at the nodes (eq. 4 normals):
        # gap′ = −f_l′ − f_u′ = n_x/n_z − m_x/m_z; NaN where the gap never closes
        slope = np.full(n, np.nan)
        slope[np.asarray(geometry.point)] = np.asarray(geometry.n_x) / np.asarray(
            geometry.n_z
        ) - np.asarray(geometry.m_x) / np.asarray(geometry.m_z)
    all_gap0 = np.sort(np.asarray(geometry.gap0, dtype=np.float64), kind="stable")
    names = ("curvature_lower", "curvature_upper", "m_x", "m_z", "n_x", "n_z")
    raw = [np.asarray(getattr(geometry, name), dtype=np.float64) for name in names]
    raw_gap0 = np.asarray(geometry.gap0, dtype=np.float64)
    return slope, all_gap0, raw, raw_gap0, None, (*_punch_quadrature(), *_quadrature())


def interacting_loading(
    geometry: Any,
    *,
    e_star: float,
    g_star: float,
    mu0: float,
    n_points: int,
    settings: InteractionSettings = InteractionSettings(),
    record_steps: NDArray[np.int64] | None = None,
    law: Any = None,
    contact_set: NDArray[np.bool_] | None = None,
    mesh: Any = None,
    carry: dict[str, Any] | None = None,
    law_state: NDArray[np.float64] | None = None,
    reuse: dict[str, Any] | None = None,
) -> tuple[dict[str, NDArray[Any]], tuple[ContactRecord, ...]]:
    """Run the interacting loading on a prepared SAD geometry (eqs. 7–14 with elastic coupling).

    Parameters
    ----------
    geometry : ContactGeometry
        From :func:`splinecontact.contact.contact_geometry` (candidates, curvatures, normals,
        displacement steps).
    e_star : float
        Effective modulus E* [GPa].
    g_star : float
        Effective shear modulus G* [GPa] (tangential springs, eq. 11).
    mu0 : float
        Molecular friction coefficient μ0 [1] (eqs. 12–13).
    n_points : int
        Grid points of the profile [1] (the segment length is n_points·dx).
    settings : InteractionSettings
        Boundary conditions, tolerance and mesh.
    record_steps : array of int, optional
        Steps at which to keep the loaded contacts.
    law : ContactLaw, optional
        Local normal law, bound (:func:`splinecontact.contact.laws.bind_law`); ``None`` or
        Hertz: eq. 10 and the linear solve; another law: the nonlinear contact-level solve of
        :mod:`.interaction_laws` (the contacts' widths are then the law's own, whatever
        ``settings.width``).
    contact_set : array of bool, optional
        A mask over the geometry's candidates: every step after the first takes the masked
        candidates as its contacts without the eq. 9 test (force control holds them fixed).
    mesh : numba typed list, optional
        A kernel cache of :func:`.interaction_operator.mesh_cache` to reuse across calls with the
        same period and E* (its meshes are computed once).
    carry : dict, optional
        In and out: the state after the last step of a previous call (loads, widths, mesh
        displacement, candidates by grid point). Given non-empty, step 0 is that state (not
        solved again) and the steps run from 1; replaced by the state after the last step.
    law_state : array of float, optional
        In and out, with a law other than Hertz: the law's history, one row per lower grid
        point (shape (n_points, law.n_state)), committed in place at every solved step; zeroed
        when not given.
    reuse : dict, optional
        In and out: what does not depend on the displacements (the candidates' gap order,
        slopes and the quadratures), kept for the next call on the same ``geometry.gap0``
        array (the same candidates); the results are the same with or without it.

    Returns
    -------
    (curves, contacts)
        Per-step arrays (the keys of :func:`splinecontact.contact.run_loading` plus
        ``coalesced_contact_length`` [µm], the union of the contact intervals,
        ``n_contact_patches`` [1], its pieces, ``interaction_iterations`` [1] and
        ``reach_exceeded`` [1]); the loaded contacts at the recorded steps (``overlap`` is the
        effective approach δ^eff, ``normal_force`` the load P).
    """
    if not (isinstance(settings.tol, float) and 0.0 < settings.tol < 1.0):
        raise ParameterError(f"interaction tol must be in (0, 1), got {settings.tol!r}")
    dx = float(geometry.dx)
    n = int(n_points)
    period_nodes = n if settings.periodic else 2 * n
    period = period_nodes * dx
    cells = settings.mesh_cells
    if cells is not None and (
        isinstance(cells, bool) or not isinstance(cells, int) or cells < 8 or cells & (cells - 1)
    ):
        raise ParameterError(f"mesh_cells must be a power of two ≥ 8, got {cells!r}")
    # the mirror images of the segment [0, (n − 1) dx] lie about its end; the largest mesh has
    # about one cell per grid node of the mirrored segment
    mirror_axis = (2 * n - 1) * dx
    max_cells = max(64, 1 << math.ceil(math.log2(max(2 * n, 2))))
    floor = 1e-6 * dx
    if isinstance(settings.width_iterations, bool) or not (
        isinstance(settings.width_iterations, int) and 1 <= settings.width_iterations <= 100
    ):
        raise ParameterError(
            f"width_iterations must be an integer in 1…100, got {settings.width_iterations!r}"
        )
    if isinstance(settings.width_tol, bool) or not (
        isinstance(settings.width_tol, float) and 0.0 < settings.width_tol < 1.0
    ):
        raise ParameterError(f"width_tol must be in (0, 1), got {settings.width_tol!r}")
    stop_force = settings.stop_force
    if stop_force is not None and (
        isinstance(stop_force, bool)
        or not isinstance(stop_force, (int, float))
        or not (math.isfinite(stop_force) and stop_force > 0.0)
    ):
        raise ParameterError(
            f"stop_force must be a finite force > 0 [mN/µm] or None, got {stop_force!r}"
        )
    if settings.width not in ("profile", "hertz"):
        raise ParameterError(f"width must be 'profile' or 'hertz', got {settings.width!r}")
    fixed = None if reuse is None else reuse.get("fixed")
    if fixed is None or fixed[0] is not geometry.gap0 or fixed[1] != settings.width:
        fixed = (geometry.gap0, settings.width, *_fixed_parts(geometry, n, settings.width))
        if reuse is not None:
            reuse["fixed"] = fixed
    elif fixed[6] is None:  # the same candidates again: their stable gap order, once
        fixed = (*fixed[:6], np.argsort(fixed[5], kind="stable"), fixed[7])
        reuse["fixed"] = fixed  # type: ignore[index]
    _, _, slope, all_gap0, raw, raw_gap0, by_gap, quadratures = fixed
    from .interaction_kernel import run_steps
    from .interaction_operator import _MAX_INNER, mesh_cache

    kernel: Any = run_steps  # compiled; its many arguments are checked by numba
    lawful = law is not None and law.code != 0
    law_args = (
        (law.code, law.kernel_parameters(e_star), float(e_star)) if lawful else
        (0, np.array([float(e_star)]), float(e_star)),
        (np.zeros((n, law.n_state)) if law_state is None else law_state) if lawful else
        np.zeros((1, 0)),
        float(law.reach) if lawful else 0.0,
    )  # fmt: skip

    displacement = np.asarray(geometry.displacement, dtype=np.float64)
    n_steps = displacement.size
    n_cand = geometry.gap0.size
    record = np.zeros(n_steps, dtype=bool)
    if record_steps is not None and len(record_steps):
        record[np.asarray(record_steps)] = True
    reach = float(all_gap0[-1]) if all_gap0.size else 0.0
    # only the candidates whose contact centre can fall in their own cell are tested at every
    # step (the same contacts are accepted, in the same order)
    kept = _can_centre_in_cell(
        raw_gap0,
        min(0.0, float(displacement.min(initial=0.0))),
        float(displacement.max(initial=0.0)),
        tuple(raw),
        dx,
    )
    # candidates in order of their gap at δ_N = 0 (the order in which they can touch); the
    # reach of the candidate set is its largest gap. With ``reuse`` the stable order of every
    # candidate, filtered: the same order (ties by position in both)
    if by_gap is None:
        keep = np.flatnonzero(kept)
        order = keep[np.argsort(raw_gap0[keep], kind="stable")]
    else:
        order = by_gap[kept[by_gap]]
    gap0 = np.ascontiguousarray(raw_gap0[order])
    columns = [np.ascontiguousarray(column[order]) for column in raw]
    points = np.ascontiguousarray(np.asarray(geometry.point)[order], dtype=np.int64)
    height_lower = np.asarray(geometry.height_lower)[order]
    n_cand = gap0.size
    point_x = points.astype(np.float64) * dx
    sines, punch_weights, nodes, node_weights = quadratures
    largest_mesh = max(max_cells, cells or 0)
    cache = mesh_cache(largest_mesh) if mesh is None else mesh
    state = np.array([0.0, 0.0, period, 1.0, 0.0])
    field = np.zeros(largest_mesh)
    per_contact = [np.zeros(n_cand) for _ in range(5)]  # load, older, tangential, width, shift
    last_j = np.zeros(n_cand, dtype=np.int64)
    idx = np.empty(n_cand, dtype=np.int64)
    scratch = [np.empty(n_cand) for _ in range(9)]
    _delta, ex, ez, reff, _offset, offset_z, out_x, out_load, out_ft = scratch
    sums = np.zeros((6, n_steps))
    counts = np.zeros((5, n_steps), dtype=np.int64)
    dummy = np.zeros(1)
    contacts: list[ContactRecord] = []
    stops = [*(int(s) + 1 for s in np.flatnonzero(record)), n_steps]
    held = {} if contact_set is None else {"hold": np.asarray(contact_set, dtype=np.bool_)[order]}
    first = 0
    if carry:  # the previous call's state on these candidates, matched by grid point
        lookup = np.full(int(max(points.max(), carry["points"].max())) + 1, -1)
        lookup[points] = np.arange(n_cand)
        new = lookup[carry["points"]]
        old = np.flatnonzero(new >= 0)
        new = new[old]
        for mine, theirs in zip(per_contact, carry["per_contact"], strict=True):
            mine[new] = theirs[old]
        last = lookup[carry["last_points"]]
        last = last[last >= 0]
        last_j[: last.size] = last
        state[:] = carry["state"]
        state[4] = last.size
        field[: carry["field"].size] = carry["field"]
        first = 1
    for stop in stops:
        if first >= n_steps:
            break  # stop_force reached
        if stop <= first:
            continue
        count, failed, residual, stopped = kernel(
            first, stop, displacement, gap0, reach, point_x, gap0, *columns, dx, n * dx,
            float(e_star), float(g_star), float(mu0), float(settings.tol), settings.width_tol,
            float(stop_force or 0.0),
            int(settings.width_iterations), not settings.periodic, mirror_axis, period,
            cells or 0, max_cells, slope is not None, dummy if slope is None else slope, dummy,
            sines, punch_weights, nodes, node_weights, floor, cache, state, field,
            *per_contact, last_j, idx, *scratch, sums, counts, *law_args, points, **held,
        )  # fmt: skip
        if failed >= 0:
            raise NoConvergenceError(
                f"the interacting contact solve did not converge in {_MAX_INNER} iterations "
                f"at step {failed} (residual {residual:.3g} > tol {settings.tol:.3g}); raise "
                "tol or use more steps"
            )
        _check_finite(sums, first, stop, displacement, period)
        if stopped >= 0:
            n_steps = stop = stopped + 1
            displacement = displacement[:n_steps]
            sums = sums[:, :n_steps]
            counts = counts[:, :n_steps]
        first = stop
        step = stop - 1
        if record[step] and count > 0:
            j = idx[:count]
            on = out_load[:count] != 0.0 if lawful else out_load[:count] > 0.0
            chosen = j[on]
            contacts.append(
                ContactRecord(
                    step=int(step),
                    point=points[chosen],
                    x=out_x[:count][on].copy(),
                    z=height_lower[chosen] + offset_z[:count][on],
                    overlap=_delta[:count][on].copy()
                    if lawful
                    else out_load[:count][on] / (_QUARTER_PI * e_star),
                    effective_radius=reff[:count][on].copy(),
                    normal_force=out_load[:count][on].copy(),
                    tangential_force=out_ft[:count][on].copy(),
                    normal_x=ex[:count][on].copy(),
                    normal_z=ez[:count][on].copy(),
                )
            )
    if carry is not None:
        carry.update(
            points=points, per_contact=per_contact, state=state, field=field[: int(state[3])],
            last_points=points[last_j[: int(state[4])]],
        )  # fmt: skip
    names = (
        "normal_force",
        "tangential_force",
        "contact_area",
        "normal_force_normal_part",
        "normal_force_tangential_part",
        "coalesced_contact_length",
    )
    curves: dict[str, NDArray[Any]] = {k: sums[i].copy() for i, k in enumerate(names)}
    for i, k in enumerate(
        (
            "n_contacts",
            "n_tilted_contacts",
            "n_contact_patches",
            "interaction_iterations",
            "reach_exceeded",
        )
    ):
        curves[k] = counts[i].copy()
    curves["displacement"] = displacement
    curves["tangential_displacement"] = np.zeros_like(displacement)
    curves["mean_separation"] = geometry.mean_gap0 - displacement
    curves["n_candidates"] = np.searchsorted(all_gap0, displacement, side="right").astype(np.int64)
    return curves, tuple(contacts)
