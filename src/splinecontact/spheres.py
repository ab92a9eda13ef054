"""Surface spheres: local normals, curvatures and centres (paper eqs. 4–6).

Every quantity here is in the body's *own* frame: heights point out of the body (as a
profilometer records them), the normal points out of the body, and the curvature is positive
where the surface is convex toward the other body (a peak):

.. math::

    n = \\frac{(-f', 1)}{\\sqrt{1 + f'^2}}, \\qquad
    κ = \\frac{1}{R} = -\\frac{f''}{(1 + f'^2)^{3/2}}, \\qquad O = a - R\\,n .

The printed eq. 5 has the opposite sign for both bodies; with it every peak looks concave, Table 1
rejects all contacts and two touching circles give no force (see ``docs/conventions.md``).

Radii are clamped to ``|R| ≥ r_min`` (paper Sec. 3, r_min = dx/2), i.e. ``|κ| ≤ 1/r_min``.
Curvature, not radius, is the primary variable: a flat spot, the spline's natural end points
(f″ = 0) and a rigid flat all have κ = 0 and stay finite throughout the contact computation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ._checks import check_real
from .errors import ParameterError
from .spline import SplineFit

__all__ = ["SurfaceSpheres", "own_frame_geometry", "surface_spheres"]


@dataclass(frozen=True, eq=False)
class SurfaceSpheres:
    """Local tangent circles ("spheres") of a smoothed profile, in the body's own frame.

    Attributes
    ----------
    x : ndarray
        Grid [µm].
    height : ndarray
        Smoothed heights f(x_i) [µm] (the sphere touches the spline there).
    curvature : ndarray
        Signed curvature κ_i [1/µm], positive where convex (peak); clamped to |κ| ≤ 1/r_min.
    normal_x, normal_z : ndarray
        Outward unit normal n_i [1] (eq. 4).
    r_min : float
        Smallest radius allowed [µm] (paper: dx/2).
    """

    x: NDArray[np.float64]
    height: NDArray[np.float64]
    curvature: NDArray[np.float64]
    normal_x: NDArray[np.float64]
    normal_z: NDArray[np.float64]
    r_min: float

    def __repr__(self) -> str:
        return f"SurfaceSpheres(n_points={self.x.size}, r_min={self.r_min:.4g} µm)"

    @property
    def is_flat(self) -> NDArray[np.bool_]:
        """Points with zero curvature (infinite radius)."""
        return np.asarray(self.curvature == 0.0)

    @property
    def radius(self) -> NDArray[np.float64]:
        """Signed radius R_i = 1/κ_i [µm]; ``inf`` where the surface is flat (κ = 0)."""
        with np.errstate(divide="ignore"):
            return np.where(self.is_flat, np.inf, 1.0 / np.where(self.is_flat, 1.0, self.curvature))

    @property
    def centre_x(self) -> NDArray[np.float64]:
        """x of the sphere centres O_i = a_i − R_i n_i [µm] (eq. 6); the point itself where flat."""
        safe = np.where(self.is_flat, 1.0, self.curvature)
        return np.where(self.is_flat, self.x, self.x - self.normal_x / safe)

    @property
    def centre_z(self) -> NDArray[np.float64]:
        """z of the sphere centres O_i = a_i − R_i n_i [µm] (eq. 6); the point itself where flat."""
        safe = np.where(self.is_flat, 1.0, self.curvature)
        return np.where(self.is_flat, self.height, self.height - self.normal_z / safe)


def own_frame_geometry(
    slope: NDArray[np.float64], second_derivative: NDArray[np.float64], r_min: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Curvature κ [1/µm] (clamped to |κ| ≤ 1/r_min) and outward normal (n_x, n_z) [1].

    Parameters
    ----------
    slope : ndarray
        f′ [1] in the body's own frame.
    second_derivative : ndarray
        f″ [1/µm] in the body's own frame.
    r_min : float
        Smallest radius [µm].
    """
    norm = np.sqrt(1.0 + slope * slope)
    curvature = -second_derivative / (norm * norm * norm)
    np.clip(curvature, -1.0 / r_min, 1.0 / r_min, out=curvature)
    return curvature, -slope / norm, 1.0 / norm


def surface_spheres(fit: SplineFit, *, r_min: float | None = None) -> SurfaceSpheres:
    """Surface spheres of a smoothing spline (eqs. 4–6, own frame, clamped radii).

    Parameters
    ----------
    fit : SplineFit
        The spline of the profile (eqs. 2–3).
    r_min : float, optional
        Smallest radius [µm]; default dx/2 (paper Sec. 3).

    Returns
    -------
    SurfaceSpheres

    Examples
    --------
    On the top of a circle of radius 50 µm every sphere of eq. 6 is that circle:

    >>> import numpy as np
    >>> from splinecontact import Profile, fit_spline, surface_spheres
    >>> x = np.linspace(-1.0, 1.0, 401)
    >>> circle = Profile(x, np.sqrt(50.0**2 - x**2) - 50.0)
    >>> spheres = surface_spheres(fit_spline(circle))
    >>> round(float(spheres.radius[200]), 3), round(float(spheres.centre_z[200]), 3)
    (50.0, -50.0)
    """
    if not isinstance(fit, SplineFit):
        raise ParameterError(
            f"fit is a {type(fit).__name__}, not a SplineFit; pass fit_spline(profile)"
        )
    if r_min is None:
        r_min = 0.5 * fit.dx
    r_min = check_real("r_min", r_min, "µm")
    if not r_min > 0:
        raise ParameterError(f"r_min = {r_min!r} µm must be > 0")
    curvature, normal_x, normal_z = own_frame_geometry(fit.slope, fit.second_derivative, r_min)
    return SurfaceSpheres(
        x=fit.x,
        height=fit.f,
        curvature=curvature,
        normal_x=normal_x,
        normal_z=normal_z,
        r_min=float(r_min),
    )
