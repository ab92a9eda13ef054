"""The monotone normal loading loop (paper Secs. 2.4–2.5, eqs. 7–14).

At every step the candidates whose gap has closed (:class:`.geometry.ContactGeometry`, ordered by
closing step) are tested by :func:`.geometry.sphere_contact` (Table 1, eq. 9, eq. 10); each
accepted contact carries the normal force of the contact law (:func:`.laws.normal_law`, Hertz
(π/4)E*δ by default) along its repulsive direction e, and a tangential force F_t along
``t = (e_z, −e_x)``, incremented by ``−G* Δu·t`` with ``Δu = (0, −Δ)`` the upper body's step
(eq. 11; the spring resists the relative motion), capped at ``μ0 |F^n|`` keeping its sign
(eqs. 12–13, :func:`.laws.tangential_spring`), and reset to 0 when the contact is not accepted.
Global sums follow eq. 14.

Cost: step k visits exactly the c_k candidates of that step (Σ_k c_k in total).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple

import numba
import numpy as np
from numpy.typing import NDArray

from ..results import ContactRecord
from .geometry import (
    ContactGeometry,
    add_contact_forces,
    contact_centre_height,
    sphere_contact,
)
from .laws import (
    ContactLaw,
    Hertz,
    Material,
    check_law,
    kernel_material,
    law_step,
    tangential_spring,
)

__all__ = ["LoadingCurves", "LoadingRun", "run_loading"]


class LoadingCurves(NamedTuple):
    """What the compiled loading loop returns: per-step sums, then the recorded contacts."""

    normal_force: NDArray[np.float64]
    tangential_force: NDArray[np.float64]
    contact_area: NDArray[np.float64]
    n_contacts: NDArray[np.int64]
    normal_force_normal_part: NDArray[np.float64]
    normal_force_tangential_part: NDArray[np.float64]
    n_tilted_contacts: NDArray[np.int64]
    rec_step: NDArray[np.int64]
    rec_index: NDArray[np.int64]
    rec_offset: NDArray[np.float64]
    rec_offset_z: NDArray[np.float64]
    rec_delta: NDArray[np.float64]
    rec_reff: NDArray[np.float64]
    rec_fn: NDArray[np.float64]
    rec_ft: NDArray[np.float64]
    rec_ex: NDArray[np.float64]
    rec_ez: NDArray[np.float64]


@dataclass(frozen=True, eq=False)
class LoadingRun:
    """Result of :func:`run_loading`.

    Attributes
    ----------
    curves : dict of str to ndarray
        Per-step arrays keyed by ``STEP_VARIABLES`` names (units there).
    contacts : tuple of ContactRecord
        The accepted contacts of the recorded steps.
    """

    curves: dict[str, NDArray[Any]]
    contacts: tuple[ContactRecord, ...]


@numba.njit(cache=True, nogil=True)
def _loading_kernel(
    gap0: NDArray[np.float64],
    kl: NDArray[np.float64],
    ku: NDArray[np.float64],
    mx: NDArray[np.float64],
    mz: NDArray[np.float64],
    nx: NDArray[np.float64],
    nz: NDArray[np.float64],
    point: NDArray[np.int64],
    active: NDArray[np.int64],
    displacement: NDArray[np.float64],
    dx: float,
    material: Material,
    record: NDArray[np.bool_],
    record_capacity: int,
) -> LoadingCurves:  # pragma: no cover - compiled
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
    law_code = material.law_code
    law_params = material.law_params
    law_state = material.law_state
    min_delta = -material.reach
    g_star = material.g_star
    mu0 = material.mu0
    for step in range(n_steps):
        d = displacement[step]
        increment = displacement[step] - displacement[step - 1] if step > 0 else 0.0
        sums = (0.0, 0.0, 0.0, 0.0, 0.0, 0)
        count = 0
        for j in range(active[step]):
            k_l = kl[j]
            k_u = ku[j]
            g = gap0[j] - d
            accepted, delta, offset, e_x, e_z, y_norm = sphere_contact(
                g, k_l, k_u, mx[j], mz[j], nx[j], nz[j], half_dx, min_delta
            )
            if not accepted:
                tangential[j] = 0.0
                was_accepted[j] = False
                continue
            reff = 2.0 / (k_l + k_u)
            f_n, width = law_step(law_code, law_params, delta, reff, law_state, point[j])
            if was_accepted[j]:
                # Δu·t with Δu = (0, −increment), t = (e_z, −e_x): increment·e_x.
                f_t, _, _ = tangential_spring(tangential[j], g_star * increment * e_x, mu0, f_n)
            else:
                f_t = 0.0
            tangential[j] = f_t
            was_accepted[j] = True
            sums = add_contact_forces(sums, f_n, f_t, e_x, e_z, width)
            if f_n != 0.0 or width > 0.0:
                count += 1  # a law acting at a gap also visits points it leaves without force
            if record[step]:
                rec_step[n_rec] = step
                rec_index[n_rec] = j
                rec_offset[n_rec] = offset
                rec_offset_z[n_rec] = contact_centre_height(
                    g, k_l, k_u, mz[j], nz[j], delta, y_norm
                )
                rec_delta[n_rec] = delta
                rec_reff[n_rec] = reff
                rec_fn[n_rec] = f_n
                rec_ft[n_rec] = f_t
                rec_ex[n_rec] = e_x
                rec_ez[n_rec] = e_z
                n_rec += 1
        out_fn[step], out_ft[step], out_area[step] = sums[0], sums[1], sums[2]
        out_fn_normal[step], out_fn_tangential[step], out_tilted[step] = sums[3], sums[4], sums[5]
        out_count[step] = count
    return LoadingCurves(
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


def run_loading(
    geometry: ContactGeometry,
    *,
    e_star: float,
    g_star: float,
    mu0: float,
    record_steps: NDArray[np.int64] | None = None,
    law: ContactLaw | None = None,
) -> LoadingRun:
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
    law : ContactLaw, optional
        Local normal contact law (default :class:`.laws.Hertz`, eq. 10); the geometry must have
        been built with its ``reach``.

    Returns
    -------
    LoadingRun
        Per-step curves keyed by ``STEP_VARIABLES`` names, and the recorded contacts.
    """
    law = Hertz() if law is None else check_law(law)
    n_records = geometry.displacement.size
    record = np.zeros(n_records, dtype=np.bool_)
    if record_steps is not None and len(record_steps):
        record[record_steps] = True
    capacity = int(geometry.first_step_index[record].sum()) if record.any() else 0
    n_points = int(geometry.point.max()) + 1 if geometry.point.size else 0
    out = _loading_kernel(
        geometry.gap0, geometry.curvature_lower, geometry.curvature_upper,
        geometry.m_x, geometry.m_z, geometry.n_x, geometry.n_z, geometry.point,
        geometry.first_step_index, geometry.displacement, geometry.dx,
        kernel_material(
            law, e_star=e_star, g_star=g_star, mu0=mu0, n_points=n_points, hertz_alone=True
        ),
        record, capacity,
    )  # fmt: skip
    curves: dict[str, NDArray[Any]] = {
        "displacement": geometry.displacement,
        "tangential_displacement": np.zeros_like(geometry.displacement),
        "normal_force": out.normal_force,
        "tangential_force": out.tangential_force,
        "contact_area": out.contact_area,
        "n_contacts": out.n_contacts,
        "mean_separation": geometry.mean_gap0 - geometry.displacement,
        "normal_force_normal_part": out.normal_force_normal_part,
        "normal_force_tangential_part": out.normal_force_tangential_part,
        "n_tilted_contacts": out.n_tilted_contacts,
        "n_candidates": geometry.first_step_index.copy(),
    }
    contacts: list[ContactRecord] = []
    for step in np.flatnonzero(record):
        sel = out.rec_step == step
        j = out.rec_index[sel]
        contacts.append(
            ContactRecord(
                step=int(step),
                point=geometry.point[j],
                x=geometry.x[j] + out.rec_offset[sel],
                z=geometry.height_lower[j] + out.rec_offset_z[sel],
                overlap=out.rec_delta[sel],
                effective_radius=out.rec_reff[sel],
                normal_force=out.rec_fn[sel],
                tangential_force=out.rec_ft[sel],
                normal_x=out.rec_ex[sel],
                normal_z=out.rec_ez[sel],
            )
        )
    return LoadingRun(curves=curves, contacts=tuple(contacts))
