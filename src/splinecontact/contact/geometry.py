"""Contact geometry: body placement, candidate ordering and the two-sphere contact (Secs. 2.4–2.5).

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

The local contact law (:mod:`splinecontact.contact.laws`) turns δ and R_eff into a force; the
kernels (:mod:`.kernel`, :mod:`.path_kernel`) call :func:`sphere_contact` for every visited point.

Cost: only points whose gap ever closes are visited; they are sorted by the step at which they
close, so step k visits exactly the c_k candidates of that step (Σ_k c_k in total).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

import numba
import numpy as np
from numpy.typing import NDArray

from .._checks import LENGTH_LIMIT, MAGNITUDE_LIMIT, check_real
from ..errors import GridMismatchError, ParameterError
from ..profile import UNIFORM_GRID_RTOL, Profile
from ..spheres import own_frame_geometry
from ..spline import SplineFit, fit_spline_pair, grown

__all__ = [
    "ContactGeometry",
    "add_contact_forces",
    "check_bodies",
    "check_positive",
    "check_same_grid",
    "contact_centre_height",
    "contact_geometry",
    "displacement_steps",
    "order_candidates",
    "sphere_contact",
]


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


#: Points per chunk of :func:`_place_bodies`' candidate search (a chunk without candidates is
#: one vector loop).
_PLACE_CHUNK = 256


@numba.njit(cache=True, nogil=True, fastmath={"reassoc", "nsz"})
def _place_bodies(
    f_l: NDArray[np.float64], f_u: NDArray[np.float64], flat: bool, final: float
) -> tuple[NDArray[np.float64], NDArray[np.int64], float]:  # pragma: no cover - compiled
    """Gap at δ_N = 0 (minimum exactly 0) at the indices with gap ≤ final, those indices, and
    the mean gap over all points.

    The gap of the other points is never needed, so no array of n gaps is made: one pass finds
    the highest point, a second the mean gap and the candidates (chunks without one are a
    vector loop).
    """
    n = f_l.size
    offset = -np.inf
    for i in range(n):
        total = f_l[i] if flat else f_u[i] + f_l[i]
        if total > offset:
            offset = total
    zeros = np.zeros(_PLACE_CHUNK)  # the flat's heights (x + 0.0 is x for every x ≠ −0.0)
    gap_sum = 0.0
    count = 0
    capacity = 1024
    gaps = np.empty(capacity)
    candidates = np.empty(capacity, dtype=np.int64)
    for start in range(0, n, _PLACE_CHUNK):
        lower = f_l[start : start + _PLACE_CHUNK]
        upper = zeros[: lower.size] if flat else f_u[start : start + _PLACE_CHUNK]
        block_sum = 0.0
        found = 0
        for i in range(lower.size):
            g = offset - (upper[i] + lower[i])
            block_sum += g
            found += 1 if g <= final else 0
        gap_sum += block_sum
        if found == 0:
            continue
        if count + found > capacity:
            capacity = max(2 * capacity, count + found)
            gaps = grown(gaps, capacity)
            candidates = grown(candidates, capacity)
        for i in range(lower.size):
            g = offset - (upper[i] + lower[i])
            if g <= final:
                gaps[count] = g
                candidates[count] = start + i
                count += 1
    return grown(gaps[:count], count), grown(candidates[:count], count), gap_sum / n


def displacement_steps(
    final_displacement: float | None,
    final_displacement_factor: float,
    peak_to_valley: float,
    steps: int,
) -> NDArray[np.float64]:
    """δ_N at steps 0…steps [µm]: up to ``final_displacement`` [µm], or by default
    ``final_displacement_factor`` [1] × the lower body's ``peak_to_valley`` height [µm]."""
    if final_displacement is None:
        check_positive("final_displacement_factor", final_displacement_factor, "")
        final = final_displacement_factor * peak_to_valley
        if not final > 0:
            raise ParameterError(
                "the lower profile is flat (peak-to-valley height 0 µm), so the default final "
                "displacement is 0; give final_displacement in µm"
            )
    else:
        final = check_positive("final_displacement", final_displacement, " µm")
    if final > LENGTH_LIMIT:
        raise ParameterError(
            f"the final displacement {final!r} µm is beyond {LENGTH_LIMIT:g} µm, where the "
            "displacement steps would overflow; give final_displacement in µm (of the order of "
            "the profile heights)"
        )
    return final * np.arange(steps + 1) / steps


def check_positive(name: str, value: float, unit: str, *, allow_zero: bool = False) -> float:
    value = check_real(name, value, unit.strip(), maximum=MAGNITUDE_LIMIT)
    if not (value >= 0 if allow_zero else value > 0):
        bound = "≥ 0" if allow_zero else "> 0"
        raise ParameterError(f"{name} = {value!r}{unit} must be finite and {bound}")
    return value


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
    reach: float = 0.0,
) -> ContactGeometry:
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
    reach : float, optional
        Gap [µm] at which the contact law starts to act (its ``reach``, 0 for Hertz): a point
        becomes a candidate at the first step where its gap is ≤ reach.

    Returns
    -------
    ContactGeometry
        Candidates ordered by the step at which they close. The surface statistics (R_A, R_q,
        R_Sq) are :func:`splinecontact.profile.surface_statistics`.

    Examples
    --------
    >>> import numpy as np
    >>> from splinecontact import Profile
    >>> from splinecontact.contact import contact_geometry
    >>> x = np.linspace(-0.5, 0.5, 101)
    >>> ball = Profile(x, np.sqrt(1.0 - x**2) - 1.0)
    >>> geometry = contact_geometry(ball, "flat", steps=10, final_displacement=1e-3,
    ...                             final_displacement_factor=0.2, alpha=2.0, x0=1.0)
    >>> int(geometry.first_step_index[0]), float(geometry.displacement[-1])
    (1, 0.001)
    """
    check_bodies(lower, upper)
    flat = isinstance(upper, str)
    check_same_grid(lower, upper)
    if fits is None:
        fit_l, fit_u = fit_spline_pair(lower, None if flat else upper, alpha=alpha, x0=x0)  # type: ignore[arg-type]
    else:
        fit_l, fit_u = fits
    f_l = fit_l.f
    displacement = displacement_steps(
        final_displacement, final_displacement_factor, lower.peak_to_valley, steps
    )
    # gap0 ≥ 0 with minimum 0 at the highest point of f^u + f^l. Only the points whose gap
    # closes to within the law's reach by the last step are ever visited (detection
    # z^u ≤ z^l + reach).
    reach = check_positive("reach", reach, " µm", allow_zero=True)
    gap_c, candidates, mean_gap0 = _place_bodies(
        f_l, f_l if fit_u is None else fit_u.f, fit_u is None, float(displacement[-1]) + reach
    )
    slope_u = None if fit_u is None else fit_u.slope[candidates]
    second_u = None if fit_u is None else fit_u.second_derivative[candidates]
    return order_candidates(
        gap_c, candidates, float(mean_gap0), displacement, reach, x=lower.x[candidates],
        height_lower=f_l[candidates], slope_lower=fit_l.slope[candidates],
        second_lower=fit_l.second_derivative[candidates], slope_upper=slope_u,
        second_upper=second_u, dx=lower.dx,
    )  # fmt: skip


def order_candidates(
    gap_c: NDArray[np.float64],
    candidates: NDArray[np.int64],
    mean_gap0: float,
    displacement: NDArray[np.float64],
    reach: float,
    *,
    x: NDArray[np.float64],
    height_lower: NDArray[np.float64],
    slope_lower: NDArray[np.float64],
    second_lower: NDArray[np.float64],
    slope_upper: NDArray[np.float64] | None,
    second_upper: NDArray[np.float64] | None,
    dx: float,
) -> ContactGeometry:
    """Order the candidates by the step at which they close; their spheres (eqs. 4–6).

    Every array but ``displacement`` [µm] is given at the candidates, in the order of
    ``candidates`` (grid indices): gaps at δ_N = 0 and positions and heights h^l [µm], spline
    slopes [1] and second derivatives [1/µm] (``None`` for a flat upper body). ``reach`` [µm]
    as in :func:`contact_geometry`, ``dx`` the grid spacing [µm].
    """
    steps = displacement.size - 1
    closing = np.searchsorted(displacement, gap_c - reach, side="left")
    order_in = np.argsort(closing, kind="stable")
    order = candidates[order_in]
    counts = np.bincount(closing[order_in], minlength=steps + 1)
    active = np.cumsum(counts).astype(np.int64)
    r_min = 0.5 * dx

    kappa_l, n_x, n_z = own_frame_geometry(slope_lower[order_in], second_lower[order_in], r_min)
    if slope_upper is None or second_upper is None:
        slope_u_c = np.zeros(order.size)
        kappa_u = np.zeros(order.size)
    else:
        slope_u_c = slope_upper[order_in]
        kappa_u, _, _ = own_frame_geometry(slope_u_c, second_upper[order_in], r_min)
    norm_u = np.sqrt(1.0 + slope_u_c**2)
    return ContactGeometry(
        point=order.astype(np.int64),
        x=x[order_in],
        gap0=gap_c[order_in],
        height_lower=height_lower[order_in],
        curvature_lower=kappa_l,
        curvature_upper=kappa_u,
        m_x=slope_u_c / norm_u,
        m_z=1.0 / norm_u,
        n_x=n_x,
        n_z=n_z,
        first_step_index=active,
        displacement=displacement,
        dx=dx,
        mean_gap0=float(mean_gap0),
    )


def check_same_grid(lower: Profile, upper: Profile | str) -> None:
    """Refuse an upper profile whose grid differs from the lower one's (GridMismatchError)."""
    if isinstance(upper, str):
        return
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


def check_bodies(lower: Any, upper: Any) -> None:
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


@numba.njit(cache=True, nogil=True)
def sphere_contact(
    g: float,
    k_l: float,
    k_u: float,
    m_x: float,
    m_z: float,
    n_x: float,
    n_z: float,
    half_dx: float,
    min_delta: float,
) -> tuple[bool, float, float, float, float, float]:  # pragma: no cover - compiled
    """Contact of the two surface spheres at one grid point (Table 1, eqs. 7–10, eq. 9).

    Parameters
    ----------
    g : float
        Gap h^u − h^l at the point [µm].
    k_l, k_u : float
        Own-frame curvatures κ^l, κ^u [1/µm].
    m_x, m_z : float
        m = −n^u [1].
    n_x, n_z : float
        Lower outward normal n^l [1].
    half_dx : float
        Half the grid spacing [µm] (eq. 9: the centre must lie in the point's own cell).
    min_delta : float
        Smallest overlap accepted, exclusive [µm]: −reach of the contact law (0 for Hertz).

    Returns
    -------
    (accepted, delta, offset, e_x, e_z, y_norm)
        Whether Table 1, δ > min_delta and eq. 9 accept the contact; the overlap δ [µm]; the
        centre offset x_c − x_i [µm]; the repulsive direction e [1]; |Y| [1/µm²·µm].
    """
    k_sum = k_l + k_u
    if not k_sum > 0.0:  # Table 1 (convex–convex, or convex–concave with the smaller convex)
        return False, 0.0, 0.0, 0.0, 0.0, 1.0
    k_prod = k_u * k_l
    y_x = k_l * m_x + k_u * n_x
    y_z = k_prod * g + k_l * m_z + k_u * n_z
    y_norm = math.sqrt(y_x * y_x + y_z * y_z)
    if not y_norm > 0.0:
        return False, 0.0, 0.0, 0.0, 0.0, 1.0
    dmx = m_x - n_x
    dmz = m_z - n_z
    delta = (dmx * dmx + dmz * dmz - k_prod * g * g - 2.0 * g * (k_l * m_z + k_u * n_z)) / (
        y_norm + k_sum
    )
    if not delta > min_delta:
        return False, delta, 0.0, 0.0, 0.0, y_norm
    if min_delta < 0.0 and g > 0.0 and delta > 0.0:
        # A law acting at a gap visits points whose surfaces are apart (g > 0): their osculating
        # spheres may still intersect elsewhere; that is no contact of this point.
        return False, delta, 0.0, 0.0, 0.0, y_norm
    offset = (2.0 * dmx + delta * (k_u * n_x - k_l * m_x)) / (2.0 * y_norm)
    if not (-half_dx <= offset < half_dx):  # eq. 9
        return False, delta, offset, 0.0, 0.0, y_norm
    return True, delta, offset, y_x / y_norm, y_z / y_norm, y_norm


@numba.njit(cache=True, nogil=True)
def contact_centre_height(
    g: float,
    k_l: float,
    k_u: float,
    m_z: float,
    n_z: float,
    delta: float,
    y_norm: float,
) -> float:  # pragma: no cover - compiled
    """Height of the contact centre above the lower surface point, z_c − h^l_i [µm] (eq. 8)."""
    return (2.0 * (m_z - n_z) + delta * (k_u * n_z - k_l * m_z) + g * k_u * (2.0 - k_l * delta)) / (
        2.0 * y_norm
    )


@numba.njit(cache=True, nogil=True)
def add_contact_forces(
    sums: tuple[float, float, float, float, float, int],
    f_n: float,
    f_t: float,
    e_x: float,
    e_z: float,
    width: float,
) -> tuple[float, float, float, float, float, int]:  # pragma: no cover - compiled
    """Add one accepted contact to the global sums of eq. 14.

    Parameters
    ----------
    sums : tuple
        (F_N, F_T [mN/µm], A_S [µm], F_N from the normal forces, F_N from the tangential forces
        [mN/µm], number of contacts whose repulsive direction points down [1]) so far.
    f_n, f_t : float
        The contact's normal force along e and tangential force along t = (e_z, −e_x) [mN/µm].
    e_x, e_z : float
        Repulsive direction e [1].
    width : float
        The contact's half-width [µm] (its share of A_S).
    """
    fn_part = f_n * e_z
    ft_part = -f_t * e_x
    return (
        sums[0] + (fn_part + ft_part),
        sums[1] + (f_n * e_x + f_t * e_z),
        sums[2] + width,
        sums[3] + fn_part,
        sums[4] + ft_part,
        sums[5] + (1 if e_z < 0.0 else 0),
    )
