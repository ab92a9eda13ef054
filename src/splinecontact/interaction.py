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
  M cells, independent of the number of grid points.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Literal

import numba
import numpy as np
import scipy.fft as sfft
from numpy.typing import NDArray

from .contact import ContactGeometry, contact_geometry
from .errors import NoConvergenceError, ParameterError
from .profile import Profile

__all__ = [
    "DEFAULT_INTERACTION_TOLERANCE",
    "NEAR_CELLS",
    "InteractionSettings",
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

#: Mesh cells per load (contact or image) when the mesh size follows the contacts [1].
CELLS_PER_SOURCE = 8

#: Pairs of contacts closer than this many mesh cells get the exact coupling coefficient.
NEAR_CELLS = 4

#: Safety factor on the largest uplift of the surface (the most negative mesh displacement) of
#: the previous step: summits whose rigid gap is below it are tested for contact [1].
UPLIFT_FACTOR = 1.5

#: Pairs closer than this many times the largest contact half-width are also near pairs (their
#: displacement gradients shape each other's contact) [1].
NEAR_WIDTHS = 6.0

#: Contacts with a Hertz half-width below this many grid spacings keep the Hertz width [1].
MIN_PUNCH_WIDTH = 0.5

#: Gauss–Legendre nodes (in θ, s = b sin θ) of the punch integrals.
PUNCH_NODES = 16

#: Gauss–Chebyshev (second kind) nodes over the Hertz distribution of a neighbour.
_QUAD_NODES = 16

#: Relative change of the contact widths and centres at which the outer loop stops [1]
#: (widths enter the coupling through logarithms only).
WIDTH_TOLERANCE = 1e-3

#: Conjugate-gradient iterations per solve.
_MAX_INNER = 10_000


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
    width_iterations : int
        Most width updates per step [1] (fewer once the widths change by less than
        ``WIDTH_TOLERANCE``); 1 lets the widths lag one step behind the loads.
    """

    periodic: bool = False
    tol: float = DEFAULT_INTERACTION_TOLERANCE
    mesh_cells: int | None = None
    width: str = "profile"
    width_iterations: int = 1


# --- closed forms ---------------------------------------------------------------------------


def periodic_green(r: NDArray[np.float64] | float, period: float, e_star: float) -> Any:
    """Zero-mean periodic plane-strain displacement of a unit line load [µm per mN/µm].

    u(r) = −(2/(πE*)) ln|2 sin(πr/L_p)|, the Fourier series 2/(E*|q|) of
    :mod:`splinecontact.bem` summed in closed form.

    Parameters
    ----------
    r : float or ndarray
        Distance from the load [µm] (not a multiple of the period).
    period : float
        Period L_p [µm].
    e_star : float
        Effective modulus E* [GPa].
    """
    return -(2.0 / (math.pi * e_star)) * np.log(
        np.abs(2.0 * np.sin(np.pi * np.asarray(r) / period))
    )


def self_coefficient(a: float, period: float, e_star: float) -> float:
    """Periodic Hertz central displacement per unit load minus SAD's local compliance [µm/(mN/µm)].

    c (ln(L_p/(π a)) + 1/2) − 2c with c = 2/(πE*): the part of a Hertzian line contact's own
    displacement (half-width ``a`` [µm], period ``period`` [µm]) that eq. 10's
    F = (π/4)E*δ does not contain.
    """
    c = 2.0 / (math.pi * e_star)
    return c * (math.log(period / (math.pi * a)) - 1.5)


@numba.njit(cache=True, nogil=True)
def _punch_log(rho: float, a: float) -> float:  # pragma: no cover - compiled
    """Flat-punch average of ln|x − y| over |x| ≤ a for a source at y = ρ."""
    t = abs(rho)
    if t <= a:
        return math.log(0.5 * a) if a > 0.0 else -1e300
    return math.log(0.5 * (t + math.sqrt(t * t - a * a)))


@numba.njit(cache=True, nogil=True)
def _pair(
    r: float,
    a_t: float,
    a_s: float,
    period: float,
    c: float,
    nodes: NDArray[np.float64],
    weights: NDArray[np.float64],
) -> float:  # pragma: no cover - compiled
    """Symmetrised coupling coefficient between contacts at distance r with half-widths a_t, a_s.

    Beyond three times the sum of the widths the averages are ln|r| − (3/16)(a_t² + a_s²)/r²
    to O((a/r)⁴) (the second moments of the punch and Hertz weights); closer by quadrature.
    """
    t = abs(r)
    if t > 3.0 * (a_t + a_s):
        mean_log = math.log(t) - 0.1875 * (a_t * a_t + a_s * a_s) / (t * t)
    else:
        total = 0.0
        for k in range(nodes.size):
            total += weights[k] * (
                _punch_log(r - a_s * nodes[k], a_t) + _punch_log(r - a_t * nodes[k], a_s)
            )
        mean_log = 0.5 * total
    x = math.pi * r / period
    sinc = math.sin(x) / x if x != 0.0 else 1.0
    return -c * (mean_log + math.log(2.0 * math.pi / period) + math.log(abs(sinc)))


def _quadrature() -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Nodes t_k and weights of (2/π)∫√(1−t²) f(t) dt ≈ Σ w_k f(t_k) (weights sum to 1)."""
    m = _QUAD_NODES
    k = np.arange(1, m + 1)
    theta = k * np.pi / (m + 1)
    return np.cos(theta), (2.0 / (m + 1)) * np.sin(theta) ** 2


def pair_coefficient(
    r: float, a_target: float, a_source: float, period: float, e_star: float
) -> float:
    """Vertical displacement at one contact per unit load on another [µm/(mN/µm)].

    The source's Hertz field (half-width ``a_source`` [µm]) averaged over the target contact
    (half-width ``a_target`` [µm]) with the flat-punch weight, symmetrised in the two widths,
    in a period ``period`` [µm] at distance ``r`` [µm] (zero-mean periodic displacement).
    """
    nodes, weights = _quadrature()
    return float(
        _pair(
            float(r),
            float(a_target),
            float(a_source),
            float(period),
            2.0 / (math.pi * e_star),
            nodes,
            weights,
        )
    )


# --- the per-step geometric pass (SAD eqs. 7–10, Table 1, eq. 9) ----------------------------


@numba.njit(cache=True, nogil=True)
def _accept(
    d: float,
    delta_min: float,
    uplift: NDArray[np.float64],
    cell: float,
    point_x: NDArray[np.float64],
    n_active: int,
    gap0: NDArray[np.float64],
    kl: NDArray[np.float64],
    ku: NDArray[np.float64],
    mx: NDArray[np.float64],
    mz: NDArray[np.float64],
    nx: NDArray[np.float64],
    nz: NDArray[np.float64],
    dx: float,
    out_index: NDArray[np.int64],
    out_delta: NDArray[np.float64],
    out_ex: NDArray[np.float64],
    out_ez: NDArray[np.float64],
    out_reff: NDArray[np.float64],
    out_offset: NDArray[np.float64],
    out_offset_z: NDArray[np.float64],
) -> int:  # pragma: no cover - compiled
    half_dx = 0.5 * dx
    count = 0
    for j in range(n_active):
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
        if delta <= delta_min:
            continue
        if delta <= 0.0:
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
        offset = (2.0 * dmx + delta * (k_u * n_x - k_l * m_x)) / (2.0 * y_norm)
        if not (-half_dx <= offset < half_dx):
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


# --- the elastic operator -------------------------------------------------------------------


@numba.njit(cache=True, nogil=True)
def _near_pairs(
    pos: NDArray[np.float64],
    a: NDArray[np.float64],
    n_targets: int,
    owner: NDArray[np.int64],
    period: float,
    cells: int,
    near: float,
    mesh_green: NDArray[np.float64],
    c: float,
    nodes: NDArray[np.float64],
    weights: NDArray[np.float64],
) -> tuple[NDArray[np.int64], NDArray[np.int64], NDArray[np.float64]]:  # pragma: no cover
    """CSR list of (target, source) pairs within ``near`` and their correction coefficients.

    Targets are sources 0 … n_targets − 1 (the contacts); the correction replaces the mesh's
    coupling of the pair by the exact one (the self pair by the self coefficient).
    """
    order = np.argsort(pos)
    sorted_pos = pos[order]
    h = period / cells
    start = np.zeros(n_targets + 1, dtype=np.int64)
    # first pass: count
    for i in range(n_targets):
        cnt = 0
        for shift in (-period, 0.0, period):
            lo = np.searchsorted(sorted_pos, pos[i] + shift - near, side="left")
            hi = np.searchsorted(sorted_pos, pos[i] + shift + near, side="right")
            cnt += hi - lo
        start[i + 1] = start[i] + cnt
    nnz = start[n_targets]
    src = np.empty(nnz, dtype=np.int64)
    coef = np.empty(nnz)
    for i in range(n_targets):
        k = start[i]
        xi = pos[i]
        ci = xi / h
        ia = math.floor(ci)
        fi = ci - ia
        for shift in (-period, 0.0, period):
            lo = np.searchsorted(sorted_pos, xi + shift - near, side="left")
            hi = np.searchsorted(sorted_pos, xi + shift + near, side="right")
            for q in range(lo, hi):
                s = order[q]
                src[k] = s
                # mesh coupling of the pair (linear weights at both ends)
                cs = pos[s] / h
                sa = math.floor(cs)
                fs = cs - sa
                mesh = 0.0
                for da in range(2):
                    wa = fi if da == 1 else 1.0 - fi
                    for db in range(2):
                        wb = fs if db == 1 else 1.0 - fs
                        mesh += wa * wb * mesh_green[(ia + da - sa - db) % cells]
                if s == i:
                    exact = c * (math.log(period / (math.pi * a[i])) - 1.5)
                else:
                    r = xi - (pos[s] - shift)
                    if owner[s] == i:  # own mirror image
                        exact = _pair(r, a[i], a[i], period, c, nodes, weights)
                    else:
                        exact = _pair(r, a[i], a[s], period, c, nodes, weights)
                coef[k] = exact - mesh
                k += 1
    return start, src, coef


@numba.njit(cache=True, nogil=True)
def _deposit(
    pos: NDArray[np.float64], q: NDArray[np.float64], cells: int, h: float
) -> NDArray[np.float64]:  # pragma: no cover
    rho = np.zeros(cells)
    for s in range(pos.size):
        cs = pos[s] / h
        sa = math.floor(cs)
        fs = cs - sa
        rho[sa % cells] += (1.0 - fs) * q[s]
        rho[(sa + 1) % cells] += fs * q[s]
    return rho


@numba.njit(cache=True, nogil=True)
def _gather(
    phi: NDArray[np.float64],
    pos: NDArray[np.float64],
    n_targets: int,
    h: float,
    start: NDArray[np.int64],
    src: NDArray[np.int64],
    coef: NDArray[np.float64],
    q: NDArray[np.float64],
) -> NDArray[np.float64]:  # pragma: no cover
    cells = phi.size
    u = np.empty(n_targets)
    for i in range(n_targets):
        ci = pos[i] / h
        ia = math.floor(ci)
        fi = ci - ia
        value = (1.0 - fi) * phi[ia % cells] + fi * phi[(ia + 1) % cells]
        for k in range(start[i], start[i + 1]):
            value += coef[k] * q[src[k]]
        u[i] = value
    return u


class _Operator:
    """Displacement at the contacts caused by contact loads: mesh far field + exact near field."""

    def __init__(
        self,
        period: float,
        cells: int | None,
        e_star: float,
        mirror: bool,
        length_nodes: int,
        dx: float,
    ) -> None:
        self.period = period
        self.fixed_cells = cells
        self.e_star = e_star
        self.c = 2.0 / (math.pi * e_star)
        self.mirror = mirror
        self.mirror_axis = (2 * length_nodes - 1) * dx
        self.max_cells = max(64, 1 << math.ceil(math.log2(max(2 * length_nodes, 2))))
        self.nodes, self.weights = _quadrature()
        self._meshes: dict[int, tuple[NDArray[np.float64], NDArray[np.complex128]]] = {}
        self._use(cells if cells is not None else 64)

    def _use(self, cells: int) -> None:
        """Switch to a mesh of ``cells`` cells (kernels cached per size)."""
        if cells not in self._meshes:
            h = self.period / cells
            m = np.arange(cells, dtype=np.float64)
            m[0] = 0.5  # the self cell: any finite value (near pairs are corrected exactly)
            green = np.asarray(periodic_green(m * h, self.period, self.e_star), dtype=np.float64)
            # linear spreading and reading each smooth the kernel by h²/12 · G″ on average over
            # the positions in a cell: take that mean smoothing out of the mesh kernel
            curvature = (
                self.c * (math.pi / self.period) ** 2 / np.sin(math.pi * m * h / self.period) ** 2
            )
            mesh_green = green - (h**2 / 6.0) * curvature
            self._meshes[cells] = (mesh_green, sfft.rfft(mesh_green))
        self.cells = cells
        self.h = self.period / cells
        self.mesh_green, self.spectrum = self._meshes[cells]

    def prepare(
        self, x: NDArray[np.float64], a: NDArray[np.float64], ez: NDArray[np.float64]
    ) -> None:
        n = x.size
        self.n = n
        if self.fixed_cells is None:
            # about CELLS_PER_SOURCE cells per load (contacts and images): the mesh follows the
            # number of contacts, not the number of grid points
            sources = 2 * n if self.mirror else n
            wanted = 1 << math.ceil(math.log2(max(CELLS_PER_SOURCE * sources, 64)))
            self._use(min(wanted, self.max_cells))
        if self.mirror:
            self.pos = np.concatenate([x, self.mirror_axis - x])
            self.a = np.concatenate([a, a])
            self.owner = np.concatenate([np.arange(n), np.arange(n)]).astype(np.int64)
            self.ez_src = np.concatenate([ez, ez])
        else:
            self.pos = x.copy()
            self.a = a.copy()
            self.owner = np.arange(n, dtype=np.int64)
            self.ez_src = ez.copy()
        self.pos = np.mod(self.pos, self.period)
        self.ez = ez
        largest = float(a.max()) if a.size else 0.0
        near = min(max(NEAR_CELLS * self.h, NEAR_WIDTHS * largest), 0.25 * self.period)
        self.start, self.src, self.coef = _near_pairs(
            self.pos,
            self.a,
            n,
            self.owner,
            self.period,
            self.cells,
            near,
            self.mesh_green,
            self.c,
            self.nodes,
            self.weights,
        )

    def displacement(self, load: NDArray[np.float64]) -> NDArray[np.float64]:
        """w_i: vertical displacement at every contact (own far part included) from loads P."""
        return self._apply(load, 0.0, np.ones(self.n))

    def apply(self, load: NDArray[np.float64]) -> NDArray[np.float64]:
        """Total compliance C P = 2c P + e_z w(P) (SAD's local law plus the coupling)."""
        return self._apply(load, 2.0 * self.c, self.ez)

    def _apply(
        self, load: NDArray[np.float64], local: float, ez: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        q, rho = _spread(load, self.owner, self.ez_src, self.pos, self.cells, self.h)
        phi = np.asarray(sfft.irfft(self.spectrum * sfft.rfft(rho), self.cells), dtype=np.float64)
        self.phi = phi
        return _collect(
            phi, self.pos, self.n, self.h, self.start, self.src, self.coef, q, load, ez, local
        )


@numba.njit(cache=True, nogil=True)
def _spread(
    load: NDArray[np.float64],
    owner: NDArray[np.int64],
    ez_src: NDArray[np.float64],
    pos: NDArray[np.float64],
    cells: int,
    h: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:  # pragma: no cover - compiled
    """Vertical source loads q = e_z P (contacts and images) and their linear mesh spreading."""
    q = np.empty(pos.size)
    for s in range(pos.size):
        q[s] = ez_src[s] * load[owner[s]]
    return q, _deposit(pos, q, cells, h)


@numba.njit(cache=True, nogil=True)
def _collect(
    phi: NDArray[np.float64],
    pos: NDArray[np.float64],
    n: int,
    h: float,
    start: NDArray[np.int64],
    src: NDArray[np.int64],
    coef: NDArray[np.float64],
    q: NDArray[np.float64],
    load: NDArray[np.float64],
    ez: NDArray[np.float64],
    local: float,
) -> NDArray[np.float64]:  # pragma: no cover - compiled
    """local·P + e_z (mesh field read back + exact near corrections) at the contacts."""
    u = _gather(phi, pos, n, h, start, src, coef, q)
    for i in range(n):
        u[i] = local * load[i] + ez[i] * u[i]
    return u


@numba.njit(cache=True, nogil=True)
def _pk_direction(
    p: NDArray[np.float64],
    cp: NDArray[np.float64],
    delta: NDArray[np.float64],
    h: NDArray[np.float64],
    t: NDArray[np.float64],
    conjugate: bool,
    g_norm_old: float,
    scale: float,
) -> tuple[float, bool, float]:  # pragma: no cover - compiled
    """Gap h = C P − δ, the largest complementarity violation / scale, and the CG direction t."""
    residual = 0.0
    g_norm = 0.0
    any_loaded = False
    for i in range(p.size):
        h[i] = cp[i] - delta[i]
        if p[i] > 0.0:
            any_loaded = True
            residual = max(residual, abs(h[i]))
            g_norm += h[i] * h[i]
        else:
            residual = max(residual, -h[i])
    beta = g_norm / g_norm_old if conjugate and g_norm_old > 0.0 else 0.0
    for i in range(p.size):
        t[i] = h[i] + beta * t[i] if p[i] > 0.0 else 0.0
    return residual / scale, any_loaded, g_norm


@numba.njit(cache=True, nogil=True)
def _pk_update(
    p: NDArray[np.float64],
    cp: NDArray[np.float64],
    r: NDArray[np.float64],
    t: NDArray[np.float64],
    h: NDArray[np.float64],
    fallback: float,
) -> tuple[bool, bool]:  # pragma: no cover - compiled
    """Step P ← max(P − τ t, 0) (overlapping unloaded contacts get −τ h); returns (conjugate,
    linear) where linear means C P was updated exactly as C P − τ C t."""
    num = 0.0
    den = 0.0
    for i in range(p.size):
        if p[i] > 0.0:
            num += h[i] * t[i]
            den += r[i] * t[i]
    tau = num / den if den > 0.0 else fallback
    conjugate = True
    linear = True
    for i in range(p.size):
        was = p[i] > 0.0
        value = p[i] - tau * t[i]
        if was and value < 0.0:
            value = 0.0
            linear = False
        if not was and h[i] < 0.0:
            value = -tau * h[i]
            conjugate = False
            linear = False
        p[i] = value
    if linear:
        for i in range(p.size):
            cp[i] -= tau * r[i]
    return conjugate, linear


def _pk_solve(
    op: _Operator, delta: NDArray[np.float64], load: NDArray[np.float64], tol: float
) -> tuple[NDArray[np.float64], int]:
    """Constrained conjugate gradients (Polonsky–Keer, displacement control) at contact level.

    Finds P ≥ 0 with h = C P − δ ≥ 0 and P·h = 0 (C at frozen widths). C P is updated
    incrementally while the loaded set does not change, and recomputed before convergence is
    declared.
    """
    scale = float(delta.max())
    if scale <= 0.0:
        return np.zeros_like(delta), 0
    p = np.clip(load, 0.0, None)
    t = np.zeros_like(p)
    h = np.empty_like(p)
    g_norm_old = 0.0
    conjugate = False
    self_part = np.maximum(op.c * (np.log(op.period / (np.pi * op.a[: op.n])) - 1.5), 0.0)
    fallback = float(1.0 / np.max(2.0 * op.c + op.ez**2 * self_part))
    cp = op.apply(p)
    exact = True
    residual = math.inf
    for iteration in range(_MAX_INNER + 1):
        residual, any_loaded, g_norm = _pk_direction(
            p, cp, delta, h, t, conjugate, g_norm_old, scale
        )
        if residual <= tol:
            if exact:
                return p, iteration
            cp = op.apply(p)
            exact = True
            continue
        if not any_loaded:
            # nothing loaded: exact line search along the overlap −h
            d = np.clip(-h, 0.0, None)
            cd = op.apply(d)
            curvature = float(d @ cd)
            step = float(d @ d) / curvature if curvature > 0.0 else fallback
            p = step * d
            conjugate = False
            cp = op.apply(p)
            exact = True
            continue
        g_norm_old = g_norm
        r = op.apply(t)
        conjugate, linear = _pk_update(p, cp, r, t, h, fallback)
        if not linear:
            cp = op.apply(p)
        exact = not linear
    raise NoConvergenceError(
        f"the interacting contact solve did not converge in {_MAX_INNER} iterations (residual "
        f"{residual:.3g} > tol {tol:.3g}); raise tol or use more steps"
    )


def _hertz_width(
    load: NDArray[np.float64], reff: NDArray[np.float64], e_star: float, floor: float
) -> NDArray[np.float64]:
    """Hertz half-width a = √(2 P R_eff/(πE*)) = √(δ^eff R_eff/2) [µm], at least ``floor``."""
    return np.maximum(np.sqrt(2.0 * np.clip(load, 0.0, None) * reff / (math.pi * e_star)), floor)


@numba.njit(cache=True, nogil=True)
def _sample(values: NDArray[np.float64], pos: float, dx: float) -> float:  # pragma: no cover
    """Linear interpolation of a grid array at position ``pos`` [µm]; NaN outside it."""
    t = pos / dx
    i0 = math.floor(t)
    if i0 < 0 or i0 + 1 >= values.size:
        return math.nan
    frac = t - i0
    return values[i0] * (1.0 - frac) + values[i0 + 1] * frac


@numba.njit(cache=True, nogil=True)
def _neighbour_slope(
    pos: float,
    first: int,
    last: int,
    src: NDArray[np.int64],
    src_pos: NDArray[np.float64],
    src_a: NDArray[np.float64],
    src_q: NDArray[np.float64],
    own: int,
    period: float,
    c0: float,
    reach: float,
) -> float:  # pragma: no cover - compiled
    """Slope of the surface displacement of the near neighbours (Hertz fields) at ``pos``.

    Neighbours farther than ``reach`` plus NEAR_WIDTHS of their own half-widths only tilt the
    contact uniformly and are left out.
    """
    total = 0.0
    for k in range(first, last):
        s = src[k]
        q = src_q[s]
        if s == own or q == 0.0:
            continue
        r = pos - src_pos[s]
        r -= period * math.floor(r / period + 0.5)
        a = src_a[s]
        t = abs(r)
        if t > reach + NEAR_WIDTHS * a:
            continue
        if t <= a:
            g = r
        else:
            g = r - math.copysign(math.sqrt(t * t - a * a), r)
        total -= 2.0 * c0 * q * g / (a * a)
    return total


@numba.njit(cache=True, nogil=True)
def _punch(
    slope: NDArray[np.float64],
    curvature: NDArray[np.float64],
    x: float,
    dx: float,
    b: float,
    c: float,
    e_star: float,
    sines: NDArray[np.float64],
    weights: NDArray[np.float64],
    first: int,
    last: int,
    src: NDArray[np.int64],
    src_pos: NDArray[np.float64],
    src_a: NDArray[np.float64],
    src_q: NDArray[np.float64],
    own: int,
    period: float,
) -> tuple[float, float]:  # pragma: no cover - compiled
    """Centre and load of a 2D frictionless punch of the local gap profile of half-width b.

    The contact [x + c − b, x + c + b] of a rigid profile with gap slope f′ has bounded pressure
    at both edges when ∫ f′(x + c + s)/√(b² − s²) ds = 0 (solved for c by Newton's method),
    and then carries P = (E*/2) ∫ s f′(x + c + s)/√(b² − s²) ds (Hertz for a parabola; the
    plane-strain punch relations, e.g. Johnson, *Contact Mechanics*, §2.8). Integrals with
    s = b sin θ and Gauss–Legendre nodes in θ. Returns (c, P), NaN beyond the candidates.
    """
    c0 = 2.0 / (math.pi * e_star)
    reach = NEAR_WIDTHS * b
    for _ in range(20):
        i0 = 0.0
        i1 = 0.0
        for k in range(sines.size):
            pos = x + c + b * sines[k]
            v = _sample(slope, pos, dx) + _neighbour_slope(
                pos, first, last, src, src_pos, src_a, src_q, own, period, c0, reach
            )
            w = _sample(curvature, pos, dx)
            if math.isnan(v) or math.isnan(w):
                return math.nan, math.nan
            i0 += weights[k] * v
            i1 += weights[k] * w
        if i1 <= 0.0:
            break
        dc = -i0 / i1
        if dc > 0.5 * b:
            dc = 0.5 * b
        elif dc < -0.5 * b:
            dc = -0.5 * b
        c += dc
        if abs(dc) <= 1e-9 * b:
            break
    total = 0.0
    for k in range(sines.size):
        s = b * sines[k]
        pos = x + c + s
        v = _sample(slope, pos, dx) + _neighbour_slope(
            pos, first, last, src, src_pos, src_a, src_q, own, period, c0, reach
        )
        if math.isnan(v):
            return math.nan, math.nan
        total += weights[k] * s * v
    return c, 0.5 * e_star * total


@numba.njit(cache=True, nogil=True)
def _bridges(
    x_sorted: NDArray[np.float64], x: float, c: float, b: float
) -> bool:  # pragma: no cover
    """Does the interval [x + c − b, x + c + b] contain another contact's summit?"""
    centre = x + c
    inside = np.searchsorted(x_sorted, centre + b) - np.searchsorted(x_sorted, centre - b)
    if abs(x - centre) < b:
        inside -= 1
    return bool(inside > 0)


@numba.njit(cache=True, nogil=True)
def _profile_widths(
    load: NDArray[np.float64],
    a_hertz: NDArray[np.float64],
    x: NDArray[np.float64],
    b_start: NDArray[np.float64],
    c_start: NDArray[np.float64],
    slope: NDArray[np.float64],
    curvature: NDArray[np.float64],
    dx: float,
    e_star: float,
    sines: NDArray[np.float64],
    weights: NDArray[np.float64],
    start: NDArray[np.int64],
    src: NDArray[np.int64],
    src_pos: NDArray[np.float64],
    src_a: NDArray[np.float64],
    src_q: NDArray[np.float64],
    period: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:  # pragma: no cover - compiled
    """Half-widths and centre shifts at which each contact's punch load equals its load.

    Secant iteration in log b (exact in one step for a parabola), warm-started from
    ``b_start``/``c_start``; contacts narrower than two grid spacings, or reaching beyond the
    candidates, keep the Hertz width and no shift.
    """
    n = load.size
    out_b = a_hertz.copy()
    out_c = np.zeros(n)
    x_sorted = np.sort(x)
    for i in range(n):
        target = load[i]
        if target <= 0.0 or a_hertz[i] < MIN_PUNCH_WIDTH * dx:
            continue
        b = b_start[i] if b_start[i] > 0.0 else a_hertz[i]
        c = c_start[i]
        b_old = 0.0
        p_old = 0.0
        ok = False
        for _ in range(40):
            c, p = _punch(
                slope,
                curvature,
                x[i],
                dx,
                b,
                c,
                e_star,
                sines,
                weights,
                start[i],
                start[i + 1],
                src,
                src_pos,
                src_a,
                src_q,
                i,
                period,
            )
            if math.isnan(p) or p <= 0.0:
                break
            if abs(p / target - 1.0) <= 1e-6:
                ok = True
                break
            m = 2.0
            if b_old > 0.0 and p_old > 0.0 and b_old != b and p_old != p:
                m = math.log(p / p_old) / math.log(b / b_old)
                m = min(max(m, 0.5), 4.0)
            b_old = b
            p_old = p
            b = b * (target / p) ** (1.0 / m)
        if ok:
            # a punch that reaches over another contact's summit is not this contact's
            # solution (it would bridge the valley between them)
            ok = not _bridges(x_sorted, x[i], c, b)
        if not ok and b_start[i] > 0.0 and not _bridges(x_sorted, x[i], c_start[i], b_start[i]):
            # keep the previous width and centre if they are admissible, else Hertz
            b = b_start[i]
            c = c_start[i]
            ok = True
        if ok:
            out_b[i] = b
            out_c[i] = c
    return out_b, out_c


class _Widths:
    """Contact half-widths from the loads: Hertz (tip curvature) or the local punch profile."""

    def __init__(
        self, slope: NDArray[np.float64] | None, dx: float, e_star: float, floor: float
    ) -> None:
        self.slope = slope
        self.curvature = None if slope is None else np.gradient(slope, dx)
        self.dx = dx
        self.e_star = e_star
        self.floor = floor
        nodes, weights = np.polynomial.legendre.leggauss(PUNCH_NODES)
        self.sines = np.sin(0.5 * np.pi * nodes)
        self.weights = 0.5 * np.pi * weights

    def __call__(
        self,
        load: NDArray[np.float64],
        reff: NDArray[np.float64],
        x: NDArray[np.float64],
        b_start: NDArray[np.float64],
        c_start: NDArray[np.float64],
        op: _Operator | None = None,
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        a = _hertz_width(load, reff, self.e_star, self.floor)
        if self.slope is None or self.curvature is None:
            return a, np.zeros_like(a)
        if op is None:  # no neighbours known yet
            start = np.zeros(load.size + 1, dtype=np.int64)
            src = np.zeros(0, dtype=np.int64)
            src_pos = src_a = src_q = np.zeros(1)
            period = 1.0
        else:
            start, src, src_pos, src_a = op.start, op.src, op.pos, op.a
            src_q = op.ez_src * load[op.owner]
            period = op.period
        b, c = _profile_widths(
            load,
            a,
            x,
            b_start,
            c_start,
            self.slope,
            self.curvature,
            self.dx,
            self.e_star,
            self.sines,
            self.weights,
            start,
            src,
            src_pos,
            src_a,
            src_q,
            period,
        )
        return np.maximum(b, self.floor), c


def solve_contacts(
    op: _Operator,
    x: NDArray[np.float64],
    delta: NDArray[np.float64],
    ez: NDArray[np.float64],
    reff: NDArray[np.float64],
    initial: NDArray[np.float64],
    b_start: NDArray[np.float64],
    c_start: NDArray[np.float64],
    e_star: float,
    widths: _Widths,
    tol: float,
    outer: int = 1,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], int]:
    """Loads P_i [mN/µm], half-widths and centre shifts [µm] of the contacts at one step.

    The widths and centres are frozen in each constrained-CG solve. Contacts loaded at the
    previous step start from their previous width and centre, new ones from the Hertz width of
    SAD's independent force; after each solve the widths are updated from the loads, at most
    ``outer`` times (1: widths lag one step behind the loads, which changes them by one step's
    increment).
    """
    floor = widths.floor
    load = initial.copy()
    fresh = b_start <= 0.0
    a = np.where(
        fresh,
        _hertz_width(_QUARTER_PI * e_star * np.clip(delta, 0.0, None), reff, e_star, floor),
        b_start,
    )
    c = np.where(fresh, 0.0, c_start)
    total = 0
    for _ in range(outer):
        op.prepare(x + c, a, ez)
        load, iterations = _pk_solve(op, delta, load, tol)
        total += iterations
        a_new, c_new = widths(load, reff, x, a, c, op)
        if not np.any(load > 0) or np.all(
            np.abs(a_new - a) + np.abs(c_new - c) <= WIDTH_TOLERANCE * np.maximum(a, floor)
        ):
            return load, a_new, c_new, total
        a, c = a_new, c_new
    return load, a, c, total


def _union_length(lo: NDArray[np.float64], hi: NDArray[np.float64]) -> tuple[float, int]:
    """Length of the union of intervals [lo, hi] and the number of its connected pieces."""
    if lo.size == 0:
        return 0.0, 0
    order = np.argsort(lo, kind="stable")
    lo = lo[order]
    hi = hi[order]
    reach = np.maximum.accumulate(hi)
    new = np.empty(lo.size, dtype=bool)
    new[0] = True
    new[1:] = lo[1:] > reach[:-1]
    starts = np.flatnonzero(new)
    ends = np.append(starts[1:], lo.size) - 1
    length = float(np.sum(reach[ends] - lo[starts]))
    return length, int(starts.size)


def extended_geometry(
    lower: Profile,
    upper: Profile | Literal["flat"],
    *,
    steps: int,
    final_displacement: float | None,
    final_displacement_factor: float,
    alpha: float,
    x0: float,
    reach: float = DEFAULT_REACH,
) -> tuple[ContactGeometry, dict[str, float]]:
    """SAD geometry whose candidate set reaches beyond the last displacement.

    In the coupled body the surface between loaded contacts rises (the displacement has zero
    mean), so summits whose rigid gap is still open can touch. The candidates are those whose gap
    closes by (1 + ``reach``) × the final displacement; the displacement steps are SAD's,
    δ_N = final · k / steps. Parameters as :func:`splinecontact.contact.contact_geometry`;
    ``reach`` [1] ≥ 0.
    """
    if not (isinstance(reach, (int, float)) and math.isfinite(reach) and reach >= 0.0):
        raise ParameterError(f"reach must be a finite number ≥ 0, got {reach!r}")
    final = (
        final_displacement_factor * lower.peak_to_valley
        if final_displacement is None
        else float(final_displacement)
    )
    geometry, stats = contact_geometry(
        lower,
        upper,
        steps=steps,
        final_displacement=final * (1.0 + reach),
        final_displacement_factor=final_displacement_factor,
        alpha=alpha,
        x0=x0,
    )
    displacement = final * np.arange(steps + 1) / steps
    return replace(geometry, displacement=displacement), stats


def interacting_loading(
    geometry: Any,
    *,
    e_star: float,
    g_star: float,
    mu0: float,
    n_points: int,
    settings: InteractionSettings = InteractionSettings(),
    record_steps: NDArray[np.int64] | None = None,
) -> tuple[dict[str, NDArray[Any]], list[dict[str, NDArray[Any]]]]:
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

    Returns
    -------
    (curves, contacts)
        Per-step arrays (the keys of :func:`splinecontact.contact.run_loading` plus
        ``contact_length`` [µm], the union of the Hertz intervals, ``n_patches`` [1], its pieces,
        and ``interaction_iterations`` [1]); recorded contacts as dicts of arrays per step.
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
    op = _Operator(period, cells, e_star, not settings.periodic, n, dx)
    floor = 1e-6 * dx
    if isinstance(settings.width_iterations, bool) or not (
        isinstance(settings.width_iterations, int) and 1 <= settings.width_iterations <= 100
    ):
        raise ParameterError(
            f"width_iterations must be an integer in 1…100, got {settings.width_iterations!r}"
        )
    if settings.width not in ("profile", "hertz"):
        raise ParameterError(f"width must be 'profile' or 'hertz', got {settings.width!r}")
    slope = None
    if settings.width == "profile":
        # slope of the rigid gap from the spline slopes at the nodes (eq. 4 normals):
        # gap′ = −f_l′ − f_u′ = n_x/n_z − m_x/m_z; NaN where the gap never closes
        slope = np.full(n, np.nan)
        slope[np.asarray(geometry.point)] = np.asarray(geometry.n_x) / np.asarray(
            geometry.n_z
        ) - np.asarray(geometry.m_x) / np.asarray(geometry.m_z)
    widths = _Widths(slope, dx, e_star, floor)
    displacement = np.asarray(geometry.displacement, dtype=np.float64)
    n_steps = displacement.size
    n_cand = geometry.gap0.size
    record = np.zeros(n_steps, dtype=bool)
    if record_steps is not None and len(record_steps):
        record[np.asarray(record_steps)] = True
    idx = np.empty(n_cand, dtype=np.int64)
    delta = np.empty(n_cand)
    ex = np.empty(n_cand)
    ez = np.empty(n_cand)
    reff = np.empty(n_cand)
    offset = np.empty(n_cand)
    offset_z = np.empty(n_cand)
    load_all = np.zeros(n_cand)
    older_all = np.zeros(n_cand)
    last_j = np.zeros(0, dtype=np.int64)
    last_increment = 0.0
    tangential = np.zeros(n_cand)
    width_all = np.zeros(n_cand)
    shift_all = np.zeros(n_cand)
    names = (
        "normal_force",
        "tangential_force",
        "contact_area",
        "normal_force_normal_part",
        "normal_force_tangential_part",
        "contact_length",
    )
    curves: dict[str, NDArray[Any]] = {k: np.zeros(n_steps) for k in names}
    for k in (
        "n_contacts",
        "n_tilted_contacts",
        "n_patches",
        "interaction_iterations",
        "reach_exceeded",
    ):
        curves[k] = np.zeros(n_steps, dtype=np.int64)
    contacts: list[dict[str, NDArray[Any]]] = []
    point_x = np.asarray(geometry.point, dtype=np.float64) * dx
    length = n * dx
    # candidates in order of closing; the reach of the candidate set is its largest gap
    closing_gap = np.maximum.accumulate(np.asarray(geometry.gap0, dtype=np.float64))
    reach = float(closing_gap[-1]) if closing_gap.size else 0.0
    margin = 0.0
    field = np.zeros(1)
    field_cell = period
    for step in range(n_steps):
        d = float(displacement[step])
        increment = d - float(displacement[step - 1]) if step > 0 else 0.0
        threshold = d + margin
        if threshold > reach:
            curves["reach_exceeded"][step] = 1
        n_active = int(np.searchsorted(closing_gap, threshold, side="right"))
        count = _accept(
            d,
            -margin,
            field,
            field_cell,
            point_x,
            n_active,
            geometry.gap0,
            geometry.curvature_lower,
            geometry.curvature_upper,
            geometry.m_x,
            geometry.m_z,
            geometry.n_x,
            geometry.n_z,
            dx,
            idx,
            delta,
            ex,
            ez,
            reff,
            offset,
            offset_z,
        )
        j = idx[:count].copy()
        previous = load_all[j]
        older = older_all[j]
        keep_tangential = tangential[j]
        b_start = width_all[j]
        c_start = shift_all[j]
        # the state lives on the contacts of the last step only: clear it there
        older_all[last_j] = 0.0
        older_all[j] = previous
        load_all[last_j] = 0.0
        tangential[last_j] = 0.0
        width_all[last_j] = 0.0
        shift_all[last_j] = 0.0
        last_j = j
        if count == 0:
            continue
        x = point_x[j] + offset[:count]
        # warm start: the loads of the last step, extrapolated along the path where known
        ratio = increment / last_increment if last_increment > 0.0 else 0.0
        guess = np.where(
            (previous > 0.0) & (older > 0.0), previous + ratio * (previous - older), previous
        )
        last_increment = increment
        # and the widths with them (a ∝ √P near a smooth summit)
        grown = (previous > 0.0) & (guess > 0.0)
        b_start = np.where(
            grown,
            b_start * np.sqrt(np.where(grown, guess, 1.0) / np.where(grown, previous, 1.0)),
            b_start,
        )
        load, a, shift, iterations = solve_contacts(
            op,
            x,
            delta[:count].copy(),
            ez[:count].copy(),
            reff[:count].copy(),
            np.clip(guess, 0.0, None),
            b_start,
            c_start,
            e_star,
            widths,
            settings.tol,
            settings.width_iterations,
        )
        width_all[j] = np.where(load > 0.0, a, 0.0)
        shift_all[j] = np.where(load > 0.0, shift, 0.0)
        x = x + shift
        curves["interaction_iterations"][step] = iterations
        if np.any(load > 0.0):
            op.displacement(load)
            field = op.phi.copy()
            field_cell = op.h
            margin = UPLIFT_FACTOR * max(0.0, -float(field.min()))
        on = load > 0.0
        f_n = load
        # tangential springs (eqs. 11–13) on loaded contacts, reset where unloaded
        f_t = np.where(previous > 0.0, keep_tangential - g_star * increment * ex[:count], 0.0)
        cap = mu0 * f_n
        f_t = np.clip(f_t, -cap, cap)
        f_t[~on] = 0.0
        load_all[j] = load
        tangential[j] = f_t
        e_x = ex[:count]
        e_z = ez[:count]
        fn_part = f_n * e_z
        ft_part = -f_t * e_x
        curves["normal_force_normal_part"][step] = fn_part[on].sum()
        curves["normal_force_tangential_part"][step] = ft_part[on].sum()
        curves["normal_force"][step] = (fn_part + ft_part)[on].sum()
        curves["tangential_force"][step] = (f_n * e_x + f_t * e_z)[on].sum()
        delta_eff = load / (_QUARTER_PI * e_star)
        r = reff[:count]
        curves["contact_area"][step] = np.sqrt(delta_eff[on] * r[on]).sum()
        curves["n_contacts"][step] = int(on.sum())
        curves["n_tilted_contacts"][step] = int(np.sum(on & (e_z < 0.0)))
        half = a[on]
        lo = np.clip(x[on] - half, 0.0, length)
        hi = np.clip(x[on] + half, 0.0, length)
        curves["contact_length"][step], curves["n_patches"][step] = _union_length(lo, hi)
        if record[step]:
            contacts.append(
                {
                    "step": np.full(int(on.sum()), step),
                    "index": j[on],
                    "x": x[on],
                    "overlap": delta_eff[on],
                    "rigid_overlap": delta[:count][on],
                    "effective_radius": r[on],
                    "normal_force": f_n[on],
                    "tangential_force": f_t[on],
                    "normal_x": e_x[on],
                    "normal_z": e_z[on],
                    "offset_z": offset_z[:count][on],
                }
            )
    curves["displacement"] = displacement
    curves["tangential_displacement"] = np.zeros_like(displacement)
    curves["mean_separation"] = geometry.mean_gap0 - displacement
    curves["n_candidates"] = np.asarray(geometry.first_step_index).copy()
    return curves, contacts
