"""Contact detection, acceptance and forces; the loading loop (paper Secs. 2.4–2.5).

Geometry (global frame, z up). The lower body's smoothed surface is h^l_i = f^l(x_i); the upper
body, given in its own frame (heights out of the body), is turned over: h^u_i(δ_N) =
C − f^u(x_i) − δ_N, with C chosen so that the smallest gap is zero at δ_N = 0. Each body carries
its own-frame curvature κ (positive on asperities that point toward the other body) and normal.
With ``m = −n^u`` (the upper body's outward normal turned into the lower's frame) and the gap
``g = h^u − h^l``, the contact of the two surface spheres at point i is (see
``docs/conventions.md``)

* ``Y = κ^u κ^l (0, g) + κ^l m + κ^u n^l`` (Y = κ^u κ^l X, X the centre separation of eq. 7);
* repulsive direction (force on the upper body) ``e = Y/|Y|`` = sgn(R^u R^l) n^c (eq. 10 fixed);
* overlap ``δ = (|m − n^l|² − κ^u κ^l g² − 2g(κ^l m_z + κ^u n^l_z)) / (|Y| + κ^u + κ^l)``
  (eq. 10's R^u + R^l − sgn·|X| without cancellation);
* contact centre offset ``x_c − x_i = (2(m_x − n^l_x) + δ(κ^u n^l_x − κ^l m_x)) / (2|Y|)``
  (eq. 8 turned into a global position);
* ``R_eff = 2/(κ^u + κ^l)`` (eq. 10).

Acceptance at step k: the gap has closed (g ≤ 0, detection), Table 1 (which in curvatures is
κ^u + κ^l > 0: convex–convex, or convex–concave with the convex sphere the smaller), the centre
lies in the point's own cell (eq. 9, x_c − x_i ∈ [−dx/2, dx/2)), and δ > 0.

Forces on the upper body: normal ``(π/4) E* δ e``; tangential a scalar F_t along
``t = (e_z, −e_x)``, incremented by ``−G* Δu·t`` with ``Δu = (0, −Δ)`` the upper body's step
(eq. 11; the spring resists the relative motion), capped at ``μ0 |F^n|`` keeping its sign
(eqs. 12–13), and reset to 0 when the contact is not accepted. Global sums follow eq. 14.

Cost: only points whose gap ever closes are visited; they are sorted by the step at which they
close, so step k visits exactly the c_k candidates of that step (Σ_k c_k in total).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numba
import numpy as np
from numpy.typing import NDArray

from ._checks import LENGTH_LIMIT, MAGNITUDE_LIMIT, check_integer, check_real
from .errors import GridMismatchError, ParameterError
from .profile import UNIFORM_GRID_RTOL, Profile
from .results import ContactRecord, SimulationResult
from .spheres import own_frame_geometry
from .spline import SplineFit, fit_spline

if TYPE_CHECKING:
    from .loadpath import Segment

__all__ = [
    "MAX_RECORDED_CONTACTS",
    "MAX_STEPS",
    "SIMULATION_PARAMETERS",
    "ContactGeometry",
    "contact_geometry",
    "run_loading",
    "simulate",
]

#: Keyword parameters of :func:`simulate` that describe the model (not ``record_contacts``).
SIMULATION_PARAMETERS = (
    "steps",
    "final_displacement",
    "final_displacement_factor",
    "e_star",
    "g_star",
    "mu0",
    "alpha",
    "x0",
)

_QUARTER_PI = 0.25 * math.pi

#: Default ceiling on ``steps`` [1] (10⁶; the paper uses 1000). Raise it with ``max_steps=``.
MAX_STEPS = 1_000_000

#: Most contact slots ``record_contacts`` may reserve (points whose gap has closed, summed over
#: the recorded steps) [1]: 2·10⁷ slots are 1.6 GB.
MAX_RECORDED_CONTACTS = 20_000_000


@dataclass(frozen=True, eq=False)
class ContactGeometry:
    """Everything the loading loop needs, for the points whose gap closes by the last step.

    Candidate arrays are ordered by the step at which the point's gap closes.

    Attributes
    ----------
    point : ndarray of int
        Grid index of each candidate.
    x : ndarray
        Grid position x_i [µm].
    gap0 : ndarray
        Gap h^u − h^l at δ_N = 0 [µm] (≥ 0, minimum 0).
    height_lower : ndarray
        h^l_i [µm].
    curvature_lower, curvature_upper : ndarray
        Own-frame curvatures κ^l, κ^u [1/µm] (clamped).
    m_x, m_z : ndarray
        m = −n^u, the upper body's outward normal reversed [1].
    n_x, n_z : ndarray
        Lower body's outward normal n^l [1].
    first_step_index : ndarray of int
        ``first_step_index[k]`` = number of candidates closed at step k (candidates
        ``[0, first_step_index[k])`` are active at step k), length steps + 1.
    displacement : ndarray
        δ_N at each step [µm], length steps + 1.
    dx : float
        Grid spacing [µm].
    mean_gap0 : float
        Mean of the gap at δ_N = 0 over all grid points [µm] (mean-line separation).
    """

    point: NDArray[np.int64]
    x: NDArray[np.float64]
    gap0: NDArray[np.float64]
    height_lower: NDArray[np.float64]
    curvature_lower: NDArray[np.float64]
    curvature_upper: NDArray[np.float64]
    m_x: NDArray[np.float64]
    m_z: NDArray[np.float64]
    n_x: NDArray[np.float64]
    n_z: NDArray[np.float64]
    first_step_index: NDArray[np.int64]
    displacement: NDArray[np.float64]
    dx: float
    mean_gap0: float


@numba.njit(cache=True, nogil=True)
def _loading_kernel(
    gap0: NDArray[np.float64],
    kl: NDArray[np.float64],
    ku: NDArray[np.float64],
    mx: NDArray[np.float64],
    mz: NDArray[np.float64],
    nx: NDArray[np.float64],
    nz: NDArray[np.float64],
    active: NDArray[np.int64],
    displacement: NDArray[np.float64],
    dx: float,
    e_star: float,
    g_star: float,
    mu0: float,
    record: NDArray[np.bool_],
    record_capacity: int,
) -> tuple[Any, ...]:  # pragma: no cover - compiled
    n_steps = displacement.size
    out_fn = np.zeros(n_steps)
    out_ft = np.zeros(n_steps)
    out_area = np.zeros(n_steps)
    out_count = np.zeros(n_steps, dtype=np.int64)
    out_fn_normal = np.zeros(n_steps)
    out_fn_tangential = np.zeros(n_steps)
    out_tilted = np.zeros(n_steps, dtype=np.int64)
    n_cand = gap0.size
    tangential = np.zeros(n_cand)
    was_accepted = np.zeros(n_cand, dtype=np.bool_)
    rec_step = np.empty(record_capacity, dtype=np.int64)
    rec_index = np.empty(record_capacity, dtype=np.int64)
    rec_offset = np.empty(record_capacity)
    rec_offset_z = np.empty(record_capacity)
    rec_delta = np.empty(record_capacity)
    rec_reff = np.empty(record_capacity)
    rec_fn = np.empty(record_capacity)
    rec_ft = np.empty(record_capacity)
    rec_ex = np.empty(record_capacity)
    rec_ez = np.empty(record_capacity)
    n_rec = 0
    half_dx = 0.5 * dx
    for step in range(n_steps):
        d = displacement[step]
        increment = displacement[step] - displacement[step - 1] if step > 0 else 0.0
        sum_fn = 0.0
        sum_ft = 0.0
        sum_area = 0.0
        sum_fn_normal = 0.0
        sum_fn_tangential = 0.0
        count = 0
        tilted = 0
        for j in range(active[step]):
            accepted = False
            delta = 0.0
            offset = 0.0
            g = 0.0
            y_x = 0.0
            y_z = 0.0
            y_norm = 1.0
            dmx = 0.0
            dmz = 0.0
            m_z = 0.0
            n_z = 0.0
            k_l = kl[j]
            k_u = ku[j]
            k_sum = k_l + k_u
            if k_sum > 0.0:  # Table 1 (convex–convex, or convex–concave with the smaller convex)
                g = gap0[j] - d
                m_x = mx[j]
                m_z = mz[j]
                n_x = nx[j]
                n_z = nz[j]
                k_prod = k_u * k_l
                y_x = k_l * m_x + k_u * n_x
                y_z = k_prod * g + k_l * m_z + k_u * n_z
                y_norm = math.sqrt(y_x * y_x + y_z * y_z)
                if y_norm > 0.0:
                    dmx = m_x - n_x
                    dmz = m_z - n_z
                    delta = (
                        dmx * dmx + dmz * dmz - k_prod * g * g - 2.0 * g * (k_l * m_z + k_u * n_z)
                    ) / (y_norm + k_sum)
                    if delta > 0.0:
                        offset = (2.0 * dmx + delta * (k_u * n_x - k_l * m_x)) / (2.0 * y_norm)
                        if -half_dx <= offset < half_dx:  # eq. 9
                            accepted = True
            if accepted:
                e_x = y_x / y_norm
                e_z = y_z / y_norm
                f_n = _QUARTER_PI * e_star * delta
                if was_accepted[j]:
                    # Δu·t with Δu = (0, −increment), t = (e_z, −e_x): increment·e_x.
                    f_t = tangential[j] - g_star * increment * e_x
                    cap = mu0 * f_n
                    if f_t > cap:
                        f_t = cap
                    elif f_t < -cap:
                        f_t = -cap
                else:
                    f_t = 0.0
                tangential[j] = f_t
                was_accepted[j] = True
                fn_part = f_n * e_z
                ft_part = -f_t * e_x
                sum_fn_normal += fn_part
                sum_fn_tangential += ft_part
                sum_fn += fn_part + ft_part
                sum_ft += f_n * e_x + f_t * e_z
                reff = 2.0 / k_sum
                sum_area += math.sqrt(delta * reff)
                count += 1
                if e_z < 0.0:
                    tilted += 1
                if record[step]:
                    rec_step[n_rec] = step
                    rec_index[n_rec] = j
                    rec_offset[n_rec] = offset
                    rec_offset_z[n_rec] = (
                        2.0 * dmz + delta * (k_u * n_z - k_l * m_z) + g * k_u * (2.0 - k_l * delta)
                    ) / (2.0 * y_norm)
                    rec_delta[n_rec] = delta
                    rec_reff[n_rec] = reff
                    rec_fn[n_rec] = f_n
                    rec_ft[n_rec] = f_t
                    rec_ex[n_rec] = e_x
                    rec_ez[n_rec] = e_z
                    n_rec += 1
            else:
                tangential[j] = 0.0
                was_accepted[j] = False
        out_fn[step] = sum_fn
        out_ft[step] = sum_ft
        out_area[step] = sum_area
        out_count[step] = count
        out_fn_normal[step] = sum_fn_normal
        out_fn_tangential[step] = sum_fn_tangential
        out_tilted[step] = tilted
    return (
        out_fn,
        out_ft,
        out_area,
        out_count,
        out_fn_normal,
        out_fn_tangential,
        out_tilted,
        rec_step[:n_rec],
        rec_index[:n_rec],
        rec_offset[:n_rec],
        rec_offset_z[:n_rec],
        rec_delta[:n_rec],
        rec_reff[:n_rec],
        rec_fn[:n_rec],
        rec_ft[:n_rec],
        rec_ex[:n_rec],
        rec_ez[:n_rec],
    )


@numba.njit(cache=True, nogil=True)
def _place_bodies(
    f_l: NDArray[np.float64], f_u: NDArray[np.float64], flat: bool, final: float
) -> tuple[NDArray[np.float64], NDArray[np.int64], float]:  # pragma: no cover - compiled
    """Gap at δ_N = 0 (minimum exactly 0), indices with gap ≤ final, and the mean gap."""
    n = f_l.size
    offset = -np.inf
    for i in range(n):
        total = f_l[i] if flat else f_u[i] + f_l[i]
        if total > offset:
            offset = total
    gap0 = np.empty(n)
    count = 0
    gap_sum = 0.0
    for i in range(n):
        total = f_l[i] if flat else f_u[i] + f_l[i]
        g = offset - total
        gap0[i] = g
        gap_sum += g
        if g <= final:
            count += 1
    candidates = np.empty(count, dtype=np.int64)
    k = 0
    for i in range(n):
        if gap0[i] <= final:
            candidates[k] = i
            k += 1
    return gap0, candidates, gap_sum / n


@numba.njit(cache=True, nogil=True)
def _height_statistics(
    z: NDArray[np.float64], dx: float
) -> tuple[float, float, float, float]:  # pragma: no cover - compiled
    """R_A, R_q, peak-to-valley [µm] and R_Sq by grid differences (eq. 15) [1] in two passes."""
    n = z.size
    mean = 0.0
    lo = z[0]
    hi = z[0]
    for i in range(n):
        mean += z[i]
        lo = min(lo, z[i])
        hi = max(hi, z[i])
    mean /= n
    abs_sum = 0.0
    sq_sum = 0.0
    slope_sq = 0.0
    for i in range(n):
        dev = z[i] - mean
        abs_sum += abs(dev)
        sq_sum += dev * dev
        if i > 0:
            step = (z[i] - z[i - 1]) / dx
            slope_sq += step * step
    return abs_sum / n, math.sqrt(sq_sum / n), hi - lo, math.sqrt(slope_sq / (n - 1))


@numba.njit(cache=True, nogil=True)
def _sum_slope_rms(
    a: NDArray[np.float64], b: NDArray[np.float64], scale: float, use_b: bool
) -> float:  # pragma: no cover - compiled
    """rms of (a + b)·scale (b ignored unless use_b)."""
    total = 0.0
    for i in range(a.size):
        v = (a[i] + b[i] if use_b else a[i]) * scale
        total += v * v
    return math.sqrt(total / a.size)


@numba.njit(cache=True, nogil=True)
def _gap_slope_rms(
    z_l: NDArray[np.float64], z_u: NDArray[np.float64], dx: float
) -> float:  # pragma: no cover - compiled
    """rms of the grid-difference slope of z_l + z_u (the gap's slope up to sign)."""
    total = 0.0
    for i in range(1, z_l.size):
        v = ((z_l[i] + z_u[i]) - (z_l[i - 1] + z_u[i - 1])) / dx
        total += v * v
    return math.sqrt(total / (z_l.size - 1))


def _check_positive(name: str, value: float, unit: str, *, allow_zero: bool = False) -> float:
    value = check_real(name, value, unit.strip(), maximum=MAGNITUDE_LIMIT)
    if not (value >= 0 if allow_zero else value > 0):
        bound = "≥ 0" if allow_zero else "> 0"
        raise ParameterError(f"{name} = {value!r}{unit} must be finite and {bound}")
    return value


def _closing_steps(gap0: NDArray[np.float64], displacement: NDArray[np.float64]) -> NDArray[Any]:
    """Index of the first step k with gap0 ≤ displacement[k] (len(displacement) if never)."""
    return np.searchsorted(displacement, gap0, side="left")


def contact_geometry(
    lower: Profile,
    upper: Profile | Literal["flat"],
    *,
    steps: int,
    final_displacement: float | None,
    final_displacement_factor: float,
    alpha: float,
    x0: float,
    fits: tuple[SplineFit, SplineFit | None] | None = None,
) -> tuple[ContactGeometry, dict[str, float]]:
    """Spline fits, spheres, placement and candidate ordering for a loading (Secs. 2.2–2.4).

    Parameters
    ----------
    lower : Profile
        Lower body, heights [µm] out of the body.
    upper : Profile or "flat"
        Upper body, heights [µm] out of its own body (turned over here), or a rigid flat.
    steps : int
        Number of equal displacement increments [1].
    final_displacement : float or None
        Displacement at the last step [µm]; ``None`` for ``final_displacement_factor`` times
        the lower profile's peak-to-valley height.
    final_displacement_factor : float
        Factor [1] used when ``final_displacement`` is ``None`` (paper: 0.2).
    alpha : float
        Tightness exponent α [1] (eq. 3).
    x0 : float
        Unit length x0 [µm] (eqs. 2–3).
    fits : (SplineFit, SplineFit or None), optional
        Spline fits of (lower, upper) already computed with the same α and x0 (``None`` for a
        flat upper body); fitted here when omitted.

    Returns
    -------
    (ContactGeometry, dict)
        The geometry and the surface statistics of ``SCALAR_VARIABLES`` (except
        ``final_displacement``).
    """
    _check_bodies(lower, upper)
    flat = isinstance(upper, str)
    if not flat:
        assert isinstance(upper, Profile)  # for mypy: _check_bodies has refused anything else
        if upper.n_points != lower.n_points:
            raise GridMismatchError(
                f"the upper profile has {upper.n_points} points and the lower {lower.n_points}; "
                "both bodies must share one grid (resample or crop one of them)"
            )
        if abs(upper.dx - lower.dx) > UNIFORM_GRID_RTOL * lower.dx:
            raise GridMismatchError(
                f"grid spacings differ: upper dx = {upper.dx!r} µm, lower dx = {lower.dx!r} µm; "
                "both bodies must share one grid (resample one of them)"
            )
    if fits is None:
        fit_l = fit_spline(lower, alpha=alpha, x0=x0)
        fit_u = None if flat else fit_spline(upper, alpha=alpha, x0=x0)  # type: ignore[arg-type]
    else:
        fit_l, fit_u = fits
    r_min = 0.5 * lower.dx
    f_l = fit_l.f
    if final_displacement is None:
        _check_positive("final_displacement_factor", final_displacement_factor, "")
        final = final_displacement_factor * lower.peak_to_valley
        if not final > 0:
            raise ParameterError(
                "the lower profile is flat (peak-to-valley height 0 µm), so the default final "
                "displacement is 0; give final_displacement in µm"
            )
    else:
        final = _check_positive("final_displacement", final_displacement, " µm")
    if final > LENGTH_LIMIT:
        raise ParameterError(
            f"the final displacement {final!r} µm is beyond {LENGTH_LIMIT:g} µm, where the "
            "displacement steps would overflow; give final_displacement in µm (of the order of "
            "the profile heights)"
        )
    displacement = final * np.arange(steps + 1) / steps
    # gap0 ≥ 0 with minimum 0 at the highest point of f^u + f^l. Only the points whose gap
    # closes by the last step are ever visited (detection z^u ≤ z^l).
    gap0, candidates, mean_gap0 = _place_bodies(
        f_l, f_l if fit_u is None else fit_u.f, fit_u is None, float(displacement[-1])
    )
    closing = np.searchsorted(displacement, gap0[candidates], side="left")
    order_in = np.argsort(closing, kind="stable")
    order = candidates[order_in]
    counts = np.bincount(closing[order_in], minlength=steps + 1)
    active = np.cumsum(counts).astype(np.int64)

    kappa_l, n_x, n_z = own_frame_geometry(
        fit_l.slope[order], fit_l.second_derivative[order], r_min
    )
    if fit_u is None:
        slope_u_c = np.zeros(order.size)
        kappa_u = np.zeros(order.size)
    else:
        slope_u_c = fit_u.slope[order]
        kappa_u, _, _ = own_frame_geometry(slope_u_c, fit_u.second_derivative[order], r_min)
    norm_u = np.sqrt(1.0 + slope_u_c**2)
    geometry = ContactGeometry(
        point=order.astype(np.int64),
        x=lower.x[order],
        gap0=gap0[order],
        height_lower=f_l[order],
        curvature_lower=kappa_l,
        curvature_upper=kappa_u,
        m_x=slope_u_c / norm_u,
        m_z=1.0 / norm_u,
        n_x=n_x,
        n_z=n_z,
        first_step_index=active,
        displacement=displacement,
        dx=lower.dx,
        mean_gap0=float(mean_gap0),
    )

    dx = lower.dx
    ra_l, rq_l, pv_l, rsq_l = _height_statistics(lower.z, dx)
    if fit_u is None:
        ra_u = rq_u = rsq_u = 0.0
        rsq_gap = rsq_l
        slope_u = fit_l.slope
    else:
        ra_u, rq_u, _, rsq_u = _height_statistics(upper.z, dx)  # type: ignore[union-attr]
        rsq_gap = _gap_slope_rms(lower.z, upper.z, dx)  # type: ignore[union-attr]
        slope_u = fit_u.slope
    flat_u = fit_u is None
    stats = {
        "ra_lower": ra_l,
        "rq_lower": rq_l,
        "peak_to_valley_lower": pv_l,
        "rsq_lower": rsq_l,
        "rsq_lower_spline": _sum_slope_rms(fit_l.slope, fit_l.slope, 1.0, False),
        "ra_upper": ra_u,
        "rq_upper": rq_u,
        "rsq_upper": rsq_u,
        "rsq_upper_spline": 0.0 if flat_u else _sum_slope_rms(slope_u, slope_u, 1.0, False),
        "rsq_gap": rsq_gap,
        "rsq_gap_spline": _sum_slope_rms(fit_l.slope, slope_u, 1.0, not flat_u),
    }
    return geometry, stats


def run_loading(
    geometry: ContactGeometry,
    *,
    e_star: float,
    g_star: float,
    mu0: float,
    record_steps: NDArray[np.int64] | None = None,
) -> tuple[dict[str, NDArray[Any]], tuple[ContactRecord, ...]]:
    """Run the loading loop on a prepared geometry (eqs. 7–14).

    Parameters
    ----------
    geometry : ContactGeometry
        From :func:`contact_geometry`.
    e_star : float
        Effective modulus E* [GPa].
    g_star : float
        Effective shear modulus G* [GPa].
    mu0 : float
        Molecular friction coefficient μ0 [1].
    record_steps : array of int, optional
        Steps at which to keep the accepted contacts.

    Returns
    -------
    (curves, contacts)
        Per-step arrays keyed by ``STEP_VARIABLES`` names, and the recorded contacts.
    """
    n_records = geometry.displacement.size
    record = np.zeros(n_records, dtype=np.bool_)
    if record_steps is not None and len(record_steps):
        record[record_steps] = True
    capacity = int(geometry.first_step_index[record].sum()) if record.any() else 0
    (fn, ft, area, count, fn_normal, fn_tangential, tilted,
     rec_step, rec_index, rec_offset, rec_offset_z, rec_delta, rec_reff, rec_fn, rec_ft,
     rec_ex, rec_ez) = _loading_kernel(
        geometry.gap0, geometry.curvature_lower, geometry.curvature_upper,
        geometry.m_x, geometry.m_z, geometry.n_x, geometry.n_z,
        geometry.first_step_index, geometry.displacement, geometry.dx,
        e_star, g_star, mu0, record, capacity,
    )  # fmt: skip
    curves: dict[str, NDArray[Any]] = {
        "displacement": geometry.displacement,
        "tangential_displacement": np.zeros_like(geometry.displacement),
        "normal_force": fn,
        "tangential_force": ft,
        "contact_area": area,
        "n_contacts": count,
        "mean_separation": geometry.mean_gap0 - geometry.displacement,
        "normal_force_normal_part": fn_normal,
        "normal_force_tangential_part": fn_tangential,
        "n_tilted_contacts": tilted,
        "n_candidates": geometry.first_step_index.copy(),
    }
    contacts: list[ContactRecord] = []
    for step in np.flatnonzero(record):
        sel = rec_step == step
        j = rec_index[sel]
        contacts.append(
            ContactRecord(
                step=int(step),
                point=geometry.point[j],
                x=geometry.x[j] + rec_offset[sel],
                z=geometry.height_lower[j] + rec_offset_z[sel],
                overlap=rec_delta[sel],
                effective_radius=rec_reff[sel],
                normal_force=rec_fn[sel],
                tangential_force=rec_ft[sel],
                normal_x=rec_ex[sel],
                normal_z=rec_ez[sel],
            )
        )
    return curves, tuple(contacts)


def _record_steps(record_contacts: Iterable[int] | str | None, steps: int) -> NDArray[np.int64]:
    if record_contacts is None:
        return np.zeros(0, dtype=np.int64)
    if isinstance(record_contacts, str):
        if record_contacts == "all":
            return np.arange(steps + 1, dtype=np.int64)
        if record_contacts == "last":
            return np.array([steps], dtype=np.int64)
        raise ParameterError(
            f"record_contacts = {record_contacts!r}; give step indices, 'all' or 'last'"
        )
    if isinstance(record_contacts, np.ndarray):
        record_contacts = record_contacts.ravel().tolist()
    if not isinstance(record_contacts, Iterable):
        raise ParameterError(
            f"record_contacts = {record_contacts!r}; give a list of step indices (for example "
            "[0, 10]), 'all' or 'last'"
        )
    chosen_steps: list[int] = []
    for value in record_contacts:
        try:
            chosen_steps.append(check_integer("record_contacts step", value, minimum=0))
        except ParameterError:
            raise ParameterError(
                f"record_contacts step {value!r} is not a step index; give integers in "
                f"0…{steps} (the steps of this run)"
            ) from None
    chosen = np.unique(np.asarray(chosen_steps, dtype=np.int64))
    bad = chosen[(chosen < 0) | (chosen > steps)]
    if bad.size:
        raise ParameterError(
            f"record_contacts step {int(bad[0])} is outside 0…{steps} (the steps of this run)"
        )
    return chosen


def _check_bodies(lower: Any, upper: Any) -> None:
    """Refuse bodies that are not Profiles (or ``"flat"`` for the upper one)."""
    if not isinstance(lower, Profile):
        raise ParameterError(
            f"lower is a {type(lower).__name__}, not a splinecontact.Profile; build one with "
            "Profile(x, z) or read_profile(path)"
        )
    if isinstance(upper, str):
        if upper != "flat":
            hint = " (did you mean 'flat'?)" if upper.strip().lower() == "flat" else ""
            raise ParameterError(f"upper = {upper!r}: give a Profile or the string 'flat'{hint}")
    elif not isinstance(upper, Profile):
        raise ParameterError(
            f"upper is a {type(upper).__name__}, not a splinecontact.Profile or the string "
            "'flat'; give the upper body's profile, or 'flat' for a rigid flat"
        )


def simulate(
    lower: Profile,
    upper: Profile | Literal["flat"],
    *,
    steps: int = 1000,
    final_displacement: float | None = None,
    final_displacement_factor: float = 0.2,
    e_star: float = 10.0,
    g_star: float | None = None,
    mu0: float = 0.3,
    alpha: float = 2.0,
    x0: float = 1.0,
    record_contacts: Iterable[int] | str | None = None,
    path: Sequence[Segment] | None = None,
    max_steps: int = MAX_STEPS,
    diagnostics: bool = True,
) -> SimulationResult:
    """Press two rough bodies (or a rough body and a rigid flat) together by SAD.

    The upper body is lowered in ``steps`` equal increments from zero minimum gap (step 0) to
    ``final_displacement``; at every step the accepted contacts of Table 1 and eq. 9 carry a
    Hertzian line-contact force (π/4)E*δ along their repulsive direction and an incremental
    tangential force (eqs. 11–13); eq. 14 sums them.

    Parameters
    ----------
    lower : Profile
        Lower body; heights [µm] point out of the body (as a profilometer records them).
    upper : Profile or "flat"
        Upper body, also with heights [µm] out of its own body (it is turned over here to face
        the lower one), or ``"flat"`` for a rigid flat. Must share the lower profile's grid.
    steps : int, optional
        Number of displacement increments N [1] (paper: 1000); results have N + 1 records.
    final_displacement : float, optional
        Displacement δ_N at the last step [µm]. Default: ``final_displacement_factor`` × the
        lower profile's peak-to-valley height.
    final_displacement_factor : float, optional
        Fraction [1] of the lower peak-to-valley height used by default (paper: 0.2).
    e_star : float, optional
        Effective modulus E* [GPa] (paper: 10 GPa).
    g_star : float, optional
        Effective shear modulus G* [GPa]; default E*/2.6 (ν = 0.3).
    mu0 : float, optional
        Molecular friction coefficient μ0 [1] capping |F^t| ≤ μ0|F^n| (eqs. 12–13).
    alpha : float, optional
        Spline tightness exponent α [1] (eq. 3; paper: 2).
    x0 : float, optional
        Spline unit length x0 [µm] (eqs. 2–3; paper: 1 µm).
    record_contacts : iterable of int, "all", "last" or None, optional
        Steps at which to keep every accepted contact (for plots such as Fig. 9). The points
        whose gap has closed, summed over these steps, may not exceed
        ``MAX_RECORDED_CONTACTS`` (2·10⁷).
    path : sequence of Segment, optional
        A load path of normal [µm] or force-controlled [mN/µm] and tangential [µm] segments
        (:class:`splinecontact.Segment`, see ``docs/friction.md``). Replaces ``steps`` and
        ``final_displacement``; without it the run is the single normal loading above.
    max_steps : int, optional
        Ceiling [1] on ``steps`` (default ``MAX_STEPS`` = 10⁶), checked before anything is
        allocated.
    diagnostics : bool, optional
        Run the checks of :mod:`splinecontact.diagnostics` (form, coarse grid, near-full
        contact) and issue their warnings (default). ``False`` skips them (about 35 ms at 10⁶
        points), e.g. for the realizations of an ensemble.

    Returns
    -------
    SimulationResult
        Curves of F_N, F_T [mN/µm], A_S [µm], contact counts and mean separation [µm] per step.

    Raises
    ------
    ParameterError
        A body is not a Profile (or ``"flat"``); a parameter is not a finite number of the right
        kind (``None``, a string, ``True``, NaN, inf); steps < 1 or above ``max_steps``,
        E* ≤ 0, G* < 0, μ0 < 0, α ≤ 0, x0 ≤ 0, final displacement ≤ 0 or beyond 10⁵⁰ µm,
        a non-integer or out-of-range ``record_contacts`` step, too many contacts to record.
    GridMismatchError
        The two profiles do not share a grid.

    Warns
    -----
    splinecontact.diagnostics.SimulationWarning
        A body dominated by tilt or form, a grid too coarse for the spline, or a final contact
        area near full contact (see :mod:`splinecontact.diagnostics`).
    """
    _check_bodies(lower, upper)
    max_steps = check_integer("max_steps", max_steps, minimum=1)
    steps = check_integer(
        "steps", steps, minimum=1, maximum=max_steps, note="paper: 1000", raise_with="max_steps"
    )
    if final_displacement is not None:
        _check_positive("final_displacement", final_displacement, " µm")
    _check_positive("final_displacement_factor", final_displacement_factor, "")
    e_star = _check_positive("e_star", e_star, " GPa")
    g_star = (
        e_star / 2.6
        if g_star is None
        else _check_positive("g_star", g_star, " GPa", allow_zero=True)
    )
    mu0 = _check_positive("mu0", mu0, "", allow_zero=True)
    _check_positive("alpha", alpha, "")
    _check_positive("x0", x0, " µm")
    if path is not None:
        from .loadpath import simulate_path

        return simulate_path(
            lower, upper, path, steps=steps, final_displacement=final_displacement, e_star=e_star,
            g_star=g_star, mu0=mu0, alpha=alpha, x0=x0, record_contacts=record_contacts,
        )  # fmt: skip
    record_steps = _record_steps(record_contacts, steps)

    geometry, stats = contact_geometry(
        lower, upper, steps=steps, final_displacement=final_displacement,
        final_displacement_factor=final_displacement_factor, alpha=alpha, x0=x0,
    )  # fmt: skip
    if record_steps.size:
        reserved = int(geometry.first_step_index[record_steps].sum())
        if reserved > MAX_RECORDED_CONTACTS:
            raise ParameterError(
                f"record_contacts would reserve {reserved} contact slots (points whose gap has "
                f"closed, summed over {record_steps.size} recorded steps), above "
                f"{MAX_RECORDED_CONTACTS}; record fewer steps"
            )
    curves, contacts = run_loading(
        geometry, e_star=e_star, g_star=g_star, mu0=mu0, record_steps=record_steps
    )
    flat = isinstance(upper, str)
    parameters: dict[str, Any] = {
        "contact_type": "rough-on-flat" if flat else "rough-on-rough",
        "steps": steps,
        "final_displacement": float(geometry.displacement[-1]),
        "final_displacement_factor": float(final_displacement_factor),
        "e_star": e_star,
        "g_star": g_star,
        "mu0": mu0,
        "alpha": float(alpha),
        "x0": float(x0),
        "r_min": 0.5 * lower.dx,
        "dx": lower.dx,
        "n_points": lower.n_points,
        "length": lower.length,
    }
    scalars = {**stats, "final_displacement": float(geometry.displacement[-1])}
    if diagnostics:
        from .diagnostics import warn_simulation  # form, coarse grid, near-full contact

        warn_simulation(lower, upper, curves, alpha=alpha, x0=x0)
    return SimulationResult(
        curves=curves,
        scalars=scalars,
        parameters=parameters,
        contacts=contacts,
        lower_metadata=dict(lower.metadata),
        upper_metadata={"source": "flat"} if flat else dict(upper.metadata),  # type: ignore[union-attr]
    )
