"""A plain, obviously-correct SAD loading loop, kept in the tests as the oracle of the fast path.

It visits *every* grid point at *every* step (cost points × steps), recomputes the spheres in
radius form from the spline, and follows the paper's steps one by one: detection (z^u ≤ z^l),
Table 1 on the signs of the radii, the centre separation X (eq. 7), eq. 8 turned into a global
point, eq. 9, eq. 10 and the incremental tangential force (eqs. 11–13). Radii are kept finite by
using moderate geometries only (the fast path's curvature form exists precisely because the
radius form cancels catastrophically for near-flat points).
"""

from __future__ import annotations

import math

import numpy as np

from splinecontact import Profile, fit_spline


def _curvature_form(
    k_l: float, k_u: float, g: float, m: np.ndarray, n_l: np.ndarray
) -> tuple[float, float, np.ndarray, float]:
    """δ, x_c − x_i, e and R_eff from PHYSICS.md's curvature formulas (no cancellation)."""
    y = k_u * k_l * np.array([0.0, g]) + k_l * m + k_u * n_l
    y_norm = float(np.hypot(*y))
    dm = m - n_l
    delta = (float(dm @ dm) - k_u * k_l * g * g - 2 * g * (k_l * m[1] + k_u * n_l[1])) / (
        y_norm + k_u + k_l
    )
    offset = (2 * dm[0] + delta * (k_u * n_l[0] - k_l * m[0])) / (2 * y_norm)
    return delta, offset, y / y_norm, 2 / (k_u + k_l)


def reference_simulate(
    lower: Profile,
    upper: Profile | str,
    *,
    steps: int,
    final_displacement: float,
    e_star: float = 10.0,
    g_star: float | None = None,
    mu0: float = 0.3,
    formulation: str = "radius",
) -> dict[str, np.ndarray]:
    """Plain SAD loop over all points and steps.

    ``formulation="radius"`` follows eqs. 7–10 literally with radii (an independent check of
    the physics, accurate to about ε·R/δ); ``"curvature"`` uses the same curvature formulas
    as the fast path (a check of the fast path's bookkeeping to rounding).
    """
    g_star = e_star / 2.6 if g_star is None else g_star
    dx = lower.dx
    r_min = dx / 2
    fit_l = fit_spline(lower)
    f_l, s_l, c_l = fit_l.f, fit_l.slope, fit_l.second_derivative
    if isinstance(upper, str):
        f_u = np.zeros_like(f_l)
        s_u = np.zeros_like(f_l)
        c_u = np.zeros_like(f_l)
    else:
        fit_u = fit_spline(upper)
        f_u, s_u, c_u = fit_u.f, fit_u.slope, fit_u.second_derivative
    offset = np.max(f_l + f_u)
    n = lower.n_points
    tangential = np.zeros(n)
    accepted_before = np.zeros(n, dtype=bool)
    out = {k: np.zeros(steps + 1) for k in ("F_N", "F_T", "A_S", "count")}
    for k in range(steps + 1):
        d = final_displacement * k / steps
        increment = final_displacement * k / steps - final_displacement * (k - 1) / steps
        for i in range(n):
            h_l = f_l[i]
            gap = (offset - (f_u[i] + f_l[i])) - d  # gap at δ_N = 0, minus the displacement
            h_u = h_l + gap
            ok = False
            if gap <= 0:  # detection, z^u ≤ z^l
                # own-frame radii, clamped (eq. 5 with the corrected sign)
                k_l = -c_l[i] / (1 + s_l[i] ** 2) ** 1.5
                k_u = -c_u[i] / (1 + s_u[i] ** 2) ** 1.5
                k_l = min(max(k_l, -1 / r_min), 1 / r_min)
                k_u = min(max(k_u, -1 / r_min), 1 / r_min)
                n_l = np.array([-s_l[i], 1.0]) / math.sqrt(1 + s_l[i] ** 2)
                n_u = np.array([-s_u[i], -1.0]) / math.sqrt(
                    1 + s_u[i] ** 2
                )  # global, pointing down
                if formulation == "curvature":
                    if k_l + k_u > 0:
                        delta, off, e, r_eff = _curvature_form(k_l, k_u, gap, -n_u, n_l)
                        ok = delta > 0 and -dx / 2 <= off < dx / 2
                elif k_l != 0 and k_u != 0:
                    r_l, r_u = 1 / k_l, 1 / k_u
                    convex_convex = r_l > 0 and r_u > 0
                    convex_concave = r_l * r_u < 0 and r_l + r_u < 0
                    if convex_convex or convex_concave:
                        o_l = np.array([lower.x[i], h_l]) - r_l * n_l
                        o_u = np.array([lower.x[i], h_u]) - r_u * n_u
                        sep = o_u - o_l  # X of eq. 7
                        dist = float(np.hypot(*sep))
                        n_c = sep / dist
                        sgn = math.copysign(1.0, r_u * r_l)
                        delta = r_u + r_l - dist * sgn
                        centre = 0.5 * (o_u + o_l) - sgn * 0.5 * (r_u - r_l) * n_c
                        e = sgn * n_c
                        r_eff = 2 * r_u * r_l / (r_u + r_l)
                        ok = delta > 0 and -dx / 2 <= centre[0] - lower.x[i] < dx / 2
                elif k_l > 0 and k_u == 0:  # sphere on a flat: the κ^u → 0 limit
                    r_l = 1 / k_l
                    o_l = np.array([lower.x[i], h_l]) - r_l * n_l
                    e = -n_u
                    # overlap of the sphere with the flat tangent line of the upper surface
                    delta = r_l - float(np.dot(np.array([lower.x[i], h_u]) - o_l, e))
                    centre = o_l + (r_l - delta / 2) * e
                    r_eff = 2 * r_l
                    ok = delta > 0 and -dx / 2 <= centre[0] - lower.x[i] < dx / 2
            if ok:
                f_n = math.pi / 4 * e_star * delta
                t = np.array([e[1], -e[0]])
                if accepted_before[i]:
                    f_t = tangential[i] - g_star * float(np.dot(np.array([0.0, -increment]), t))
                    if abs(f_t) >= mu0 * f_n:
                        f_t = math.copysign(mu0 * f_n, f_t)
                else:
                    f_t = 0.0
                tangential[i] = f_t
                accepted_before[i] = True
                force = f_n * e + f_t * t
                out["F_N"][k] += force[1]
                out["F_T"][k] += force[0]
                out["A_S"][k] += math.sqrt(delta * r_eff)
                out["count"][k] += 1
            else:
                tangential[i] = 0.0
                accepted_before[i] = False
    return out
